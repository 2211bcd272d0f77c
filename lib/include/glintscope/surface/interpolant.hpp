#pragma once
// The one heightfield interpolant every method uses (conventions.md "Heightfield
// interpolation"): a periodic bicubic Catmull–Rom (Keys a = −1/2) surface. It passes through
// every sample, is C¹, reproduces quadratics exactly, and its analytic gradient H' converges
// to the true gradient to second order in dx. Texels may be rectangular: x reads the field's dx,
// y its dy (heightfield.hpp).
#include <vector>

#include "glintscope/surface/heightfield.hpp"

namespace glintscope {

struct SurfacePoint {
    double height = 0.0;  // H(s), µm
    double dh_dx = 0.0;   // ∂H/∂x, dimensionless slope
    double dh_dy = 0.0;   // ∂H/∂y
};

// The Hessian H'' of the interpolant, 1/µm. Catmull–Rom is C¹ only: across a sample line the
// second derivative along its normal jumps, and there it is taken as the second difference of the
// three samples across the line (the curvature of the parabola through them, exact for
// quadratics); the mixed derivative is continuous. Chosen by measurement for second-order Gabor
// kernels centred on the samples (docs/gabor.md "Second order": the mean of the two one-sided
// values, (−½, 3, −5, 3, −½), amplifies the highest frequencies three times more and errs up to
// five times more).
struct SurfaceCurvature {
    double d2h_dx2 = 0.0;
    double d2h_dxdy = 0.0;
    double d2h_dy2 = 0.0;
};

class BicubicInterpolant {
public:
    // The field must have no missing points (fill them first); throws Error otherwise.
    explicit BicubicInterpolant(const Heightfield& field);

    // s in µm, map-view coordinates; the surface tiles periodically in x and y.
    double height(double x_um, double y_um) const;
    SurfacePoint evaluate(double x_um, double y_um) const;
    // evaluate() at the grid points (x0 + i·step, y0 + j·step), 0 ≤ i < nx, 0 ≤ j < ny, into
    // out[j·nx + i]: the same values, several times faster per point (taps shared per grid line).
    void evaluate_grid(double x0_um, double y0_um, double step_um, int nx, int ny, SurfacePoint* out) const {
        evaluate_grid(x0_um, y0_um, step_um, step_um, nx, ny, out);
    }
    // The same with different steps along x and y.
    void evaluate_grid(double x0_um, double y0_um, double step_x_um, double step_y_um, int nx, int ny,
                       SurfacePoint* out) const;
    // evaluate() at the samples themselves, where the weights reduce to the sample and central
    // differences: sample columns c0 … c0 + nx − 1 and y-up rows j0 … j0 + ny − 1 (sample (c, j)
    // at ((c + ½)dx, (j + ½)dy), indices wrapped periodically), into out[j·nx + i].
    void evaluate_samples(long long c0, long long j0, int nx, int ny, SurfacePoint* out) const;
    // The same at one sample (c, j), 0 ≤ c < cols(), 0 ≤ j < rows() (y-up). At t = 0 the
    // Catmull–Rom weights are (0, 1, 0, 0) and their derivatives (−½, 0, ½, 0).
    SurfacePoint sample_point(int c, int j) const {
        const float* row = sample_row(j);
        const float* below = sample_row(j == 0 ? rows_ - 1 : j - 1);
        const float* above = sample_row(j + 1 == rows_ ? 0 : j + 1);
        const int left = c == 0 ? cols_ - 1 : c - 1;
        const int right = c + 1 == cols_ ? 0 : c + 1;
        return {row[c], (-0.5 * row[left] + 0.5 * row[right]) * inverse_texel_,
                (-0.5 * below[c] + 0.5 * above[c]) * inverse_texel_y_};
    }
    // H'' at s (µm), as SurfaceCurvature describes.
    SurfaceCurvature curvature(double x_um, double y_um) const;
    // curvature() at the sample (c, j), 0 ≤ c < cols(), 0 ≤ j < rows() (y-up): the second
    // differences (H(c−1) − 2H(c) + H(c+1))/dx² (dy² along y) and the mixed one (H(c+1, j+1) −
    // H(c−1, j+1) − H(c+1, j−1) + H(c−1, j−1))/(4dx·dy).
    SurfaceCurvature sample_curvature(int c, int j) const;
    // The samples of y-up row j (0 ≤ j < rows()), cols() of them, for code that tests many
    // samples' central differences at once.
    const float* sample_row(int j) const { return grid_.data() + static_cast<std::size_t>(j) * cols_; }

    double texel_um() const { return texel_um_; }      // dx
    double texel_y_um() const { return texel_y_um_; }  // dy
    bool square_texels() const { return texel_y_um_ == texel_um_; }
    int rows() const { return rows_; }
    int cols() const { return cols_; }
    // Largest |∂H/∂x|, |∂H/∂y| over the sample grid: bounds the phase slope for sampling choices.
    double max_slope() const { return max_slope_; }

private:
    int rows_ = 0;
    int cols_ = 0;
    double texel_um_ = 1.0;
    double texel_y_um_ = 1.0;
    double inverse_texel_ = 1.0;    // 1/dx: x derivatives multiply by it, identically everywhere
    double inverse_texel_y_ = 1.0;  // 1/dy, the same for y
    double max_slope_ = 0.0;
    std::vector<float> grid_;  // y-up order: grid_[j·cols + c] is the sample at y = (j + 0.5)·dy
};

}  // namespace glintscope
