// A footprint's kernels sorted by slope cell (gabor_slope_index.hpp).
#include "gabor_slope_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace glintscope::gabor {
namespace {

// The cell tests widen the kernels' reach by this factor, so that their rounding (which differs
// from the sum's) never leaves out a kernel the sum keeps; the sum itself cuts each term exactly.
constexpr double kReachMargin = 1.0 + 1e-9;

// About this many kernels per cell: small cells fit a direction's box closely, large ones make
// fewer runs to sum.
constexpr double kKernelsPerCell = 4.0;
constexpr int kMaxCellsPerAxis = 64;

}  // namespace

inline int SlopeIndex::cell_of(double slope, double origin, double inverse_width, int cells) {
    const double t = (slope - origin) * inverse_width;
    if (!(t >= 0.0)) return 0;
    return t >= cells ? cells - 1 : static_cast<int>(t);
}

SlopeIndex::SlopeIndex(const KernelArrays& kernels, const KernelGrid& grid,
                       const std::vector<double>& prepared_xi3_over_lambda)
    : grid_(grid) {
    const std::size_t count = kernels.size();
    if (count > 0) {
        const auto [min_x, max_x] = std::minmax_element(kernels.slope_x.begin(), kernels.slope_x.begin() + count);
        const auto [min_y, max_y] = std::minmax_element(kernels.slope_y.begin(), kernels.slope_y.begin() + count);
        origin_x_ = *min_x;
        last_x_ = *max_x;
        origin_y_ = *min_y;
        last_y_ = *max_y;
        const int cells = std::clamp(static_cast<int>(std::sqrt(count / kKernelsPerCell)), 1, kMaxCellsPerAxis);
        cells_x_ = cells;
        cells_y_ = cells;
        inverse_width_x_ = last_x_ > origin_x_ ? cells / (last_x_ - origin_x_) : 0.0;
        inverse_width_y_ = last_y_ > origin_y_ ? cells / (last_y_ - origin_y_) : 0.0;
    }
    const std::size_t cell_count = static_cast<std::size_t>(cells_x_) * cells_y_;
    std::vector<std::uint32_t> cell(count);
    starts_.assign(cell_count + 1, 0);
    for (std::size_t k = 0; k < count; ++k) {
        cell[k] = static_cast<std::uint32_t>(
            cell_of(kernels.slope_y[k], origin_y_, inverse_width_y_, cells_y_) * cells_x_ +
            cell_of(kernels.slope_x[k], origin_x_, inverse_width_x_, cells_x_));
        ++starts_[cell[k] + 1];
    }
    for (std::size_t c = 0; c < cell_count; ++c) starts_[c + 1] += starts_[c];
    // A stable counting sort: within a cell the kernels keep the footprint's gathering order.
    std::vector<std::uint32_t> next(starts_.begin(), starts_.end() - 1);
    kernels_.resize(count);
    for (std::size_t k = 0; k < count; ++k) kernels_.copy(next[cell[k]]++, kernels, k);
    const double inf = std::numeric_limits<double>::infinity();
    bounds_.assign(cell_count, {inf, -inf, inf, -inf, 0.0});
    for (std::size_t c = 0; c < cell_count; ++c)
        for (std::size_t k = starts_[c]; k < starts_[c + 1]; ++k) {
            CellBounds& b = bounds_[c];
            b.x_min = std::min(b.x_min, kernels_.slope_x[k]);
            b.x_max = std::max(b.x_max, kernels_.slope_x[k]);
            b.y_min = std::min(b.y_min, kernels_.slope_y[k]);
            b.y_max = std::max(b.y_max, kernels_.slope_y[k]);
            if (grid_.order == 2)
                b.radius = std::max(b.radius, spectral_radius(kernels_.curvature_xx[k], kernels_.curvature_xy[k],
                                                              kernels_.curvature_yy[k]));
            largest_radius_ = std::max(largest_radius_, b.radius);
        }
    if (grid_.order != 2) return;
    for (const double xi3_over_lambda : prepared_xi3_over_lambda) {
        Prepared& prepared = prepared_.emplace_back();
        prepared.factors = chirp_factors(kernels_, grid_, xi3_over_lambda);
        prepared.cell_reach.resize(cell_count);
        for (std::size_t c = 0; c < cell_count; ++c)
            prepared.cell_reach[c] = cell_reach(bounds_[c].radius, xi3_over_lambda);
    }
}

double SlopeIndex::cell_reach(double radius, double t) const {
    return kReachMargin * (grid_.order == 2 ? chirped_reach(grid_.reach, grid_.chirp_scale, t, radius) : grid_.reach);
}

std::complex<double> SlopeIndex::sum_run(std::size_t begin, std::size_t end, const TransformPoint& point,
                                         const ChirpFactors* factors) const {
    return factors ? sum_transforms(kernels_, *factors, begin, end, point)
                   : sum_transforms(kernels_, begin, end, point, grid_);
}

std::complex<double> SlopeIndex::sum(const TransformPoint& point) const {
    const double t = point.xi3_over_lambda;
    if (!(t > 0.0 && std::isfinite(t))) return sum_transforms(kernels_, 0, kernels_.size(), point, grid_);
    // Kernel k reaches v when |v + t H'_k| ≤ R_k per axis (Yan 2018 eq. 15 and §5), i.e. when
    // H'_k ∈ [(−R_k − v)/t, (R_k − v)/t]; R_k = reach at first order, chirped_reach at second.
    const double widest = cell_reach(largest_radius_, t);
    if ((widest - point.vx) / t < origin_x_ || (-widest - point.vx) / t > last_x_ ||
        (widest - point.vy) / t < origin_y_ || (-widest - point.vy) / t > last_y_)
        return {0.0, 0.0};
    // The rectangle of cells that the widest reach meets, then each cell by its kernels' bounds.
    const int i0 = cell_of((-widest - point.vx) / t, origin_x_, inverse_width_x_, cells_x_);
    const int i1 = cell_of((widest - point.vx) / t, origin_x_, inverse_width_x_, cells_x_);
    const int j0 = cell_of((-widest - point.vy) / t, origin_y_, inverse_width_y_, cells_y_);
    const int j1 = cell_of((widest - point.vy) / t, origin_y_, inverse_width_y_, cells_y_);
    const ChirpFactors* factors = nullptr;
    const double* prepared_reach = nullptr;  // each cell's reach when the factors are prepared
    for (const Prepared& prepared : prepared_)
        if (prepared.factors.xi3_over_lambda == t) {
            factors = &prepared.factors;
            prepared_reach = prepared.cell_reach.data();
        }
    const bool chirped = grid_.order == 2;
    std::complex<double> total = 0.0;
    for (int j = j0; j <= j1; ++j) {
        const std::size_t row = static_cast<std::size_t>(j) * cells_x_;
        std::size_t run_begin = 0;
        std::size_t run_end = 0;  // [run_begin, run_end): reaching kernels not yet summed
        for (int i = i0; i <= i1; ++i) {
            const CellBounds& b = bounds_[row + i];
            const double reach = prepared_reach ? prepared_reach[row + i] : chirped ? cell_reach(b.radius, t) : widest;
            if (!slopes_reach(point.vx, point.vy, t, reach, b.x_min, b.x_max, b.y_min, b.y_max)) continue;
            if (starts_[row + i] != run_end) {
                if (run_end > run_begin) total += sum_run(run_begin, run_end, point, factors);
                run_begin = starts_[row + i];
            }
            run_end = starts_[row + i + 1];
        }
        if (run_end > run_begin) total += sum_run(run_begin, run_end, point, factors);
    }
    return total;
}

}  // namespace glintscope::gabor
