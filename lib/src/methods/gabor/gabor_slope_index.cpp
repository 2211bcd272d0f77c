// A footprint's kernels sorted by slope cell (gabor_slope_index.hpp).
#include "gabor_slope_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace glintscope::gabor {
namespace {

// About this many kernels per cell: small cells fit a direction's box closely, large ones make
// fewer runs to sum.
constexpr double kKernelsPerCell = 4.0;
constexpr int kMaxCellsPerAxis = 64;

}  // namespace

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

std::complex<double> SlopeIndex::sum(const TransformPoint& point) const {
    // Reused by each thread: no allocation per call.
    thread_local std::vector<KernelRun> runs;
    runs.clear();
    const ChirpFactors* factors = reaching_runs(point, runs);
    if (factors) return sum_transforms(kernels_, *factors, runs, point);
    std::complex<double> total = 0.0;
    for (const KernelRun& run : runs) total += sum_transforms(kernels_, run.begin, run.end, point, grid_);
    return total;
}

const ChirpFactors* SlopeIndex::reaching_runs(const TransformPoint& point, std::vector<KernelRun>& runs) const {
    const double t = point.xi3_over_lambda;
    // Kernel k reaches v when |v + t H'_k| ≤ R_k per axis (Yan 2018 eq. 15 and §5); R_k = reach
    // at first order, chirped_reach at second.
    const ChirpFactors* factors = nullptr;
    const double* prepared_reach = nullptr;  // each cell's reach when the factors are prepared
    for (const Prepared& prepared : prepared_)
        if (prepared.factors.xi3_over_lambda == t) {
            factors = &prepared.factors;
            prepared_reach = prepared.cell_reach.data();
        }
    const bool chirped = grid_.order == 2;
    const double widest = cell_reach(largest_radius_, t);
    const auto keep = [&](const CellBounds& b, std::size_t cell) {
        const double reach = prepared_reach ? prepared_reach[cell] : chirped ? cell_reach(b.radius, t) : widest;
        return slopes_reach(point.vx, point.vy, t, reach, b.x_min, b.x_max, b.y_min, b.y_max);
    };
    for_each_run(point.vx, point.vy, t, widest, keep,
                 [&](std::size_t begin, std::size_t end) { runs.push_back({begin, end}); });
    return factors;
}

}  // namespace glintscope::gabor
