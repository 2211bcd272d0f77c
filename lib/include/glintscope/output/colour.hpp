#pragma once
// Lobe images to colour (conventions.md "Spectra and colour", docs/colour.md).
//
// A spectral lobe (two or more wavelengths) becomes CIE XYZ through the spectral weights
// (spectrum.hpp) and then an output colour space through OpenColorIO. A single-wavelength lobe
// has no colour: it is shown achromatic, as the D65 white scaled to luminance Y = f_r.
//
// White point: the weights are followed by a Bradford adaptation from the illuminant's white
// (computed from the tables) to the nominal D65 white (x, y) = (0.3127, 0.3290) of the colour
// spaces, so a lobe that is the same at every wavelength is exactly neutral, R = G = B, with
// Y unchanged. For D65 this removes the 3e-5 chromaticity difference between the tabulated
// D65 and its nominal value; for E it is a white balance, so E only reweights the wavelengths.
//
// The OpenColorIO config is, in order: ColourSettings::config_path, else $OCIO, else the
// built-in data/ocio/config.ocio. XYZ is taken to be its colour space of role
// cie_xyz_d65_interchange, else the one named CIE-XYZ-D65.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "glintscope/lobe/image.hpp"
#include "glintscope/optics/spectrum.hpp"

namespace glintscope {

struct ColourSettings {
    std::string config_path;                   // OpenColorIO config file; empty: $OCIO or built in
    std::string output_space = "lin_rec709";   // scene-linear space of EXR R, G, B
    std::string display_space = "sRGB";        // encoding of PNG pixels
    Illuminant illuminant = Illuminant::d65;
    std::optional<double> exposure_ev;         // PNG exposure: pixels are scaled by 2^EV; unset: auto
    double auto_percentile = 99.5;             // auto, linear: this percentile of luminance in the disk maps to 1
    bool log_scale = false;                    // PNG: luminance on a log scale; auto puts the maximum at 1
    double log_decades = 4.0;                  // log scale: white·10^-decades .. white maps to 0 .. 1
};

// The nominal D65 white of the output colour spaces.
inline constexpr Chromaticity d65_white{0.3127, 0.3290};
XYZ d65_white_xyz();  // (x/y, 1, (1 − x − y)/y)

// Bradford chromatic adaptation of `colour` from white `source_white` to the nominal D65 white.
XYZ adapt_to_d65(XYZ colour, XYZ source_white);

// Where the config comes from: its path, or "built-in data/ocio/config.ocio".
std::string colour_config_name(const ColourSettings& settings);

// The colour spaces of the selected config; throws Error if it cannot be loaded.
std::vector<std::string> colour_space_names(const ColourSettings& settings);

// Converts packed XYZ pixels (x, y, z, x, y, z, ...) in place to the colour space `space`;
// throws Error for an unknown space (listing the known ones) or an unusable config.
void convert_from_xyz(std::vector<float>& pixels, const ColourSettings& settings, const std::string& space);

// N×N×3 XYZ of a lobe, D65-adapted as described above; pixels outside the disk are 0.
std::vector<float> lobe_to_xyz(const LobeImage& lobe, Illuminant illuminant);

// Packed XYZ of any image of per-wavelength layers ([layer][pixel], `pixels` per layer; a render),
// weighted and adapted as lobe_to_xyz, every pixel counted.
std::vector<float> layers_to_xyz(std::span<const float> values, std::size_t pixels,
                                 const std::vector<double>& wavelengths_um, Illuminant illuminant);

// The space's primaries and white as the EXR "chromaticities" attribute (red, green, blue, white
// xy), for the spaces whose primaries are known (lin_rec709, lin_rec2020, ACEScg, CIE-XYZ-D65);
// empty for others. Throws Error if the space is display-encoded (not scene-linear), which an
// EXR must not hold.
std::vector<float> scene_linear_chromaticities(const ColourSettings& settings, const std::string& space);

// N×N×3 linear RGB in settings.output_space.
std::vector<float> lobe_to_rgb(const LobeImage& lobe, const ColourSettings& settings);

// How a PNG was exposed. Linear: pixels are scaled by 2^ev, so luminance white_level = 2^−ev
// shows as 1. Log: luminance Y shows as 1 + log10(Y / white_level)/decades, clamped to [0, 1],
// with the colour's chromaticity kept.
struct DisplayExposure {
    double ev = 0.0;
    double white_level = 1.0;  // 2^−ev, in sr⁻¹
    bool log_scale = false;
    double log_decades = 4.0;
    std::string rule;          // how ev was chosen, e.g. "auto: 99.5th percentile of luminance in the disk"
};

// The exposure `settings` ask for: the given EV, or auto: the luminance percentile inside the
// disk (the maximum on a log scale, or when the percentile is 0) shows as 1; EV 0 for a black lobe.
DisplayExposure display_exposure(const LobeImage& lobe, const ColourSettings& settings);

// display_exposure's rules over packed XYZ pixels, every pixel counted (a render).
DisplayExposure xyz_exposure(const std::vector<float>& xyz, const ColourSettings& settings);

// Packed XYZ pixels exposed as `exposure` says, as 8-bit pixels in settings.display_space.
std::vector<std::uint8_t> xyz_to_display(std::vector<float> xyz, const DisplayExposure& exposure,
                                         const ColourSettings& settings);

// N×N×3 8-bit display pixels in settings.display_space, exposed by display_exposure.
struct DisplayImage {
    int resolution = 0;
    std::vector<std::uint8_t> pixels;
    DisplayExposure exposure;
};
DisplayImage lobe_to_display(const LobeImage& lobe, const ColourSettings& settings);

}  // namespace glintscope
