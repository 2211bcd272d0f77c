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

// Σ over kernels [begin, end) four per step in SIMD lanes: add(i, a, b, c) adds the terms of
// kernels i… to the sums a, b, c (double or Double4; a caller may leave some unused). Each lane
// sums a fixed subset of the kernels, so the result depends only on the kernel order. The last
// 1–3 kernels take the upper lanes of the four that end at `end`, whose lower lanes (the kernels
// before them in the arrays, which hold [0, end)) are computed and left out; only when end < 4
// are they added one by one.
template <typename Add>
[[gnu::always_inline]] inline void sum_in_lanes(std::size_t begin, std::size_t end, const Add& add, double& out_a,
                                                double& out_b, double& out_c) {
    Double4 a4 = {0.0, 0.0, 0.0, 0.0};
    Double4 b4 = a4;
    Double4 c4 = a4;
    std::size_t i = begin;
    for (; i + 4 <= end; i += 4) add(i, a4, b4, c4);
    double a = 0.0;
    double b = 0.0;
    double c = 0.0;
    if (i < end && end >= 4) {
        Double4 tail_a = {0.0, 0.0, 0.0, 0.0};
        Double4 tail_b = tail_a;
        Double4 tail_c = tail_a;
        add(end - 4, tail_a, tail_b, tail_c);
        for (std::size_t lane = i + 4 - end; lane < 4; ++lane) {
            a += tail_a[lane];
            b += tail_b[lane];
            c += tail_c[lane];
        }
    } else {
        for (; i < end; ++i) add(i, a, b, c);
    }
    out_a = ((a4[0] + a4[1]) + (a4[2] + a4[3])) + a;
    out_b = ((b4[0] + b4[1]) + (b4[2] + b4[3])) + b;
    out_c = ((c4[0] + c4[1]) + (c4[2] + c4[3])) + c;
}

}  // namespace glintscope::gabor_math
