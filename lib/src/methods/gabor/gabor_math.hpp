#pragma once
// Branch-free exp(−x) and e^{−i2πt} for the Gabor kernel sums: plain polynomials, so that they
// also run on SIMD vectors, where libm has no calls to offer.
#include <cstddef>
#include <cstdint>
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

// exp(−x) for 0 ≤ x ≤ 25 as exp(−x/32)^32: a degree-9 polynomial 1 + y g(y) in y = −x/32 (g fitted to
// (e^y − 1)/y on [−25/32, 0] by Chebyshev interpolation, relative error < 3e-13, exact at 0), then
// five squarings (each doubles the relative error): < 1e-11 over the range. The kernel sums only
// use x ≤ (kernel truncation)². Three multiply-adds fewer than the Taylor polynomial it replaced,
// which was 50× less accurate at x = 25.
template <typename T>
[[gnu::always_inline]] inline T exp_neg(T x) {
    const T y = x * (-1.0 / 32.0);
    T g = y * 1.946155389285314e-06 + 2.3687673765400804e-05;
    g = g * y + 0.00019755951815544144;
    g = g * y + 0.001388503026176915;
    g = g * y + 0.008333230133136577;
    g = g * y + 0.04166665110008082;
    g = g * y + 0.1666666654872725;
    g = g * y + 0.4999999999655262;
    g = g * y + 0.9999999999998338;
    T p = g * y + 1.0;
    p *= p;
    p *= p;
    p *= p;
    p *= p;
    return p * p;
}

// cos(2πt) and sin(2πt) for any t with |t| < 2^51: t is reduced to r ∈ [−1/2, 1/2] by
// subtracting the nearest integer (adding and subtracting 1.5·2^52 rounds to nearest without a
// libm call), θ = 2πr/4 ∈ [−π/4, π/4] goes through polynomials in q = θ², sin θ = θ(1 + q g_s(q))
// and cos θ = 1 + q g_c(q) (g fitted by Chebyshev interpolation on [0, (π/4)²]: relative error
// < 2e-14 and < 3e-16), and two angle doublings give 2πr.
template <typename T>
[[gnu::always_inline]] inline void cos_sin_turns(T t, T& cos_out, T& sin_out) {
    constexpr double kRoundingShift = 6755399441055744.0;  // 1.5 · 2^52
    const T r = t - ((t + kRoundingShift) - kRoundingShift);
    const T theta = r * 1.5707963267948966;  // 2π/4
    const T q = theta * theta;
    T s = q * -2.4805636241834762e-08 + 2.755599092956532e-06;
    s = s * q - 0.00019841266916985966;
    s = s * q + 0.008333333331079223;
    s = s * q - 0.16666666666663885;
    s = theta + theta * q * s;
    T c = q * 2.066550487012274e-09 - 2.755585551192951e-07;
    c = c * q + 2.480158262335195e-05;
    c = c * q - 0.0013888888882127952;
    c = c * q + 0.04166666666663093;
    c = c * q - 0.49999999999999967;
    c = 1.0 + q * c;
    const T s2 = 2.0 * s * c;  // 2θ
    const T c2 = (c - s) * (c + s);
    sin_out = 2.0 * s2 * c2;  // 4θ = 2πr
    cos_out = (c2 - s2) * (c2 + s2);
}

// Single precision for the spectral sums (gabor_kernels.cpp, sum_wavelength_free_terms): twice
// the lanes per register, terms to ~1e-7 of their size.
using Single8 = float __attribute__((vector_size(32)));
using Single16 = float __attribute__((vector_size(64)));  // AVX-512
using Int8 = std::int32_t __attribute__((vector_size(32)));
using Int16 = std::int32_t __attribute__((vector_size(64)));

// exp(−x) in single precision for 0 ≤ x ≤ 87: −x = k ln 2 + r with k an integer and |r| ≤ ½ ln 2
// (r from ln 2 in two parts, Cody & Waite 1980, the first exact in k ln 2, so that r keeps its
// accuracy however large x), e^r by its Taylor polynomial of degree 7 (remainder < 6e-9
// relative, below single precision's rounding), and 2^k added to the exponent bits.
template <typename F>
[[gnu::always_inline]] inline F exp_neg_single(F x) {
    using Int = std::conditional_t<sizeof(F) == 64, Int16, Int8>;
    const F k = (x * -1.44269504f + 12582912.0f) - 12582912.0f;  // 1.5 · 2^23: rounds to the nearest integer
    const F r = (k * -0.693359375f - x) + k * 2.12194440e-4f;    // ln 2 = 0.693359375 − 2.12194440e-4
    F p = r * (1.0f / 5040.0f) + (1.0f / 720.0f);
    p = p * r + (1.0f / 120.0f);
    p = p * r + (1.0f / 24.0f);
    p = p * r + (1.0f / 6.0f);
    p = p * r + 0.5f;
    p = p * r + 1.0f;
    p = p * r + 1.0f;
    Int bits;
    std::memcpy(&bits, &p, sizeof bits);
    bits += __builtin_convertvector(k, Int) << 23;
    std::memcpy(&p, &bits, sizeof p);
    return p;
}

// cos(2πt) and sin(2πt) in single precision for |t| < 2^22, as cos_sin_turns (above) with Taylor
// polynomials of degrees 10 and 9 on [−π/4, π/4] (remainders < 2e-9): errors of a few 1e-7.
template <typename F>
[[gnu::always_inline]] inline void cos_sin_turns_single(F t, F& cos_out, F& sin_out) {
    const F r = t - ((t + 12582912.0f) - 12582912.0f);
    const F theta = r * 1.57079633f;
    const F q = theta * theta;
    F s = q * (1.0f / 362880.0f) - (1.0f / 5040.0f);
    s = s * q + (1.0f / 120.0f);
    s = s * q - (1.0f / 6.0f);
    s = theta + theta * q * s;
    F c = q * (-1.0f / 3628800.0f) + (1.0f / 40320.0f);
    c = c * q - (1.0f / 720.0f);
    c = c * q + (1.0f / 24.0f);
    c = c * q - 0.5f;
    c = 1.0f + q * c;
    const F s2 = 2.0f * s * c;
    const F c2 = (c - s) * (c + s);
    sin_out = 2.0f * s2 * c2;
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
