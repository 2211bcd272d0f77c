#pragma once
// What gabor_lobe (images) and GaborSurface (point queries) share: the kernel grid, the
// coherence window, kernels as flat arrays, the per-direction constants and the kernel sum.
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <vector>

#include "gabor.hpp"
#include "glintscope/optics/material.hpp"

namespace glintscope::gabor {

// Kernel centres m = ((i + ½) l, (j + ½) l) for all integers i, j (x right, y up), so with K = 1
// they are the heightfield samples and the cells tile each texel exactly for any K.
struct KernelGrid {
    int kernels_per_texel = 1;  // K
    double spacing_um = 1.0;  // l = dx/K
    double sigma_um = 0.5;    // σ_k = l/2 (Yan 2018 §4.2)
    double reach = 1.0;       // kernel_sigmas/(2πσ_k), cycles/µm: half-width of each transform's box
    double beta = 0.5;        // 2π²σ_k²: |F[g_k](v)| = e^{−β|v + a_k|²} (Yan 2018 eq. 8)
    int order = 1;            // 2: chirped kernels, whose transforms carry H'' (GaborSettings::order)
    double chirp_scale = 1.0;  // 2πσ_k²: ε = chirp_scale · ξ3/λ · H'' is M − I of each chirped kernel
    double centre(long long index) const { return (static_cast<double>(index) + 0.5) * spacing_um; }
};
KernelGrid kernel_grid(double texel_um, const GaborSettings& settings);

// H and H' from the shared interpolant at the kernel centres i0 … i0 + nx − 1, j0 … j0 + ny − 1,
// into out[(j − j0)·nx + (i − i0)]. With K = 1 the centres are the samples themselves.
void evaluate_kernels(const BicubicInterpolant& surface, const KernelGrid& grid, long long i0, long long j0, int nx,
                      int ny, SurfacePoint* out);

// H'' at the kernel centre (i, j): the samples' stencil with K = 1, the interpolant's otherwise.
SurfaceCurvature kernel_curvature(const BicubicInterpolant& surface, const KernelGrid& grid, long long i, long long j);

// ρ(H'') = max |eigenvalue| of a curvature: a chirped kernel's transform spreads by ε = 2πσ²ξ3ρ/λ.
inline double spectral_radius(double hxx, double hxy, double hyy) {
    const double half_difference = 0.5 * (hxx - hyy);
    return std::fabs(0.5 * (hxx + hyy)) + std::sqrt(half_difference * half_difference + hxy * hxy);
}

// A chirped kernel's transform is cut to |v + a_k| ≤ reach·√(1 + ε²) per axis: along H'''s
// steepest eigenvector the Gaussian e^{−2π²σ² Re(uᵀM⁻¹u)} has standard deviation √(1 + ε²)/(2πσ), so
// the cut lies at the same fraction of the peak as a first-order kernel's.
inline double chirped_reach(double reach, double chirp_scale, double xi3_over_lambda, double radius) {
    const double epsilon = chirp_scale * xi3_over_lambda * radius;
    return reach * std::sqrt(1.0 + epsilon * epsilon);
}

// A footprint may hold at most this many kernels (their arrays take 48 bytes each).
constexpr double kMaxFootprintKernels = 2e7;

// w(s − x_c) and its support (conventions.md "Coherence / footprint"), in coordinates p = s − x_c.
class CoherenceWindow {
public:
    CoherenceWindow(const Footprint& footprint, double footprint_sigmas);

    // The support lies in the rectangle |p_x| ≤ half_extent_um().x, |p_y| ≤ half_extent_um().y
    // (a box's half sides; a Gaussian's truncation radius on both).
    Point2 half_extent_um() const { return half_extent_um_; }
    bool contains(double px, double py) const {
        return box_ ? std::fabs(px) <= half_extent_um_.x && std::fabs(py) <= half_extent_um_.y
                    : px * px + py * py <= radius_squared_;
    }
    double weight(double px, double py) const {  // separable: weight(px, 0) · weight(0, py)
        return box_ ? 1.0 : std::exp(-(px * px + py * py) * inverse_two_variance_);
    }
    // The kernels i in [first, last] of a kernel row at p_y whose centres the support contains,
    // searched within [lo, hi]; false if there are none.
    bool row_span(const KernelGrid& grid, double centre_x, double py, long long lo, long long hi, long long& first,
                  long long& last) const;
    // Whether the support meets the rectangle [x_min, x_max] × [y_min, y_max] of p.
    bool overlaps(double x_min, double x_max, double y_min, double y_max) const;
    double area_um2() const { return area_um2_; }  // A_c = ∫|w|² ds
    // Throws Error when the support's bounding rectangle holds more than kMaxFootprintKernels kernels.
    void check_kernel_count(const KernelGrid& grid) const;

private:
    bool box_ = false;
    double inverse_two_variance_ = 0.0;  // 1/(2σ_c²)
    double radius_squared_ = 0.0;  // Gaussian support: |p| ≤ footprint_sigmas σ_c
    Point2 half_extent_um_;
    double area_um2_ = 0.0;
};

// An integral-valued index clamped to [lo, hi] exactly: a clamp in double loses integers above
// 2^53 and let a span leave its buffer, so only the conversion to integer goes through double.
inline long long clamp_kernel_index(double index, long long lo, long long hi) {
    constexpr double limit = 0x1p62;  // inside the long long range, beyond any footprint index
    return std::clamp(static_cast<long long>(std::clamp(index, -limit, limit)), lo, hi);
}

// Inline: a point query calls these once per kernel row and per hierarchy node.
inline bool CoherenceWindow::row_span(const KernelGrid& grid, double centre_x, double py, long long lo,
                                      long long hi, long long& first, long long& last) const {
    const double reach2 = box_ ? (std::fabs(py) <= half_extent_um_.y ? half_extent_um_.x * half_extent_um_.x : -1.0)
                               : radius_squared_ - py * py;
    if (reach2 < 0.0) return false;
    // The support's chord at p_y, in kernel indices, then confirmed with contains() at its ends.
    const double half = std::sqrt(reach2);
    const double from = std::ceil((centre_x - half) / grid.spacing_um - 0.5);
    const double to = std::floor((centre_x + half) / grid.spacing_um - 0.5);
    first = clamp_kernel_index(from, lo, hi + 1);
    last = clamp_kernel_index(to, lo - 1, hi);
    while (first > lo && contains(grid.centre(first - 1) - centre_x, py)) --first;
    while (first <= last && !contains(grid.centre(first) - centre_x, py)) ++first;
    while (last < hi && last >= first && contains(grid.centre(last + 1) - centre_x, py)) ++last;
    while (last >= first && !contains(grid.centre(last) - centre_x, py)) --last;
    return first <= last;
}

inline bool CoherenceWindow::overlaps(double x_min, double x_max, double y_min, double y_max) const {
    if (box_)
        return x_max >= -half_extent_um_.x && x_min <= half_extent_um_.x && y_max >= -half_extent_um_.y &&
               y_min <= half_extent_um_.y;
    const double dx = std::max({x_min, -x_max, 0.0});  // distance from the origin to the rectangle
    const double dy = std::max({y_min, -y_max, 0.0});
    return dx * dx + dy * dy <= radius_squared_;
}

// Kernels as parallel arrays: p = m − x_c, H(m) − H_ref, H'(m), and the weight w_k l². The
// arrays only grow, so a thread can reuse one set for every query.
class KernelArrays {
public:
    std::size_t size() const { return size_; }
    void clear() { size_ = 0; }
    // Makes room for `count` more push() calls.
    void reserve_more(std::size_t count) {
        if (size_ + count <= px.size()) return;
        const std::size_t capacity = std::max(2 * px.size(), size_ + count);
        for (auto* array : {&px, &py, &height, &slope_x, &slope_y, &weight, &curvature_xx, &curvature_xy,
                            &curvature_yy})
            array->resize(capacity);
    }
    // Appends `count` unset kernels, returning the index of the first, for callers that fill
    // the arrays directly.
    std::size_t extend(std::size_t count) {
        reserve_more(count);
        size_ += count;
        return size_ - count;
    }
    // Sets the size to `count` kernels (new ones unset), to be filled by copy().
    void resize(std::size_t count) {
        clear();
        reserve_more(count);
        size_ = count;
    }
    void copy(std::size_t to, const KernelArrays& source, std::size_t from) {
        px[to] = source.px[from];
        py[to] = source.py[from];
        height[to] = source.height[from];
        slope_x[to] = source.slope_x[from];
        slope_y[to] = source.slope_y[from];
        weight[to] = source.weight[from];
        curvature_xx[to] = source.curvature_xx[from];
        curvature_xy[to] = source.curvature_xy[from];
        curvature_yy[to] = source.curvature_yy[from];
    }
    // Sets H'' of kernel k (second order only; first-order sums never read it).
    void set_curvature(std::size_t k, const SurfaceCurvature& c) {
        curvature_xx[k] = c.d2h_dx2;
        curvature_xy[k] = c.d2h_dxdy;
        curvature_yy[k] = c.d2h_dy2;
    }
    void push(double x, double y, const SurfacePoint& at_centre, double reference_height, double w) {
        push(x, y, at_centre.height - reference_height, at_centre.dh_dx, at_centre.dh_dy, w);
    }
    void push(double x, double y, double relative_height, double dh_dx, double dh_dy, double w) {
        px[size_] = x;
        py[size_] = y;
        height[size_] = relative_height;
        slope_x[size_] = dh_dx;
        slope_y[size_] = dh_dy;
        weight[size_] = w;
        ++size_;
    }

    std::vector<double> px;
    std::vector<double> py;
    std::vector<double> height;
    std::vector<double> slope_x;
    std::vector<double> slope_y;
    std::vector<double> weight;
    std::vector<double> curvature_xx;  // H'' (second order)
    std::vector<double> curvature_xy;
    std::vector<double> curvature_yy;

private:
    std::size_t size_ = 0;
};

// The kernels inside the coherence window centred at `centre`, gathered block by block (8 × 8
// cells of the kernel grid), which fixes their order and so the rounding of every sum over them;
// H'' too at second order. Heights are relative to H(centre). Throws Error (check_kernel_count)
// for a footprint of too many kernels.
struct FootprintKernels {
    KernelArrays arrays;
};
FootprintKernels gather_kernels(const BicubicInterpolant& surface, const KernelGrid& grid,
                                const CoherenceWindow& window, Point2 centre);

// The constants of one (ω_i, ω_o, λ): v = ψ̄/λ, ξ3/λ, Kirchhoff's ξ2 = 1 − g·H' (g = 0 for the
// other models, whose ξ2 = 1), and the factor ξ1/A_c that turns |Σ|² into f_r.
struct TransformPoint {
    double vx = 0.0;
    double vy = 0.0;
    double xi3_over_lambda = 0.0;
    double xi2_gx = 0.0;
    double xi2_gy = 0.0;
    double brdf_scale = 0.0;  // ξ1 (with F/λ²) / A_c
};

// F(λ, cos θ) of a material at one wavelength, the refractive index looked up once.
class FresnelAtWavelength {
public:
    FresnelAtWavelength(const MaterialChoice& material, double lambda_um);
    double operator()(double cos_theta) const;

private:
    bool none_ = true;
    ComplexIndex eta_;
};

// Whether some slope H' in [x_min, x_max] × [y_min, y_max] puts v + ξ3 H'/λ inside the box
// |·| ≤ reach in both axes (ξ3 > 0 for every model): the directional pruning test of Yan 2018 §5.
inline bool slopes_reach(double vx, double vy, double xi3_over_lambda, double reach, double x_min, double x_max,
                         double y_min, double y_max) {
    return vx + xi3_over_lambda * x_min <= reach && vx + xi3_over_lambda * x_max >= -reach &&
           vy + xi3_over_lambda * y_min <= reach && vy + xi3_over_lambda * y_max >= -reach;
}

TransformPoint transform_point(DiffractionModel model, const FresnelAtWavelength& fresnel, Vec3 omega_i,
                               Vec3 omega_o, double lambda_um, double area_um2);

// Σ_k w_k C_k F[g_k](v) over kernels [begin, end), each transform cut to its box |v + a_k| ≤ reach
// (second order: ≤ chirped_reach, and each term also carries det(M_k)^{−1/2} e^{−β uᵀM_k⁻¹u},
// M_k = I + iε_k, ε_k = 2πσ_k² ξ3 H''_k/λ, in place of e^{−β|u|²}: gabor_kernel_transform).
// With C_k (Yan 2018 eq. 14), a_k (Yan 2018 eq. 15) and F[g_k] (Yan 2018 eq. 8), m_k·a_k = ξ3 H'_k·m_k/λ cancels the
// H'·m term of C_k, leaving
//   w_k C_k F[g_k](v) = w_k l² ξ2 e^{−i2π(ξ3 H_k/λ + m_k·v)} e^{−β|v + a_k|²}.
// Measuring m from x_c and H from H_ref multiplies every term by the same unit phasor
// e^{i2π(x_c·v + ξ3 H_ref/λ)}, which |Σ|² drops, and keeps the phases small.
std::complex<double> sum_transforms(const KernelArrays& kernels, std::size_t begin, std::size_t end,
                                    const TransformPoint& point, const KernelGrid& grid);

// sum_transforms of second-order kernels [0, end), each term in single precision as
// sum_wavelength_free_terms computes it (the phase reduced to [−½, ½] turn and the factors that
// depend on H' and H'' in double first), within 2^−20 of its size; the cut is decided in double
// with sum_transforms' arithmetic, so exactly its kernels are summed. 16 terms per step with
// AVX-512, 8 without.
std::complex<double> sum_chirped_transforms_single(const KernelArrays& kernels, std::size_t end,
                                                  const TransformPoint& point, const KernelGrid& grid);

// Second-order terms of one (ω_i, ω_o) prepared for sums at several wavelengths. With ψ = ω_i + ω_o
// and U_k = ψ + ξ3 H'_k, a term depends on λ only through 1/λ and s = 2πσ²ξ3/λ (E = s H''_k):
//   u = v + a_k = U_k/λ,   uᵀ adj(M) u = (|U|² + i s Uᵀ adj(H'') U)/λ²,
//   det M = 1 − s² det H'' + i s tr H'',   ξ3 H_k/λ + m_k·v = (ξ3 H_k + m_k·ψ)/λ,
// so these are computed once per kernel instead of once per wavelength. Its cut |u| ≤ reach·√(1 + ε²)
// per axis, ε = s ρ(H''), holds exactly when λ² ≥ λ_k² = max_axis U²/reach² − (2πσ² ξ3 ρ)².
// The factors that only scale a term are single precision, as the sums over them (below); the
// phase, hundreds of turns, and the cut stay double.
struct WavelengthFreeTerms {
    static constexpr std::size_t kSpare = 16;  // elements past n: a sum's last step reads a whole step
    std::vector<float> length_squared;  // |U|²
    std::vector<float> adjugate_form;   // Uᵀ adj(H'') U = H''_yy U_x² − 2 H''_xy U_x U_y + H''_xx U_y²
    std::vector<float> determinant;     // det H''
    std::vector<float> trace;           // tr H''
    std::vector<float> weight;          // w_k l² ξ2 (ξ2 does not depend on λ)
    std::vector<double> phase;          // ξ3 H_k + m_k·ψ
    std::vector<double> first_wavelength_squared;  // λ_k²
    void resize(std::size_t n) {
        for (auto* array : {&length_squared, &adjugate_form, &determinant, &trace, &weight}) array->resize(n + kSpare);
        for (auto* array : {&phase, &first_wavelength_squared}) array->resize(n + kSpare);
    }
};
// The terms of second-order kernels [0, kernels.size()) for the directions of `at_one_micron`,
// transform_point's at λ = 1 µm (whose v is ψ and whose ξ3/λ is ξ3), into `terms`.
void wavelength_free_terms(const KernelArrays& kernels, const KernelGrid& grid, const TransformPoint& at_one_micron,
                           WavelengthFreeTerms& terms);
// Σ_k over the terms [0, end) within their cut at wavelength λ (λ_k² ≤ λ²) of the second-order
// sum_transforms; the others are left out lane by lane. Each term is computed in
// single precision after its phase is reduced to [−½, ½] turn in double, and summed in double: a
// term's error is below 2^−20 of its size, so the sum's is below 2^−20 Σ_k |w_k l² ξ2| (tests:
// gabor_chirped_test.cpp); 16 terms per step with AVX-512, 8 without.
std::complex<double> sum_wavelength_free_terms(const WavelengthFreeTerms& terms, std::size_t end, double lambda_um,
                                               double xi3_over_lambda, const KernelGrid& grid);
// How many of the terms [0, end) are within their cut at λ: those sum_wavelength_free_terms adds.
std::size_t count_within_cut(const WavelengthFreeTerms& terms, std::size_t end, double lambda_um);

// The factors of second-order terms that depend on a kernel and on ξ3/λ but not on v, for one
// ξ3/λ: with E = 2πσ² ξ3 H''/λ and M = I + iE, A = β M⁻¹ (complex symmetric: xx, xy, yy),
// f = w l² det(M)^{−1/2} and the widened cut reach²(1 + ρ(E)²). Where ξ3 does not depend on the
// directions (OHS, R-OHS) a footprint evaluated at many directions computes them once per
// wavelength instead of once per term (a division and three square roots).
struct ChirpFactors {
    double xi3_over_lambda = 0.0;
    std::vector<double> a_xx_re, a_xx_im, a_xy_re, a_xy_im, a_yy_re, a_yy_im, f_re, f_im, reach2;
};
ChirpFactors chirp_factors(const KernelArrays& kernels, const KernelGrid& grid, double xi3_over_lambda);

// Kernels [begin, end) of a footprint's arrays.
struct KernelRun {
    std::size_t begin = 0;
    std::size_t end = 0;
};

// sum_transforms of second-order kernels, those of the runs, with their factors at
// point.xi3_over_lambda (which must equal factors.xi3_over_lambda): the same terms,
// w l² ξ2 e^{−i2π(ξ3 H/λ + m·v)} det(M)^{−1/2} e^{−uᵀAu}, each cut at its widened reach.
std::complex<double> sum_transforms(const KernelArrays& kernels, const ChirpFactors& factors,
                                    const std::vector<KernelRun>& runs, const TransformPoint& point);

// That sum, and in the same pass Σ norm_k e^{−Re q_k} over the same kernels where
// Re q_k < density_cut (≤ 25), added to `density`: where the sampler's ξ3 is the point's (OHS, R-OHS), Re q_k = β uᵀRe(M⁻¹)u
// is the exponent of kernel k's sampling Gaussian at d = λv − ω̄_i, so with norm_k its weight over
// its normalisation (gabor_sampling.hpp) this is the mixture's density from these kernels, and
// the two sums share each kernel's exponential.
std::complex<double> sum_transforms_and_density(const KernelArrays& kernels, const ChirpFactors& factors,
                                                const double* norm, double density_cut,
                                                const std::vector<KernelRun>& runs, const TransformPoint& point,
                                                double& density);

}  // namespace glintscope::gabor
