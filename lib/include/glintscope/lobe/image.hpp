#pragma once
// The one image type every method returns: an N×N projected-disk image per wavelength
// (conventions.md "Frames and images"), row 0 at the top (largest y), pixels outside the unit
// disk 0. What a pixel holds is the image's quantity:
//   brdf  pixel = ω_o, value f_r(ω_i, ω_o) in sr⁻¹;     Σ f_r (2/N)² = albedo ∫ f_r cosθ_o dω_o
//   ndf   pixel = h (a normal), value D(h);            Σ D (2/N)² = 1 (∫ D (h·n) dω_h = 1)
// Colour, output and comparison code depend on this header only, not on queries or surfaces.
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "glintscope/core/geometry.hpp"
#include "glintscope/surface/metadata.hpp"

namespace glintscope {

enum class Quantity { brdf, ndf };

std::string to_string(Quantity quantity);
Quantity parse_quantity(const std::string& name);  // "brdf" or "ndf"; throws Error otherwise

// How writers and summaries name a quantity, so no writer assumes a BRDF.
struct QuantityLabels {
    std::string symbol;       // "f_r" or "D"
    std::string units;        // "sr^-1" or "1"
    std::string channel;      // single-wavelength EXR channel: "Y" or "D"
    std::string pixel;        // what a pixel's position is: "omega_o" or "h"
    std::string sum_name;     // what Σ value·(2/N)² is: "albedo" or "normalisation"
    std::string description;  // one line for legends and headers
};
const QuantityLabels& labels(Quantity quantity);

struct LobeImage {
    int resolution = 0;
    Quantity quantity = Quantity::brdf;
    std::vector<double> wavelengths_um;
    std::vector<float> values;  // [layer][row][col]
    Provenance metadata;        // the query and what the method chose (grid, kernels, ...)

    std::size_t layers() const { return wavelengths_um.size(); }
    float at(std::size_t layer, int row, int col) const {
        return values[(layer * resolution + row) * static_cast<std::size_t>(resolution) + col];
    }
    float& at(std::size_t layer, int row, int col) {
        return values[(layer * resolution + row) * static_cast<std::size_t>(resolution) + col];
    }
};

// One layer's N×N values, row-major.
std::span<const float> layer_values(const LobeImage& image, std::size_t layer);

// Σ value (2/N)² over the pixels inside the unit disk, in row-major order: the albedo
// ∫ f_r cos θ_o dω_o of a BRDF layer, the normalisation (1) of an NDF (see above).
double disk_sum(std::span<const float> layer, int resolution);
double disk_sum(const LobeImage& image, std::size_t layer = 0);

// A zero image with one layer per wavelength.
LobeImage make_lobe_image(int resolution, const std::vector<double>& wavelengths_um,
                          Quantity quantity = Quantity::brdf);

// The supersample average every method shares: layer pixel (r, c) = pixel_sums[r·N + c]/K²,
// the sum over its K×K sub-pixels (geometry.hpp), and 0 where the pixel's centre lies outside
// the disk (conventions.md: such a pixel holds no direction, even if some sub-pixels do).
void store_subpixel_means(LobeImage& image, std::size_t layer, const std::vector<double>& pixel_sums, int supersample);

// A layer from a function of the sub-pixel's disk point (inside the unit disk), K×K sub-pixels
// averaged by store_subpixel_means; rows in parallel, each pixel summed in a fixed order.
void fill_by_direction(LobeImage& image, std::size_t layer, int supersample,
                       const std::function<double(DiskPoint)>& value);

// For wavelength-independent results: copies layer 0 into every other layer, so colour and
// comparisons need no special case.
void copy_first_layer_to_all(LobeImage& image);

}  // namespace glintscope
