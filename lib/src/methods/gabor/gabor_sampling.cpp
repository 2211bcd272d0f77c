#include "gabor_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

// gabor_math's helpers are always inlined, so the vector calling convention that -Wpsabi warns
// about never applies.
#pragma GCC diagnostic ignored "-Wpsabi"
#include "gabor_math.hpp"

namespace glintscope::gabor {
namespace {

// Each Gaussian is cut where it falls to e^{−kCut} of its peak (Mahalanobis radius √(2 kCut)),
// the range of gabor_math::exp_neg; it keeps 1 − e^{−kCut} of its mass.
constexpr double kCut = 25.0;
const double kKeptMass = -std::expm1(-kCut);

struct Covariance {
    double xx, xy, yy;
    double det() const { return xx * yy - xy * xy; }
};

using Double4 = double __attribute__((vector_size(32)));

// Σ_k norm_k e^{−q_k/2} over the Gaussians' q_k = (e − μ_k)ᵀ S_k⁻¹ (e − μ_k) < 2 kCut, with
// e − μ_k = (px, py) + ξ3 H'_k; four kernels per SIMD step, the rest one by one.
__attribute__((target_clones("arch=x86-64-v3", "default")))
double sum_gaussians(const double* slope_x, const double* slope_y, const double* qxx, const double* qxy,
                     const double* qyy, const double* norm, std::size_t n, double px, double py, double xi) {
    const auto add = [&](std::size_t k, auto& sum) __attribute__((always_inline)) {
        using T = std::decay_t<decltype(sum)>;
        const T ex = px + xi * gabor_math::lanes<T>(slope_x + k);
        const T ey = py + xi * gabor_math::lanes<T>(slope_y + k);
        const T half_q = gabor_math::lanes<T>(qxx + k) * ex * ex + gabor_math::lanes<T>(qxy + k) * ex * ey + gabor_math::lanes<T>(qyy + k) * ey * ey;
        const T kept = half_q < kCut ? gabor_math::lanes<T>(norm + k) : T{} * 0.0;
        sum += kept * gabor_math::exp_neg(half_q < kCut ? half_q : T{} + kCut);
    };
    Double4 sum4 = {0.0, 0.0, 0.0, 0.0};
    std::size_t k = 0;
    for (; k + 4 <= n; k += 4) add(k, sum4);
    double sum = 0.0;
    for (; k < n; ++k) add(k, sum);
    return ((sum4[0] + sum4[1]) + (sum4[2] + sum4[3])) + sum;
}

}  // namespace

KernelMixture::KernelMixture(const KernelArrays& kernels, const KernelGrid& grid, DiffractionModel model,
                             std::vector<double> wavelengths_um)
    : model_(model), wavelengths_um_(std::move(wavelengths_um)), sigma_um_(grid.sigma_um) {
    double total = 0.0;
    for (std::size_t k = 0; k < kernels.size(); ++k) total += kernels.weight[k];
    double running = 0.0;
    for (std::size_t k = 0; k < kernels.size(); ++k) {
        if (!(kernels.weight[k] > 0.0)) continue;
        probability_.push_back(kernels.weight[k] / total);
        running += kernels.weight[k];
        cumulative_.push_back(running / total);
        slope_x_.push_back(kernels.slope_x[k]);
        slope_y_.push_back(kernels.slope_y[k]);
        // (H'')² of the symmetric H'' = [[a, b], [b, c]]: [[a² + b², b(a + c)], [b(a + c), c² + b²]].
        const bool chirped = grid.order == 2;
        const double a = chirped ? kernels.curvature_xx[k] : 0.0;
        const double b = chirped ? kernels.curvature_xy[k] : 0.0;
        const double c = chirped ? kernels.curvature_yy[k] : 0.0;
        square_xx_.push_back(a * a + b * b);
        square_xy_.push_back(b * (a + c));
        square_yy_.push_back(c * c + b * b);
    }
    if (!cumulative_.empty()) cumulative_.back() = 1.0;
    // The covariances depend on ω_i only through ξ3, and not at all without curvature.
    chirped_ = grid.order == 2;
    if (!(chirped_ && phase_depends_on_outgoing(model_)))
        for (double lambda : wavelengths_um_)
            fixed_.push_back(gaussians(lambda, curvature_scale({0.0, 0.0, 1.0})));
}

double KernelMixture::sampling_xi3(Vec3 omega_i) const {
    return xi3(model_, omega_i, {-omega_i.x, -omega_i.y, omega_i.z});
}

double KernelMixture::curvature_scale(Vec3 omega_i) const {
    const double xi = sampling_xi3(omega_i);
    return chirped_ ? sigma_um_ * sigma_um_ * xi * xi : 0.0;
}

double KernelMixture::diffraction_variance(double lambda_um) const {
    const double s = lambda_um / (2.0 * pi * sigma_um_);
    return s * s;
}

KernelMixture::Gaussians KernelMixture::gaussians(double lambda_um, double curvature) const {
    const double diffraction = diffraction_variance(lambda_um);
    Gaussians g;
    const std::size_t n = probability_.size();
    for (auto* v : {&g.qxx, &g.qxy, &g.qyy, &g.norm}) v->resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Covariance s{diffraction + curvature * square_xx_[k], curvature * square_xy_[k],
                           diffraction + curvature * square_yy_[k]};
        const double det = s.det();
        // q/2 = (S_yy e_x² − 2 S_xy e_x e_y + S_xx e_y²) / (2 det S).
        g.qxx[k] = 0.5 * s.yy / det;
        g.qxy[k] = -s.xy / det;
        g.qyy[k] = 0.5 * s.xx / det;
        // The Gaussian's normalisation 1/(2π √det S), over the mass the cut keeps.
        g.norm[k] = probability_[k] / (2.0 * pi * std::sqrt(det) * kKeptMass);
    }
    return g;
}

std::optional<Vec3> KernelMixture::draw(Vec3 omega_i, double u1, double u2) const {
    if (cumulative_.empty()) return std::nullopt;
    // u1 chooses the wavelength, then the kernel, and what is left of it the Gaussian's radius.
    const std::size_t layers = wavelengths_um_.size();
    const std::size_t layer = std::min(static_cast<std::size_t>(u1 * layers), layers - 1);
    const double u = u1 * layers - layer;
    const std::size_t k = std::min<std::size_t>(
        std::upper_bound(cumulative_.begin(), cumulative_.end(), u) - cumulative_.begin(), cumulative_.size() - 1);
    const double below = k == 0 ? 0.0 : cumulative_[k - 1];
    const double rest = std::clamp((u - below) / probability_[k], 0.0, 1.0);
    // Box–Muller with the radius cut at √(2 kCut): r² = −2 ln(1 − rest · kept mass).
    const double radius = std::sqrt(-2.0 * std::log1p(-rest * kKeptMass));
    const double z1 = radius * std::cos(2.0 * pi * u2);
    const double z2 = radius * std::sin(2.0 * pi * u2);
    const double diffraction = diffraction_variance(wavelengths_um_[layer]);
    const double curvature = curvature_scale(omega_i);
    const Covariance s{diffraction + curvature * square_xx_[k], curvature * square_xy_[k],
                       diffraction + curvature * square_yy_[k]};
    // d = μ_k + L z with L Lᵀ = S (Cholesky).
    const double l11 = std::sqrt(s.xx);
    const double l21 = s.xy / l11;
    const double l22 = std::sqrt(s.det()) / l11;
    const double xi = sampling_xi3(omega_i);
    const double dx = -omega_i.x - xi * slope_x_[k] + l11 * z1;
    const double dy = -omega_i.y - xi * slope_y_[k] + l21 * z1 + l22 * z2;
    if (!(dx * dx + dy * dy < 1.0)) return std::nullopt;
    return direction_from_disk(dx, dy);
}

DirectionSample KernelMixture::sample(Vec3 omega_i, double u1, double u2) const {
    const std::optional<Vec3> omega_o = draw(omega_i, u1, u2);
    if (!omega_o) return {};
    return {*omega_o, pdf(omega_i, *omega_o)};
}

double KernelMixture::pdf(Vec3 omega_i, Vec3 omega_o) const {
    const double xi = sampling_xi3(omega_i);
    // d − μ_k = (ω_o + ω_i)_xy + ξ3 H'_k.
    const double px = omega_o.x + omega_i.x, py = omega_o.y + omega_i.y;
    const std::size_t n = probability_.size();
    double density = 0.0;
    for (std::size_t layer = 0; layer < wavelengths_um_.size(); ++layer) {
        const Gaussians computed = fixed_.empty() ? gaussians(wavelengths_um_[layer], curvature_scale(omega_i)) : Gaussians{};
        const Gaussians& g = fixed_.empty() ? computed : fixed_[layer];
        density += sum_gaussians(slope_x_.data(), slope_y_.data(), g.qxx.data(), g.qxy.data(), g.qyy.data(),
                                 g.norm.data(), n, px, py, xi);
    }
    // The mean over wavelengths, and dA = cosθ_o dω_o.
    return density / wavelengths_um_.size() * omega_o.z;
}

}  // namespace glintscope::gabor
