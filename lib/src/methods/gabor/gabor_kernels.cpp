#include "gabor_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>

#include "glintscope/core/error.hpp"

// The SIMD helpers here and in gabor_math.hpp are always inlined, so the vector calling
// convention that -Wpsabi warns about never applies.
#pragma GCC diagnostic ignored "-Wpsabi"
#include "gabor_math.hpp"

namespace glintscope::gabor {
namespace {


using Double4 = double __attribute__((vector_size(32)));

[[gnu::always_inline]] inline void load4(const double* values, Double4& v) { std::memcpy(&v, values, sizeof v); }

// The kernel's amplitude where v lies in its box |v + a_k| ≤ reach, else 0 (per lane).
[[gnu::always_inline]] inline double keep_inside(double dx, double dy, double reach2, double amplitude) {
    return dx * dx <= reach2 && dy * dy <= reach2 ? amplitude : 0.0;
}

[[gnu::always_inline]] inline Double4 keep_inside(const Double4& dx, const Double4& dy, double reach2,
                                                 const Double4& amplitude) {
    const Double4 zero = {0.0, 0.0, 0.0, 0.0};
    return ((dx * dx <= reach2) & (dy * dy <= reach2)) ? amplitude : zero;
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

// Four kernels per step in SIMD lanes, the remainder one by one; each lane sums a fixed subset
// of the kernels, so the result depends only on the kernel order.
__attribute__((target_clones("arch=x86-64-v3", "default")))
void sum_kernel_terms(const KernelArrays& k, std::size_t begin, std::size_t end, const TransformPoint& point,
                      double reach, double beta, double& out_re, double& out_im) {
    const double reach2 = reach * reach;
    Double4 re4 = {0.0, 0.0, 0.0, 0.0};
    Double4 im4 = {0.0, 0.0, 0.0, 0.0};
    std::size_t i = begin;
    for (; i + 4 <= end; i += 4) {
        Double4 px, py, height, slope_x, slope_y, weight;
        load4(&k.px[i], px);
        load4(&k.py[i], py);
        load4(&k.height[i], height);
        load4(&k.slope_x[i], slope_x);
        load4(&k.slope_y[i], slope_y);
        load4(&k.weight[i], weight);
        add_term(px, py, height, slope_x, slope_y, weight, point, reach2, beta, re4, im4);
    }
    double re = 0.0;
    double im = 0.0;
    for (; i < end; ++i)
        add_term(k.px[i], k.py[i], k.height[i], k.slope_x[i], k.slope_y[i], k.weight[i], point, reach2, beta, re, im);
    out_re = ((re4[0] + re4[1]) + (re4[2] + re4[3])) + re;
    out_im = ((im4[0] + im4[1]) + (im4[2] + im4[3])) + im;
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
    return grid;
}

void evaluate_kernels(const BicubicInterpolant& surface, const KernelGrid& grid, long long i0, long long j0, int nx,
                      int ny, SurfacePoint* out) {
    if (grid.kernels_per_texel == 1)
        surface.evaluate_samples(i0, j0, nx, ny, out);
    else
        surface.evaluate_grid(grid.centre(i0), grid.centre(j0), grid.spacing_um, nx, ny, out);
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

std::complex<double> sum_transforms(const KernelArrays& kernels, std::size_t begin, std::size_t end,
                                    const TransformPoint& point, const KernelGrid& grid) {
    double re = 0.0;
    double im = 0.0;
    sum_kernel_terms(kernels, begin, end, point, grid.reach, grid.beta, re, im);
    return {re, im};
}

}  // namespace glintscope::gabor
