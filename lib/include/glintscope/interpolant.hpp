#pragma once
// The one heightfield interpolant every method uses (conventions.md "Heightfield
// interpolation"): a periodic bicubic Catmull–Rom (Keys a = −1/2) surface. It passes through
// every sample, is C¹, reproduces quadratics exactly, and its analytic gradient H' converges
// to the true gradient to second order in dx.
#include <vector>

#include "glintscope/heightfield.hpp"

namespace glintscope {

struct SurfacePoint {
    double height = 0.0;  // H(s), µm
    double dh_dx = 0.0;   // ∂H/∂x, dimensionless slope
    double dh_dy = 0.0;   // ∂H/∂y
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
    void evaluate_grid(double x0_um, double y0_um, double step_um, int nx, int ny, SurfacePoint* out) const;
    // evaluate() at the samples themselves, where the weights reduce to the sample and central
    // differences: sample columns c0 … c0 + nx − 1 and y-up rows j0 … j0 + ny − 1 (sample (c, j)
    // at ((c + ½)dx, (j + ½)dx), indices wrapped periodically), into out[j·nx + i].
    void evaluate_samples(long long c0, long long j0, int nx, int ny, SurfacePoint* out) const;
    // The same at scattered samples (columns[k], rows[k]), 0 ≤ column < cols(), 0 ≤ row < rows()
    // (y-up), into out[k].
    void evaluate_samples(const int* columns, const int* rows, std::size_t count, SurfacePoint* out) const;

    double texel_um() const { return texel_um_; }
    int rows() const { return rows_; }
    int cols() const { return cols_; }
    // Largest |∂H/∂x|, |∂H/∂y| over the sample grid: bounds the phase slope for sampling choices.
    double max_slope() const { return max_slope_; }

private:
    int rows_ = 0;
    int cols_ = 0;
    double texel_um_ = 1.0;
    double max_slope_ = 0.0;
    std::vector<float> grid_;  // y-up order: grid_[j·cols + c] is the sample at y = (j + 0.5)·dx
};

}  // namespace glintscope
