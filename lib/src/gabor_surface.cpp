// Point queries of the Gabor lobe with the pruning hierarchy of Yan 2018 §5.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <emmintrin.h>  // SSE2, part of x86-64: 16 slope codes per compare
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
static_assert(kLeafKernels * kLeafKernels == 64, "leaf kernels are bits of a 64-bit mask");

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

// For each byte, the positions of its set bits, lowest first (the rest 0).
constexpr std::array<std::array<std::uint8_t, 8>, 256> kSetBitPositions = [] {
    std::array<std::array<std::uint8_t, 8>, 256> table{};
    for (int value = 0; value < 256; ++value)
        for (int bit = 0, count = 0; bit < 8; ++bit)
            if (value >> bit & 1) table[value][count++] = static_cast<std::uint8_t>(bit);
    return table;
}();

// 8-bit codes of slopes within a leaf's range [lo, hi]: code(h) = ⌊(h − lo)·255/(hi − lo)⌋. A
// slope interval [a, b] maps to the codes [⌊·⌋ − 1, ⌈·⌉ + 1], so rounding in either mapping
// never drops a code inside it. Ranges under 1e-6 are coded as 1e-6 wide, which keeps that
// rounding far below one code.
class SlopeCodec {
public:
    SlopeCodec(double lo, double hi) : lo_(lo), scale_(255.0 / std::max(hi - lo, 1e-6)) {}
    unsigned char code(double h) const {
        return static_cast<unsigned char>(std::clamp(std::floor((h - lo_) * scale_), 0.0, 255.0));
    }
    // The codes [first, first + span] that may hold slopes in [a, b] (a ≤ b), clamped to 0…255.
    void codes_of(double a, double b, int& first, int& span) const {
        const double from = std::clamp(std::floor((a - lo_) * scale_) - 1.0, 0.0, 255.0);
        const double to = std::clamp(std::ceil((b - lo_) * scale_) + 1.0, 0.0, 255.0);
        first = static_cast<int>(from);
        span = static_cast<int>(to) - first;
    }

private:
    double lo_;
    double scale_;
};

// The kernels of 64 codes whose x code lies in [first_x, first_x + span_x] and whose y code
// lies in [first_y, first_y + span_y], as bits: (code − first) mod 256 ≤ span is both bounds in
// one unsigned compare.
std::uint64_t codes_within(const unsigned char* x, const unsigned char* y, int first_x, int span_x, int first_y,
                           int span_y) {
    std::uint64_t bits = 0;
    for (int block = 0; block < 64; block += 16) {
        const __m128i cx = _mm_sub_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(x + block)),
                                        _mm_set1_epi8(static_cast<char>(first_x)));
        const __m128i cy = _mm_sub_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(y + block)),
                                        _mm_set1_epi8(static_cast<char>(first_y)));
        const __m128i in_x = _mm_cmpeq_epi8(_mm_min_epu8(cx, _mm_set1_epi8(static_cast<char>(span_x))), cx);
        const __m128i in_y = _mm_cmpeq_epi8(_mm_min_epu8(cy, _mm_set1_epi8(static_cast<char>(span_y))), cy);
        bits |= static_cast<std::uint64_t>(static_cast<unsigned>(_mm_movemask_epi8(_mm_and_si128(in_x, in_y))))
                << block;
    }
    return bits;
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
    // The kernels of a leaf whose codes may hold a slope that reaches: v + ξ3 H'/λ ∈ [−reach,
    // reach] per axis is H' ∈ [(−reach − v)λ/ξ3, (reach − v)λ/ξ3] (ξ3 > 0).
    std::uint64_t leaf_reaches(const GaborSurface::SlopeBox& box, const unsigned char* codes_x,
                               const unsigned char* codes_y) const {
        int first_x, span_x, first_y, span_y;
        SlopeCodec(box.x_min, box.x_max)
            .codes_of((-reach - vx) / xi3_over_lambda, (reach - vx) / xi3_over_lambda, first_x, span_x);
        SlopeCodec(box.y_min, box.y_max)
            .codes_of((-reach - vy) / xi3_over_lambda, (reach - vy) / xi3_over_lambda, first_y, span_y);
        return codes_within(codes_x, codes_y, first_x, span_x, first_y, span_y);
    }
};

// w(p) = w(p_x, 0)·w(0, p_y) for both footprints: its factors at the kernel columns and rows
// around one footprint centre, tabulated once per query instead of once per kernel.
class SeparableWeights {
public:
    void tabulate(const gabor::CoherenceWindow& window, const gabor::KernelGrid& grid, double cx, double cy) {
        tabulate_axis(window, grid, cx, first_column_, columns_);
        tabulate_axis(window, grid, cy, first_row_, rows_);
    }
    double along_x(long long i) const { return columns_[i - first_column_]; }
    double along_y(long long j) const { return rows_[j - first_row_]; }

private:
    static void tabulate_axis(const gabor::CoherenceWindow& window, const gabor::KernelGrid& grid, double centre,
                              long long& first, std::vector<double>& factors) {
        const double extent = window.half_extent_um();
        first = static_cast<long long>(std::floor((centre - extent) / grid.spacing_um - 0.5));
        const long long last = static_cast<long long>(std::ceil((centre + extent) / grid.spacing_um - 0.5));
        factors.resize(last - first + 1);
        // Along a row of kernel centres p_i = p_0 + i l the Gaussian factor obeys w_{i+1} = w_i r_i,
        // r_{i+1} = r_i q with q = w(l)²: three exps instead of one per kernel, and relative
        // errors that grow only by an ulp or so per step (1 for a box window). A footprint far
        // narrower than l underflows the recurrence and takes the exps.
        const double p0 = grid.centre(first) - centre;
        double w = window.weight(p0, 0.0);
        const double step = window.weight(grid.spacing_um, 0.0);
        const double ratio_step = step * step;
        if (!(w > 1e-150 && ratio_step > 1e-150)) {
            for (long long i = first; i <= last; ++i) factors[i - first] = window.weight(grid.centre(i) - centre, 0.0);
            return;
        }
        double ratio = window.weight(p0 + grid.spacing_um, 0.0) / w;
        for (double& factor : factors) {
            factor = w;
            w *= ratio;
            ratio *= ratio_step;
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
    // 2 bytes of codes per kernel and 16 bytes of bounds per leaf of kLeafKernels² kernels: 2^29
    // kernels take 1.2 GB.
    if (double(kernels_x_) * kernels_y_ > 536870912.0)
        throw Error("gabor: " + std::to_string(surface_->cols()) + "x" + std::to_string(surface_->rows()) +
                    " heightfield at " + std::to_string(settings_.kernels_per_texel) +
                    " kernels per texel exceeds 2^29 kernels; use fewer kernels_per_texel");
    build_leaves();
    build_parents();
}

void GaborSurface::build_leaves() {
    const gabor::KernelGrid grid = gabor::kernel_grid(surface_->texel_um(), settings_);
    Level leaves;
    leaves.nx = (kernels_x_ + kLeafKernels - 1) / kLeafKernels;
    leaves.ny = (kernels_y_ + kLeafKernels - 1) / kLeafKernels;
    leaves.boxes.resize(static_cast<std::size_t>(leaves.nx) * leaves.ny);
    leaf_codes_.resize(leaves.boxes.size());
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
                const SlopeBox box{round_down(x_min), round_up(x_max), round_down(y_min), round_up(y_max)};
                leaves.boxes[leaf_row * leaves.nx + leaf_col] = box;
                const SlopeCodec codec_x(box.x_min, box.x_max);
                const SlopeCodec codec_y(box.y_min, box.y_max);
                LeafCodes& codes = leaf_codes_[leaf_row * leaves.nx + leaf_col];
                std::fill(std::begin(codes.x), std::end(codes.x), 0);
                std::fill(std::begin(codes.y), std::end(codes.y), 0);
                for (int j = 0; j < rows; ++j)
                    for (int i = i0; i < i1; ++i) {
                        const SurfacePoint& p = points[static_cast<std::size_t>(j) * kernels_x_ + i];
                        codes.x[j * kLeafKernels + i - i0] = codec_x.code(p.dh_dx);
                        codes.y[j * kLeafKernels + i - i0] = codec_y.code(p.dh_dy);
                    }
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
    std::size_t bytes = sizeof(*this) + leaf_codes_.capacity() * sizeof(LeafCodes);
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
    thread_local std::vector<std::pair<int, int>> nodes;  // (column, row) of one level's nodes
    thread_local std::vector<std::pair<int, int>> children;
    thread_local std::vector<int> columns;  // kernels that survive pruning, in one tile copy
    thread_local std::vector<int> rows;
    thread_local std::vector<SurfacePoint> points;  // and H, H' there
    thread_local std::vector<SurfacePoint> block;
    thread_local std::vector<std::uint64_t> band_bits;  // per leaf of a leaf row: kernels that may reach
    thread_local SeparableWeights weights;
    std::size_t survivors = 0;  // entries of columns, rows and points in use
    GaborQueryStatistics counts;

    // Yan 2018 §5: top-down through the hierarchy, dropping nodes outside the footprint or whose
    // directional box cannot reach the query. Level by level, so that the bounds of a level's
    // nodes are fetched from memory together.
    const auto find_leaves = [&](double cx, double cy) {
        const auto overlaps = [&](int level, int ix, int iy) {
            const int span = kLeafKernels << level;  // kernels per node side
            const int i0 = ix * span;
            const int j0 = iy * span;
            const int i1 = std::min(kernels_x_, i0 + span);
            const int j1 = std::min(kernels_y_, j0 + span);
            return window.overlaps(grid.centre(i0) - cx, grid.centre(i1 - 1) - cx, grid.centre(j0) - cy,
                                   grid.centre(j1 - 1) - cy);
        };
        const int root = static_cast<int>(levels_.size()) - 1;
        nodes.assign(1, {0, 0});
        if (!overlaps(root, 0, 0)) return;
        for (int level_index = root; level_index >= 0; --level_index) {
            const Level& level = levels_[level_index];
            children.clear();
            for (const auto& [ix, iy] : nodes) {
                ++counts.nodes_visited;
                const std::size_t index = static_cast<std::size_t>(iy) * level.nx + ix;
                if (!reach.box_reaches(level.boxes[index])) continue;
                if (level_index == 0) {
                    leaves.emplace_back(iy, ix);
                    __builtin_prefetch(&leaf_codes_[index]);
                    __builtin_prefetch(reinterpret_cast<const char*>(&leaf_codes_[index]) + 64);
                    continue;
                }
                const Level& below = levels_[level_index - 1];
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const int child_x = 2 * ix + dx;
                        const int child_y = 2 * iy + dy;
                        if (child_x >= below.nx || child_y >= below.ny || !overlaps(level_index - 1, child_x, child_y))
                            continue;
                        children.emplace_back(child_x, child_y);
                        __builtin_prefetch(&below.boxes[static_cast<std::size_t>(child_y) * below.nx + child_x]);
                    }
            }
            std::swap(nodes, children);
        }
    };

    // The kernels of one leaf whose bits are set, interpolated from the leaf's block of the
    // kernel grid (K > 1).
    const auto add_interpolated = [&](int leaf_row, int leaf_col, std::uint64_t bits) {
        const int i0 = leaf_col * kLeafKernels;
        const int j0 = leaf_row * kLeafKernels;
        const int nx = std::min(kLeafKernels, kernels_x_ - i0);
        const int ny = std::min(kLeafKernels, kernels_y_ - j0);
        block.resize(static_cast<std::size_t>(kLeafKernels) * kLeafKernels);
        gabor::evaluate_kernels(*surface_, grid, i0, j0, nx, ny, block.data());
        counts.kernels_evaluated += static_cast<std::size_t>(nx) * ny;
        for (; bits != 0; bits &= bits - 1, ++survivors) {
            const int k = std::countr_zero(bits);
            columns[survivors] = i0 + k % kLeafKernels;
            rows[survivors] = j0 + k / kLeafKernels;
            points[survivors] = block[static_cast<std::size_t>(k / kLeafKernels) * nx + k % kLeafKernels];
        }
    };

    // The surviving leaves [begin, end) of one leaf row: the window's chord on each kernel row,
    // then per leaf the kernels inside it whose codes may reach.
    const auto add_leaf_row = [&](double cx, double cy, const std::pair<int, int>* begin,
                                  const std::pair<int, int>* end) {
        const int j0 = begin->first * kLeafKernels;
        const int j1 = std::min(kernels_y_, j0 + kLeafKernels);
        const int i0 = begin->second * kLeafKernels;
        const int i1 = std::min(kernels_x_, ((end - 1)->second + 1) * kLeafKernels);
        long long first[kLeafKernels];
        long long last[kLeafKernels];
        for (int j = j0; j < j1; ++j)
            if (!window.row_span(grid, cx, grid.centre(j) - cy, i0, i1 - 1, first[j - j0], last[j - j0])) {
                first[j - j0] = i1;
                last[j - j0] = i1 - 1;
            }
        const Level& leaves_level = levels_.front();
        band_bits.resize(end - begin);
        for (const std::pair<int, int>* leaf = begin; leaf != end; ++leaf) {
            band_bits[leaf - begin] = 0;
            const long long leaf_i0 = static_cast<long long>(leaf->second) * kLeafKernels;
            std::uint64_t inside = 0;  // kernels of the leaf that the window contains
            for (int j = j0; j < j1; ++j) {
                const long long from = std::max(first[j - j0], leaf_i0);
                const long long to = std::min(last[j - j0], leaf_i0 + kLeafKernels - 1);
                if (from > to) continue;
                const std::uint64_t run = (std::uint64_t{2} << (to - from)) - 1;
                inside |= run << ((j - j0) * kLeafKernels + (from - leaf_i0));
            }
            if (inside == 0) continue;
            const std::size_t index = static_cast<std::size_t>(leaf->first) * leaves_level.nx + leaf->second;
            const LeafCodes& codes = leaf_codes_[index];
            band_bits[leaf - begin] = inside & reach.leaf_reaches(leaves_level.boxes[index], codes.x, codes.y);
        }
        if (grid.kernels_per_texel != 1) {
            for (const std::pair<int, int>* leaf = begin; leaf != end; ++leaf)
                if (band_bits[leaf - begin] != 0) add_interpolated(leaf->first, leaf->second, band_bits[leaf - begin]);
            return;
        }
        // Samples, gathered later: listed row by row across the leaves, so that consecutive
        // samples share cache lines. Each byte of bits is unpacked through a table, without a
        // branch on the number of bits set (8 slots are written, popcount of them kept).
        for (int j = j0; j < j1; ++j)
            for (const std::pair<int, int>* leaf = begin; leaf != end; ++leaf) {
                const int i0_leaf = leaf->second * kLeafKernels;
                const std::uint64_t bits = band_bits[leaf - begin] >> ((j - j0) * kLeafKernels);
                const auto row_bits = static_cast<unsigned>(bits & 0xFF);
                const std::array<std::uint8_t, 8>& positions = kSetBitPositions[row_bits];
                for (int k = 0; k < 8; ++k) {
                    columns[survivors + k] = i0_leaf + positions[k];
                    rows[survivors + k] = j;
                }
                survivors += std::popcount(row_bits);
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
            // The buffers only grow, so a thread's queries stop allocating after the first few.
            const std::size_t most = leaves.size() * kLeafKernels * kLeafKernels + 8;  // + 8: unpacking slack
            if (columns.size() < most) {
                columns.resize(most);
                rows.resize(most);
                points.resize(most);
            }
            survivors = 0;
            std::sort(leaves.begin(), leaves.end());
            for (std::size_t begin = 0; begin < leaves.size();) {
                std::size_t end = begin + 1;
                while (end < leaves.size() && leaves[end].first == leaves[begin].first) ++end;
                add_leaf_row(cx, cy, leaves.data() + begin, leaves.data() + end);
                begin = end;
            }
            if (grid.kernels_per_texel == 1) {
                surface_->evaluate_samples(columns.data(), rows.data(), survivors, points.data());
                counts.kernels_evaluated += survivors;
            }
            kernels.reserve_more(survivors);
            for (std::size_t k = 0; k < survivors; ++k)
                kernels.push(grid.centre(columns[k]) - cx, grid.centre(rows[k]) - cy, points[k], reference_height,
                             weights.along_x(columns[k]) * weights.along_y(rows[k]) * weight_scale);
        }
    if (statistics) {
        statistics->nodes_visited += counts.nodes_visited;
        statistics->kernels_evaluated += counts.kernels_evaluated;
    }
}

double GaborSurface::f_r(const GaborPointQuery& query, double lambda_um, GaborQueryStatistics* statistics) const {
    thread_local std::vector<double> wavelength(1);
    wavelength[0] = lambda_um;
    return f_r(query, wavelength, statistics).front();
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
