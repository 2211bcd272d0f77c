// Point queries of the Gabor lobe with the pruning hierarchy of Yan 2018 §5.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "gabor_kernels.hpp"
#include "glintscope/error.hpp"
#include "glintscope/gabor.hpp"
#include "glintscope/parallel.hpp"

namespace glintscope {
namespace {

// A leaf holds kLeafKernels² kernels: small enough that pruning is selective, large enough that
// the bounds of an 8192² field at K = 1 take 16 MB.
constexpr int kLeafKernels = 8;

float round_down(double value) {
    const float f = static_cast<float>(value);
    return static_cast<double>(f) > value ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

float round_up(double value) {
    const float f = static_cast<float>(value);
    return static_cast<double>(f) < value ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

GaborSurface::SlopeBox empty_box() {
    const float inf = std::numeric_limits<float>::infinity();
    return {inf, -inf, inf, -inf};
}

void include(GaborSurface::SlopeBox& box, const GaborSurface::SlopeBox& other) {
    box.x_min = std::min(box.x_min, other.x_min);
    box.x_max = std::max(box.x_max, other.x_max);
    box.y_min = std::min(box.y_min, other.y_min);
    box.y_max = std::max(box.y_max, other.y_max);
}

// The directional test at the pruning wavelength, for node boxes and single kernels.
struct DirectionalReach {
    double vx = 0.0;
    double vy = 0.0;
    double xi3_over_lambda = 0.0;
    double reach = 0.0;

    bool box_reaches(const GaborSurface::SlopeBox& box) const {
        return gabor::slopes_reach(vx, vy, xi3_over_lambda, reach, box.x_min, box.x_max, box.y_min, box.y_max);
    }
    bool slope_reaches(double hx, double hy) const {
        return gabor::slopes_reach(vx, vy, xi3_over_lambda, reach, hx, hx, hy, hy);
    }
};

// w(p) = w(p_x, 0)·w(0, p_y) for both footprints: its factors at the kernel columns and rows
// around one footprint centre, tabulated once per query instead of once per kernel.
class SeparableWeights {
public:
    void tabulate(const gabor::CoherenceWindow& window, const gabor::KernelGrid& grid, double cx, double cy) {
        tabulate_axis(window, grid, cx, true, first_column_, columns_);
        tabulate_axis(window, grid, cy, false, first_row_, rows_);
    }
    double along_x(long long i) const { return columns_[i - first_column_]; }
    double along_y(long long j) const { return rows_[j - first_row_]; }

private:
    static void tabulate_axis(const gabor::CoherenceWindow& window, const gabor::KernelGrid& grid, double centre,
                              bool along_x, long long& first, std::vector<double>& factors) {
        const double extent = window.half_extent_um();
        first = static_cast<long long>(std::floor((centre - extent) / grid.spacing_um - 0.5));
        const long long last = static_cast<long long>(std::ceil((centre + extent) / grid.spacing_um - 0.5));
        factors.resize(last - first + 1);
        for (long long i = first; i <= last; ++i) {
            const double p = grid.centre(i) - centre;
            factors[i - first] = along_x ? window.weight(p, 0.0) : window.weight(0.0, p);
        }
    }

    long long first_column_ = 0;
    long long first_row_ = 0;
    std::vector<double> columns_;
    std::vector<double> rows_;
};

void check_finite(const GaborPointQuery& query) {
    const Vec3 wi = query.omega_i;
    const Vec3 wo = query.omega_o;
    const Point2 c = query.footprint.centre_um;
    if (!std::isfinite(wi.x + wi.y + wi.z + wo.x + wo.y + wo.z + c.x + c.y))
        throw Error("gabor: point query directions and footprint centre must be finite");
    const bool box = query.footprint.shape == FootprintShape::box;
    const double size = box ? query.footprint.size_um : query.footprint.sigma_um;
    if (!(size > 0.0 && size <= 1e5)) throw Error("gabor: point query footprint size must be positive and finite");
}

}  // namespace

GaborSurface::GaborSurface(std::shared_ptr<const BicubicInterpolant> surface, GaborSettings settings)
    : surface_(std::move(surface)), settings_(settings) {
    if (!surface_) throw Error("gabor: GaborSurface needs a heightfield interpolant");
    validate(settings_);
    kernels_x_ = surface_->cols() * settings_.kernels_per_texel;
    kernels_y_ = surface_->rows() * settings_.kernels_per_texel;
    // 16 bytes of bounds per leaf of kLeafKernels² kernels: 2^33 kernels take 2 GB.
    if (double(kernels_x_) * kernels_y_ > 8589934592.0)
        throw Error("gabor: " + std::to_string(surface_->cols()) + "x" + std::to_string(surface_->rows()) +
                    " heightfield at " + std::to_string(settings_.kernels_per_texel) +
                    " kernels per texel exceeds 2^33 kernels; use fewer kernels_per_texel");
    build_leaves();
    build_parents();
}

void GaborSurface::build_leaves() {
    const gabor::KernelGrid grid = gabor::kernel_grid(surface_->texel_um(), settings_);
    Level leaves;
    leaves.nx = (kernels_x_ + kLeafKernels - 1) / kLeafKernels;
    leaves.ny = (kernels_y_ + kLeafKernels - 1) / kLeafKernels;
    leaves.boxes.resize(static_cast<std::size_t>(leaves.nx) * leaves.ny);
    // One row of leaves per chunk: interpolate its kLeafKernels rows of kernels in one grid call.
    parallel_for(leaves.ny, 1, [&](std::size_t begin, std::size_t end) {
        std::vector<SurfacePoint> points(static_cast<std::size_t>(kernels_x_) * kLeafKernels);
        for (std::size_t leaf_row = begin; leaf_row < end; ++leaf_row) {
            const int j0 = static_cast<int>(leaf_row) * kLeafKernels;
            const int rows = std::min(kLeafKernels, kernels_y_ - j0);
            gabor::evaluate_kernels(*surface_, grid, 0, j0, kernels_x_, rows, points.data());
            for (int leaf_col = 0; leaf_col < leaves.nx; ++leaf_col) {
                double x_min = std::numeric_limits<double>::infinity();
                double x_max = -x_min;
                double y_min = x_min;
                double y_max = -x_min;
                const int i0 = leaf_col * kLeafKernels;
                const int i1 = std::min(kernels_x_, i0 + kLeafKernels);
                for (int j = 0; j < rows; ++j)
                    for (int i = i0; i < i1; ++i) {
                        const SurfacePoint& p = points[static_cast<std::size_t>(j) * kernels_x_ + i];
                        x_min = std::min(x_min, p.dh_dx);
                        x_max = std::max(x_max, p.dh_dx);
                        y_min = std::min(y_min, p.dh_dy);
                        y_max = std::max(y_max, p.dh_dy);
                    }
                leaves.boxes[leaf_row * leaves.nx + leaf_col] = {round_down(x_min), round_up(x_max), round_down(y_min),
                                                                 round_up(y_max)};
            }
        }
    });
    levels_.push_back(std::move(leaves));
}

void GaborSurface::build_parents() {
    while (levels_.back().nx > 1 || levels_.back().ny > 1) {
        const Level& child = levels_.back();
        Level parent;
        parent.nx = (child.nx + 1) / 2;
        parent.ny = (child.ny + 1) / 2;
        parent.boxes.assign(static_cast<std::size_t>(parent.nx) * parent.ny, empty_box());
        for (int j = 0; j < child.ny; ++j)
            for (int i = 0; i < child.nx; ++i)
                include(parent.boxes[static_cast<std::size_t>(j / 2) * parent.nx + i / 2],
                        child.boxes[static_cast<std::size_t>(j) * child.nx + i]);
        levels_.push_back(std::move(parent));
    }
}

std::size_t GaborSurface::memory_bytes() const {
    std::size_t bytes = sizeof(*this);
    for (const Level& level : levels_) bytes += level.boxes.capacity() * sizeof(SlopeBox);
    return bytes;
}

void GaborSurface::collect(const GaborPointQuery& query, double prune_lambda_um, gabor::KernelArrays& kernels,
                           GaborQueryStatistics* statistics) const {
    const gabor::KernelGrid grid = gabor::kernel_grid(surface_->texel_um(), settings_);
    const gabor::CoherenceWindow window(query.footprint, settings_.footprint_sigmas);
    window.check_kernel_count(grid);
    const Vec3 psi = query.omega_i + query.omega_o;
    const DirectionalReach reach{psi.x / prune_lambda_um, psi.y / prune_lambda_um,
                                 xi3(query.model, query.omega_i, query.omega_o) / prune_lambda_um, grid.reach};
    const Point2 centre = query.footprint.centre_um;
    const double reference_height = surface_->height(centre.x, centre.y);
    const double weight_scale = grid.spacing_um * grid.spacing_um;
    const double tile_x = kernels_x_ * grid.spacing_um;
    const double tile_y = kernels_y_ * grid.spacing_um;
    const double extent = window.half_extent_um();
    thread_local std::vector<std::pair<int, int>> leaves;  // (row, column) of surviving leaves
    thread_local std::vector<SurfacePoint> points;
    thread_local SeparableWeights weights;
    GaborQueryStatistics counts;

    // Yan 2018 §5: top-down through the hierarchy, dropping nodes outside the footprint or whose
    // directional box cannot reach the query.
    const auto find_leaves = [&](double cx, double cy) {
        struct Node {
            int level;
            int ix;
            int iy;
        };
        Node stack[4 * 32];
        int top = 0;
        stack[top++] = {static_cast<int>(levels_.size()) - 1, 0, 0};
        while (top > 0) {
            const Node node = stack[--top];
            ++counts.nodes_visited;
            const int span = kLeafKernels << node.level;  // kernels per node side
            const int i0 = node.ix * span;
            const int j0 = node.iy * span;
            const int i1 = std::min(kernels_x_, i0 + span);
            const int j1 = std::min(kernels_y_, j0 + span);
            if (!window.overlaps(grid.centre(i0) - cx, grid.centre(i1 - 1) - cx, grid.centre(j0) - cy,
                                 grid.centre(j1 - 1) - cy))
                continue;
            const Level& level = levels_[node.level];
            if (!reach.box_reaches(level.boxes[static_cast<std::size_t>(node.iy) * level.nx + node.ix])) continue;
            if (node.level == 0) {
                leaves.emplace_back(node.iy, node.ix);
                continue;
            }
            const Level& below = levels_[node.level - 1];
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) {
                    const int ix = 2 * node.ix + dx;
                    const int iy = 2 * node.iy + dy;
                    if (ix < below.nx && iy < below.ny) stack[top++] = {node.level - 1, ix, iy};
                }
        }
    };

    // Kernels of leaves [column_begin, column_end) in one leaf row: one interpolant call for the
    // rectangle spanned by their kernels inside the window, then the per-kernel tests.
    const auto add_run = [&](double cx, double cy, int leaf_row, int column_begin, int column_end) {
        const int i0 = column_begin * kLeafKernels;
        const int i1 = std::min(kernels_x_, column_end * kLeafKernels);
        const int j0 = leaf_row * kLeafKernels;
        const int j1 = std::min(kernels_y_, j0 + kLeafKernels);
        long long first[kLeafKernels];
        long long last[kLeafKernels];
        int i_min = i1;
        int i_max = i0 - 1;
        for (int j = j0; j < j1; ++j) {
            long long& f = first[j - j0] = 0;
            long long& l = last[j - j0] = -1;
            if (!window.row_span(grid, cx, grid.centre(j) - cy, i0, i1 - 1, f, l)) continue;
            i_min = std::min(i_min, static_cast<int>(f));
            i_max = std::max(i_max, static_cast<int>(l));
        }
        if (i_min > i_max) return;
        const int width = i_max - i_min + 1;
        points.resize(static_cast<std::size_t>(width) * (j1 - j0));
        gabor::evaluate_kernels(*surface_, grid, i_min, j0, width, j1 - j0, points.data());
        counts.kernels_evaluated += points.size();
        kernels.reserve_more(points.size());
        for (int j = j0; j < j1; ++j) {
            const double py = grid.centre(j) - cy;
            const double row_weight = weights.along_y(j) * weight_scale;
            for (int i = static_cast<int>(first[j - j0]); i <= last[j - j0]; ++i) {
                const SurfacePoint& p = points[static_cast<std::size_t>(j - j0) * width + (i - i_min)];
                kernels.push_if(reach.slope_reaches(p.dh_dx, p.dh_dy), grid.centre(i) - cx, py, p, reference_height,
                                weights.along_x(i) * row_weight);
            }
        }
    };

    // The surface tiles periodically: visit every tile copy the footprint overlaps, with the
    // footprint centre expressed in that copy's coordinates.
    for (long long ty = std::llround(std::floor((centre.y - extent) / tile_y));
         ty <= std::llround(std::floor((centre.y + extent) / tile_y)); ++ty)
        for (long long tx = std::llround(std::floor((centre.x - extent) / tile_x));
             tx <= std::llround(std::floor((centre.x + extent) / tile_x)); ++tx) {
            const double cx = centre.x - tx * tile_x;
            const double cy = centre.y - ty * tile_y;
            weights.tabulate(window, grid, cx, cy);
            leaves.clear();
            find_leaves(cx, cy);
            // Adjacent surviving leaves of a row share one interpolant call.
            std::sort(leaves.begin(), leaves.end());
            for (std::size_t begin = 0; begin < leaves.size();) {
                std::size_t end = begin + 1;
                while (end < leaves.size() && leaves[end].first == leaves[begin].first &&
                       leaves[end].second == leaves[end - 1].second + 1)
                    ++end;
                add_run(cx, cy, leaves[begin].first, leaves[begin].second, leaves[end - 1].second + 1);
                begin = end;
            }
        }
    if (statistics) {
        statistics->nodes_visited += counts.nodes_visited;
        statistics->kernels_evaluated += counts.kernels_evaluated;
    }
}

double GaborSurface::f_r(const GaborPointQuery& query, double lambda_um, GaborQueryStatistics* statistics) const {
    return f_r(query, std::vector<double>{lambda_um}, statistics).front();
}

std::vector<double> GaborSurface::f_r(const GaborPointQuery& query, const std::vector<double>& wavelengths_um,
                                      GaborQueryStatistics* statistics) const {
    check_finite(query);
    for (double lambda : wavelengths_um)
        if (!(lambda > 0.0 && std::isfinite(lambda))) throw Error("gabor: wavelengths must be positive and finite");
    std::vector<double> values(wavelengths_um.size(), 0.0);
    if (wavelengths_um.empty() || query.omega_i.z <= 0.0 || query.omega_o.z <= 0.0) return values;

    // A kernel's directional box, in slope space, is |ψ̄ + ξ3 H'| ≤ reach·λ: widest at the longest
    // wavelength, so the kernels pruned there are pruned at every wavelength.
    std::vector<double> ascending = wavelengths_um;
    std::sort(ascending.begin(), ascending.end());
    thread_local gabor::KernelArrays collected;
    collected.clear();
    collect(query, ascending.back(), collected, statistics);

    const gabor::KernelGrid grid = gabor::kernel_grid(surface_->texel_um(), settings_);
    const double area = gabor::CoherenceWindow(query.footprint, settings_.footprint_sigmas).area_um2();
    const auto sum = [&](const gabor::KernelArrays& kernels, std::size_t end, double lambda) {
        const gabor::TransformPoint point = gabor::transform_point(
            query.model, gabor::FresnelAtWavelength(query.material, lambda), query.omega_i, query.omega_o, lambda,
            area);
        if (statistics) statistics->kernels_summed += end;
        // Yan 2018 eq. 16–17.
        return point.brdf_scale * std::norm(gabor::sum_transforms(kernels, 0, end, point, grid));
    };
    if (wavelengths_um.size() == 1) {
        values[0] = sum(collected, collected.size(), wavelengths_um[0]);
        return values;
    }

    // Order the survivors by the shortest wavelength that still reaches them, so that each
    // wavelength sums a prefix: kernel k reaches λ when λ ≥ λ_k = max_axis |ψ̄ + ξ3 H'_k| / reach.
    const Vec3 psi = query.omega_i + query.omega_o;
    const double xi3_value = xi3(query.model, query.omega_i, query.omega_o);
    thread_local std::vector<int> first_reached;
    first_reached.resize(collected.size());
    std::vector<std::size_t> prefix(ascending.size() + 1, 0);
    for (std::size_t k = 0; k < collected.size(); ++k) {
        const double needed = std::max(std::fabs(psi.x + xi3_value * collected.slope_x[k]),
                                       std::fabs(psi.y + xi3_value * collected.slope_y[k])) /
                              grid.reach * (1.0 - 1e-9);  // rounding errs towards keeping the kernel
        int shorter = 0;  // wavelengths too short to reach the kernel (a branch-free count)
        for (const double lambda : ascending) shorter += lambda < needed;
        first_reached[k] = shorter;
        ++prefix[std::min<std::size_t>(first_reached[k], ascending.size() - 1) + 1];
    }
    for (std::size_t i = 1; i < prefix.size(); ++i) prefix[i] += prefix[i - 1];
    thread_local gabor::KernelArrays ordered;
    ordered.resize(collected.size());
    std::vector<std::size_t> next(prefix.begin(), prefix.end() - 1);
    for (std::size_t k = 0; k < collected.size(); ++k)
        ordered.copy(next[std::min<std::size_t>(first_reached[k], ascending.size() - 1)]++, collected, k);

    for (std::size_t i = 0; i < wavelengths_um.size(); ++i) {
        const double lambda = wavelengths_um[i];
        const auto reached = std::upper_bound(ascending.begin(), ascending.end(), lambda) - ascending.begin();
        values[i] = sum(ordered, prefix[reached], lambda);
    }
    return values;
}

}  // namespace glintscope
