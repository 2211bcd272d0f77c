// Point queries of the Gabor lobe with the pruning hierarchy of Yan 2018 §5.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <emmintrin.h>  // SSE2, part of x86-64: 16 slope codes per compare, 4 columns per add
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "gabor_kernels.hpp"
#include "glintscope/core/error.hpp"
#include "gabor.hpp"
#include "glintscope/core/parallel.hpp"
#include "core/target_clones.hpp"


namespace glintscope {
namespace gabor {

// Range of ∂H/∂x and ∂H/∂y over a node's kernels, rounded outward.
struct SlopeBox {
    float x_min, x_max, y_min, y_max;
};

// One level of the quadtree over the kernel grid.
struct Level {
    int nx = 0;
    int ny = 0;
    std::vector<SlopeBox> boxes;  // row-major, y-up like the kernel grid
    // Second order: the largest ρ(H'') over each node's kernels (max |eigenvalue|, 1/µm,
    // rounded up), which widens the node's directional reach; empty at first order.
    std::vector<float> curvature_radii;
};

// Per leaf (K > 1 only), the codes of its kernels' ∂H/∂x then those of ∂H/∂y, kernel (i, j)
// of the leaf at j·kLeafKernels + i: code = ⌊(H' − min) · 255/max(max − min, 1e-6)⌋ over the
// leaf's box.
struct LeafCodes {
    unsigned char x[64];
    unsigned char y[64];
};

}  // namespace gabor

struct gabor::Hierarchy {
    int kernels_x = 0;  // kernel grid of one tile of the periodic surface
    int kernels_y = 0;
    // K = 1, second order: the largest |H| difference between neighbouring samples along x or y
    // (periodic), rounded up, which bounds the rounding of the float curvature stencils that
    // test each kernel's own chirped reach (ChirpedDifferenceTest).
    float largest_step = 0.0f;
    std::vector<gabor::Level> levels;  // levels[0]: leaves of kLeafKernels² kernels; back(): the root
    std::vector<gabor::LeafCodes> leaf_codes;  // parallel to levels[0].boxes; empty at K = 1
};

namespace {

// A leaf holds kLeafKernels² kernels: small enough that pruning is selective, large enough that
// the bounds of an 8192² field at K = 1 take 16 MB.
constexpr int kLeafKernels = 8;
static_assert(kLeafKernels * kLeafKernels == 64, "leaf kernels are bits of a 64-bit mask");

// The float next to a finite f toward +∞ (up) or −∞, by its bits: nextafter is a library call,
// and the point query rounds a pair of bounds per leaf.
float float_step(float f, bool up) {
    if (f == 0.0f) return up ? std::numeric_limits<float>::denorm_min() : -std::numeric_limits<float>::denorm_min();
    const auto bits = std::bit_cast<std::uint32_t>(f);
    return std::bit_cast<float>((f > 0.0f) == up ? bits + 1 : bits - 1);
}

// The nearest float at or below (round_down) or above (round_up) a finite value within float's range.
float round_down(double value) {
    const float f = static_cast<float>(value);
    return static_cast<double>(f) > value ? float_step(f, false) : f;
}

float round_up(double value) {
    const float f = static_cast<float>(value);
    return static_cast<double>(f) < value ? float_step(f, true) : f;
}

gabor::SlopeBox empty_box() {
    const float inf = std::numeric_limits<float>::infinity();
    return {inf, -inf, inf, -inf};
}

void include(gabor::SlopeBox& box, const gabor::SlopeBox& other) {
    box.x_min = std::min(box.x_min, other.x_min);
    box.x_max = std::max(box.x_max, other.x_max);
    box.y_min = std::min(box.y_min, other.y_min);
    box.y_max = std::max(box.y_max, other.y_max);
}

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

// Bounds on a sample's central differences Δx = H(c + 1, j) − H(c − 1, j) = 2dx ∂H/∂x and
// Δy = H(c, j + 1) − H(c, j − 1), computed in float.
struct DifferenceBounds {
    float x_lo, x_hi, y_lo, y_hi;
};

// The SIMD helpers below are always inlined, so the vector calling convention that -Wpsabi warns
// about never applies.
#pragma GCC diagnostic ignored "-Wpsabi"
using Float8 = float __attribute__((vector_size(32)));
using Int8 = int __attribute__((vector_size(32)));

// Bit k set where lane k of a vector compare is true (all bits set or none): the sign bits of
// each half through SSE's movmskps.
[[gnu::always_inline]] inline unsigned lane_bits(const Int8& inside) {
    using Int4 = int __attribute__((vector_size(16)));
    const Int4 low = __builtin_shufflevector(inside, inside, 0, 1, 2, 3);
    const Int4 high = __builtin_shufflevector(inside, inside, 4, 5, 6, 7);
    return static_cast<unsigned>(_mm_movemask_ps(std::bit_cast<__m128>(low))) |
           static_cast<unsigned>(_mm_movemask_ps(std::bit_cast<__m128>(high))) << 4;
}

[[gnu::always_inline]] inline Float8 load8(const float* p) {
    Float8 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

// K = 1, second order: each kernel against its own chirped reach, |v + ξ3 H'/λ| ≤
// reach·√(1 + ε²) per axis with ε = 2πσ² ξ3 ρ(H'')/λ (gabor::chirped_reach, the sum's cut), on
// its samples' central differences Δ = 2dx H' and second differences (dx² H''), in float:
// |Δ − centre| ≤ half_width·√(1 + (curvature_scale·ρ)²). A leaf's bound, at its largest ρ, keeps
// 12–19% more kernels than this on the isotropic builtin (docs/performance.md). Float rounding is covered outward:
// Δ − centre is off by at most 2^-23 (|Δ − centre| + 2|centre|) (slack 2^-20 |centre| and the
// 2^-16 widening of half_width²); each second difference by at most 4·2^-24 of the largest step
// between neighbouring samples, so ρ by at most 6.4·2^-24 of it (Weyl's inequality with the
// error's Frobenius norm; + 2^-18 of it) and ρ's formula by 8·2^-24 ρ (× (1 + 2^-18)).
struct ChirpedDifferenceTest {
    float centre_x, centre_y;  // Δ where v + ξ3 H'/λ = 0: −2dx v/(ξ3/λ)
    float slack_x, slack_y;    // 2^-20 |centre|
    float half_width2;         // (2dx · reach/(ξ3/λ))², widened by 2^-16 and rounded up
    float curvature_scale;     // 2πσ² (ξ3/λ)/dx², rounded up: ε = curvature_scale · ρ(second differences)
};

// Elementwise helpers for float and Float8.
[[gnu::always_inline]] inline float abs_of(float x) { return std::fabs(x); }
[[gnu::always_inline]] inline float max_of(float a, float b) { return a > b ? a : b; }
[[gnu::always_inline]] inline float sqrt_of(float x) { return std::sqrt(x); }
[[gnu::always_inline]] inline Float8 abs_of(const Float8& x) { return x < 0.0f ? -x : x; }
[[gnu::always_inline]] inline Float8 max_of(const Float8& a, const Float8& b) { return a > b ? a : b; }
[[gnu::always_inline]] inline Float8 sqrt_of(const Float8& x) {
    Float8 root;
    for (int lane = 0; lane < 8; ++lane) root[lane] = std::sqrt(x[lane]);
    return root;
}

// The samples of eight kernels, columns c0 … c0 + 7 of a y-up row: H at the kernel and at its
// neighbours in rows j − 1 (down), j and j + 1 (up), columns wrapped periodically. The corners
// only at second order.
struct SampleStencil {
    Float8 mid, left, right, down, up, down_left, down_right, up_left, up_right;
};

// One row's eight kernels as every aim tests them: their samples, central differences
// Δx = H(c + 1) − H(c − 1), Δy = H(j + 1) − H(j − 1) and, second order, the bound ρ on their second
// differences' spectral radius (with its rounding slack), computed once however many aims test
// them. Lanes past the row's end hold NaN, which no test passes.
struct SampleLanes {
    SampleStencil samples;
    Float8 dx, dy, rho;
};

// ρ of the kernel at `mid` from its eight neighbours (T: float, or Float8 for eight kernels):
// the spectral radius of its second differences, rounded up (ChirpedDifferenceTest).
template <typename T>
[[gnu::always_inline]] inline T curvature_radius(const T& left, const T& mid, const T& right, const T& down,
                                                 const T& up, const T& down_left, const T& down_right,
                                                 const T& up_left, const T& up_right, float curvature_slack) {
    const T hxx = (left - mid) + (right - mid);
    const T hyy = (down - mid) + (up - mid);
    const T hxy = 0.25f * ((up_right - up_left) - (down_right - down_left));
    const T mean = 0.5f * (hxx + hyy);
    const T half_difference = 0.5f * (hxx - hyy);
    return (abs_of(mean) + sqrt_of(half_difference * half_difference + hxy * hxy)) * (1.0f + 0x1p-18f) +
           curvature_slack;
}

// The stencil of samples c0 … c0 + count − 1 (count ≤ 8); columns wrap periodically over `cols`.
// Eight at once (AVX, or two SSE halves) away from the seam. Corners only when `chirped`.
[[gnu::always_inline]] inline SampleStencil sample_stencil(const float* below, const float* row, const float* above,
                                                           int c0, int count, int cols, bool chirped) {
    SampleStencil s;
    if (c0 >= 1 && c0 + 9 <= cols && count == 8) {
        s.mid = load8(row + c0);
        s.left = load8(row + c0 - 1);
        s.right = load8(row + c0 + 1);
        s.down = load8(below + c0);
        s.up = load8(above + c0);
        if (chirped) {
            s.down_left = load8(below + c0 - 1);
            s.down_right = load8(below + c0 + 1);
            s.up_left = load8(above + c0 - 1);
            s.up_right = load8(above + c0 + 1);
        }
        return s;
    }
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int k = 0; k < 8; ++k) {
        s.mid[k] = s.left[k] = s.right[k] = s.down[k] = s.up[k] = nan;
        s.down_left[k] = s.down_right[k] = s.up_left[k] = s.up_right[k] = nan;
        if (k >= count) continue;
        const int c = c0 + k;
        const int left = c == 0 ? cols - 1 : c - 1;
        const int right = c + 1 == cols ? 0 : c + 1;
        s.mid[k] = row[c];
        s.left[k] = row[left];
        s.right[k] = row[right];
        s.down[k] = below[c];
        s.up[k] = above[c];
        if (!chirped) continue;
        s.down_left[k] = below[left];
        s.down_right[k] = below[right];
        s.up_left[k] = above[left];
        s.up_right[k] = above[right];
    }
    return s;
}

// The lanes of samples c0 … c0 + count − 1 (count ≤ 8). ρ only when `chirped`.
[[gnu::always_inline]] inline SampleLanes sample_lanes(const float* below, const float* row, const float* above,
                                                       int c0, int count, int cols, bool chirped,
                                                       float curvature_slack) {
    SampleLanes lanes;
    lanes.samples = sample_stencil(below, row, above, c0, count, cols, chirped);
    const SampleStencil& s = lanes.samples;
    lanes.dx = s.right - s.left;
    lanes.dy = s.up - s.down;
    if (chirped)
        lanes.rho = curvature_radius(s.left, s.mid, s.right, s.down, s.up, s.down_left, s.down_right, s.up_left,
                                     s.up_right, curvature_slack);
    return lanes;
}

// The lanes whose differences lie within the bounds, as bits (bit k: lane k).
[[gnu::always_inline]] inline unsigned differences_within(const SampleLanes& lanes, const DifferenceBounds& bounds) {
    return lane_bits((lanes.dx >= bounds.x_lo) & (lanes.dx <= bounds.x_hi) & (lanes.dy >= bounds.y_lo) &
                     (lanes.dy <= bounds.y_hi));
}

// The lanes whose kernels pass their own chirped reach, as bits.
[[gnu::always_inline]] inline unsigned chirped_within(const SampleLanes& lanes, const ChirpedDifferenceTest& test) {
    const Float8 epsilon = test.curvature_scale * lanes.rho;
    const Float8 limit = test.half_width2 * (1.0f + epsilon * epsilon);
    const Float8 off_x = max_of(abs_of(lanes.dx - test.centre_x) - test.slack_x, Float8{} + 0.0f);
    const Float8 off_y = max_of(abs_of(lanes.dy - test.centre_y) - test.slack_y, Float8{} + 0.0f);
    return lane_bits((off_x * off_x <= limit) & (off_y * off_y <= limit));
}

// One aim's test of a row's lanes (K = 1): its chirped test at second order where it has one,
// else its difference bounds (which keep every kernel at second order).
struct RowTest {
    DifferenceBounds bounds;
    std::optional<ChirpedDifferenceTest> chirped;
};

// The directional test at the pruning wavelength, for node boxes and single kernels.
struct DirectionalReach {
    double vx = 0.0;
    double vy = 0.0;
    double xi3_over_lambda = 0.0;
    double reach = 0.0;
    double chirp_scale = 0.0;  // second order: 2πσ_k² (first order: 0, the reach never widens)

    // The reach of kernels whose ρ(H'') is at most `radius` (gabor::chirped_reach, with the margin).
    double reach_within(double radius) const {
        return chirp_scale == 0.0 ? reach : gabor::chirped_reach(reach, chirp_scale, xi3_over_lambda, radius);
    }
    bool box_reaches(const gabor::SlopeBox& box, double reach_here) const {
        return gabor::slopes_reach(vx, vy, xi3_over_lambda, reach_here, box.x_min, box.x_max, box.y_min, box.y_max);
    }
    // The kernels of a leaf whose codes may hold a slope that reaches: v + ξ3 H'/λ ∈ [−reach,
    // reach] per axis is H' ∈ [(−reach − v)λ/ξ3, (reach − v)λ/ξ3] (ξ3 > 0).
    std::uint64_t leaf_reaches(const gabor::SlopeBox& box, const unsigned char* codes_x,
                               const unsigned char* codes_y, double reach) const {
        int first_x, span_x, first_y, span_y;
        SlopeCodec(box.x_min, box.x_max)
            .codes_of((-reach - vx) / xi3_over_lambda, (reach - vx) / xi3_over_lambda, first_x, span_x);
        SlopeCodec(box.y_min, box.y_max)
            .codes_of((-reach - vy) / xi3_over_lambda, (reach - vy) / xi3_over_lambda, first_y, span_y);
        return codes_within(codes_x, codes_y, first_x, span_x, first_y, span_y);
    }
    // The same test on the central differences of samples dx apart (K = 1): H' = Δ/(2dx). Δ is
    // rounded once in float, by at most 2^-24 of a Δ inside the bounds, so widening the bounds
    // by 2^-20 of their size and rounding them outward never drops a kernel that reaches.
    DifferenceBounds difference_bounds(double texel_um, double reach) const {
        DifferenceBounds bounds;
        const auto axis = [&](double v, float& lo, float& hi) {
            const double a = 2.0 * texel_um * (-reach - v) / xi3_over_lambda;
            const double b = 2.0 * texel_um * (reach - v) / xi3_over_lambda;
            const float inf = std::numeric_limits<float>::infinity();
            if (!(std::isfinite(a) && std::isfinite(b))) {  // ξ3 → 0: keep every kernel
                lo = -inf;
                hi = inf;
                return;
            }
            const double margin = 0x1p-20 * std::max(std::fabs(a), std::fabs(b));
            lo = a - margin < -1e30 ? -inf : round_down(std::min(a - margin, 1e30));
            hi = b + margin > 1e30 ? inf : round_up(std::max(b + margin, -1e30));
        };
        axis(vx, bounds.x_lo, bounds.x_hi);
        axis(vy, bounds.y_lo, bounds.y_hi);
        return bounds;
    }
    // Second order (K = 1): the test of each kernel against its own chirped reach, for samples dx
    // apart; none where its float constants would leave float's range (ξ3/λ → 0 or → ∞: then
    // every kernel is kept).
    std::optional<ChirpedDifferenceTest> chirped_difference_test(double texel_um) const {
        const double to_difference = 2.0 * texel_um / xi3_over_lambda;
        const double centre_x = -vx * to_difference;
        const double centre_y = -vy * to_difference;
        const double half_width = reach * to_difference;
        const double curvature_scale = chirp_scale * xi3_over_lambda / (texel_um * texel_um);
        if (!(std::fabs(centre_x) <= 1e30 && std::fabs(centre_y) <= 1e30 && half_width >= 1e-15 &&
              half_width <= 1e18 && curvature_scale <= 1e30))
            return std::nullopt;
        const double widened = half_width * (1.0 + 0x1p-17);
        return ChirpedDifferenceTest{static_cast<float>(centre_x),
                                     static_cast<float>(centre_y),
                                     round_up(0x1p-20 * std::fabs(centre_x)),
                                     round_up(0x1p-20 * std::fabs(centre_y)),
                                     round_up(widened * widened),
                                     round_up(curvature_scale)};
    }
};

// The pruning tests widen the reach by this factor, so that rounding in them (which may differ
// from the kernel sum's, e.g. by fused multiply-adds) never drops a kernel the sum keeps; the
// sum itself cuts each transform exactly.
constexpr double kReachMargin = 1.0 + 1e-9;

// A reach beyond every kernel's (difference bounds that keep them all).
constexpr double kKeepEvery = std::numeric_limits<double>::infinity();

// One direction pair's pruning tests and the kernels it collects.
struct Aim {
    DirectionalReach reach;
    gabor::KernelArrays* kernels;
    RowTest row_test;  // K = 1
};

// At most this many aims share one walk: their sets are bits of a 64-bit mask.
constexpr std::size_t kMaxAims = 64;

// A leaf's first column and the bits of its kernels that pass a row test (bit k: column c0 + k).
struct PassingLeaf {
    int c0;
    unsigned bits;
};

// K = 1: one y-up kernel row's samples (rows j − 1, j, j + 1, wrapped), its surviving leaves
// leaf_columns[0 … leaf_count) (ascending, for any aim) around the window's chord [first, last],
// and what its kernels share.
struct SampledRow {
    const float* below;
    const float* row;
    const float* above;
    int cols;
    const int* leaf_columns;
    std::size_t leaf_count;
    long long first, last;
    bool chirped;             // second order: ρ in the lanes (several aims) and H'' in the kernels
    float curvature_slack;    // ChirpedDifferenceTest
    double texel_um;
    double half_inverse_texel;  // ½/dx
    double curvature_scale;     // 1/dx²
    double centre_x;          // x_c in this tile copy
    double py;                // kernel centre y − x_c,y
    double reference_height;  // H(x_c)
    double weight_y;          // w(0, p_y) l²
    const double* weight_x;   // w(p_x, 0) of columns first_column, first_column + 1, …, padded by kLeafKernels
    long long first_column;
    PassingLeaf* passing_leaves;  // room for leaf_count (one aim's first pass)
};

// For each leaf i of `given` that the chord meets: visit(row, i, c0, chord, lanes) with a copy
// of the row, the leaf's first column c0, the chord's columns as bits (bit k: column c0 + k) and
// its samples' lanes (ρ only when `chirped`). visit() reads the row from the copy: the kernels
// it stores may alias `given`, which would reload every field after each leaf.
template <typename Visit>
[[gnu::always_inline]] inline void for_each_leaf_in_chord(const SampledRow& given, bool chirped, const Visit& visit) {
    const SampledRow row = given;
    const long long first = row.first, last = row.last;
    std::size_t leaf = 0;
    while (leaf < row.leaf_count && (row.leaf_columns[leaf] + 1LL) * kLeafKernels <= first) ++leaf;
    for (; leaf < row.leaf_count && row.leaf_columns[leaf] * static_cast<long long>(kLeafKernels) <= last; ++leaf) {
        const int c0 = row.leaf_columns[leaf] * kLeafKernels;
        // The leaf meets the chord, so fewer than kLeafKernels columns are skipped on either side.
        const int skip_left = static_cast<int>(std::max<long long>(first - c0, 0));
        const int skip_right = static_cast<int>(std::max<long long>(c0 + kLeafKernels - 1 - last, 0));
        const unsigned chord = (0xFFu << skip_left) & (0xFFu >> skip_right);
        visit(row, leaf, c0, chord,
              sample_lanes(row.below, row.row, row.above, c0, std::min(kLeafKernels, row.cols - c0), row.cols,
                           chirped, row.curvature_slack));
    }
}

using Double4 = double __attribute__((vector_size(32)));

// For each 4-bit mask, the 32-bit lanes that move the double lanes whose bits are set to the
// front, in order (lane p is the pair 2p, 2p + 1; the slots after them repeat lane 0).
constexpr std::array<std::array<int, 8>, 16> kSetLanesFirst = [] {
    std::array<std::array<int, 8>, 16> table{};
    for (int bits = 0; bits < 16; ++bits) {
        int slot = 0;
        for (int lane = 0; lane < 4; ++lane)
            if (bits >> lane & 1) {
                table[bits][2 * slot] = 2 * lane;
                table[bits][2 * slot + 1] = 2 * lane + 1;
                ++slot;
            }
    }
    return table;
}();

// v's lanes in the given order (lane k of the result is v[order[k]]): one permutation.
template <typename V, typename Order>
[[gnu::always_inline]] inline V permuted(const V& v, const Order& order) {
#if defined(__clang__)  // no variable __builtin_shuffle
    V moved;
    for (std::size_t k = 0; k < sizeof(V) / sizeof(v[0]); ++k) moved[k] = v[order[k]];
    return moved;
#else
    return __builtin_shuffle(v, order);
#endif
}

// Stores the lanes of v whose bits (4) are set to out[0 … popcount(bits)), in lane order, with one
// permutation (AVX2's vpermd) and no branch on which are set; writes out[0 … 4).
[[gnu::always_inline]] inline void store_set_lanes(const Double4& v, unsigned bits, double* __restrict out) {
    using UnalignedDouble4 = double __attribute__((vector_size(32), aligned(8)));
    Int8 order;
    std::memcpy(&order, kSetLanesFirst[bits].data(), sizeof order);
    const Int8 moved = permuted(std::bit_cast<Int8>(v), order);
    *reinterpret_cast<UnalignedDouble4*>(out) = std::bit_cast<UnalignedDouble4>(moved);
}

// The next free slots of a kernel arrays' arrays (room reserved), where a row's kernels go.
struct KernelSlots {
    double* __restrict px;
    double* __restrict py;
    double* __restrict height;
    double* __restrict slope_x;
    double* __restrict slope_y;
    double* __restrict weight;
    double* __restrict curvature_xx;
    double* __restrict curvature_xy;
    double* __restrict curvature_yy;
};

// Reserves room for `count` more kernels (and the kLeafKernels slots a store may write past
// them) and returns the slots after the last.
KernelSlots reserve_slots(gabor::KernelArrays& kernels, std::size_t count) {
    kernels.reserve_more(count + kLeafKernels);
    const std::size_t at = kernels.size();
    return {kernels.px.data() + at,           kernels.py.data() + at,           kernels.height.data() + at,
            kernels.slope_x.data() + at,      kernels.slope_y.data() + at,      kernels.weight.data() + at,
            kernels.curvature_xx.data() + at, kernels.curvature_xy.data() + at, kernels.curvature_yy.data() + at};
}

using Double8 = double __attribute__((vector_size(64)));

// Lanes 0–3 (half 0) or 4–7 (half 1) of a Float8, in double.
[[gnu::always_inline]] inline Double4 half_in_double(const Float8& v, int half) {
    const Double8 all = __builtin_convertvector(v, Double8);
    return half == 0 ? __builtin_shufflevector(all, all, 0, 1, 2, 3) : __builtin_shufflevector(all, all, 4, 5, 6, 7);
}

// Kernels of a row in the lanes of V (Double4: four, one half of a SampleStencil; Double8: a
// leaf's eight, with AVX-512) as the sum reads them (p_y is the row's).
template <typename V>
struct KernelVectors {
    V px, height, slope_x, slope_y, weight, curvature_xx, curvature_xy, curvature_yy;
};
using KernelLanes = KernelVectors<Double4>;
using WideLeafKernels = KernelVectors<Double8>;

// The kernels at columns first, first + 1, … (one per lane of V), whose samples in_double() takes
// from the stencil's lanes: p relative to x_c, H − H(x_c), H' as sample_point()'s
// (−½H(c − 1) + ½H(c + 1))/dx, computed as (H(c + 1) − H(c − 1))·(½/dx), which rounds identically
// (halving is exact), w_k l², and at second order H'' with sample_curvature()'s arithmetic. The
// same arithmetic lane for lane at either width, so the same values.
template <typename V, typename InDouble>
[[gnu::always_inline]] inline KernelVectors<V> kernel_vectors(const SampledRow& r, int first, const SampleStencil& s,
                                                              bool chirped, const InDouble& in_double) {
    KernelVectors<V> k;
    V offsets;  // 0.5, 1.5, …: the kernel centres within their texels
    for (std::size_t lane = 0; lane < sizeof(V) / sizeof(double); ++lane) offsets[lane] = double(lane) + 0.5;
    k.px = (double(first) + offsets) * r.texel_um - r.centre_x;
    const V mid = in_double(s.mid);
    const V left = in_double(s.left);
    const V right = in_double(s.right);
    const V down = in_double(s.down);
    const V up = in_double(s.up);
    k.height = mid - r.reference_height;
    k.slope_x = (right - left) * r.half_inverse_texel;
    k.slope_y = (up - down) * r.half_inverse_texel;
    std::memcpy(&k.weight, r.weight_x + (first - r.first_column), sizeof k.weight);
    k.weight *= r.weight_y;
    if (!chirped) return k;
    k.curvature_xx = (left - 2.0 * mid + right) * r.curvature_scale;
    k.curvature_yy = (down - 2.0 * mid + up) * r.curvature_scale;
    k.curvature_xy = 0.25 *
                     (in_double(s.up_right) - in_double(s.up_left) - in_double(s.down_right) +
                      in_double(s.down_left)) *
                     r.curvature_scale;
    return k;
}

// A leaf's eight kernels, columns c0 … c0 + 7, as two halves of four lanes.
struct LeafKernels {
    KernelLanes half[2];
};

[[gnu::always_inline]] inline LeafKernels leaf_kernels(const SampledRow& r, int c0, const SampleStencil& s,
                                                       bool chirped) {
    const auto half = [&](int h) __attribute__((always_inline)) {
        return kernel_vectors<Double4>(r, c0 + 4 * h, s, chirped,
                                       [h](const Float8& v) __attribute__((always_inline)) { return half_in_double(v, h); });
    };
    return {{half(0), half(1)}};
}

// With AVX-512: a leaf's eight kernels in one vector per quantity, written with one permutation
// and one store per array.
[[gnu::always_inline]] inline WideLeafKernels wide_leaf_kernels(const SampledRow& r, int c0, const SampleStencil& s,
                                                                bool chirped) {
    // Inlined, so that the conversion stays in the AVX-512 function (as in builds that inline less).
    return kernel_vectors<Double8>(r, c0, s, chirped, [](const Float8& v) __attribute__((always_inline)) {
        return __builtin_convertvector(v, Double8);
    });
}

using Int64x8 = long long __attribute__((vector_size(64)));

// For each 8-bit mask, the lanes whose bits are set, in order, then lane 0 repeated.
constexpr std::array<std::array<unsigned char, 8>, 256> kSetLanesFirst8 = [] {
    std::array<std::array<unsigned char, 8>, 256> table{};
    for (int bits = 0; bits < 256; ++bits) {
        int slot = 0;
        for (int lane = 0; lane < 8; ++lane)
            if (bits >> lane & 1) table[bits][slot++] = static_cast<unsigned char>(lane);
    }
    return table;
}();

// Writes the kernels of the lanes whose bits are set to slots[at …] in column order and returns
// how many: one eight-lane permutation per array (one instruction where the CPU has AVX-512,
// where the two halves of write_lanes below take two), writing eight slots.
[[gnu::always_inline]] inline std::size_t write_lanes(const SampledRow& r, const WideLeafKernels& k, unsigned bits,
                                                      bool chirped, const KernelSlots& slots, std::size_t at) {
    using Bytes8 = unsigned char __attribute__((vector_size(8)));
    Bytes8 packed;
    std::memcpy(&packed, kSetLanesFirst8[bits].data(), sizeof packed);
    const Int64x8 order = __builtin_convertvector(packed, Int64x8);
    const auto store = [&](const Double8& v, double* __restrict out) __attribute__((always_inline)) {
        const Double8 moved = permuted(v, order);
        std::memcpy(out, &moved, sizeof moved);
    };
    const Double8 py = Double8{} + r.py;
    std::memcpy(slots.py + at, &py, sizeof py);  // every lane the same: nothing to move
    store(k.px, slots.px + at);
    store(k.height, slots.height + at);
    store(k.slope_x, slots.slope_x + at);
    store(k.slope_y, slots.slope_y + at);
    store(k.weight, slots.weight + at);
    if (chirped) {
        store(k.curvature_xx, slots.curvature_xx + at);
        store(k.curvature_xy, slots.curvature_xy + at);
        store(k.curvature_yy, slots.curvature_yy + at);
    }
    return static_cast<std::size_t>(std::popcount(bits));
}

// A leaf's kernels as Kernels holds them.
template <typename Kernels>
[[gnu::always_inline]] inline Kernels leaf_kernels_of(const SampledRow& r, int c0, const SampleStencil& s,
                                                      bool chirped) {
    if constexpr (std::is_same_v<Kernels, WideLeafKernels>)
        return wide_leaf_kernels(r, c0, s, chirped);
    else
        return leaf_kernels(r, c0, s, chirped);
}

// Writes the kernels of the lanes whose bits are set (bit k: column c0 + k) to slots[at …], in
// column order, and returns how many; writes up to kLeafKernels slots. Four lanes are stored at
// a time and the kept ones moved to the front of each array's store, so no branch depends on
// which pass.
[[gnu::always_inline]] inline std::size_t write_lanes(const SampledRow& r, const LeafKernels& leaf, unsigned bits,
                                                      bool chirped, const KernelSlots& slots, std::size_t at) {
    const std::size_t first = at;
    for (int half = 0; half < 2; ++half) {
        const unsigned set = bits >> (4 * half) & 0xFu;
        const KernelLanes& k = leaf.half[half];
        store_set_lanes(k.px, set, slots.px + at);
        store_set_lanes(Double4{} + r.py, set, slots.py + at);
        store_set_lanes(k.height, set, slots.height + at);
        store_set_lanes(k.slope_x, set, slots.slope_x + at);
        store_set_lanes(k.slope_y, set, slots.slope_y + at);
        store_set_lanes(k.weight, set, slots.weight + at);
        if (chirped) {
            store_set_lanes(k.curvature_xx, set, slots.curvature_xx + at);
            store_set_lanes(k.curvature_xy, set, slots.curvature_xy + at);
            store_set_lanes(k.curvature_yy, set, slots.curvature_yy + at);
        }
        at += static_cast<std::size_t>(std::popcount(set));
    }
    return at - first;
}

// K = 1, one aim: appends the row's kernels that pass `passes` (lanes → bits) to `kernels`;
// returns how many. First every leaf is tested and those with passing kernels listed without a
// branch on the outcome (a branch at the end of the test's long chain of arithmetic would be
// mispredicted for about a quarter of the leaves); then the listed leaves' kernels are written
// from their samples, loaded again.
template <typename Kernels, typename Passes>
[[gnu::always_inline]] inline std::size_t append_passing(const SampledRow& row, bool chirped, const Passes& passes,
                                                         gabor::KernelArrays& kernels) {
    PassingLeaf* const passing = row.passing_leaves;
    std::size_t listed = 0;
    for_each_leaf_in_chord(row, chirped, [&](const SampledRow&, std::size_t, int c0, unsigned chord,
                                             const SampleLanes& lanes) {
        const unsigned bits = chord & passes(lanes);
        passing[listed] = {c0, bits};
        listed += bits != 0;
    });
    const KernelSlots slots = reserve_slots(kernels, row.leaf_count * kLeafKernels);
    const SampledRow r = row;  // a copy, which the kernels' stores cannot alias
    std::size_t count = 0;
    for (std::size_t k = 0; k < listed; ++k) {
        const int c0 = passing[k].c0;
        const SampleStencil samples =
            sample_stencil(r.below, r.row, r.above, c0, std::min(kLeafKernels, r.cols - c0), r.cols, chirped);
        count += write_lanes(r, leaf_kernels_of<Kernels>(r, c0, samples, chirped), passing[k].bits, chirped, slots,
                             count);
    }
    kernels.extend(count);
    return count;
}

// append_passing compiled for each kind of test alone: difference bounds, and (second order) each
// kernel's own chirped reach; Kernels: WideLeafKernels (AVX-512 only) or LeafKernels. The tests
// are taken by value, so that the kernels' stores cannot alias them.
template <typename Kernels>
[[gnu::always_inline]] inline std::size_t append_bounded(const SampledRow& row, const DifferenceBounds& bounds,
                                                         gabor::KernelArrays& kernels) {
    const auto passes = [&](const SampleLanes& lanes) { return differences_within(lanes, bounds); };
    return row.chirped ? append_passing<Kernels>(row, true, passes, kernels)
                       : append_passing<Kernels>(row, false, passes, kernels);
}

template <typename Kernels>
[[gnu::always_inline]] inline std::size_t append_chirped(const SampledRow& row, const ChirpedDifferenceTest& test,
                                                         gabor::KernelArrays& kernels) {
    return append_passing<Kernels>(row, true, [&](const SampleLanes& lanes) { return chirped_within(lanes, test); },
                                   kernels);
}

GLINTSCOPE_OUT_OF_LINE_CLONES
std::size_t append_row_survivors(const SampledRow& row, const DifferenceBounds bounds, gabor::KernelArrays& kernels) {
    return append_bounded<LeafKernels>(row, bounds, kernels);
}

GLINTSCOPE_AVX512
std::size_t append_row_survivors_avx512(const SampledRow& row, const DifferenceBounds bounds,
                                        gabor::KernelArrays& kernels) {
    return append_bounded<WideLeafKernels>(row, bounds, kernels);
}

GLINTSCOPE_OUT_OF_LINE_CLONES
std::size_t append_chirped_row_survivors(const SampledRow& row, const ChirpedDifferenceTest test,
                                         gabor::KernelArrays& kernels) {
    return append_chirped<LeafKernels>(row, test, kernels);
}

GLINTSCOPE_AVX512
std::size_t append_chirped_row_survivors_avx512(const SampledRow& row, const ChirpedDifferenceTest test,
                                                gabor::KernelArrays& kernels) {
    return append_chirped<WideLeafKernels>(row, test, kernels);
}

// K = 1, several aims at once: each leaf's lanes once, then for each aim a of leaf_aims[leaf]
// the kernels that pass aims[a].row_test, appended to its kernels; returns how many in all.
// Kernels: a leaf's kernels as WideLeafKernels (AVX-512 only) or as LeafKernels' two halves.
template <typename Kernels>
[[gnu::always_inline]] inline std::size_t append_survivors_of_aims(const SampledRow& row, const std::uint64_t* leaf_aims,
                                                                   const Aim* aims, std::size_t aim_count) {
    std::array<KernelSlots, kMaxAims> slots;
    std::array<std::size_t, kMaxAims> counts{};
    for (std::size_t a = 0; a < aim_count; ++a) slots[a] = reserve_slots(*aims[a].kernels, row.leaf_count * kLeafKernels);
    // The leaf's kernels are computed once, when the first aim keeps one of them, and written for
    // every aim that keeps some.
    const auto test_leaf = [&](const SampledRow& r, std::size_t leaf, int c0, unsigned chord, const SampleLanes& lanes)
                               __attribute__((always_inline)) {
        Kernels kernels;
        bool computed = false;
        for (std::uint64_t left = leaf_aims[leaf]; left != 0; left &= left - 1) {
            const int a = std::countr_zero(left);
            const RowTest& test = aims[a].row_test;
            const unsigned bits =
                chord & (test.chirped ? chirped_within(lanes, *test.chirped) : differences_within(lanes, test.bounds));
            if (bits == 0) continue;
            if (!computed) {
                kernels = leaf_kernels_of<Kernels>(r, c0, lanes.samples, r.chirped);
                computed = true;
            }
            counts[a] += write_lanes(r, kernels, bits, r.chirped, slots[a], counts[a]);
        }
    };
    for_each_leaf_in_chord(row, row.chirped, test_leaf);
    std::size_t appended = 0;
    for (std::size_t a = 0; a < aim_count; ++a) {
        aims[a].kernels->extend(counts[a]);
        appended += counts[a];
    }
    return appended;
}

GLINTSCOPE_OUT_OF_LINE_CLONES
std::size_t append_row_survivors(const SampledRow& row, const std::uint64_t* leaf_aims, const Aim* aims,
                                 std::size_t aim_count) {
    return append_survivors_of_aims<LeafKernels>(row, leaf_aims, aims, aim_count);
}

GLINTSCOPE_AVX512
std::size_t append_row_survivors_avx512(const SampledRow& row, const std::uint64_t* leaf_aims, const Aim* aims,
                                        std::size_t aim_count) {
    return append_survivors_of_aims<WideLeafKernels>(row, leaf_aims, aims, aim_count);
}

// The directions of one walk, the Collector's policy. OneAim: a single direction (every render
// and eval), tested directly: a node or leaf is kept for it or not (Mask 1 or 0), with no loop
// over aims. SeveralAims: up to kMaxAims directions (light sweeps): each node and leaf carries
// the set of aims it may reach as bits of a mask, and each test runs over that set.
class OneAim {
public:
    using Mask = unsigned char;
    explicit OneAim(const Aim& aim) : aim_(aim) {}
    std::size_t size() const { return 1; }
    Mask every() const { return 1; }
    // The aims in `within` for which reaches(aim) holds.
    template <typename Reaches>
    Mask reaching(Mask, const Reaches& reaches) const {
        return reaches(aim_.reach);
    }
    template <typename Visit>
    void for_each(Mask, const Visit& visit) {
        visit(aim_);
    }
    // K = 1: appends the row's kernels that pass the aim's test to its kernels; returns how many.
    std::size_t append_survivors(const SampledRow& row, const Mask*) const {
        const RowTest& test = aim_.row_test;
        if (cpu_runs_avx512())
            return test.chirped ? append_chirped_row_survivors_avx512(row, *test.chirped, *aim_.kernels)
                                : append_row_survivors_avx512(row, test.bounds, *aim_.kernels);
        return test.chirped ? append_chirped_row_survivors(row, *test.chirped, *aim_.kernels)
                            : append_row_survivors(row, test.bounds, *aim_.kernels);
    }

private:
    Aim aim_;  // held here, not behind a pointer, so the walk reads its reach directly
};

class SeveralAims {
public:
    using Mask = std::uint64_t;  // bit a: aims[a]
    explicit SeveralAims(std::vector<Aim>& aims) : aims_(aims) {}
    std::size_t size() const { return aims_.size(); }
    Mask every() const { return aims_.size() == kMaxAims ? ~Mask{0} : (Mask{1} << aims_.size()) - 1; }
    template <typename Reaches>
    Mask reaching(Mask within, const Reaches& reaches) const {
        Mask reached = 0;
        for (; within != 0; within &= within - 1)
            if (reaches(aims_[std::countr_zero(within)].reach)) reached |= within & -within;
        return reached;
    }
    template <typename Visit>
    void for_each(Mask within, const Visit& visit) const {
        for (; within != 0; within &= within - 1) visit(aims_[std::countr_zero(within)]);
    }
    // K = 1: appends to each aim's kernels the row's kernels that pass its test; returns how many in all.
    std::size_t append_survivors(const SampledRow& row, const Mask* leaf_aims) const {
        if (cpu_runs_avx512()) return append_row_survivors_avx512(row, leaf_aims, aims_.data(), aims_.size());
        return append_row_survivors(row, leaf_aims, aims_.data(), aims_.size());
    }

private:
    std::vector<Aim>& aims_;
};

// w(p) = w(p_x, 0)·w(0, p_y) for both footprints: its factors at the kernel columns and rows
// around one footprint centre, tabulated once per query instead of once per kernel. kPadding
// zeros on either side let a leaf's eight columns be read at once wherever the chord meets it.
class SeparableWeights {
public:
    static constexpr long long kPadding = kLeafKernels;
    void tabulate(const gabor::CoherenceWindow& window, const gabor::KernelGrid& grid, double cx, double cy) {
        tabulate_axis(window, grid, cx, window.half_extent_um().x, first_column_, columns_);
        tabulate_axis(window, grid, cy, window.half_extent_um().y, first_row_, rows_);
    }
    double along_x(long long i) const { return columns_[kPadding + i - first_column_]; }
    // along_x of first_column(), first_column() + 1, …, valid from kPadding columns before the first.
    const double* columns() const { return columns_.data() + kPadding; }
    long long first_column() const { return first_column_; }
    double along_y(long long j) const { return rows_[kPadding + j - first_row_]; }

private:
    static void tabulate_axis(const gabor::CoherenceWindow& window, const gabor::KernelGrid& grid, double centre,
                              double extent, long long& first, std::vector<double>& padded) {
        first = static_cast<long long>(std::floor((centre - extent) / grid.spacing_um - 0.5));
        const long long last = static_cast<long long>(std::ceil((centre + extent) / grid.spacing_um - 0.5));
        padded.assign(last - first + 1 + 2 * kPadding, 0.0);
        double* const factors = padded.data() + kPadding;
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
        for (long long i = 0; i <= last - first; ++i) {
            factors[i] = w;
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
    const Footprint& footprint = query.footprint;
    const double smallest = box ? std::min(box_width_um(footprint), box_height_um(footprint)) : footprint.sigma_um;
    const double largest = box ? std::max(box_width_um(footprint), box_height_um(footprint)) : footprint.sigma_um;
    if (!(smallest > 0.0 && largest <= 1e5)) throw Error("gabor: point query footprint size must be positive and finite");
}

}  // namespace

namespace {

void build_leaves(const BicubicInterpolant& surface, const GaborSettings& settings, gabor::Hierarchy& h) {
    const gabor::KernelGrid grid = gabor::kernel_grid(surface.texel_um(), settings);
    gabor::Level leaves;
    leaves.nx = (h.kernels_x + kLeafKernels - 1) / kLeafKernels;
    leaves.ny = (h.kernels_y + kLeafKernels - 1) / kLeafKernels;
    leaves.boxes.resize(static_cast<std::size_t>(leaves.nx) * leaves.ny);
    // With K = 1 the kernels' H' are central differences of samples, as cheap to test as codes.
    const bool coded = settings.kernels_per_texel > 1;
    if (coded) h.leaf_codes.resize(leaves.boxes.size());
    const bool chirped = settings.order == 2;
    if (chirped) leaves.curvature_radii.resize(leaves.boxes.size());
    // One row of leaves per chunk: interpolate its kLeafKernels rows of kernels in one grid call.
    parallel_for(leaves.ny, 1, [&](std::size_t begin, std::size_t end) {
        std::vector<SurfacePoint> points(static_cast<std::size_t>(h.kernels_x) * kLeafKernels);
        for (std::size_t leaf_row = begin; leaf_row < end; ++leaf_row) {
            const int j0 = static_cast<int>(leaf_row) * kLeafKernels;
            const int rows = std::min(kLeafKernels, h.kernels_y - j0);
            gabor::evaluate_kernels(surface, grid, 0, j0, h.kernels_x, rows, points.data());
            for (int leaf_col = 0; leaf_col < leaves.nx; ++leaf_col) {
                double x_min = std::numeric_limits<double>::infinity();
                double x_max = -x_min;
                double y_min = x_min;
                double y_max = -x_min;
                const int i0 = leaf_col * kLeafKernels;
                const int i1 = std::min(h.kernels_x, i0 + kLeafKernels);
                for (int j = 0; j < rows; ++j)
                    for (int i = i0; i < i1; ++i) {
                        const SurfacePoint& p = points[static_cast<std::size_t>(j) * h.kernels_x + i];
                        x_min = std::min(x_min, p.dh_dx);
                        x_max = std::max(x_max, p.dh_dx);
                        y_min = std::min(y_min, p.dh_dy);
                        y_max = std::max(y_max, p.dh_dy);
                    }
                const gabor::SlopeBox box{round_down(x_min), round_up(x_max), round_down(y_min), round_up(y_max)};
                leaves.boxes[leaf_row * leaves.nx + leaf_col] = box;
                if (chirped) {
                    double radius = 0.0;
                    for (int j = j0; j < j0 + rows; ++j)
                        for (int i = i0; i < i1; ++i) {
                            const SurfaceCurvature c = gabor::kernel_curvature(surface, grid, i, j);
                            radius = std::max(radius, gabor::spectral_radius(c.d2h_dx2, c.d2h_dxdy, c.d2h_dy2));
                        }
                    leaves.curvature_radii[leaf_row * leaves.nx + leaf_col] = round_up(radius);
                }
                if (!coded) continue;
                const SlopeCodec codec_x(box.x_min, box.x_max);
                const SlopeCodec codec_y(box.y_min, box.y_max);
                gabor::LeafCodes& codes = h.leaf_codes[leaf_row * leaves.nx + leaf_col];
                std::fill(std::begin(codes.x), std::end(codes.x), 0);
                std::fill(std::begin(codes.y), std::end(codes.y), 0);
                for (int j = 0; j < rows; ++j)
                    for (int i = i0; i < i1; ++i) {
                        const SurfacePoint& p = points[static_cast<std::size_t>(j) * h.kernels_x + i];
                        codes.x[j * kLeafKernels + i - i0] = codec_x.code(p.dh_dx);
                        codes.y[j * kLeafKernels + i - i0] = codec_y.code(p.dh_dy);
                    }
            }
        }
    });
    h.levels.push_back(std::move(leaves));
}

// The largest |H(c + 1, j) − H(c, j)| and |H(c, j + 1) − H(c, j)| over the samples, wrapped
// periodically, rounded up (the differences of floats are exact in double).
float largest_step(const BicubicInterpolant& surface) {
    const int rows = surface.rows();
    const int cols = surface.cols();
    std::vector<double> row_largest(rows, 0.0);
    parallel_for(rows, 64, [&](std::size_t begin, std::size_t end) {
        for (std::size_t j = begin; j < end; ++j) {
            const float* row = surface.sample_row(static_cast<int>(j));
            const float* above = surface.sample_row(j + 1 == std::size_t(rows) ? 0 : static_cast<int>(j) + 1);
            double largest = 0.0;
            for (int c = 0; c < cols; ++c) {
                const double here = row[c];
                largest = std::max({largest, std::fabs(double(row[c + 1 == cols ? 0 : c + 1]) - here),
                                    std::fabs(double(above[c]) - here)});
            }
            row_largest[j] = largest;
        }
    });
    return round_up(*std::max_element(row_largest.begin(), row_largest.end()));
}

void build_parents(gabor::Hierarchy& h) {
    while (h.levels.back().nx > 1 || h.levels.back().ny > 1) {
        const gabor::Level& child = h.levels.back();
        gabor::Level parent;
        parent.nx = (child.nx + 1) / 2;
        parent.ny = (child.ny + 1) / 2;
        parent.boxes.assign(static_cast<std::size_t>(parent.nx) * parent.ny, empty_box());
        const bool chirped = !child.curvature_radii.empty();
        if (chirped) parent.curvature_radii.assign(parent.boxes.size(), 0.0f);
        for (int j = 0; j < child.ny; ++j)
            for (int i = 0; i < child.nx; ++i) {
                const std::size_t to = static_cast<std::size_t>(j / 2) * parent.nx + i / 2;
                const std::size_t from = static_cast<std::size_t>(j) * child.nx + i;
                include(parent.boxes[to], child.boxes[from]);
                if (chirped)
                    parent.curvature_radii[to] = std::max(parent.curvature_radii[to], child.curvature_radii[from]);
            }
        h.levels.push_back(std::move(parent));
    }
}

}  // namespace

GaborSurface::GaborSurface(std::shared_ptr<const BicubicInterpolant> surface, GaborSettings settings)
    : surface_(std::move(surface)), settings_(settings) {
    if (!surface_) throw Error("gabor: GaborSurface needs a heightfield interpolant");
    // The pipeline resamples rectangular texels for gabor (MethodInfo::needs_square_texels).
    if (!surface_->square_texels()) throw Error("gabor: GaborSurface needs square texels (make_texels_square)");
    validate(settings_);
    auto hierarchy = std::make_shared<gabor::Hierarchy>();
    hierarchy->kernels_x = surface_->cols() * settings_.kernels_per_texel;
    hierarchy->kernels_y = surface_->rows() * settings_.kernels_per_texel;
    // 2 bytes of codes per kernel and 16 bytes of bounds per leaf of kLeafKernels² kernels: 2^29
    // kernels take 1.2 GB.
    if (double(hierarchy->kernels_x) * hierarchy->kernels_y > 536870912.0)
        throw Error("gabor: " + std::to_string(surface_->cols()) + "x" + std::to_string(surface_->rows()) +
                    " heightfield at " + std::to_string(settings_.kernels_per_texel) +
                    " kernels per texel exceeds 2^29 kernels; use fewer kernels_per_texel");
    build_leaves(*surface_, settings_, *hierarchy);
    if (settings_.kernels_per_texel == 1 && settings_.order == 2) hierarchy->largest_step = largest_step(*surface_);
    build_parents(*hierarchy);
    hierarchy_ = std::move(hierarchy);
}

std::size_t GaborSurface::memory_bytes() const {
    const gabor::Hierarchy& h = *hierarchy_;
    std::size_t bytes = sizeof(*this) + sizeof(h) + h.leaf_codes.capacity() * sizeof(gabor::LeafCodes);
    for (const gabor::Level& level : h.levels)
        bytes += level.boxes.capacity() * sizeof(gabor::SlopeBox) + level.curvature_radii.capacity() * sizeof(float);
    return bytes;
}

namespace {

// A hierarchy node of one level and the aims (a Mask of the walk's policy) whose reach it may hold.
template <typename Mask>
struct NodeAims {
    int column, row;
    Mask aims;
};

// Scratch space of the collector, kept per thread across queries so that a query allocates
// nothing once warm.
template <typename Mask>
struct CollectScratch {
    std::vector<NodeAims<Mask>> nodes;  // one level's nodes
    std::vector<NodeAims<Mask>> children;
    std::vector<Mask> leaf_map;              // over the footprint's leaves: the aims it survives for
    std::vector<int> leaf_columns;           // the surviving leaves of one leaf row (for any aim)
    std::vector<PassingLeaf> passing_leaves;  // parallel to leaf_columns: K = 1, one aim's passing leaves
    std::vector<Mask> leaf_aims;             // parallel to leaf_columns
    std::vector<SurfacePoint> block;
    SeparableWeights weights;
};

// The leaves [x0, x1] × [y0, y1] that may hold kernels of the footprint in one tile copy.
struct LeafRange {
    int x0, x1, y0, y1;
    int width() const { return x1 - x0 + 1; }
};

// The pruning tests of one direction pair at the pruning wavelength.
DirectionalReach directional_reach(const GaborPointQuery& query, double lambda_um, const gabor::KernelGrid& grid) {
    const Vec3 psi = query.omega_i + query.omega_o;
    return {psi.x / lambda_um, psi.y / lambda_um, xi3(query.model, query.omega_i, query.omega_o) / lambda_um,
            grid.reach * kReachMargin, grid.order == 2 ? grid.chirp_scale : 0.0};
}

}  // namespace

// One footprint's walk (Yan 2018 §5) for the direction pairs of Aims (OneAim or SeveralAims):
// for each tile copy the footprint overlaps, find the leaves that survive pruning for any of
// them, then append to each pair's kernels those of its leaves that survive its tests. What
// depends only on the footprint (the window, its chords and weights, the tiles and the walk's
// nodes) is done once; each pair's kernels are exactly, and in the same order, those a walk for
// it alone appends.
template <typename Aims>
struct GaborSurface::Collector {
    using Mask = typename Aims::Mask;
    const GaborSurface& surface;
    const gabor::KernelGrid grid;
    const gabor::CoherenceWindow window;
    const bool sampled;  // K = 1: the kernels are the samples
    const bool chirped;  // second order: each node's reach widens with its curvature radius
    Aims aims;
    const Point2 centre;
    const double reference_height;
    const double weight_scale;
    const Point2 extent;
    // K = 1, second order: the rounding slack of ρ, 2^-18 of the largest step between
    // neighbouring samples (ChirpedDifferenceTest).
    const float curvature_slack;
    CollectScratch<Mask>& scratch;
    GaborQueryStatistics counts;

    // `pairs` holds the pairs' reaches and kernels; their row tests are set here.
    Collector(const GaborSurface& surface, const Footprint& footprint, Aims pairs, CollectScratch<Mask>& scratch)
        : surface(surface),
          grid(gabor::kernel_grid(surface.surface_->texel_um(), surface.settings_)),
          window(footprint, surface.settings_.footprint_sigmas),
          sampled(grid.kernels_per_texel == 1),
          chirped(grid.order == 2),
          aims(pairs),
          centre(footprint.centre_um),
          reference_height(surface.surface_->height(centre.x, centre.y)),
          weight_scale(grid.spacing_um * grid.spacing_um),
          extent(window.half_extent_um()),
          curvature_slack(round_up(0x1p-18 * double(surface.hierarchy_->largest_step))),
          scratch(scratch) {
        window.check_kernel_count(grid);
        if (!sampled) return;
        // Of every kernel at first order (all kept when chirped); second order: each kernel's own reach.
        aims.for_each(aims.every(), [&](Aim& aim) {
            aim.row_test = {aim.reach.difference_bounds(grid.spacing_um, chirped ? kKeepEvery : aim.reach.reach),
                            chirped ? aim.reach.chirped_difference_test(grid.spacing_um) : std::nullopt};
        });
    }

    // The directional reach of a node for one aim: widened by its curvature radius at second order.
    double node_reach(const DirectionalReach& reach, const gabor::Level& level, std::size_t index) const {
        return chirped ? reach.reach_within(level.curvature_radii[index]) : reach.reach;
    }

    bool leaf_range(double cx, double cy, LeafRange& range) const {
        const auto axis = [&](double c, double reach, int count, int& first, int& last) {
            const double from = std::max(0.0, std::floor((c - reach) / grid.spacing_um - 0.5));
            const double to = std::min(count - 1.0, std::ceil((c + reach) / grid.spacing_um - 0.5));
            first = static_cast<int>(std::min(from, count - 1.0)) / kLeafKernels;
            last = static_cast<int>(std::max(to, 0.0)) / kLeafKernels;
            return from <= to;
        };
        return axis(cx, extent.x, surface.hierarchy_->kernels_x, range.x0, range.x1) &&
               axis(cy, extent.y, surface.hierarchy_->kernels_y, range.y0, range.y1);
    }

    // K = 1 reads the samples of the footprint's rows (and one more on each side), a few cache
    // lines per row: those come from outer caches one by one unless asked for ahead of time, a
    // couple of leaf rows ahead so that they arrive while earlier rows are processed.
    static constexpr int kPrefetchLeafRows = 2;
    void prefetch_samples(const LeafRange& range, int leaf_row) const {
        if (leaf_row > range.y1) return;
        const int c0 = std::max(0, range.x0 * kLeafKernels - 1);
        const int c1 = std::min(surface.hierarchy_->kernels_x, (range.x1 + 1) * kLeafKernels + 1);
        const int j0 = leaf_row * kLeafKernels + (leaf_row == range.y0 ? -1 : 1);
        const int j1 = (leaf_row + 1) * kLeafKernels + 1;
        for (int j = j0; j < j1; ++j) {
            const float* row = surface.surface_->sample_row((j + surface.hierarchy_->kernels_y) % surface.hierarchy_->kernels_y);
            for (int c = c0; c < c1; c += 16) __builtin_prefetch(row + c);
            __builtin_prefetch(row + c1 - 1);
        }
    }

    bool node_overlaps(double cx, double cy, int level, int ix, int iy) const {
        const int span = kLeafKernels << level;  // kernels per node side
        const int i0 = ix * span;
        const int j0 = iy * span;
        const int i1 = std::min(surface.hierarchy_->kernels_x, i0 + span);
        const int j1 = std::min(surface.hierarchy_->kernels_y, j0 + span);
        return window.overlaps(grid.centre(i0) - cx, grid.centre(i1 - 1) - cx, grid.centre(j0) - cy,
                               grid.centre(j1 - 1) - cy);
    }

    // The finest level on which the footprint spans at most 16 × 16 nodes: testing those directly
    // is cheaper than descending to them.
    int start_level(const LeafRange& range) const {
        const auto nodes_spanned = [&](int level) {
            return ((range.x1 >> level) - (range.x0 >> level) + 1) * ((range.y1 >> level) - (range.y0 >> level) + 1);
        };
        int start = 0;
        while (start + 1 < static_cast<int>(surface.hierarchy_->levels.size()) && nodes_spanned(start) > 16 * 16) ++start;
        return start;
    }

    // Yan 2018 §5: down the hierarchy, dropping nodes outside the footprint or whose directional
    // box cannot reach the query; the survivors are marked in leaf_map. The walk goes level by
    // level so that the bounds of a level's nodes are fetched from memory together.
    void find_leaves(double cx, double cy, const LeafRange& range) {
        scratch.leaf_map.assign(static_cast<std::size_t>(range.width()) * (range.y1 - range.y0 + 1), 0);
        const int start = start_level(range);
        scratch.nodes.clear();
        for (int iy = range.y0 >> start; iy <= range.y1 >> start; ++iy)
            for (int ix = range.x0 >> start; ix <= range.x1 >> start; ++ix)
                if (node_overlaps(cx, cy, start, ix, iy)) scratch.nodes.push_back({ix, iy, aims.every()});
        for (int level_index = start; level_index >= 0; --level_index) {
            scratch.children.clear();
            for (const NodeAims<Mask>& node : scratch.nodes) visit_node(cx, cy, range, level_index, node);
            std::swap(scratch.nodes, scratch.children);
        }
    }

    // A node that reaches some of its aims: a leaf is marked with them, a parent's overlapping
    // children are queued with them.
    void visit_node(double cx, double cy, const LeafRange& range, int level_index, const NodeAims<Mask>& node) {
        const int ix = node.column, iy = node.row;
        const gabor::Level& level = surface.hierarchy_->levels[level_index];
        ++counts.nodes_visited;
        const std::size_t index = static_cast<std::size_t>(iy) * level.nx + ix;
        const Mask reached = aims.reaching(node.aims, [&](const DirectionalReach& reach) {
            return reach.box_reaches(level.boxes[index], node_reach(reach, level, index));
        });
        if (reached == 0) return;
        if (level_index == 0) {
            scratch.leaf_map[static_cast<std::size_t>(iy - range.y0) * range.width() + (ix - range.x0)] = reached;
            if (!sampled) {
                __builtin_prefetch(&surface.hierarchy_->leaf_codes[index]);
                __builtin_prefetch(reinterpret_cast<const char*>(&surface.hierarchy_->leaf_codes[index]) + 64);
            }
            return;
        }
        const gabor::Level& below = surface.hierarchy_->levels[level_index - 1];
        const int shift = level_index - 1;
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const int child_x = 2 * ix + dx;
                const int child_y = 2 * iy + dy;
                if (child_x < range.x0 >> shift || child_x > range.x1 >> shift || child_y < range.y0 >> shift ||
                    child_y > range.y1 >> shift || !node_overlaps(cx, cy, shift, child_x, child_y))
                    continue;
                scratch.children.push_back({child_x, child_y, reached});
                __builtin_prefetch(&below.boxes[static_cast<std::size_t>(child_y) * below.nx + child_x]);
            }
    }

    // K = 1: for each aim, the kernels of its surviving leaves inside the window's chord [first,
    // last] on kernel row j, tested on their samples' central differences (computed once for all
    // aims); each leaf's survivors go straight into the aim's kernel arrays, eight lanes computed
    // at once and the kept ones moved together, so that no branch depends on which kernels
    // survive (write_lanes; with one aim after all the row's leaves are tested, append_passing).
    void add_sampled_row(double cx, double cy, int j, long long first, long long last) {
        const int rows = surface.hierarchy_->kernels_y;
        const SampledRow row{surface.surface_->sample_row(j == 0 ? rows - 1 : j - 1),
                             surface.surface_->sample_row(j),
                             surface.surface_->sample_row(j + 1 == rows ? 0 : j + 1),
                             surface.hierarchy_->kernels_x,
                             scratch.leaf_columns.data(),
                             scratch.leaf_columns.size(),
                             first,
                             last,
                             chirped,
                             curvature_slack,
                             grid.spacing_um,
                             0.5 / grid.spacing_um,
                             1.0 / (grid.spacing_um * grid.spacing_um),
                             cx,
                             grid.centre(j) - cy,
                             reference_height,
                             scratch.weights.along_y(j) * weight_scale,
                             scratch.weights.columns(),
                             scratch.weights.first_column(),
                             scratch.passing_leaves.data()};
        counts.kernels_evaluated += aims.append_survivors(row, scratch.leaf_aims.data());
    }

    // K > 1: per surviving leaf, the kernels inside the window whose codes may reach; the leaf's
    // block of the kernel grid is interpolated once if any are left.
    void add_coded_leaf(double cx, double cy, int leaf_row, int leaf_column, Mask leaf_aims,
                        const long long* first, const long long* last) {
        const int i0 = leaf_column * kLeafKernels;
        const int j0 = leaf_row * kLeafKernels;
        const int nx = std::min(kLeafKernels, surface.hierarchy_->kernels_x - i0);
        const int ny = std::min(kLeafKernels, surface.hierarchy_->kernels_y - j0);
        std::uint64_t inside = 0;  // kernels of the leaf that the window contains
        for (int j = 0; j < ny; ++j) {
            const long long from = std::max<long long>(first[j], i0);
            const long long to = std::min<long long>(last[j], i0 + kLeafKernels - 1);
            if (from > to) continue;
            const std::uint64_t run = (std::uint64_t{2} << (to - from)) - 1;
            inside |= run << (j * kLeafKernels + (from - i0));
        }
        if (inside == 0) return;
        const std::size_t index = static_cast<std::size_t>(leaf_row) * surface.hierarchy_->levels.front().nx + leaf_column;
        const gabor::LeafCodes& codes = surface.hierarchy_->leaf_codes[index];
        const gabor::Level& leaves = surface.hierarchy_->levels.front();
        bool evaluated = false;  // the leaf's block, interpolated for the first aim that needs it
        aims.for_each(leaf_aims, [&](const Aim& aim) {
            std::uint64_t bits =
                inside & aim.reach.leaf_reaches(leaves.boxes[index], codes.x, codes.y, node_reach(aim.reach, leaves, index));
            if (bits == 0) return;
            if (!evaluated) {
                scratch.block.resize(static_cast<std::size_t>(kLeafKernels) * kLeafKernels);
                gabor::evaluate_kernels(*surface.surface_, grid, i0, j0, nx, ny, scratch.block.data());
                evaluated = true;
            }
            counts.kernels_evaluated += static_cast<std::size_t>(nx) * ny;
            gabor::KernelArrays& kernels = *aim.kernels;
            for (; bits != 0; bits &= bits - 1) {
                const int k = std::countr_zero(bits);
                const int i = i0 + k % kLeafKernels;
                const int j = j0 + k / kLeafKernels;
                kernels.push(grid.centre(i) - cx, grid.centre(j) - cy,
                             scratch.block[static_cast<std::size_t>(k / kLeafKernels) * nx + k % kLeafKernels],
                             reference_height, scratch.weights.along_x(i) * scratch.weights.along_y(j) * weight_scale);
                if (chirped)
                    kernels.set_curvature(kernels.size() - 1, gabor::kernel_curvature(*surface.surface_, grid, i, j));
            }
        });
    }

    // One leaf row's surviving leaves (leaf_columns, ascending): the window's chord on each of its
    // kernel rows over their span, then the kernels.
    void add_leaf_row(double cx, double cy, int leaf_row) {
        const std::vector<int>& leaf_columns = scratch.leaf_columns;
        const int j0 = leaf_row * kLeafKernels;
        const int j1 = std::min(surface.hierarchy_->kernels_y, j0 + kLeafKernels);
        const int i0 = leaf_columns.front() * kLeafKernels;
        const int i1 = std::min(surface.hierarchy_->kernels_x, (leaf_columns.back() + 1) * kLeafKernels);
        long long first[kLeafKernels];
        long long last[kLeafKernels];
        for (int j = j0; j < j1; ++j)
            if (!window.row_span(grid, cx, grid.centre(j) - cy, i0, i1 - 1, first[j - j0], last[j - j0])) {
                first[j - j0] = i1;
                last[j - j0] = i1 - 1;
            }
        if (sampled) {
            scratch.passing_leaves.resize(leaf_columns.size());
            for (int j = j0; j < j1; ++j)
                if (first[j - j0] <= last[j - j0]) add_sampled_row(cx, cy, j, first[j - j0], last[j - j0]);
            return;
        }
        const std::size_t most = leaf_columns.size() * kLeafKernels * kLeafKernels;
        aims.for_each(aims.every(), [&](const Aim& aim) { aim.kernels->reserve_more(most); });
        for (std::size_t k = 0; k < leaf_columns.size(); ++k)
            add_coded_leaf(cx, cy, leaf_row, leaf_columns[k], scratch.leaf_aims[k], first, last);
    }

    // The footprint centre expressed in one tile copy's coordinates (cx, cy): its leaves.
    void add_tile_copy(double cx, double cy) {
        LeafRange range;
        if (!leaf_range(cx, cy, range)) return;
        if (sampled)
            for (int ahead = 0; ahead < kPrefetchLeafRows; ++ahead) prefetch_samples(range, range.y0 + ahead);
        scratch.weights.tabulate(window, grid, cx, cy);
        find_leaves(cx, cy, range);
        for (int leaf_row = range.y0; leaf_row <= range.y1; ++leaf_row) {
            if (sampled) prefetch_samples(range, leaf_row + kPrefetchLeafRows);
            scratch.leaf_columns.clear();
            scratch.leaf_aims.clear();
            const Mask* marks =
                &scratch.leaf_map[static_cast<std::size_t>(leaf_row - range.y0) * range.width()];
            for (int k = 0; k < range.width(); ++k)
                if (marks[k]) {
                    scratch.leaf_columns.push_back(range.x0 + k);
                    scratch.leaf_aims.push_back(marks[k]);
                }
            if (!scratch.leaf_columns.empty()) add_leaf_row(cx, cy, leaf_row);
        }
    }

    // The surface tiles periodically: visit every tile copy the footprint overlaps.
    void add_tile_copies() {
        const double tile_x = surface.hierarchy_->kernels_x * grid.spacing_um;
        const double tile_y = surface.hierarchy_->kernels_y * grid.spacing_um;
        for (long long ty = std::llround(std::floor((centre.y - extent.y) / tile_y));
             ty <= std::llround(std::floor((centre.y + extent.y) / tile_y)); ++ty)
            for (long long tx = std::llround(std::floor((centre.x - extent.x) / tile_x));
                 tx <= std::llround(std::floor((centre.x + extent.x) / tile_x)); ++tx)
                add_tile_copy(centre.x - tx * tile_x, centre.y - ty * tile_y);
    }
};

namespace {

// Walks a collector over every tile copy, adding its counts to `statistics` (if any).
template <typename AnyCollector>
void walk(AnyCollector&& collector, GaborQueryStatistics* statistics) {
    collector.add_tile_copies();
    if (!statistics) return;
    statistics->nodes_visited += collector.counts.nodes_visited;
    statistics->kernels_evaluated += collector.counts.kernels_evaluated;
}

}  // namespace

void GaborSurface::collect(const GaborPointQuery& query, double prune_lambda_um, gabor::KernelArrays& kernels,
                           GaborQueryStatistics* statistics) const {
    gabor::KernelArrays* const target = &kernels;
    collect(query, &query.omega_i, 1, prune_lambda_um, &target, statistics);
}

// One direction (count 1: every render and eval) walks with the Collector compiled for it alone.
void GaborSurface::collect(const GaborPointQuery& query, const Vec3* omegas_i, std::size_t count,
                           double prune_lambda_um, gabor::KernelArrays* const* kernels,
                           GaborQueryStatistics* statistics) const {
    const gabor::KernelGrid grid = gabor::kernel_grid(surface_->texel_um(), settings_);
    GaborPointQuery one = query;
    const auto aim = [&](std::size_t k) {
        one.omega_i = omegas_i[k];
        return Aim{directional_reach(one, prune_lambda_um, grid), kernels[k], {}};
    };
    if (count == 1) {
        thread_local CollectScratch<OneAim::Mask> scratch;
        walk(Collector<OneAim>(*this, query.footprint, OneAim(aim(0)), scratch), statistics);
        return;
    }
    thread_local CollectScratch<SeveralAims::Mask> scratch;
    thread_local std::vector<Aim> aims;
    for (std::size_t first = 0; first < count; first += kMaxAims) {
        aims.clear();
        for (std::size_t k = first; k < std::min(count, first + kMaxAims); ++k) aims.push_back(aim(k));
        walk(Collector<SeveralAims>(*this, query.footprint, SeveralAims(aims), scratch), statistics);
    }
}

namespace {

// f_r = ξ1/A_c |Σ_k w_k C_k F[g_k](v)|² at one wavelength (Yan 2018 eq. 16–17), the sum over `end`
// kernels taken by sum(point).
template <typename Sum>
double brdf_of_sum(const GaborPointQuery& query, std::size_t end, double lambda_um, double area_um2,
                   GaborQueryStatistics* statistics, const Sum& sum) {
    const gabor::TransformPoint point =
        gabor::transform_point(query.model, gabor::FresnelAtWavelength(query.material, lambda_um), query.omega_i,
                               query.omega_o, lambda_um, area_um2);
    if (statistics) statistics->kernels_summed += end;
    return point.brdf_scale * std::norm(sum(point));
}

// brdf_of_sum over kernels [0, end).
double brdf_of_kernels(const GaborPointQuery& query, const gabor::KernelArrays& kernels, std::size_t end,
                       double lambda_um, const gabor::KernelGrid& grid, double area_um2,
                       GaborQueryStatistics* statistics) {
    return brdf_of_sum(query, end, lambda_um, area_um2, statistics, [&](const gabor::TransformPoint& point) {
        return grid.order == 2 ? gabor::sum_chirped_transforms_single(kernels, end, point, grid)
                               : gabor::sum_transforms(kernels, 0, end, point, grid);
    });
}

// The class of each kernel: how many of the first `tested` ascending wavelengths are too short
// for it (ascending[a]² < needed[k]). Up to eight wavelengths are compared in registers, in one
// vectorised pass; more take one pass each.
GLINTSCOPE_OUT_OF_LINE_CLONES
void classify_by_first_wavelength(const double* __restrict needed, std::size_t n, const std::vector<double>& ascending,
                                  std::size_t tested, std::int64_t* __restrict classes) {
    constexpr std::size_t kInRegisters = 8;
    if (tested <= kInRegisters) {
        std::array<double, kInRegisters> squared;
        for (std::size_t a = 0; a < kInRegisters; ++a)
            squared[a] = a < tested ? ascending[a] * ascending[a] : std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < n; ++k) {
            std::int64_t shorter = 0;
            for (std::size_t a = 0; a < kInRegisters; ++a) shorter += squared[a] < needed[k];
            classes[k] = shorter;
        }
        return;
    }
    std::fill(classes, classes + n, 0);
    for (std::size_t a = 0; a < tested; ++a) {
        const double lambda_squared = ascending[a] * ascending[a];
        for (std::size_t k = 0; k < n; ++k) classes[k] += lambda_squared < needed[k];
    }
}

// Orders kernels by the shortest wavelength that reaches them, so that each wavelength sums a
// prefix: copies from[j][k] to to[j][position of k] for each array j, stably by class
// (classify_by_first_wavelength); returns prefix: the kernels reaching ascending[a] are [0,
// prefix[a + 1]) (those reaching none of the tested wavelengths after prefix[tested]). The
// kernels are dealt to four contiguous streams, counted and placed side by side: each class's
// running position is a chain through memory, and four chains overlap where one would wait.
constexpr std::size_t kOrderedArrays = 6;
std::vector<std::size_t> order_by_class(const double* needed, std::size_t n, const std::vector<double>& ascending,
                                        std::size_t tested, const std::array<const double*, kOrderedArrays>& from,
                                        const std::array<double*, kOrderedArrays>& to) {
    thread_local std::vector<std::int64_t> class_of;
    class_of.resize(n);
    classify_by_first_wavelength(needed, n, ascending, tested, class_of.data());
    constexpr std::size_t kStreams = 4;
    const std::size_t classes = tested + 1;
    const std::size_t quarter = n / kStreams;  // stream q: [q·quarter, (q+1)·quarter), the last one to n
    thread_local std::vector<std::size_t> position;  // [stream][class]
    position.assign(kStreams * classes, 0);
    const std::int64_t* const cls = class_of.data();
    std::size_t* const at = position.data();
    for (std::size_t i = 0; i < quarter; ++i)
        for (std::size_t q = 0; q < kStreams; ++q) ++at[q * classes + cls[q * quarter + i]];
    for (std::size_t k = kStreams * quarter; k < n; ++k) ++at[(kStreams - 1) * classes + cls[k]];
    // Counts to first positions: class by class, stream by stream (the order the kernels had).
    std::vector<std::size_t> prefix(tested + 2, 0);
    std::size_t next = 0;
    for (std::size_t c = 0; c < classes; ++c) {
        for (std::size_t q = 0; q < kStreams; ++q) {
            const std::size_t count = at[q * classes + c];
            at[q * classes + c] = next;
            next += count;
        }
        prefix[c + 1] = next;
    }
    const auto place = [&](std::size_t q, std::size_t k) {
        const std::size_t destination = at[q * classes + cls[k]]++;
        for (std::size_t j = 0; j < kOrderedArrays; ++j) to[j][destination] = from[j][k];
    };
    for (std::size_t i = 0; i < quarter; ++i)
        for (std::size_t q = 0; q < kStreams; ++q) place(q, q * quarter + i);
    for (std::size_t k = kStreams * quarter; k < n; ++k) place(kStreams - 1, k);
    return prefix;
}

// First order: orders the kernels by the shortest wavelength that still reaches them, λ_k =
// max_axis |ψ̄ + ξ3 H'_k| / reach, into `ordered` (returns prefix as order_by_class).
// Every kernel reaches the longest wavelength, at which it was collected; the sum applies the exact
// cut, so the squares compared here carry a margin that errs towards keeping.
GLINTSCOPE_OUT_OF_LINE_CLONES
std::vector<std::size_t> order_by_first_wavelength(const GaborPointQuery& query, const gabor::KernelGrid& grid,
                                                   const std::vector<double>& ascending,
                                                   const gabor::KernelArrays& collected,
                                                   gabor::KernelArrays& ordered) {
    const Vec3 psi = query.omega_i + query.omega_o;
    const double xi3_value = xi3(query.model, query.omega_i, query.omega_o);
    const std::size_t n = collected.size();
    thread_local std::vector<double> needed_squared;  // λ_k², less the margin
    needed_squared.resize(n);
    double* __restrict needed = needed_squared.data();
    const double* __restrict slope_x = collected.slope_x.data();
    const double* __restrict slope_y = collected.slope_y.data();
    const double inverse_reach = 1.0 / grid.reach;
    constexpr double kKeep = 1.0 - 2e-9;
    for (std::size_t k = 0; k < n; ++k) {
        const double across = std::max(std::fabs(psi.x + xi3_value * slope_x[k]),
                                       std::fabs(psi.y + xi3_value * slope_y[k])) * inverse_reach;
        needed[k] = across * across * kKeep;
    }
    ordered.resize(n);
    return order_by_class(needed, n, ascending, ascending.size() - 1,
                          {collected.px.data(), collected.py.data(), collected.height.data(), collected.slope_x.data(),
                           collected.slope_y.data(), collected.weight.data()},
                          {ordered.px.data(), ordered.py.data(), ordered.height.data(), ordered.slope_x.data(),
                           ordered.slope_y.data(), ordered.weight.data()});
}

void check_wavelength(double lambda_um) {
    if (!(lambda_um > 0.0 && std::isfinite(lambda_um))) throw Error("gabor: wavelengths must be positive and finite");
}

// f_r at each wavelength from the kernels collected at the longest one (ascending: the
// wavelengths sorted), into values[0 … wavelengths).
void values_of_kernels(const GaborPointQuery& query, const gabor::KernelArrays& collected,
                       const std::vector<double>& wavelengths_um, const std::vector<double>& ascending,
                       const gabor::KernelGrid& grid, double area_um2, GaborQueryStatistics* statistics,
                       double* values) {
    if (wavelengths_um.size() == 1) {
        values[0] = brdf_of_kernels(query, collected, collected.size(), wavelengths_um[0], grid, area_um2, statistics);
        return;
    }
    // The kernels reaching wavelength λ: the prefix of those reaching the ascending wavelengths up to λ.
    const auto reaching = [&](const std::vector<std::size_t>& prefix, double lambda) {
        return prefix[std::upper_bound(ascending.begin(), ascending.end(), lambda) - ascending.begin()];
    };
    if (grid.order == 2) {
        // Every kernel's terms, in the order collected: each wavelength's sum leaves out the kernels
        // beyond their cut there, lane by lane (gabor::sum_wavelength_free_terms).
        thread_local gabor::WavelengthFreeTerms terms;
        const gabor::TransformPoint at_one_micron = gabor::transform_point(
            query.model, gabor::FresnelAtWavelength({}, 1.0), query.omega_i, query.omega_o, 1.0, 1.0);
        gabor::wavelength_free_terms(collected, grid, at_one_micron, terms);
        const std::size_t n = collected.size();
        for (std::size_t i = 0; i < wavelengths_um.size(); ++i) {
            const double lambda = wavelengths_um[i];
            const gabor::TransformPoint point =
                gabor::transform_point(query.model, gabor::FresnelAtWavelength(query.material, lambda), query.omega_i,
                                       query.omega_o, lambda, area_um2);
            if (statistics) statistics->kernels_summed += gabor::count_within_cut(terms, n, lambda);
            values[i] = point.brdf_scale *
                        std::norm(gabor::sum_wavelength_free_terms(terms, n, lambda, point.xi3_over_lambda, grid));
        }
        return;
    }
    thread_local gabor::KernelArrays ordered;
    const std::vector<std::size_t> prefix = order_by_first_wavelength(query, grid, ascending, collected, ordered);
    for (std::size_t i = 0; i < wavelengths_um.size(); ++i) {
        const double lambda = wavelengths_um[i];
        values[i] = brdf_of_kernels(query, ordered, reaching(prefix, lambda), lambda, grid, area_um2, statistics);
    }
}

}  // namespace

double GaborSurface::f_r(const GaborPointQuery& query, double lambda_um, GaborQueryStatistics* statistics) const {
    check_finite(query);
    check_wavelength(lambda_um);
    if (query.omega_i.z <= 0.0 || query.omega_o.z <= 0.0) return 0.0;
    thread_local gabor::KernelArrays collected;
    collected.clear();
    collect(query, lambda_um, collected, statistics);
    const gabor::KernelGrid grid = gabor::kernel_grid(surface_->texel_um(), settings_);
    const double area = gabor::CoherenceWindow(query.footprint, settings_.footprint_sigmas).area_um2();
    return brdf_of_kernels(query, collected, collected.size(), lambda_um, grid, area, statistics);
}

// A kernel's directional box, in slope space, is |ψ̄ + ξ3 H'| ≤ reach·λ: widest at the longest
// wavelength, so the kernels are collected there, and those pruned there are pruned at every
// wavelength.
std::vector<double> GaborSurface::f_r(const GaborPointQuery& query, const std::vector<double>& wavelengths_um,
                                      GaborQueryStatistics* statistics) const {
    check_finite(query);
    for (double lambda : wavelengths_um) check_wavelength(lambda);
    std::vector<double> values(wavelengths_um.size(), 0.0);
    if (wavelengths_um.empty() || query.omega_i.z <= 0.0 || query.omega_o.z <= 0.0) return values;
    std::vector<double> ascending = wavelengths_um;
    std::sort(ascending.begin(), ascending.end());
    thread_local gabor::KernelArrays collected;
    collected.clear();
    collect(query, ascending.back(), collected, statistics);
    const gabor::KernelGrid grid = gabor::kernel_grid(surface_->texel_um(), settings_);
    const double area = gabor::CoherenceWindow(query.footprint, settings_.footprint_sigmas).area_um2();
    values_of_kernels(query, collected, wavelengths_um, ascending, grid, area, statistics, values.data());
    return values;
}

std::vector<double> GaborSurface::f_r(const GaborPointQuery& query, const std::vector<Vec3>& omegas_i,
                                      const std::vector<double>& wavelengths_um) const {
    GaborPointQuery one = query;
    for (const Vec3 omega_i : omegas_i) {
        one.omega_i = omega_i;
        check_finite(one);
    }
    for (double lambda : wavelengths_um) check_wavelength(lambda);
    const std::size_t layers = wavelengths_um.size();
    std::vector<double> values(omegas_i.size() * layers, 0.0);
    if (layers == 0 || query.omega_o.z <= 0.0) return values;
    // The directions above the horizon (the others' f_r stays 0), each with its kernels.
    std::vector<std::size_t> lit;
    std::vector<Vec3> lit_omegas;
    for (std::size_t d = 0; d < omegas_i.size(); ++d)
        if (omegas_i[d].z > 0.0) {
            lit.push_back(d);
            lit_omegas.push_back(omegas_i[d]);
        }
    thread_local std::vector<gabor::KernelArrays> collected;
    if (collected.size() < lit.size()) collected.resize(lit.size());
    std::vector<gabor::KernelArrays*> targets;
    for (std::size_t k = 0; k < lit.size(); ++k) {
        collected[k].clear();
        targets.push_back(&collected[k]);
    }
    std::vector<double> ascending = wavelengths_um;
    std::sort(ascending.begin(), ascending.end());
    collect(query, lit_omegas.data(), lit_omegas.size(), ascending.back(), targets.data(), nullptr);
    const gabor::KernelGrid grid = gabor::kernel_grid(surface_->texel_um(), settings_);
    const double area = gabor::CoherenceWindow(query.footprint, settings_.footprint_sigmas).area_um2();
    for (std::size_t k = 0; k < lit.size(); ++k) {
        one.omega_i = lit_omegas[k];
        values_of_kernels(one, collected[k], wavelengths_um, ascending, grid, area, nullptr, &values[lit[k] * layers]);
    }
    return values;
}

}  // namespace glintscope
