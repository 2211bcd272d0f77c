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

    // A disk about 0 in e = p + ξ·H' whose radius grows with a cell's largest ρ(H''):
    // |e|² ≤ fixed + per_radius2 · ρ². The kernel mixture's cut Gaussians (gabor_sampling.hpp) reach
    // d = μ_k + e only within such a disk, p = (ω_o + ω_i)_xy, ξ = ξ3.
    struct DiskReach {
        double px, py, xi, fixed, per_radius2;
        double reach2(double radius) const { return fixed + per_radius2 * radius * radius; }
        // Whether a cell's slope box, mapped to e, meets the cell's disk.
        bool meets(const CellBounds& b) const {
            // The square of the distance from 0 to the box [x_min, x_max] × [y_min, y_max] of e.
            const double x_min = px + xi * b.x_min, x_max = px + xi * b.x_max;
            const double y_min = py + xi * b.y_min, y_max = py + xi * b.y_max;
            const double x = x_min > 0.0 ? x_min : x_max < 0.0 ? x_max : 0.0;
            const double y = y_min > 0.0 ? y_min : y_max < 0.0 ? y_max : 0.0;
            return x * x + y * y <= reach2(b.radius);
        }
    };
    // Runs of consecutive kernels that hold every kernel of the cells whose box meets the disk
    // (appended to `runs`, sorted, disjoint).
    void disk_runs(const DiskReach& disk, std::vector<KernelRun>& runs) const;
    // reaching_runs(point, runs) and, from the same scan of the cells, `others`: the runs of
    // disk_runs(disk) that those leave. The disk must hold every box of the point's reach
    // (|v + t·H'| within each cell's reach per axis, scaled by λ = ξ/t).
    const ChirpFactors* reaching_runs(const TransformPoint& point, const DiskReach& disk,
                                      std::vector<KernelRun>& runs, std::vector<KernelRun>& others) const;

private:
    // The slopes H' that put v + t·H' (t > 0) within `widest` of 0 in both axes (with `disk`: in
    // the disk |v + t·H'| ≤ widest, whose chord narrows each row's scan).
    struct Reach {
        double vx, vy, t, widest;
        bool disk = false;
    };
    // The cells a scan keeps: those holding a kernel within the reach that `keep(bounds, cell)`
    // accepts, where keep may drop a cell only when none of its kernels reach.
    template <typename Keep>
    struct Scan : Reach {
        const Keep& keep;
    };
    // Calls run(begin, end) for runs of consecutive kernels (the index's order) that together hold
    // every kernel of the cells the scan keeps; the runs may hold other kernels too. With t ≤ 0 or
    // not finite: one run of every kernel.
    template <typename Keep, typename Run>
    void for_each_run(const Scan<Keep>& scan, const Run& run) const;
    // Whether every kernel's slope H' puts v + t·H' (t > 0) within `widest` of 0 in both axes.
    bool within_reach_of_all(double vx, double vy, double t, double widest) const {
        return vx + t * origin_x_ >= -widest && vx + t * last_x_ <= widest && vy + t * origin_y_ >= -widest &&
               vy + t * last_y_ <= widest;
    }
    // reaching_runs' test: whether a cell may hold a kernel whose box holds the point's v.
    struct ReachKeep {
        const SlopeIndex& index;
        const TransformPoint& point;
        const double* prepared_reach;  // each cell's reach when the factors are prepared
        double widest;
        bool operator()(const CellBounds& b, std::size_t cell) const {
            const double t = point.xi3_over_lambda;
            const double reach = prepared_reach      ? prepared_reach[cell]
                                 : index.grid_.order == 2 ? index.cell_reach(b.radius, t)
                                                         : widest;
            return slopes_reach(point.vx, point.vy, t, reach, b.x_min, b.x_max, b.y_min, b.y_max);
        }
    };
    // The test for the point, and the chirp factors prepared for its ξ3/λ (else null).
    ReachKeep reach_keep(const TransformPoint& point, const ChirpFactors*& factors) const;
    // The reach of a cell's kernels at ξ3/λ = t, with the cell tests' margin.
    double cell_reach(double radius, double t) const;
    // The cell along one axis that holds a slope, clamped to the grid: monotonic in the slope,
    // so the kernels with slopes in [a, b] lie in the cells [cell(a), cell(b)].
    static int cell_of(double slope, double origin, double inverse_width, int cells) {
        const double t = (slope - origin) * inverse_width;
        if (!(t >= 0.0)) return 0;
        return t >= cells ? cells - 1 : static_cast<int>(t);
    }

    // Consecutive runs handed to `run` merged: a span that starts where the last ended extends it.
    template <typename Run>
    struct RunMerger {
        const Run& run;
        std::size_t begin = 0;
        std::size_t end = 0;  // [begin, end): not yet handed to run()
        void add(std::size_t span_begin, std::size_t span_end) {
            if (span_begin != end) {
                flush();
                begin = span_begin;
            }
            end = span_end;
        }
        void flush() const {
            if (end > begin) run(begin, end);
        }
    };
    // The cells [i0, i1] × [j0, j1] whose slopes can put v + t·H' within the scan's widest of 0 per
    // axis (t > 0); false when no kernel's slope can.
    bool cell_rectangle(const Reach& scan, int& i0, int& i1, int& j0, int& j1) const;
    // Row j's scan range [i0, i1] narrowed to the row's cells that hold kernels and to the chord
    // of the scan's disk (inverse_t = 1/t); false when nothing is left.
    bool narrow_row(const Reach& scan, double inverse_t, int j, int& i0, int& i1) const;
    // The first and last cells of [lo, hi] in row `row` (its first cell's index) that the scan
    // keeps: two scans in from the ends that stop at the first kept cell. False when none is kept.
    template <typename Keep>
    [[gnu::always_inline]] inline bool kept_span(const Scan<Keep>& scan, std::size_t row, int lo, int hi, int& first, int& last) const;
    // Kernels of cells [first, last] of a row.
    std::size_t cells_begin(std::size_t row, int first) const { return starts_[row + first]; }
    std::size_t cells_end(std::size_t row, int last) const { return starts_[row + last + 1]; }

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
    // Per row of cells, the first and last that hold kernels (first > last: none), the range of
    // its kernels' slopes H'_y and their largest ρ(H'').
    struct Occupied {
        int first, last;
        double y_min, y_max, radius;
    };
    std::vector<Occupied> occupied_;
    // Second order, per prepared ξ3/λ: the kernels' chirp factors (in the kernels' order) and each
    // cell's widened reach.
    struct Prepared {
        ChirpFactors factors;
        std::vector<double> cell_reach;
    };
    std::vector<Prepared> prepared_;
    double largest_radius_ = 0.0;
};

inline bool SlopeIndex::cell_rectangle(const Reach& scan, int& i0, int& i1, int& j0, int& j1) const {
    const double vx = scan.vx, vy = scan.vy, t = scan.t, widest = scan.widest;
    // H'_k reaches when H'_k ∈ [(−widest − v)/t, (widest − v)/t] per axis.
    if ((widest - vx) / t < origin_x_ || (-widest - vx) / t > last_x_ || (widest - vy) / t < origin_y_ ||
        (-widest - vy) / t > last_y_)
        return false;
    i0 = cell_of((-widest - vx) / t, origin_x_, inverse_width_x_, cells_x_);
    i1 = cell_of((widest - vx) / t, origin_x_, inverse_width_x_, cells_x_);
    j0 = cell_of((-widest - vy) / t, origin_y_, inverse_width_y_, cells_y_);
    j1 = cell_of((widest - vy) / t, origin_y_, inverse_width_y_, cells_y_);
    return true;
}

inline bool SlopeIndex::narrow_row(const Reach& scan, double inverse_t, int j, int& i0, int& i1) const {
    const Occupied& row = occupied_[j];
    i0 = std::max(i0, row.first);
    i1 = std::min(i1, row.last);
    if (i0 > i1) return false;
    if (!scan.disk) return true;
    // The row's slopes H'_y lie in [y_min, y_max], so |v_y + t H'_y| ≥ gap there, and the disk's
    // chord at that gap bounds |v_x + t H'_x|.
    const double low = scan.vy + scan.t * row.y_min;
    const double high = scan.vy + scan.t * row.y_max;
    const double gap = low > 0.0 ? low : high < 0.0 ? -high : 0.0;
    if (gap > scan.widest) return false;
    const double chord = std::sqrt(scan.widest * scan.widest - gap * gap);
    i0 = std::max(i0, cell_of((-chord - scan.vx) * inverse_t, origin_x_, inverse_width_x_, cells_x_));
    i1 = std::min(i1, cell_of((chord - scan.vx) * inverse_t, origin_x_, inverse_width_x_, cells_x_));
    return true;
}

template <typename Keep>
inline bool SlopeIndex::kept_span(const Scan<Keep>& scan, std::size_t row, int lo, int hi, int& first, int& last) const {
    first = lo;
    while (first <= hi && !scan.keep(bounds_[row + first], row + first)) ++first;
    if (first > hi) return false;
    last = hi;
    while (last > first && !scan.keep(bounds_[row + last], row + last)) --last;
    return true;
}

template <typename Keep, typename Run>
void SlopeIndex::for_each_run(const Scan<Keep>& scan, const Run& run) const {
    if (!(scan.t > 0.0 && std::isfinite(scan.t))) {
        run(std::size_t{0}, kernels_.size());
        return;
    }
    // The rectangle of cells that the widest reach meets, then each cell by keep(). Per row, the
    // span from its first to its last kept cell (the cells between them, rarely not kept, are
    // included). Spans that follow each other in the index's order (whole rows) make one run.
    int i0, i1, j0, j1;
    if (!cell_rectangle(scan, i0, i1, j0, j1)) return;
    const double inverse_t = 1.0 / scan.t;
    RunMerger<Run> runs{run};
    for (int j = j0; j <= j1; ++j) {
        const std::size_t row = static_cast<std::size_t>(j) * cells_x_;
        int lo = i0, hi = i1, first, last;
        if (narrow_row(scan, inverse_t, j, lo, hi) && kept_span(scan, row, lo, hi, first, last))
            runs.add(cells_begin(row, first), cells_end(row, last));
    }
    runs.flush();
}

}  // namespace glintscope::gabor
