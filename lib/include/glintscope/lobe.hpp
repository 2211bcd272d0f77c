#pragma once
// One query describes a lobe; every method (fft, gabor, and later geometric, kirchhoff, stam,
// discrete) answers it with the same image type. A method is a free function in its own file,
// listed once in the method table (lib/src/lobe/method_table.cpp); adding one touches no other method.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "glintscope/diffraction_model.hpp"
#include "glintscope/geometry.hpp"
#include "glintscope/heightfield.hpp"
#include "glintscope/interpolant.hpp"

namespace glintscope {

enum class FootprintShape { gaussian, box, whole };  // whole: uniform over one period of the field

// The coherence footprint (conventions.md "Coherence / footprint"): a Gaussian
// w(s) = exp(−|s − x_c|²/(2σ_c²)), A_c = πσ_c², or a box of side `size_um`.
struct Footprint {
    Point2 centre_um;
    double sigma_um = 10.0;
    FootprintShape shape = FootprintShape::gaussian;
    double size_um = 0.0;  // box side length (box only)
};

// A material's Fresnel reflectance F(λ, cos θ); empty name means F = 1.
struct MaterialChoice {
    std::string name;
};

struct LobeQuery {
    std::shared_ptr<const Heightfield> field;
    std::shared_ptr<const BicubicInterpolant> surface;  // of `field`; built by make_surface_view
    Footprint footprint;
    Vec3 omega_i{0.0, 0.0, 1.0};          // toward the light, unit length, z > 0
    std::vector<double> wavelengths_um{0.5};
    DiffractionModel model = DiffractionModel::rohs;
    MaterialChoice material;
    int resolution = 256;                 // N of the N×N projected-disk image
    int supersample = 1;                  // K×K sub-pixel average
    // Method-specific settings by name (e.g. "kernels_per_texel" for gabor, "step" for fft);
    // each method reads its own keys and rejects keys it does not know.
    std::map<std::string, std::string> method_options;
};

// Outgoing-direction image over the projected disk, one N×N layer per wavelength, row 0 at
// the top (largest y); pixels outside the unit disk are 0. Values are f_r in sr⁻¹.
struct LobeImage {
    int resolution = 0;
    std::vector<double> wavelengths_um;
    std::vector<float> values;  // [layer][row][col]
    Provenance metadata;        // the query and what the method chose (grid, kernels, ...)

    float at(std::size_t layer, int row, int col) const {
        return values[(layer * resolution + row) * static_cast<std::size_t>(resolution) + col];
    }
    float& at(std::size_t layer, int row, int col) {
        return values[(layer * resolution + row) * static_cast<std::size_t>(resolution) + col];
    }
};

LobeImage make_lobe_image(int resolution, const std::vector<double>& wavelengths_um);

// Builds the shared interpolant for a field and fills query.field / query.surface.
void set_heightfield(LobeQuery& query, Heightfield field);

// Checks a query (directions, wavelengths, footprint inside reason, resolution, ...) and throws
// Error with a one-line message naming the bad parameter.
void validate(const LobeQuery& query);

// The query as key/value text (for EXR metadata and JSON sidecars; enough to reproduce it).
Provenance describe(const LobeQuery& query);

// Method-option helpers for methods: reject keys the method does not know, read numbers and
// lengths (with unit suffixes) with defaults. Each throws Error naming the option.
void check_method_options(const LobeQuery& query, const std::string& method, const std::vector<std::string>& known);
double method_option_number(const LobeQuery& query, const std::string& key, double fallback);
double method_option_length_um(const LobeQuery& query, const std::string& key, double fallback);

using LobeMethod = LobeImage (*)(const LobeQuery&);

std::vector<std::string> lobe_method_names();
std::string lobe_method_description(const std::string& name);

// Validates the query and runs the named method; throws Error for unknown names.
LobeImage compute_lobe(const std::string& method, const LobeQuery& query);

}  // namespace glintscope
