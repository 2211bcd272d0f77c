#pragma once
// Branch-free exp(−x) and e^{−i2πt} for the Gabor kernel sums: plain polynomials, so that they
// also run on SIMD vectors, where libm has no calls to offer.
#include <cstddef>
#include <cstring>
#include <type_traits>

namespace glintscope::gabor_math {

// T values from consecutive doubles at p: one for double, all lanes for a vector type.
template <typename T>
[[gnu::always_inline]] inline T lanes(const double* p) {
    if constexpr (std::is_same_v<T, double>) {
        return *p;
    } else {
        T v;
        std::memcpy(&v, p, sizeof v);
        return v;
    }
}

// Each function is a template over double and GCC vector types of double (vector_size), whose
// arithmetic is elementwise with scalars broadcast.

// exp(−x) for 0 ≤ x ≤ 25 as exp(−x/32)^32: a degree-12 Taylor polynomial in −x/32, then five
// squarings (each doubles the relative error). Relative error < 1e-12 for x ≤ 16, < 5e-10 for
// x ≤ 25; the kernel sums only use x ≤ (kernel truncation)².
template <typename T>
[[gnu::always_inline]] inline T exp_neg(T x) {
    const T y = x * (-1.0 / 32.0);
    T p = y * (1.0 / 479001600.0) + 1.0 / 39916800.0;
    p = p * y + 1.0 / 3628800.0;
    p = p * y + 1.0 / 362880.0;
    p = p * y + 1.0 / 40320.0;
    p = p * y + 1.0 / 5040.0;
    p = p * y + 1.0 / 720.0;
    p = p * y + 1.0 / 120.0;
    p = p * y + 1.0 / 24.0;
    p = p * y + 1.0 / 6.0;
    p = p * y + 0.5;
    p = p * y + 1.0;
    p = p * y + 1.0;
    p *= p;
    p *= p;
    p *= p;
    p *= p;
    return p * p;
}

// cos(2πt) and sin(2πt) for any t with |t| < 2^51: t is reduced to r ∈ [−1/2, 1/2] by
// subtracting the nearest integer (adding and subtracting 1.5·2^52 rounds to nearest without a
// libm call), θ = 2πr/4 ∈ [−π/4, π/4] goes through Taylor polynomials (error < 3e-14), and two
// angle doublings give 2πr.
template <typename T>
[[gnu::always_inline]] inline void cos_sin_turns(T t, T& cos_out, T& sin_out) {
    constexpr double kRoundingShift = 6755399441055744.0;  // 1.5 · 2^52
    const T r = t - ((t + kRoundingShift) - kRoundingShift);
    const T theta = r * 1.5707963267948966;  // 2π/4
    const T q = theta * theta;
    T s = q * (-1.0 / 6227020800.0) + 1.0 / 39916800.0;  // sin: odd terms up to θ^13
    s = s * q - 1.0 / 362880.0;
    s = s * q + 1.0 / 5040.0;
    s = s * q - 1.0 / 120.0;
    s = s * q + 1.0 / 6.0;
    s = theta - theta * q * s;
    T c = q * (1.0 / 87178291200.0) - 1.0 / 479001600.0;  // cos: even terms up to θ^14
    c = c * q + 1.0 / 3628800.0;
    c = c * q - 1.0 / 40320.0;
    c = c * q + 1.0 / 720.0;
    c = c * q - 1.0 / 24.0;
    c = c * q + 0.5;
    c = 1.0 - q * c;
    const T s2 = 2.0 * s * c;  // 2θ
    const T c2 = (c - s) * (c + s);
    sin_out = 2.0 * s2 * c2;  // 4θ = 2πr
    cos_out = (c2 - s2) * (c2 + s2);
}

using Double4 = double __attribute__((vector_size(32)));
using Double8 = double __attribute__((vector_size(64)));  // AVX-512 (core/target_clones.hpp)

template <typename V>
inline constexpr std::size_t kLanes = sizeof(V) / sizeof(double);

// The lanes' sum, pairwise: ((0 + 1) + (2 + 3)) for four, and the two halves' so for eight.
template <typename V>
[[gnu::always_inline]] inline double lane_total(const V& v) {
    if constexpr (kLanes<V> == 4) {
        return (v[0] + v[1]) + (v[2] + v[3]);
    } else {
        return ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]));
    }
}

// Σ over kernels [begin, end) kLanes<V> per step in SIMD lanes (V: Double4 or Double8):
// add(i, a, b, c) adds the terms of kernels i… to the sums a, b, c (double or V; a caller may
// leave some unused). Each lane sums a fixed subset of the kernels, so the result depends only on
// the kernel order and V. The last kernels that fill no whole step take the upper lanes of the
// step that ends at `end`, whose lower lanes (the kernels before them in the arrays, which hold
// [0, end)) are computed and left out; only when end is shorter than a step are they added one by one.
template <typename V = Double4, typename Add>
[[gnu::always_inline]] inline void sum_in_lanes(std::size_t begin, std::size_t end, const Add& add, double& out_a,
                                                double& out_b, double& out_c) {
    constexpr std::size_t n = kLanes<V>;
    V a_lanes = V{} + 0.0;
    V b_lanes = a_lanes;
    V c_lanes = a_lanes;
    std::size_t i = begin;
    for (; i + n <= end; i += n) add(i, a_lanes, b_lanes, c_lanes);
    double a = 0.0;
    double b = 0.0;
    double c = 0.0;
    if (i < end && end >= n) {
        V tail_a = V{} + 0.0;
        V tail_b = tail_a;
        V tail_c = tail_a;
        add(end - n, tail_a, tail_b, tail_c);
        for (std::size_t lane = i + n - end; lane < n; ++lane) {
            a += tail_a[lane];
            b += tail_b[lane];
            c += tail_c[lane];
        }
    } else {
        for (; i < end; ++i) add(i, a, b, c);
    }
    out_a = lane_total(a_lanes) + a;
    out_b = lane_total(b_lanes) + b;
    out_c = lane_total(c_lanes) + c;
}

}  // namespace glintscope::gabor_math
