#pragma once
// One footprint's kernels ordered by their slope, for a BSDF that evaluates many directions at
// one footprint. A direction reaches kernel k only when v + ξ3 H'_k/λ lies in the kernel's box
// (Yan 2018 §5 "Acceleration by pruning"): a box in slope space around −vλ/ξ3. With the kernels
// sorted into the cells of a grid over slope space, the kernels a direction can reach are a few
// contiguous runs of cells, so eval reads only them and sums them in place, where GaborSurface
// (any footprint, once) walks its hierarchy and copies its survivors per query.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <vector>

#include "gabor_kernels.hpp"

namespace glintscope::gabor {

class SlopeIndex {
public:
    // Takes a footprint's kernels (gather_kernels), at the grid's order. At second order, the
    // chirp factors of each ξ3/λ in `prepared_xi3_over_lambda` are computed once (a model whose ξ3
    // does not depend on the directions, at the wavelengths it will be asked for).
    SlopeIndex(const KernelArrays& kernels, const KernelGrid& grid,
               const std::vector<double>& prepared_xi3_over_lambda = {});

    // Σ_k w_k C_k F[g_k](v) (sum_transforms) over every kernel whose box may hold the point's v:
    // the kernels of the other cells contribute exactly 0 to that sum, so this is the sum over
    // all kernels, in the index's order.
    std::complex<double> sum(const TransformPoint& point) const;

    // Appends to `runs` the runs of kernels that sum() sums, in order, and returns the chirp
    // factors prepared for the point's ξ3/λ (else null).
    const ChirpFactors* reaching_runs(const TransformPoint& point, std::vector<KernelRun>& runs) const;

    // The kernels, in the index's order.
    const KernelArrays& kernels() const { return kernels_; }
    const KernelGrid& grid() const { return grid_; }

    // A cell's kernels' range of slopes (tighter than the cell) and at second order the largest
    // ρ(H'') among them, which widens their reach.
    struct CellBounds {
        double x_min, x_max, y_min, y_max, radius;
    };
    // Cell tests widen the kernels' reach by this factor, so that their rounding (which differs
    // from the sum's) never leaves out a kernel the sum keeps; the sum itself cuts each term exactly.
    static constexpr double kReachMargin = 1.0 + 1e-9;
    // The largest ρ(H'') of all kernels (0 at first order).
    double largest_radius() const { return largest_radius_; }

    // Calls run(begin, end) for runs of consecutive kernels (the index's order) that together hold
    // every kernel whose slope H' puts v + t·H' (t > 0) within `widest` of 0 in both axes and
    // whose cell `keep(bounds, cell)` accepts, where keep may drop a cell only when none of its
    // kernels reach; the runs may hold other kernels too. With t ≤ 0 or not finite: one run of
    // every kernel.
    // `disk`: the reach is the disk |v + t·H'| ≤ widest, whose chord narrows each row's scan.
    template <typename Keep, typename Run>
    void for_each_run(double vx, double vy, double t, double widest, const Keep& keep, const Run& run,
                      bool disk = false) const;
    // Whether every kernel's slope H' puts v + t·H' (t > 0) within `widest` of 0 in both axes: then
    // testing cells costs more than it can save.
    bool within_reach_of_all(double vx, double vy, double t, double widest) const {
        return vx + t * origin_x_ >= -widest && vx + t * last_x_ <= widest && vy + t * origin_y_ >= -widest &&
               vy + t * last_y_ <= widest;
    }

private:
    // The reach of a cell's kernels at ξ3/λ = t, with the cell tests' margin.
    double cell_reach(double radius, double t) const;
    // The cell along one axis that holds a slope, clamped to the grid: monotonic in the slope,
    // so the kernels with slopes in [a, b] lie in the cells [cell(a), cell(b)].
    static int cell_of(double slope, double origin, double inverse_width, int cells) {
        const double t = (slope - origin) * inverse_width;
        if (!(t >= 0.0)) return 0;
        return t >= cells ? cells - 1 : static_cast<int>(t);
    }

    KernelArrays kernels_;
    KernelGrid grid_;
    int cells_x_ = 1;
    int cells_y_ = 1;
    double origin_x_ = 0.0;  // the smallest slope of each axis, where cell 0 starts
    double origin_y_ = 0.0;
    double last_x_ = 0.0;  // the largest slope of each axis
    double last_y_ = 0.0;
    double inverse_width_x_ = 0.0;  // cells per unit slope
    double inverse_width_y_ = 0.0;
    std::vector<std::uint32_t> starts_;  // kernels of cell (i, j) at [starts_[c], starts_[c + 1]), c = j·cells_x_ + i
    std::vector<CellBounds> bounds_;
    // Second order, per prepared ξ3/λ: the kernels' chirp factors (in the kernels' order) and each
    // cell's widened reach.
    struct Prepared {
        ChirpFactors factors;
        std::vector<double> cell_reach;
    };
    std::vector<Prepared> prepared_;
    double largest_radius_ = 0.0;
};

template <typename Keep, typename Run>
void SlopeIndex::for_each_run(double vx, double vy, double t, double widest, const Keep& keep, const Run& run,
                              bool disk) const {
    if (!(t > 0.0 && std::isfinite(t))) {
        run(std::size_t{0}, kernels_.size());
        return;
    }
    // H'_k reaches when H'_k ∈ [(−widest − v)/t, (widest − v)/t] per axis.
    if ((widest - vx) / t < origin_x_ || (-widest - vx) / t > last_x_ || (widest - vy) / t < origin_y_ ||
        (-widest - vy) / t > last_y_)
        return;
    // The rectangle of cells that the widest reach meets, then each cell by keep().
    const int i0 = cell_of((-widest - vx) / t, origin_x_, inverse_width_x_, cells_x_);
    const int i1 = cell_of((widest - vx) / t, origin_x_, inverse_width_x_, cells_x_);
    const int j0 = cell_of((-widest - vy) / t, origin_y_, inverse_width_y_, cells_y_);
    const int j1 = cell_of((widest - vy) / t, origin_y_, inverse_width_y_, cells_y_);
    // Per row, the span from its first to its last kept cell (the cells between them, rarely not
    // kept, are included): two scans that stop at the first kept cell from each end. Spans that
    // follow each other in the index's order (whole rows) make one run.
    std::size_t run_begin = 0;
    std::size_t run_end = 0;  // [run_begin, run_end): not yet handed to run()
    for (int j = j0; j <= j1; ++j) {
        const std::size_t row = static_cast<std::size_t>(j) * cells_x_;
        int row_i0 = i0;
        int row_i1 = i1;
        if (disk && inverse_width_y_ > 0.0) {
            // The row's slopes H'_y lie in [origin + j w, origin + (j + 1) w] (w the cell height), so
            // |v_y + t H'_y| ≥ gap there, and the disk's chord at that gap bounds |v_x + t H'_x|.
            const double low = vy + t * (origin_y_ + j / inverse_width_y_);
            const double high = vy + t * (origin_y_ + (j + 1) / inverse_width_y_);
            const double gap = low > 0.0 ? low : high < 0.0 ? -high : 0.0;
            if (gap > widest) continue;
            const double chord = std::sqrt(widest * widest - gap * gap);
            row_i0 = std::max(i0, cell_of((-chord - vx) / t, origin_x_, inverse_width_x_, cells_x_));
            row_i1 = std::min(i1, cell_of((chord - vx) / t, origin_x_, inverse_width_x_, cells_x_));
        }
        int first = row_i0;
        while (first <= row_i1 && !keep(bounds_[row + first], row + first)) ++first;
        if (first > row_i1) continue;
        int last = row_i1;
        while (last > first && !keep(bounds_[row + last], row + last)) --last;
        if (starts_[row + first] != run_end) {
            if (run_end > run_begin) run(run_begin, run_end);
            run_begin = starts_[row + first];
        }
        run_end = starts_[row + last + 1];
    }
    if (run_end > run_begin) run(run_begin, run_end);
}

}  // namespace glintscope::gabor
