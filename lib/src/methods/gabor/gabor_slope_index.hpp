#pragma once
// One footprint's kernels ordered by their slope, for a BSDF that evaluates many directions at
// one footprint. A direction reaches kernel k only when v + ξ3 H'_k/λ lies in the kernel's box
// (Yan 2018 §5 "Acceleration by pruning"): a box in slope space around −vλ/ξ3. With the kernels
// sorted into the cells of a grid over slope space, the kernels a direction can reach are a few
// contiguous runs of cells, so eval reads only them and sums them in place, where GaborSurface
// (any footprint, once) walks its hierarchy and copies its survivors per query.
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

    // The kernels, in the index's order.
    const KernelArrays& kernels() const { return kernels_; }

private:
    // Σ over the kernels [begin, end), with prepared chirp factors when there are some.
    std::complex<double> sum_run(std::size_t begin, std::size_t end, const TransformPoint& point,
                                 const ChirpFactors* factors) const;
    // The reach of a cell's kernels at ξ3/λ = t, with the cell tests' margin.
    double cell_reach(double radius, double t) const;
    // The cell along one axis that holds a slope, clamped to the grid: monotonic in the slope,
    // so the kernels with slopes in [a, b] lie in the cells [cell(a), cell(b)].
    static int cell_of(double slope, double origin, double inverse_width, int cells);

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
    // Per cell, the range of its kernels' slopes (tighter than the cell) and at second order the
    // largest ρ(H'') among them, which widens their reach.
    struct CellBounds {
        double x_min, x_max, y_min, y_max, radius;
    };
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

}  // namespace glintscope::gabor
