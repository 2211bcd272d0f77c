#include "gabor_kernels.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <type_traits>

#include "core/target_clones.hpp"
#include "glintscope/core/error.hpp"

// The SIMD helpers here and in gabor_math.hpp are always inlined, so the vector calling
// convention that -Wpsabi warns about never applies.
#pragma GCC diagnostic ignored "-Wpsabi"
#include "gabor_math.hpp"

namespace glintscope::gabor {
namespace {

using gabor_math::Double4;


// The kernel's amplitude where v lies in its box |v + a_k| ≤ reach, else 0 (per lane).
[[gnu::always_inline]] inline double keep_inside(double dx, double dy, double reach2, double amplitude) {
    return dx * dx <= reach2 && dy * dy <= reach2 ? amplitude : 0.0;
}

[[gnu::always_inline]] inline Double4 keep_inside(const Double4& dx, const Double4& dy, double reach2,
                                                 const Double4& amplitude) {
    const Double4 zero = {0.0, 0.0, 0.0, 0.0};
    return ((dx * dx <= reach2) & (dy * dy <= reach2)) ? amplitude : zero;
}

[[gnu::always_inline]] inline Double4 keep_inside(const Double4& dx, const Double4& dy, const Double4& reach2,
                                                 const Double4& amplitude) {
    const Double4 zero = {0.0, 0.0, 0.0, 0.0};
    return ((dx * dx <= reach2) & (dy * dy <= reach2)) ? amplitude : zero;
}

// Elementwise helpers for double and Double4 (GCC lowers the lane loops to vector instructions).
[[gnu::always_inline]] inline double sqrt_of(double x) { return std::sqrt(x); }
[[gnu::always_inline]] inline double abs_of(double x) { return std::fabs(x); }
[[gnu::always_inline]] inline double min_of(double a, double b) { return a < b ? a : b; }
[[gnu::always_inline]] inline Double4 sqrt_of(const Double4& x) {
    return Double4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
}
[[gnu::always_inline]] inline Double4 abs_of(const Double4& x) { return x < 0.0 ? -x : x; }
[[gnu::always_inline]] inline Double4 min_of(const Double4& a, const Double4& b) { return a < b ? a : b; }

using gabor_math::Single16;
using gabor_math::Single8;

// For det = det_re + i det_im (for the spectral terms' M = I + iE, |det M|² = (1 + s²ρ₁²)(1 + s²ρ₂²)
// over H'''s eigenvalues ρ: at least 1, so a rounding in det_re or det_im stays small against
// |det|, even where 1 − s² det H'' cancels): 1/|det|, 1/|det|² and √det = (root_re, root_im) with root_re > 0, √det = (r, det_im/(2r)), r = √((|det| + det_re)/2),
// by reciprocal square roots: 1/|det| and g = 1/√(2(|det| + det_re)), which give r = (|det| + det_re) g
// and det_im/(2r) = det_im g. F: Single8 or Single16.
template <typename F>
struct DeterminantRoots {
    F inverse_abs;
    F inverse_norm2;
    F root_re;
    F root_im;
};

template <typename F>
[[gnu::always_inline]] inline F reciprocal_sqrt(const F& x) {
    F root;
    for (std::size_t lane = 0; lane < sizeof(F) / sizeof(float); ++lane) root[lane] = std::sqrt(x[lane]);
    return 1.0f / root;
}

// With AVX-512: its estimate (relative error < 2^−14) and one Newton step (to ~2^−28), without
// the divider. One instruction of assembly: its intrinsic would need the AVX-512 target on every
// template between here and sum_single16; Clang refuses a 512-bit operand outside an AVX-512
// function, so its builds (the fuzz targets) take the one above.
#if !defined(__clang__)
template <>
[[gnu::always_inline]] inline Single16 reciprocal_sqrt(const Single16& x) {
    Single16 y;
    asm("vrsqrt14ps %1, %0" : "=v"(y) : "v"(x));
    return y + y * (0.5f - 0.5f * x * y * y);  // y(3 − x y²)/2
}
#endif

template <typename F>
[[gnu::always_inline]] inline DeterminantRoots<F> determinant_roots(const F& det_re, const F& det_im) {
    const F norm2 = det_re * det_re + det_im * det_im;
    const F inverse_abs = reciprocal_sqrt(norm2);
    const F abs_plus_re = norm2 * inverse_abs + det_re;
    const F g = reciprocal_sqrt(2.0f * abs_plus_re);
    return {inverse_abs, inverse_abs * inverse_abs, abs_plus_re * g, det_im * g};
}

// One kernel's term w_k l² ξ2 e^{−i2π(ξ3 H_k/λ + m_k·v)} e^{−β|v + a_k|²} (T: double or Double4).
template <typename T>
[[gnu::always_inline]] inline void add_term(const T& px, const T& py, const T& height, const T& slope_x,
                                            const T& slope_y, const T& weight, const TransformPoint& point,
                                            double reach2, double beta, T& sum_re, T& sum_im) {
    const T dx = point.vx + point.xi3_over_lambda * slope_x;  // v + a_k (Yan 2018 eq. 15)
    const T dy = point.vy + point.xi3_over_lambda * slope_y;
    const T xi2 = 1.0 - point.xi2_gx * slope_x - point.xi2_gy * slope_y;
    const T amplitude = weight * xi2 * gabor_math::exp_neg(beta * (dx * dx + dy * dy));
    T cos_phase;
    T sin_phase;
    gabor_math::cos_sin_turns(point.xi3_over_lambda * height + px * point.vx + py * point.vy, cos_phase, sin_phase);
    // Outside the box exp_neg's argument may leave its range (even overflow to inf): a select,
    // not a product, discards those lanes.
    const T kept = keep_inside(dx, dy, reach2, amplitude);
    sum_re += kept * cos_phase;
    sum_im -= kept * sin_phase;
}

GLINTSCOPE_OUT_OF_LINE_CLONES_V4
void sum_kernel_terms(const KernelArrays& k, std::size_t begin, std::size_t end, const TransformPoint& point,
                      double reach, double beta, double& out_re, double& out_im) {
    const double reach2 = reach * reach;
    const auto add = [&](std::size_t i, auto& re, auto& im, auto&) __attribute__((always_inline)) {
        using T = std::decay_t<decltype(re)>;
        add_term(gabor_math::lanes<T>(&k.px[i]), gabor_math::lanes<T>(&k.py[i]), gabor_math::lanes<T>(&k.height[i]), gabor_math::lanes<T>(&k.slope_x[i]),
                 gabor_math::lanes<T>(&k.slope_y[i]), gabor_math::lanes<T>(&k.weight[i]), point, reach2, beta, re, im);
    };
    double unused = 0.0;
    gabor_math::sum_in_lanes(begin, end, add, out_re, out_im, unused);
}

// The second-order term: w_k l² ξ2 e^{−i2π(ξ3 H_k/λ + m_k·v)} det(M)^{−1/2} e^{−β uᵀM⁻¹u} with
// u = v + a_k, M = I + iE, E = 2πσ² ξ3 H''_k/λ (Folland 1989 App. A Thm. 1; gabor_kernel_transform),
// cut to |u| ≤ reach·√(1 + ε²) per axis, ε = ρ(E).
template <typename T, bool SlopeFactor>
[[gnu::always_inline]] inline void add_chirped_term(const T& px, const T& py, const T& height, const T& slope_x,
                                                    const T& slope_y, const T& weight, const T& hxx, const T& hxy,
                                                    const T& hyy, const TransformPoint& point, double reach2,
                                                    double beta, double chirp_scale, T& sum_re, T& sum_im) {
    const T ux = point.vx + point.xi3_over_lambda * slope_x;  // v + a_k (Yan 2018 eq. 15)
    const T uy = point.vy + point.xi3_over_lambda * slope_y;
    const double e = chirp_scale * point.xi3_over_lambda;
    const T exx = e * hxx;
    const T exy = e * hxy;
    const T eyy = e * hyy;
    // det M = (1 + iE_xx)(1 + iE_yy) + E_xy², uᵀM⁻¹u = uᵀ adj(M) u / det M.
    const T det_re = 1.0 - (exx * eyy - exy * exy);
    const T det_im = exx + eyy;
    const T inverse_norm2 = 1.0 / (det_re * det_re + det_im * det_im);
    const T inverse_abs = sqrt_of(inverse_norm2);  // 1/|det M|
    const T det_abs = (det_re * det_re + det_im * det_im) * inverse_abs;
    const T ux2 = ux * ux;
    const T uy2 = uy * uy;
    const T num_re = ux2 + uy2;
    const T num_im = eyy * ux2 - 2.0 * exy * ux * uy + exx * uy2;
    const T q_re = (num_re * det_re + num_im * det_im) * inverse_norm2;
    const T q_im = (num_im * det_re - num_re * det_im) * inverse_norm2;
    // det^{−1/2} = conj(√det)/|det|, √det = (r, det_im/(2r)), r = √((|det| + det_re)/2) > 0.
    const T root_re = sqrt_of(0.5 * (det_abs + det_re));
    const T root_im = det_im / (2.0 * root_re);
    // Inside the widened box β Re(uᵀM⁻¹u) may exceed exp_neg's range; e^{−25} ≈ 1.4e-11 of a peak
    // stands for anything smaller.
    const T exponent = min_of(beta * q_re, T{} + 25.0);
    // ξ2 = 1 exactly where it does not depend on H' (all models but Kirchhoff): weight·1 is weight.
    T weight_xi2 = weight;
    if constexpr (SlopeFactor) weight_xi2 = weight * (1.0 - point.xi2_gx * slope_x - point.xi2_gy * slope_y);
    const T amplitude = weight_xi2 * gabor_math::exp_neg(exponent) * inverse_abs;
    T cos_phase;
    T sin_phase;
    gabor_math::cos_sin_turns(point.xi3_over_lambda * height + px * point.vx + py * point.vy +
                                  beta * (0.5 / pi) * q_im,
                              cos_phase, sin_phase);
    const T half_difference = 0.5 * (exx - eyy);
    const T mean = 0.5 * (exx + eyy);
    const T epsilon = abs_of(mean) + sqrt_of(half_difference * half_difference + exy * exy);
    const T reach2_k = reach2 * (1.0 + epsilon * epsilon);
    const T kept = keep_inside(ux, uy, reach2_k, amplitude);
    // (cos − i sin)(root_re − i root_im)
    sum_re += kept * (cos_phase * root_re - sin_phase * root_im);
    sum_im -= kept * (sin_phase * root_re + cos_phase * root_im);
}

// A second-order term from its prepared factors (ChirpFactors): u = v + a_k, q = uᵀAu,
// w l² ξ2 det(M)^{−1/2} e^{−Re q} e^{−i2π(ξ3 H_k/λ + m_k·v + Im q/(2π))}, cut at its widened reach;
// and norm e^{−Re q} where Re q < density_cut added to `density` (the kernel's cut sampling
// Gaussian, whose exponent is Re q: sum_transforms_and_density). `SlopeFactor`: ξ2 depends on H' (Kirchhoff),
// else ξ2 = 1 and the term skips it.
template <typename T, bool WithDensity, bool SlopeFactor>
[[gnu::always_inline]] inline void add_prepared_chirped_term(const T& px, const T& py, const T& height,
                                                             const T& slope_x, const T& slope_y, const T& axx_re,
                                                             const T& axx_im, const T& axy_re, const T& axy_im,
                                                             const T& ayy_re, const T& ayy_im, const T& f_re,
                                                             const T& f_im, const T& reach2, const T& norm,
                                                             double density_cut, const TransformPoint& point,
                                                             T& sum_re, T& sum_im, T& density) {
    const T ux = point.vx + point.xi3_over_lambda * slope_x;  // v + a_k (Yan 2018 eq. 15)
    const T uy = point.vy + point.xi3_over_lambda * slope_y;
    const T ux2 = ux * ux;
    const T uxy = 2.0 * ux * uy;
    const T uy2 = uy * uy;
    const T q_re = axx_re * ux2 + axy_re * uxy + ayy_re * uy2;
    const T q_im = axx_im * ux2 + axy_im * uxy + ayy_im * uy2;
    // As in add_chirped_term: e^{−25} stands for anything smaller inside the widened box.
    const T gaussian = gabor_math::exp_neg(min_of(q_re, T{} + 25.0));
    T amplitude = gaussian;
    if constexpr (SlopeFactor) amplitude *= 1.0 - point.xi2_gx * slope_x - point.xi2_gy * slope_y;
    if constexpr (WithDensity) density += (q_re < density_cut ? norm : T{} * 0.0) * gaussian;
    T cos_phase;
    T sin_phase;
    gabor_math::cos_sin_turns(point.xi3_over_lambda * height + px * point.vx + py * point.vy + (0.5 / pi) * q_im,
                              cos_phase, sin_phase);
    const T kept = keep_inside(ux, uy, reach2, amplitude);
    // (cos − i sin)(f_re + i f_im)
    sum_re += kept * (cos_phase * f_re + sin_phase * f_im);
    sum_im += kept * (cos_phase * f_im - sin_phase * f_re);
}

// The prepared terms of the runs' kernels into re, im and, with the norms (`WithDensity`), the
// sampling density (cut at density_cut) into `density`.
template <bool WithDensity, bool SlopeFactor>
[[gnu::always_inline]] inline void sum_prepared_terms(const KernelArrays& k, const ChirpFactors& c, const double* norm,
                                                      double density_cut, const KernelRun* runs, std::size_t run_count,
                                                      const TransformPoint& point, double& out_re, double& out_im,
                                                      double& density) {
    const auto add = [&](std::size_t i, auto& re, auto& im, auto& d) __attribute__((always_inline)) {
        using T = std::decay_t<decltype(re)>;
        using gabor_math::lanes;
        add_prepared_chirped_term<T, WithDensity, SlopeFactor>(
            lanes<T>(&k.px[i]), lanes<T>(&k.py[i]), lanes<T>(&k.height[i]), lanes<T>(&k.slope_x[i]),
            lanes<T>(&k.slope_y[i]), lanes<T>(&c.a_xx_re[i]), lanes<T>(&c.a_xx_im[i]), lanes<T>(&c.a_xy_re[i]),
            lanes<T>(&c.a_xy_im[i]), lanes<T>(&c.a_yy_re[i]), lanes<T>(&c.a_yy_im[i]), lanes<T>(&c.f_re[i]),
            lanes<T>(&c.f_im[i]), lanes<T>(&c.reach2[i]), WithDensity ? lanes<T>(norm + i) : T{} * 0.0, density_cut, point,
            re, im, d);
    };
    for (std::size_t r = 0; r < run_count; ++r) {
        double re = 0.0, im = 0.0, d = 0.0;
        gabor_math::sum_in_lanes(runs[r].begin, runs[r].end, add, re, im, d);
        out_re += re;
        out_im += im;
        density += d;
    }
}

GLINTSCOPE_OUT_OF_LINE_CLONES_V4
void sum_prepared_chirped_terms(const KernelArrays& k, const ChirpFactors& c, const KernelRun* runs,
                                std::size_t run_count, const TransformPoint& point, double& out_re, double& out_im) {
    double unused = 0.0;
    if (point.xi2_gx == 0.0 && point.xi2_gy == 0.0)
        sum_prepared_terms<false, false>(k, c, nullptr, 0.0, runs, run_count, point, out_re, out_im, unused);
    else
        sum_prepared_terms<false, true>(k, c, nullptr, 0.0, runs, run_count, point, out_re, out_im, unused);
}

GLINTSCOPE_OUT_OF_LINE_CLONES_V4
void sum_prepared_chirped_terms_and_density(const KernelArrays& k, const ChirpFactors& c, const double* norm,
                                            double density_cut, const KernelRun* runs, std::size_t run_count,
                                            const TransformPoint& point, double& out_re, double& out_im,
                                            double& density) {
    if (point.xi2_gx == 0.0 && point.xi2_gy == 0.0)
        sum_prepared_terms<true, false>(k, c, norm, density_cut, runs, run_count, point, out_re, out_im, density);
    else
        sum_prepared_terms<true, true>(k, c, norm, density_cut, runs, run_count, point, out_re, out_im, density);
}

// The factors of a WavelengthFreeTerms term at one wavelength: s = 2πσ²ξ3/λ, and β/λ² and βs/λ²,
// which turn |U|² and Uᵀ adj(H'')U into β uᵀu and β uᵀ adj(E) u.
struct WavelengthScales {
    double s = 0.0;
    double s_squared = 0.0;
    double beta_over_lambda2 = 0.0;
    double beta_s_over_lambda2 = 0.0;
    double inverse_lambda = 0.0;
    double lambda_squared = 0.0;
};

// Whether a kernel is within its cut at λ: λ² ≥ λ_k², written !(λ² < λ_k²) so that a NaN λ_k²
// counts as within (T: double, or Double4/Double8 giving a lane mask). The one rule of the sums
// and of count_within_cut.
template <typename T>
[[gnu::always_inline]] inline auto within_cut(const T& lambda_squared, const T& first_wavelength_squared) {
    return !(lambda_squared < first_wavelength_squared);
}

// Lanes [0, 8) or [8, 16) of a Single16 (or [0, 4), [4, 8) of a Single8) in double.
template <typename F>
[[gnu::always_inline]] inline auto half_in_double(const F& v, int half) {
    if constexpr (sizeof(F) == 64) {
        const gabor_math::Single8 part = half == 0 ? __builtin_shufflevector(v, v, 0, 1, 2, 3, 4, 5, 6, 7)
                                                   : __builtin_shufflevector(v, v, 8, 9, 10, 11, 12, 13, 14, 15);
        return __builtin_convertvector(part, gabor_math::Double8);
    } else {
        using Single4 = float __attribute__((vector_size(16)));
        const Single4 part = half == 0 ? __builtin_shufflevector(v, v, 0, 1, 2, 3) : __builtin_shufflevector(v, v, 4, 5, 6, 7);
        return __builtin_convertvector(part, Double4);
    }
}

// Two double vectors as one single-precision vector of twice the lanes.
template <typename F, typename D>
[[gnu::always_inline]] inline F joined_in_single(const D& low, const D& high) {
    if constexpr (sizeof(F) == 64) {
        const Single8 a = __builtin_convertvector(low, Single8), b = __builtin_convertvector(high, Single8);
        return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    } else {
        using Single4 = float __attribute__((vector_size(16)));
        const Single4 a = __builtin_convertvector(low, Single4), b = __builtin_convertvector(high, Single4);
        return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
    }
}

// The lane mask of F (32-bit lanes: −1 where set) from two double vectors' compare results.
template <typename F>
using SingleMask = std::conditional_t<sizeof(F) == 64, gabor_math::Int16, gabor_math::Int8>;

template <typename F, typename M>
[[gnu::always_inline]] inline SingleMask<F> joined_mask(const M& low, const M& high) {
    if constexpr (sizeof(F) == 64)
        return __builtin_convertvector(
            __builtin_shufflevector(low, high, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15), SingleMask<F>);
    else
        return __builtin_convertvector(__builtin_shufflevector(low, high, 0, 1, 2, 3, 4, 5, 6, 7), SingleMask<F>);
}

// Lanes from `valid` on cleared.
template <typename F>
[[gnu::always_inline]] inline SingleMask<F> first_lanes(SingleMask<F> mask, std::size_t valid) {
    constexpr std::size_t n = sizeof(F) / sizeof(float);
    if (valid < n) {
        SingleMask<F> lane{};
        for (std::size_t k = 0; k < n; ++k) lane[k] = static_cast<std::int32_t>(k);
        mask &= lane < static_cast<std::int32_t>(valid);
    }
    return mask;
}

// One step's terms in single precision: their wavelength-free factors (WavelengthFreeTerms'
// meaning, at the step's wavelength), the fraction of a turn of ξ3 H_k/λ + m_k·v (reduced in
// double), and the lanes within the cut.
template <typename F>
struct SingleStep {
    F fraction, length_squared, adjugate_form, determinant, trace, weight;
    SingleMask<F> within;
};

// add_chirped_term's terms from a SingleStep, with β uᵀM⁻¹u = β uᵀ adj(M) u / det M,
// adj(M) = I + i adj(E); lanes outside `within` left out. Added to sum_re and sum_im.
template <typename F>
[[gnu::always_inline]] inline void add_single_terms(const SingleStep<F>& t, const WavelengthScales& w, F& sum_re,
                                                    F& sum_im) {
    const F det_re = 1.0f - static_cast<float>(w.s_squared) * t.determinant;
    const F det_im = static_cast<float>(w.s) * t.trace;
    const DeterminantRoots<F> roots = determinant_roots(det_re, det_im);
    const F num_re = static_cast<float>(w.beta_over_lambda2) * t.length_squared;
    const F num_im = static_cast<float>(w.beta_s_over_lambda2) * t.adjugate_form;
    const F q_re = (num_re * det_re + num_im * det_im) * roots.inverse_norm2;
    const F q_im = (num_im * det_re - num_re * det_im) * roots.inverse_norm2;
    // As in add_chirped_term: e^{−25} stands for anything smaller inside the widened box.
    F amplitude = t.weight * gabor_math::exp_neg_single(q_re < 25.0f ? q_re : F{} + 25.0f) * roots.inverse_abs;
    amplitude = t.within != 0 ? amplitude : F{};
    F cos_phase;
    F sin_phase;
    gabor_math::cos_sin_turns_single(t.fraction + static_cast<float>(0.5 / pi) * q_im, cos_phase, sin_phase);
    // det^{−1/2} = conj(√det)/|det|.
    sum_re += amplitude * (cos_phase * roots.root_re - sin_phase * roots.root_im);
    sum_im -= amplitude * (sin_phase * roots.root_re + cos_phase * roots.root_im);
}

// The fraction of a turn in [−½, ½] of `turns` (|turns| < 2^51).
template <typename D>
[[gnu::always_inline]] inline D turn_fraction(const D& turns) {
    return turns - ((turns + 6755399441055744.0) - 6755399441055744.0);  // 1.5 · 2^52
}

// One step of n (8 or 16) terms i … i + n − 1 (those from `valid` on left out) of WavelengthFreeTerms
// at wavelength λ: ξ3 H_k/λ + m_k·v = phase/λ turns, up to hundreds, is reduced in double; the cut
// is a lane mask (kernels with λ² < λ_k² left out). Added to sum_re and sum_im.
template <typename F, typename D>
[[gnu::always_inline]] inline void add_single_step(const WavelengthFreeTerms& t, std::size_t i, std::size_t valid,
                                                   const WavelengthScales& w, F& sum_re, F& sum_im) {
    constexpr std::size_t n = sizeof(F) / sizeof(float);
    const auto reaches = [&](std::size_t at) __attribute__((always_inline)) {
        return within_cut(D{} + w.lambda_squared, gabor_math::lanes<D>(&t.first_wavelength_squared[at]));
    };
    const auto load = [i](const std::vector<float>& array) __attribute__((always_inline)) {
        F v;
        std::memcpy(&v, &array[i], sizeof v);
        return v;
    };
    const auto fraction = [&](std::size_t at) __attribute__((always_inline)) {
        return turn_fraction(gabor_math::lanes<D>(&t.phase[at]) * w.inverse_lambda);
    };
    SingleStep<F> step;
    step.fraction = joined_in_single<F>(fraction(i), fraction(i + n / 2));
    step.length_squared = load(t.length_squared);
    step.adjugate_form = load(t.adjugate_form);
    step.determinant = load(t.determinant);
    step.trace = load(t.trace);
    step.weight = load(t.weight);
    step.within = first_lanes<F>(joined_mask<F>(reaches(i), reaches(i + n / 2)), valid);
    add_single_terms(step, w, sum_re, sum_im);
}

template <typename F, typename D>
[[gnu::always_inline]] inline void sum_single(const WavelengthFreeTerms& t, std::size_t end, const WavelengthScales& w,
                                              double& out_re, double& out_im) {
    constexpr std::size_t n = sizeof(F) / sizeof(float);
    constexpr std::size_t kStepsInSingle = 4;  // steps summed in single precision before they join the double sums
    D sum_re = D{} + 0.0;
    D sum_im = sum_re;
    // Inlined, as everything here, so that the AVX-512 clone's code stays in its own function.
    const auto add_steps = [&](std::size_t first, std::size_t steps, std::size_t valid_in_last)
                               __attribute__((always_inline)) {
        F re = F{} + 0.0f;
        F im = re;
        for (std::size_t k = 0; k < steps; ++k)
            add_single_step<F, D>(t, first + k * n, k + 1 == steps ? valid_in_last : n, w, re, im);
        sum_re += half_in_double(re, 0) + half_in_double(re, 1);
        sum_im += half_in_double(im, 0) + half_in_double(im, 1);
    };
    std::size_t i = 0;
    for (; i + kStepsInSingle * n <= end; i += kStepsInSingle * n) add_steps(i, kStepsInSingle, n);
    // The rest: whole steps, and a last one whose lanes past `end` read the arrays' spare elements and are left out.
    if (i < end) add_steps(i, (end - i + n - 1) / n, end - i - (end - i - 1) / n * n);
    out_re = gabor_math::lane_total(sum_re);
    out_im = gabor_math::lane_total(sum_im);
}

GLINTSCOPE_OUT_OF_LINE_CLONES
void sum_single8(const WavelengthFreeTerms& t, std::size_t end, const WavelengthScales& w, double& out_re, double& out_im) {
    sum_single<Single8, Double4>(t, end, w, out_re, out_im);
}

// Sixteen lanes where the CPU has AVX-512.
GLINTSCOPE_AVX512
void sum_single16(const WavelengthFreeTerms& t, std::size_t end, const WavelengthScales& w, double& out_re,
                  double& out_im) {
    sum_single<Single16, gabor_math::Double8>(t, end, w, out_re, out_im);
}

// The arrays that wavelength_free_terms reads and writes, as plain pointers: taken by value, they let
// its loop vectorise (read from the vectors inside the function, GCC would not).
struct KernelColumns {
    const double* __restrict px;
    const double* __restrict py;
    const double* __restrict height;
    const double* __restrict slope_x;
    const double* __restrict slope_y;
    const double* __restrict weight;
    const double* __restrict hxx;
    const double* __restrict hxy;
    const double* __restrict hyy;
};
struct TermColumns {
    float* __restrict length_squared;
    float* __restrict adjugate_form;
    float* __restrict determinant;
    float* __restrict trace;
    double* __restrict phase;
    float* __restrict weight;
    double* __restrict first_wavelength_squared;
};

GLINTSCOPE_OUT_OF_LINE_CLONES
void fill_wavelength_free_terms(std::size_t n, const KernelColumns k, const TermColumns t, const KernelGrid& grid,
                                const TransformPoint& at) {
    const double psi_x = at.vx;
    const double psi_y = at.vy;
    const double xi3_value = at.xi3_over_lambda;
    const double xi2_gx = at.xi2_gx;
    const double xi2_gy = at.xi2_gy;
    const double inverse_reach2 = 1.0 / (grid.reach * grid.reach);
    const double spread_scale = grid.chirp_scale * xi3_value;
    for (std::size_t i = 0; i < n; ++i) {
        const double ux = psi_x + xi3_value * k.slope_x[i];  // U = λ(v + a_k) (Yan 2018 eq. 15)
        const double uy = psi_y + xi3_value * k.slope_y[i];
        const double ux2 = ux * ux;
        const double uy2 = uy * uy;
        t.length_squared[i] = static_cast<float>(ux2 + uy2);
        t.adjugate_form[i] = static_cast<float>(k.hyy[i] * ux2 - 2.0 * k.hxy[i] * ux * uy + k.hxx[i] * uy2);
        t.determinant[i] = static_cast<float>(k.hxx[i] * k.hyy[i] - k.hxy[i] * k.hxy[i]);
        t.trace[i] = static_cast<float>(k.hxx[i] + k.hyy[i]);
        t.phase[i] = xi3_value * k.height[i] + k.px[i] * psi_x + k.py[i] * psi_y;
        // Where ξ2 does not depend on H' (all models but Kirchhoff) its slope terms are 0 and ξ2 is 1 exactly.
        t.weight[i] = static_cast<float>(k.weight[i] * (1.0 - xi2_gx * k.slope_x[i] - xi2_gy * k.slope_y[i]));
        const double spread = spread_scale * spectral_radius(k.hxx[i], k.hxy[i], k.hyy[i]);
        t.first_wavelength_squared[i] = (ux2 > uy2 ? ux2 : uy2) * inverse_reach2 - spread * spread;
    }
}

// One step of n (8 or 16) second-order terms i … i + n − 1 of `k` at one (ω_i, ω_o, λ) (those
// from `valid` on left out), in single precision as add_single_step's: the factors that depend on
// H' and H'' and the phase's fraction of a turn in double, then rounded; the cut decided in double
// with add_chirped_term's arithmetic, so the same kernels are within it.
template <typename F, typename D>
[[gnu::always_inline]] inline SingleStep<F> kernel_step(const KernelColumns& k, std::size_t i, std::size_t valid,
                                                        const TransformPoint& point, double reach2,
                                                        double chirp_scale) {
    constexpr std::size_t n = sizeof(F) / sizeof(float);
    const double e = chirp_scale * point.xi3_over_lambda;
    struct Half {
        D length_squared, adjugate_form, determinant, trace, weight, fraction;
        decltype(D{} < D{}) within;
    };
    const auto half = [&](std::size_t at) __attribute__((always_inline)) {
        using gabor_math::lanes;
        const D slope_x = lanes<D>(k.slope_x + at), slope_y = lanes<D>(k.slope_y + at);
        const D hxx = lanes<D>(k.hxx + at), hxy = lanes<D>(k.hxy + at), hyy = lanes<D>(k.hyy + at);
        const D ux = point.vx + point.xi3_over_lambda * slope_x;  // v + a_k (Yan 2018 eq. 15)
        const D uy = point.vy + point.xi3_over_lambda * slope_y;
        const D ux2 = ux * ux;
        const D uy2 = uy * uy;
        Half h;
        h.length_squared = ux2 + uy2;
        h.adjugate_form = hyy * ux2 - 2.0 * hxy * ux * uy + hxx * uy2;
        h.determinant = hxx * hyy - hxy * hxy;
        h.trace = hxx + hyy;
        h.weight = lanes<D>(k.weight + at) * (1.0 - point.xi2_gx * slope_x - point.xi2_gy * slope_y);
        h.fraction = turn_fraction(point.xi3_over_lambda * lanes<D>(k.height + at) + lanes<D>(k.px + at) * point.vx +
                                   lanes<D>(k.py + at) * point.vy);
        const D exx = e * hxx, exy = e * hxy, eyy = e * hyy;
        const D half_difference = 0.5 * (exx - eyy);
        const D mean = 0.5 * (exx + eyy);
        D radius;
        const D radius_squared = half_difference * half_difference + exy * exy;
        for (std::size_t lane = 0; lane < n / 2; ++lane) radius[lane] = std::sqrt(radius_squared[lane]);
        const D epsilon = (mean < 0.0 ? -mean : mean) + radius;
        const D reach2_k = reach2 * (1.0 + epsilon * epsilon);
        h.within = (ux2 > uy2 ? ux2 : uy2) <= reach2_k;  // both within: one compare, which GCC keeps in vectors
        return h;
    };
    const Half low = half(i), high = half(i + n / 2);
    SingleStep<F> step;
    step.fraction = joined_in_single<F>(low.fraction, high.fraction);
    step.length_squared = joined_in_single<F>(low.length_squared, high.length_squared);
    step.adjugate_form = joined_in_single<F>(low.adjugate_form, high.adjugate_form);
    step.determinant = joined_in_single<F>(low.determinant, high.determinant);
    step.trace = joined_in_single<F>(low.trace, high.trace);
    step.weight = joined_in_single<F>(low.weight, high.weight);
    step.within = first_lanes<F>(joined_mask<F>(low.within, high.within), valid);
    return step;
}

// Σ over second-order kernels [0, end) at one wavelength, each term in single precision
// (kernel_step), summed as sum_single sums: kStepsInSingle steps in single, then in double. The
// last, partial step reads a zero-padded copy of its kernels.
template <typename F, typename D>
[[gnu::always_inline]] inline void sum_kernels_single(const KernelColumns& k, std::size_t end,
                                                      const TransformPoint& point, double reach2, double beta,
                                                      double chirp_scale, double& out_re, double& out_im) {
    constexpr std::size_t n = sizeof(F) / sizeof(float);
    constexpr std::size_t kStepsInSingle = 4;
    WavelengthScales scales;  // at the query's own wavelength: E = s H'', β uᵀu and β uᵀ adj(E) u
    scales.s = chirp_scale * point.xi3_over_lambda;
    scales.s_squared = scales.s * scales.s;
    scales.beta_over_lambda2 = beta;
    scales.beta_s_over_lambda2 = beta * scales.s;
    D sum_re = D{} + 0.0;
    D sum_im = sum_re;
    const auto add_steps = [&](const KernelColumns& columns, std::size_t first, std::size_t steps,
                               std::size_t valid_in_last) __attribute__((always_inline)) {
        F re = F{} + 0.0f;
        F im = re;
        for (std::size_t s = 0; s < steps; ++s)
            add_single_terms(kernel_step<F, D>(columns, first + s * n, s + 1 == steps ? valid_in_last : n, point,
                                               reach2, chirp_scale),
                             scales, re, im);
        sum_re += half_in_double(re, 0) + half_in_double(re, 1);
        sum_im += half_in_double(im, 0) + half_in_double(im, 1);
    };
    std::size_t i = 0;
    for (; i + kStepsInSingle * n <= end; i += kStepsInSingle * n) add_steps(k, i, kStepsInSingle, n);
    for (; i + n <= end; i += n) add_steps(k, i, 1, n);
    if (i < end) {
        std::array<std::array<double, n>, 9> padded{};
        const double* const from[9] = {k.px, k.py, k.height, k.slope_x, k.slope_y, k.weight, k.hxx, k.hxy, k.hyy};
        for (std::size_t a = 0; a < 9; ++a) std::copy(from[a] + i, from[a] + end, padded[a].begin());
        const KernelColumns tail{padded[0].data(), padded[1].data(), padded[2].data(), padded[3].data(), padded[4].data(),
                                 padded[5].data(), padded[6].data(), padded[7].data(), padded[8].data()};
        add_steps(tail, 0, 1, end - i);
    }
    out_re = gabor_math::lane_total(sum_re);
    out_im = gabor_math::lane_total(sum_im);
}

GLINTSCOPE_OUT_OF_LINE_CLONES
void sum_kernels_single8(const KernelColumns& k, std::size_t end, const TransformPoint& point, double reach2,
                         double beta, double chirp_scale, double& out_re, double& out_im) {
    sum_kernels_single<Single8, Double4>(k, end, point, reach2, beta, chirp_scale, out_re, out_im);
}

GLINTSCOPE_AVX512
void sum_kernels_single16(const KernelColumns& k, std::size_t end, const TransformPoint& point, double reach2,
                          double beta, double chirp_scale, double& out_re, double& out_im) {
    sum_kernels_single<Single16, gabor_math::Double8>(k, end, point, reach2, beta, chirp_scale, out_re, out_im);
}

template <bool SlopeFactor>
[[gnu::always_inline]] inline void sum_chirped_terms_with(const KernelArrays& k, std::size_t begin, std::size_t end,
                                                          const TransformPoint& point, double reach, double beta,
                                                          double chirp_scale, double& out_re, double& out_im) {
    const double reach2 = reach * reach;
    const auto add = [&](std::size_t i, auto& re, auto& im, auto&) __attribute__((always_inline)) {
        using T = std::decay_t<decltype(re)>;
        using gabor_math::lanes;
        add_chirped_term<T, SlopeFactor>(lanes<T>(&k.px[i]), lanes<T>(&k.py[i]), lanes<T>(&k.height[i]),
                                         lanes<T>(&k.slope_x[i]), lanes<T>(&k.slope_y[i]), lanes<T>(&k.weight[i]),
                                         lanes<T>(&k.curvature_xx[i]), lanes<T>(&k.curvature_xy[i]),
                                         lanes<T>(&k.curvature_yy[i]), point, reach2, beta, chirp_scale, re, im);
    };
    double unused = 0.0;
    gabor_math::sum_in_lanes(begin, end, add, out_re, out_im, unused);
}

// Compiled without ξ2's slope terms where it is 1 (every model but Kirchhoff): two multiply-adds and
// two registers per step fewer, the same sums bit for bit.
GLINTSCOPE_OUT_OF_LINE_CLONES_V4
void sum_chirped_terms(const KernelArrays& k, std::size_t begin, std::size_t end, const TransformPoint& point,
                       double reach, double beta, double chirp_scale, double& out_re, double& out_im) {
    if (point.xi2_gx == 0.0 && point.xi2_gy == 0.0)
        sum_chirped_terms_with<false>(k, begin, end, point, reach, beta, chirp_scale, out_re, out_im);
    else
        sum_chirped_terms_with<true>(k, begin, end, point, reach, beta, chirp_scale, out_re, out_im);
}

}  // namespace

KernelGrid kernel_grid(double texel_um, const GaborSettings& settings) {
    KernelGrid grid;
    grid.kernels_per_texel = settings.kernels_per_texel;
    grid.spacing_um = texel_um / settings.kernels_per_texel;
    grid.sigma_um = 0.5 * grid.spacing_um;
    // The transform's Gaussian e^{−2π²σ²|v + a|²} has standard deviation 1/(2πσ) in v.
    grid.reach = settings.kernel_sigmas / (2.0 * pi * grid.sigma_um);
    grid.beta = 2.0 * pi * pi * grid.sigma_um * grid.sigma_um;
    grid.order = settings.order;
    grid.chirp_scale = 2.0 * pi * grid.sigma_um * grid.sigma_um;
    return grid;
}

void evaluate_kernels(const BicubicInterpolant& surface, const KernelGrid& grid, long long i0, long long j0, int nx,
                      int ny, SurfacePoint* out) {
    if (grid.kernels_per_texel == 1)
        surface.evaluate_samples(i0, j0, nx, ny, out);
    else
        surface.evaluate_grid(grid.centre(i0), grid.centre(j0), grid.spacing_um, nx, ny, out);
}

SurfaceCurvature kernel_curvature(const BicubicInterpolant& surface, const KernelGrid& grid, long long i, long long j) {
    if (grid.kernels_per_texel == 1) {
        const auto wrapped = [](long long index, int n) { return static_cast<int>(((index % n) + n) % n); };
        return surface.sample_curvature(wrapped(i, surface.cols()), wrapped(j, surface.rows()));
    }
    return surface.curvature(grid.centre(i), grid.centre(j));
}

CoherenceWindow::CoherenceWindow(const Footprint& footprint, double footprint_sigmas) {
    box_ = footprint.shape == FootprintShape::box;
    if (box_) {
        half_extent_um_ = {0.5 * box_width_um(footprint), 0.5 * box_height_um(footprint)};
        area_um2_ = box_width_um(footprint) * box_height_um(footprint);
    } else {
        const double sigma = footprint.sigma_um;
        inverse_two_variance_ = 1.0 / (2.0 * sigma * sigma);
        half_extent_um_ = {footprint_sigmas * sigma, footprint_sigmas * sigma};
        radius_squared_ = half_extent_um_.x * half_extent_um_.x;
        area_um2_ = pi * sigma * sigma;
    }
}

void CoherenceWindow::check_kernel_count(const KernelGrid& grid) const {
    const double kernels = (2.0 * half_extent_um_.x / grid.spacing_um + 1.0) * (2.0 * half_extent_um_.y / grid.spacing_um + 1.0);
    if (kernels > kMaxFootprintKernels) {
        char message[200];
        std::snprintf(message, sizeof message,
                      "gabor: the footprint covers %.3g kernels (limit %.3g); use a smaller footprint or fewer "
                      "kernels_per_texel",
                      kernels, kMaxFootprintKernels);
        throw Error(message);
    }
}

namespace {

constexpr int kBlockKernels = 8;  // kernels gathered in blocks of this side (their order)

// Kernel indices i with centre (i + ½) l in [centre − extent, centre + extent].
void index_range(double centre, double extent, double spacing, long long& first, long long& last) {
    first = static_cast<long long>(std::ceil((centre - extent) / spacing - 0.5));
    last = static_cast<long long>(std::floor((centre + extent) / spacing - 0.5));
}

}  // namespace

FootprintKernels gather_kernels(const BicubicInterpolant& surface, const KernelGrid& grid,
                                const CoherenceWindow& window, Point2 centre) {
    window.check_kernel_count(grid);
    long long i0, i1, j0, j1;
    index_range(centre.x, window.half_extent_um().x, grid.spacing_um, i0, i1);
    index_range(centre.y, window.half_extent_um().y, grid.spacing_um, j0, j1);
    const double reference_height = surface.height(centre.x, centre.y);
    const double weight_scale = grid.spacing_um * grid.spacing_um;
    FootprintKernels kernels;
    std::vector<SurfacePoint> row(kBlockKernels);
    for (long long bj = j0; bj <= j1; bj += kBlockKernels)
        for (long long bi = i0; bi <= i1; bi += kBlockKernels) {
            for (long long j = bj; j <= std::min(j1, bj + kBlockKernels - 1); ++j) {
                const double py = grid.centre(j) - centre.y;
                long long first = 0;
                long long last = -1;
                if (!window.row_span(grid, centre.x, py, bi, std::min(i1, bi + kBlockKernels - 1), first, last))
                    continue;
                const int count = static_cast<int>(last - first + 1);
                evaluate_kernels(surface, grid, first, j, count, 1, row.data());
                kernels.arrays.reserve_more(count);
                for (int k = 0; k < count; ++k) {
                    const double px = grid.centre(first + k) - centre.x;
                    kernels.arrays.push(px, py, row[k], reference_height, window.weight(px, py) * weight_scale);
                    if (grid.order == 2)
                        kernels.arrays.set_curvature(kernels.arrays.size() - 1,
                                                     kernel_curvature(surface, grid, first + k, j));
                }
            }
        }
    return kernels;
}

FresnelAtWavelength::FresnelAtWavelength(const MaterialChoice& material, double lambda_um)
    : none_(material.name.empty()) {
    if (!none_) eta_ = complex_refractive_index(material.name, lambda_um);
}

// The same F as fresnel_reflectance(material, λ, cos θ), with the table lookup done once.
double FresnelAtWavelength::operator()(double cos_theta) const {
    return none_ ? 1.0 : fresnel_conductor(eta_, cos_theta);
}

TransformPoint transform_point(DiffractionModel model, const FresnelAtWavelength& fresnel, Vec3 omega_i,
                               Vec3 omega_o, double lambda_um, double area_um2) {
    const Vec3 psi = omega_i + omega_o;
    TransformPoint point;
    point.vx = psi.x / lambda_um;
    point.vy = psi.y / lambda_um;
    point.xi3_over_lambda = xi3(model, omega_i, omega_o) / lambda_um;
    // ξ2 is affine in H' for every model (Yan 2018 Fig. 6): read its slope coefficients off xi2().
    point.xi2_gx = 1.0 - xi2(model, omega_i, omega_o, 1.0, 0.0);
    point.xi2_gy = 1.0 - xi2(model, omega_i, omega_o, 0.0, 1.0);
    // F at the half vector: cos θ = ω_i·h = |ψ|/2.
    const double xi1 = xi1_geometric(model, omega_i, omega_o) * fresnel(0.5 * length(psi)) / (lambda_um * lambda_um);
    point.brdf_scale = xi1 / area_um2;
    return point;
}

ChirpFactors chirp_factors(const KernelArrays& kernels, const KernelGrid& grid, double xi3_over_lambda) {
    ChirpFactors c;
    c.xi3_over_lambda = xi3_over_lambda;
    const std::size_t n = kernels.size();
    for (auto* array : {&c.a_xx_re, &c.a_xx_im, &c.a_xy_re, &c.a_xy_im, &c.a_yy_re, &c.a_yy_im, &c.f_re, &c.f_im,
                        &c.reach2})
        array->resize(n);
    const double e = grid.chirp_scale * xi3_over_lambda;
    for (std::size_t k = 0; k < n; ++k) {
        const double exx = e * kernels.curvature_xx[k];
        const double exy = e * kernels.curvature_xy[k];
        const double eyy = e * kernels.curvature_yy[k];
        // M = I + iE, det M = (1 + iE_xx)(1 + iE_yy) + E_xy², M⁻¹ = adj(M)/det M (Folland 1989 App. A Thm. 1).
        const std::complex<double> det(1.0 - (exx * eyy - exy * exy), exx + eyy);
        const std::complex<double> beta_over_det = grid.beta / det;
        const std::complex<double> axx = beta_over_det * std::complex<double>(1.0, eyy);
        const std::complex<double> axy = beta_over_det * std::complex<double>(0.0, -exy);
        const std::complex<double> ayy = beta_over_det * std::complex<double>(1.0, exx);
        c.a_xx_re[k] = axx.real();
        c.a_xx_im[k] = axx.imag();
        c.a_xy_re[k] = axy.real();
        c.a_xy_im[k] = axy.imag();
        c.a_yy_re[k] = ayy.real();
        c.a_yy_im[k] = ayy.imag();
        // det^{−1/2}: the principal root, as in add_chirped_term (Re √det > 0).
        const std::complex<double> f = kernels.weight[k] / std::sqrt(det);
        c.f_re[k] = f.real();
        c.f_im[k] = f.imag();
        const double epsilon = spectral_radius(exx, exy, eyy);
        c.reach2[k] = grid.reach * grid.reach * (1.0 + epsilon * epsilon);
    }
    return c;
}

std::complex<double> sum_transforms(const KernelArrays& kernels, const ChirpFactors& factors,
                                    const std::vector<KernelRun>& runs, const TransformPoint& point) {
    double re = 0.0;
    double im = 0.0;
    sum_prepared_chirped_terms(kernels, factors, runs.data(), runs.size(), point, re, im);
    return {re, im};
}

std::complex<double> sum_transforms_and_density(const KernelArrays& kernels, const ChirpFactors& factors,
                                                const double* norm, double density_cut,
                                                const std::vector<KernelRun>& runs, const TransformPoint& point,
                                                double& density) {
    double re = 0.0;
    double im = 0.0;
    sum_prepared_chirped_terms_and_density(kernels, factors, norm, density_cut, runs.data(), runs.size(), point, re, im, density);
    return {re, im};
}

void wavelength_free_terms(const KernelArrays& kernels, const KernelGrid& grid, const TransformPoint& at_one_micron,
                           WavelengthFreeTerms& terms) {
    terms.resize(kernels.size());
    const KernelColumns in{kernels.px.data(),           kernels.py.data(),           kernels.height.data(),
                           kernels.slope_x.data(),      kernels.slope_y.data(),      kernels.weight.data(),
                           kernels.curvature_xx.data(), kernels.curvature_xy.data(), kernels.curvature_yy.data()};
    const TermColumns out{terms.length_squared.data(), terms.adjugate_form.data(), terms.determinant.data(),
                          terms.trace.data(),          terms.phase.data(),         terms.weight.data(),
                          terms.first_wavelength_squared.data()};
    fill_wavelength_free_terms(kernels.size(), in, out, grid, at_one_micron);
}

std::complex<double> sum_wavelength_free_terms(const WavelengthFreeTerms& terms, std::size_t end, double lambda_um,
                                               double xi3_over_lambda, const KernelGrid& grid) {
    WavelengthScales scales;
    scales.s = grid.chirp_scale * xi3_over_lambda;
    scales.s_squared = scales.s * scales.s;
    scales.inverse_lambda = 1.0 / lambda_um;
    scales.beta_over_lambda2 = grid.beta * scales.inverse_lambda * scales.inverse_lambda;
    scales.beta_s_over_lambda2 = scales.beta_over_lambda2 * scales.s;
    scales.lambda_squared = lambda_um * lambda_um;
    double re = 0.0;
    double im = 0.0;
    (cpu_runs_avx512() ? sum_single16 : sum_single8)(terms, end, scales, re, im);
    return {re, im};
}

std::complex<double> sum_chirped_transforms_single(const KernelArrays& kernels, std::size_t end,
                                                  const TransformPoint& point, const KernelGrid& grid) {
    const KernelColumns in{kernels.px.data(),           kernels.py.data(),           kernels.height.data(),
                           kernels.slope_x.data(),      kernels.slope_y.data(),      kernels.weight.data(),
                           kernels.curvature_xx.data(), kernels.curvature_xy.data(), kernels.curvature_yy.data()};
    double re = 0.0;
    double im = 0.0;
    (cpu_runs_avx512() ? sum_kernels_single16 : sum_kernels_single8)(in, end, point, grid.reach * grid.reach,
                                                                     grid.beta, grid.chirp_scale, re, im);
    return {re, im};
}

std::size_t count_within_cut(const WavelengthFreeTerms& terms, std::size_t end, double lambda_um) {
    const double lambda_squared = lambda_um * lambda_um;
    std::size_t count = 0;
    for (std::size_t k = 0; k < end; ++k) count += within_cut(lambda_squared, terms.first_wavelength_squared[k]);
    return count;
}

std::complex<double> sum_transforms(const KernelArrays& kernels, std::size_t begin, std::size_t end,
                                    const TransformPoint& point, const KernelGrid& grid) {
    double re = 0.0;
    double im = 0.0;
    if (grid.order == 2)
        sum_chirped_terms(kernels, begin, end, point, grid.reach, grid.beta, grid.chirp_scale, re, im);
    else
        sum_kernel_terms(kernels, begin, end, point, grid.reach, grid.beta, re, im);
    return {re, im};
}

}  // namespace glintscope::gabor
