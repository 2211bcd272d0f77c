#pragma once
// Writing lobe images (every file atomically, through atomic_output.hpp):
//
// Labels (channel names, units, legends, JSON keys) come from the image's quantity (image.hpp):
// below, "Y" and f_r stand for a BRDF; an NDF image writes "D" and D.
//
// EXR (scene-linear, 32-bit float, zip): a single-wavelength lobe is one channel "Y" holding
// f_r in sr⁻¹; a spectral lobe is R, G, B in the chosen linear colour space and, on request,
// one channel per wavelength named after Fichet, Pacanowski & Wilkie 2021, "An OpenEXR Layout
// for Spectral Images" (JCGT 10(3)): "S0.<λ in nm, 6 decimals, comma as decimal mark>nm",
// e.g. "S0.560,000000nm", with the header attributes spectralLayoutVersion = "1.0" and
// emissiveUnits = "W.m^-2.sr^-1". The layout's emissive form fits because f_r is the outgoing
// radiance for unit incident irradiance. Every metadata entry becomes the string attribute
// "glintscope:<key>"; the writer adds its own facts under "glintscope:output.<name>" (units,
// wavelengths_um, channels, colour space, ...), a namespace reserved for it.
//
// PNG (display-referred 8-bit sRGB): a spectral lobe in colour with exposure (colour.hpp);
// a single-wavelength lobe colour-mapped (inferno or viridis, colormap.hpp) with a legend of
// its value range, or in grey through the display path. The colour and grey PNGs carry the
// metadata and exposure as text; the colour-mapped one shows its range in the legend.
//
// JSON sidecar: the metadata, the wavelengths, the colour settings and exposure, and per
// wavelength the peak value with its pixel and direction and the albedo Σ f_r (2/N)².
#include <span>
#include <string>
#include <vector>

#include "glintscope/output/colour.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/image.hpp"

namespace glintscope {

struct LobeOutputOptions {
    ColourSettings colour;
    bool spectral_channels = false;    // EXR of a spectral lobe: also one channel per wavelength
    std::string colormap = "inferno";  // PNG of a single wavelength: "inferno", "viridis" or "grey"
    bool bare = false;                 // PNG: the image alone, without guides, caption or colour bar (figure.hpp)
};

struct WavelengthSummary {
    double wavelength_um = 0.0;
    float peak_value = 0.0f;  // largest finite f_r in sr⁻¹ (first in row-major order on ties)
    int peak_row = 0;
    int peak_col = 0;
    Vec3 peak_direction;      // the direction at the centre of the peak pixel
    double disk_sum = 0.0;    // Σ value (2/N)²: the albedo ∫ f_r cos θ_o dω_o (brdf), 1 (ndf)
};

// Over the pixels inside the unit disk (outside it there are no directions), per wavelength.
std::vector<WavelengthSummary> summarize_lobe(const LobeImage& lobe);

// The spectral channel name of a wavelength (Fichet et al. 2021), e.g. 0.56 → "S0.560,000000nm".
std::string spectral_channel_name(double wavelength_um);

// The options' colour map, OpenColorIO config and output colour space (known, scene-linear)
// checked as the writers will use them, so that a bad --colormap, --ocio-config or
// --colour-space fails before any computation. Throws Error with one line.
void check_output_options(const LobeOutputOptions& options);

void write_lobe_exr(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options);

// Annotated (figure.hpp: write_lobe_picture) unless options.bare. Returns the exposure used
// (for single-wavelength colour maps: white_level is the top of the colour bar).
DisplayExposure write_lobe_png(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options);

void write_lobe_json(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options);

// The PNG exposure (EV) recorded in a JSON sidecar written by write_lobe_json, so that another
// picture can be exposed alike. Throws Error naming the file if it has none.
double recorded_exposure_ev(const std::string& json_path);

// By the extension of `path`: .exr, .png or .json; anything else throws Error.
void write_lobe(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options);

// The layers of an EXR written by write_lobe_exr, as they can be compared: one per wavelength
// (the "Y" or "D" channel, or a spectral lobe's S0.<nm> channels) or, for a spectral lobe
// written without per-wavelength channels, its R, G and B channels.
struct LobeExrLayers {
    int resolution = 0;
    Quantity quantity = Quantity::brdf;
    std::vector<double> wavelengths_um;  // the lobe's, as recorded
    Provenance metadata;                 // without the writer's "output." attributes
    bool colour = false;                 // the layers are R, G, B, not wavelengths
    std::string colour_encoding;         // when colour: the recorded colour space and illuminant
    std::vector<std::string> names;      // per layer: "0.5 um", or "R", "G", "B"
    std::vector<float> values;           // [layer][row][col]

    std::size_t layers() const { return names.size(); }
    std::span<const float> layer(std::size_t k) const {
        const std::size_t pixels = std::size_t(resolution) * resolution;
        return std::span<const float>(values).subspan(k * pixels, pixels);
    }
};
LobeExrLayers load_lobe_exr_layers(const std::string& path);

// Reads an EXR written by write_lobe_exr back: the "Y" or "D" channel, or the per-wavelength
// channels of a spectral lobe (an RGB-only file throws Error; load_lobe_exr_layers reads it).
// Values and metadata come back exactly; the writer's "output." attributes are not part of the
// metadata.
LobeImage load_lobe_exr(const std::string& path);

}  // namespace glintscope
