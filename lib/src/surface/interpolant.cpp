#include "glintscope/surface/interpolant.hpp"

#include <algorithm>
#include <cmath>

#include "glintscope/core/error.hpp"
#include "surface/catmull_rom.hpp"

namespace glintscope {
namespace {

int wrap(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
}

}  // namespace

BicubicInterpolant::BicubicInterpolant(const Heightfield& field) {
    validate(field, "interpolant", /*allow_missing=*/false);
    rows_ = field.rows;
    cols_ = field.cols;
    texel_um_ = field.dx_um();
    texel_y_um_ = field.dy_um();
    inverse_texel_ = 1.0 / texel_um_;
    inverse_texel_y_ = 1.0 / texel_y_um_;
    grid_.resize(field.heights_um.size());
    for (int j = 0; j < rows_; ++j)
        for (int c = 0; c < cols_; ++c) grid_[static_cast<std::size_t>(j) * cols_ + c] = field.at(rows_ - 1 - j, c);
    for (int j = 0; j < rows_; ++j) {
        for (int c = 0; c < cols_; ++c) {
            const auto g = [&](int jj, int cc) {
                return static_cast<double>(grid_[static_cast<std::size_t>(wrap(jj, rows_)) * cols_ + wrap(cc, cols_)]);
            };
            const double sx = 0.5 * (g(j, c + 1) - g(j, c - 1)) / texel_um_;
            const double sy = 0.5 * (g(j + 1, c) - g(j - 1, c)) / texel_y_um_;
            max_slope_ = std::fmax(max_slope_, std::fmax(std::fabs(sx), std::fabs(sy)));
        }
    }
}

namespace {

// The four samples along one axis that a coordinate reads, with their Catmull–Rom weights.
struct AxisTaps {
    int index[4];
    CubicWeights weights;
};

AxisTaps axis_taps(double s_um, double texel_um, int count) {
    // Continuous sample coordinates: sample c sits at u = c, i.e. x = (u + 0.5)·dx.
    const double u = s_um / texel_um - 0.5;
    const double u_floor = std::floor(u);
    AxisTaps taps{{}, catmull_rom(u - u_floor)};
    // Most coordinates lie on the first tile, where no division is needed.
    const int first = u_floor >= 0.0 && u_floor < count ? static_cast<int>(u_floor)
                                                         : wrap(static_cast<int>(std::fmod(u_floor, count)), count);
    for (int k = 0; k < 4; ++k) {
        const int index = first + k - 1;  // in [−1, count + 1]
        taps.index[k] = count >= 3 ? (index < 0 ? index + count : index >= count ? index - count : index)
                                   : wrap(index, count);
    }
    return taps;
}

SurfacePoint combine(const std::vector<float>& grid, int cols, double inverse_dx, double inverse_dy,
                     const AxisTaps& x, const AxisTaps& y) {
    double h = 0.0;
    double dh_du = 0.0;
    double dh_dv = 0.0;
    for (int m = 0; m < 4; ++m) {
        const float* row = &grid[static_cast<std::size_t>(y.index[m]) * cols];
        double along_x = 0.0;
        double along_x_du = 0.0;
        for (int k = 0; k < 4; ++k) {
            along_x += x.weights.w[k] * row[x.index[k]];
            along_x_du += x.weights.dw[k] * row[x.index[k]];
        }
        h += y.weights.w[m] * along_x;
        dh_du += y.weights.w[m] * along_x_du;
        dh_dv += y.weights.dw[m] * along_x;
    }
    return {h, dh_du * inverse_dx, dh_dv * inverse_dy};
}

}  // namespace

SurfacePoint BicubicInterpolant::evaluate(double x_um, double y_um) const {
    return combine(grid_, cols_, inverse_texel_, inverse_texel_y_, axis_taps(x_um, texel_um_, cols_),
                   axis_taps(y_um, texel_y_um_, rows_));
}

void BicubicInterpolant::evaluate_grid(double x0_um, double y0_um, double step_x_um, double step_y_um, int nx,
                                       int ny, SurfacePoint* out) const {
    // combine() separated: each sample row is filtered along x once per block of columns (its
    // inner sums, bit-identical to combine's) and reused by every grid row that reads it.
    constexpr int kBlock = 64;
    constexpr int kCachedRows = 8;
    struct FilteredRow {
        int index = -1;
        double along_x[kBlock];
        double along_x_du[kBlock];
    };
    AxisTaps x_taps[kBlock];
    FilteredRow cache[kCachedRows];
    for (int i0 = 0; i0 < nx; i0 += kBlock) {
        const int count = std::min(kBlock, nx - i0);
        for (int i = 0; i < count; ++i) x_taps[i] = axis_taps(x0_um + (i0 + i) * step_x_um, texel_um_, cols_);
        for (FilteredRow& row : cache) row.index = -1;
        int next_slot = 0;
        for (int j = 0; j < ny; ++j) {
            const AxisTaps y = axis_taps(y0_um + j * step_y_um, texel_y_um_, rows_);
            const FilteredRow* rows[4];
            bool in_use[kCachedRows] = {};
            for (int m = 0; m < 4; ++m) {
                int slot = 0;
                while (slot < kCachedRows && cache[slot].index != y.index[m]) ++slot;
                if (slot == kCachedRows) {
                    while (in_use[next_slot]) next_slot = (next_slot + 1) % kCachedRows;
                    slot = next_slot;
                    next_slot = (next_slot + 1) % kCachedRows;
                    FilteredRow& filtered = cache[slot];
                    filtered.index = y.index[m];
                    const float* row = &grid_[static_cast<std::size_t>(y.index[m]) * cols_];
                    for (int i = 0; i < count; ++i) {
                        double along_x = 0.0;
                        double along_x_du = 0.0;
                        for (int k = 0; k < 4; ++k) {
                            along_x += x_taps[i].weights.w[k] * row[x_taps[i].index[k]];
                            along_x_du += x_taps[i].weights.dw[k] * row[x_taps[i].index[k]];
                        }
                        filtered.along_x[i] = along_x;
                        filtered.along_x_du[i] = along_x_du;
                    }
                }
                in_use[slot] = true;
                rows[m] = &cache[slot];
            }
            SurfacePoint* line = out + static_cast<std::size_t>(j) * nx + i0;
            for (int i = 0; i < count; ++i) {
                double h = 0.0;
                double dh_du = 0.0;
                double dh_dv = 0.0;
                for (int m = 0; m < 4; ++m) {
                    h += y.weights.w[m] * rows[m]->along_x[i];
                    dh_du += y.weights.w[m] * rows[m]->along_x_du[i];
                    dh_dv += y.weights.dw[m] * rows[m]->along_x[i];
                }
                line[i] = {h, dh_du * inverse_texel_, dh_dv * inverse_texel_y_};
            }
        }
    }
}

void BicubicInterpolant::evaluate_samples(long long c0, long long j0, int nx, int ny, SurfacePoint* out) const {
    const auto wrapped = [](long long i, int n) { return static_cast<int>(((i % n) + n) % n); };
    for (int j = 0; j < ny; ++j) {
        const int row = wrapped(j0 + j, rows_);
        int column = wrapped(c0, cols_);
        for (int i = 0; i < nx; ++i, column = column + 1 == cols_ ? 0 : column + 1)
            out[static_cast<std::size_t>(j) * nx + i] = sample_point(column, row);
    }
}

namespace {

// Five samples along one axis around a coordinate, with the Catmull–Rom weights of the value,
// first and second derivative in sample units. Off a sample line only the first four are used
// (the fifth weighs 0); on one (t = 0), where the cubic's second derivative jumps, it is the second
// difference (1, −2, 1) (interpolant.hpp).
struct CurvatureTaps {
    int index[5];
    double w[5];
    double dw[5];
    double d2w[5];
};

CurvatureTaps curvature_taps(double s_um, double texel_um, int count) {
    const double u = s_um / texel_um - 0.5;
    const double u_floor = std::floor(u);
    const double t = u - u_floor;
    const int first = wrap(static_cast<int>(std::fmod(u_floor, count)), count);
    CurvatureTaps taps{};
    if (t == 0.0) {
        for (int k = 0; k < 5; ++k) taps.index[k] = wrap(first + k - 2, count);
        const double w[5] = {0.0, 0.0, 1.0, 0.0, 0.0};
        const double dw[5] = {0.0, -0.5, 0.0, 0.5, 0.0};
        const double d2w[5] = {0.0, 1.0, -2.0, 1.0, 0.0};
        std::copy(w, w + 5, taps.w);
        std::copy(dw, dw + 5, taps.dw);
        std::copy(d2w, d2w + 5, taps.d2w);
        return taps;
    }
    const CubicWeights weights = catmull_rom(t);
    for (int k = 0; k < 4; ++k) {
        taps.index[k] = wrap(first + k - 1, count);
        taps.w[k] = weights.w[k];
        taps.dw[k] = weights.dw[k];
    }
    taps.index[4] = taps.index[3];
    // d²/dt² of catmull_rom's weights.
    taps.d2w[0] = 2.0 - 3.0 * t;
    taps.d2w[1] = 9.0 * t - 5.0;
    taps.d2w[2] = 4.0 - 9.0 * t;
    taps.d2w[3] = 3.0 * t - 1.0;
    return taps;
}

}  // namespace

SurfaceCurvature BicubicInterpolant::curvature(double x_um, double y_um) const {
    const CurvatureTaps x = curvature_taps(x_um, texel_um_, cols_);
    const CurvatureTaps y = curvature_taps(y_um, texel_y_um_, rows_);
    double hxx = 0.0, hxy = 0.0, hyy = 0.0;
    for (int m = 0; m < 5; ++m) {
        const float* row = sample_row(y.index[m]);
        double along_x = 0.0, along_x_du = 0.0, along_x_du2 = 0.0;
        for (int k = 0; k < 5; ++k) {
            along_x += x.w[k] * row[x.index[k]];
            along_x_du += x.dw[k] * row[x.index[k]];
            along_x_du2 += x.d2w[k] * row[x.index[k]];
        }
        hxx += y.w[m] * along_x_du2;
        hxy += y.dw[m] * along_x_du;
        hyy += y.d2w[m] * along_x;
    }
    return {hxx * inverse_texel_ * inverse_texel_, hxy * inverse_texel_ * inverse_texel_y_,
            hyy * inverse_texel_y_ * inverse_texel_y_};
}

SurfaceCurvature BicubicInterpolant::sample_curvature(int c, int j) const {
    const auto at = [&](int dc, int dj) {
        return static_cast<double>(sample_row(wrap(j + dj, rows_))[wrap(c + dc, cols_)]);
    };
    const double hxx = at(-1, 0) - 2.0 * at(0, 0) + at(1, 0);
    const double hyy = at(0, -1) - 2.0 * at(0, 0) + at(0, 1);
    const double hxy = 0.25 * (at(1, 1) - at(-1, 1) - at(1, -1) + at(-1, -1));
    return {hxx * inverse_texel_ * inverse_texel_, hxy * inverse_texel_ * inverse_texel_y_,
            hyy * inverse_texel_y_ * inverse_texel_y_};
}

double BicubicInterpolant::height(double x_um, double y_um) const { return evaluate(x_um, y_um).height; }

}  // namespace glintscope
