#pragma once
// Comparing two images of the same query (e.g. gabor against the fft ground truth, a wave lobe
// against the geometric one): the numbers `validate` reports and the tests assert.
#include <span>
#include <vector>

#include "glintscope/lobe/image.hpp"

namespace glintscope {

struct LayerComparison {
    double wavelength_um = 0.0;
    double relative_l2 = 0.0;       // √(Σ (t − r)²) / √(Σ r²) over the pixels inside the disk
    double max_abs_difference = 0.0;
    int max_row = 0;                // where |t − r| is largest
    int max_col = 0;
    double test_sum = 0.0;          // Σ t (2/N)²: albedo (brdf) or normalisation (ndf)
    double reference_sum = 0.0;
    double peak_offset_pixels = 0.0;  // distance between the two peaks' pixels
    double peak_relative_error = 0.0; // |t − r|/r at the reference's peak pixel
    // Root mean square of log10(t/r) over the pixels where r is above 1e-3 of its peak: how
    // well the tails agree, which the relative L2 (dominated by the peak) does not show. A
    // pixel where t ≤ 0 counts as log10 of 1e-3 of the peak over r.
    double log_rms_error = 0.0;
    // The relative L2 after both layers are blurred by a Gaussian of one pixel (smooth_layer):
    // speckle-free, for a geometric lobe against a wave one, whose speckle (grains of
    // ~λ/footprint) would otherwise dominate the error at any λ. With it the Kirchhoff FFT lobe
    // converges to the geometric one as λ → 0 (docs/validation.md "Geometric against wave optics").
    double smoothed_relative_l2 = 0.0;

    double energy_ratio() const { return reference_sum != 0.0 ? test_sum / reference_sum : 0.0; }
};

// Per layer; throws Error when the images differ in resolution, quantity or wavelengths.
std::vector<LayerComparison> compare_lobes(const LobeImage& test, const LobeImage& reference);

// One layer of two N×N images in LobeImage's layout (row-major, row 0 at the top), for layers
// that are not wavelengths (the R, G, B channels of a colour EXR). wavelength_um is left 0.
LayerComparison compare_layer(std::span<const float> test, std::span<const float> reference, int resolution);

// One N×N layer blurred by a Gaussian of σ = 1 pixel (separable, truncated at 4σ, zero outside
// the image): the smoothing of LayerComparison::smoothed_relative_l2.
std::vector<double> smooth_layer(std::span<const float> layer, int resolution);

// test − reference, per pixel and layer, with the test's metadata and method "TEST - REFERENCE"
// (a signed image: figure.hpp draws it on a diverging scale). Throws as compare_lobes.
LobeImage difference_image(const LobeImage& test, const LobeImage& reference);

}  // namespace glintscope
