#pragma once
// The regular grid on which the FFT lobe samples R*(s) = w(s − x_c) ξ2 e^{−i2π ξ3 H(s)/λ}
// (Yan 2018 eq. 4): the footprint's extent, the interpolated surface on the grid, and the
// alias-free choice of the step.
#include <vector>

#include "glintscope/surface/interpolant.hpp"
#include "glintscope/lobe/query.hpp"

namespace glintscope {

// The sampled rectangle of the coherence footprint (conventions.md "Coherence / footprint").
struct FootprintExtent {
    Point2 centre_um;
    Point2 half_width_um;        // per axis; Gaussian: window·σ_c; box: side/2
    bool box = false;
    double sigma_um = 0.0;       // Gaussian only
    double area_um2 = 0.0;       // A_c = ∫|w|² ds: πσ_c² or the box's area
    double spectral_width = 0.0; // width of w̃ in cycles/µm: 1/(2πσ_c), or 1/(shorter side)
};

FootprintExtent footprint_extent(const Footprint& footprint, double window_sigmas);

// Sample positions along one axis: first + j·step, j < count. A Gaussian footprint is sampled
// symmetrically about x_c; a box by the centres of `count` equal cells tiling it exactly.
struct SampleAxis {
    int count = 0;
    double step_um = 0.0;
    double first_um = 0.0;
};

// Along x (`along_x`) or y. Throws Error when the step would need more than `max_count` samples
// across the footprint.
SampleAxis sample_axis(const FootprintExtent& extent, bool along_x, double step_um, int max_count);

struct FootprintSamples {
    SampleAxis x;
    SampleAxis y;
    std::vector<double> weight;   // w(s − x_c), index k·x.count + j for s = (x_j, y_k)
    std::vector<double> height;   // H(s) − H̄, H̄ the w-weighted mean height over the footprint
    std::vector<double> slope_x;  // ∂H/∂x, kept only on request (Kirchhoff ξ2)
    std::vector<double> slope_y;
    double max_slope_x = 0.0;     // max |∂H/∂x| over the samples
    double max_slope_y = 0.0;
    double mean_height_um = 0.0;  // H̄
};

// Evaluates the shared interpolant at every grid point (in parallel; bit-identical for any
// thread count).
FootprintSamples sample_footprint(const BicubicInterpolant& surface, const FootprintExtent& extent, SampleAxis x,
                                  SampleAxis y, bool keep_slopes);

// The largest step along one axis at which the spectral copies of R̃* stay off the image.
// Locally R* oscillates at ξ3 H'(s)/λ cycles/µm, so R̃* lives in |v| ≤ ξ3max·max|H'|/λ widened
// by the footprint's own spectrum (the guard band). A grid of step h repeats R̃* at v + k/h, and
// the image reads |v| ≤ max|ψ̄|/λ; no repeat reaches it when
//   1/h ≥ (max|ψ̄| + q·ξ3max·max|H'|)/λ + guard,
// with q = 1. The shared interpolant is only C¹: its curvature jumps at every texel line give
// R̃* algebraic tails beyond that band, so q > 1 (the `oversampling`) pushes the repeats further.
double alias_free_step(double psi_max, double xi3_max, double slope_max, double lambda_um, double guard,
                       double oversampling);

}  // namespace glintscope
