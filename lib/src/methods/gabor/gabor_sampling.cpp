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

// The cut of the mixture's Gaussians, ½eᵀS⁻¹e < cut (Mahalanobis radius √(2 cut)), within
// gabor_math::exp_neg's range (25). Where the sampler's ξ3 is the model's (OHS, R-OHS) a kernel's
// Gaussian is its transform's magnitude e^{−Re q}, Re q = β uᵀ(I + E²)⁻¹u ≤ β|u|², so the cut
// 2βR² = kernel_sigmas² holds the kernel's whole box |u_x|, |u_y| ≤ R (its corners' Re q ≤ 2βR²),
// and at second order all of the widened box where the transform is above e^{−cut} of its peak:
// every d the kernel adds to f_r. Other models place the Gaussians with the mirror direction's ξ3,
// off the transforms' peaks, and keep the widest cut for that slack.
double gaussian_cut(const KernelGrid& grid, DiffractionModel model) {
    constexpr double widest = 25.0;
    return phase_depends_on_outgoing(model) ? widest : std::min(widest, 2.0 * grid.beta * grid.reach * grid.reach);
}

struct Covariance {
    double xx, xy, yy;
    double det() const { return xx * yy - xy * xy; }
};

// Σ_k norm_k e^{−q_k/2} over the Gaussians' q_k = (e − μ_k)ᵀ S_k⁻¹ (e − μ_k) < 2 cut, with
// e − μ_k = (px, py) + ξ3 H'_k, over the kernels of the runs, indices from `first` (where the
// arrays start; the tail's lanes may read kernels before a run).
__attribute__((target_clones("arch=x86-64-v3", "default")))
double sum_cut_gaussians(const double* slope_x, const double* slope_y, const double* qxx, const double* qxy,
                         const double* qyy, const double* norm, double cut, std::size_t first,
                         const KernelRun* runs, std::size_t run_count, double px, double py, double xi) {
    const auto add = [&](std::size_t k, auto& sum, auto&, auto&) __attribute__((always_inline)) {
        using T = std::decay_t<decltype(sum)>;
        const T ex = px + xi * gabor_math::lanes<T>(slope_x + k);
        const T ey = py + xi * gabor_math::lanes<T>(slope_y + k);
        const T half_q = gabor_math::lanes<T>(qxx + k) * ex * ex + gabor_math::lanes<T>(qxy + k) * ex * ey + gabor_math::lanes<T>(qyy + k) * ey * ey;
        const T kept = half_q < cut ? gabor_math::lanes<T>(norm + k) : T{} * 0.0;
        sum += kept * gabor_math::exp_neg(half_q < cut ? half_q : T{} + cut);
    };
    double total = 0.0;
    for (std::size_t r = 0; r < run_count; ++r) {
        double sum = 0.0;
        double unused = 0.0;
        gabor_math::sum_in_lanes(runs[r].begin - first, runs[r].end - first, add, sum, unused, unused);
        total += sum;
    }
    return total;
}

}  // namespace

KernelMixture::KernelMixture(std::shared_ptr<const SlopeIndex> index, DiffractionModel model,
                             std::vector<double> wavelengths_um)
    : index_(std::move(index)),
      model_(model),
      wavelengths_um_(std::move(wavelengths_um)),
      sigma_um_(index_->grid().sigma_um),
      chirped_(index_->grid().order == 2),
      cut_(gaussian_cut(index_->grid(), model)),
      kept_mass_(-std::expm1(-cut_)) {
    const KernelArrays& kernels = index_->kernels();
    const std::size_t n = kernels.size();
    double total = 0.0;
    for (std::size_t k = 0; k < n; ++k) total += kernels.weight[k];
    double running = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        probability_.push_back(kernels.weight[k] / total);
        running += kernels.weight[k];
        cumulative_.push_back(running / total);
        // (H'')² of the symmetric H'' = [[a, b], [b, c]]: [[a² + b², b(a + c)], [b(a + c), c² + b²]].
        const double a = chirped_ ? kernels.curvature_xx[k] : 0.0;
        const double b = chirped_ ? kernels.curvature_xy[k] : 0.0;
        const double c = chirped_ ? kernels.curvature_yy[k] : 0.0;
        square_xx_.push_back(a * a + b * b);
        square_xy_.push_back(b * (a + c));
        square_yy_.push_back(c * c + b * b);
    }
    if (!cumulative_.empty()) cumulative_.back() = 1.0;
    // The covariances depend on ω_i only through ξ3, and not at all without curvature.
    if (!(chirped_ && phase_depends_on_outgoing(model_)))
        for (double lambda : wavelengths_um_)
            fixed_.push_back(gaussians(lambda, curvature_scale({0.0, 0.0, 1.0}), 0, n));
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

KernelMixture::Gaussians KernelMixture::gaussians(double lambda_um, double curvature, std::size_t first,
                                                  std::size_t end) const {
    const double diffraction = diffraction_variance(lambda_um);
    Gaussians g;
    g.first = first;
    for (auto* v : {&g.qxx, &g.qxy, &g.qyy, &g.norm}) v->resize(end - first);
    for (std::size_t k = first; k < end; ++k) {
        const Covariance s{diffraction + curvature * square_xx_[k], curvature * square_xy_[k],
                           diffraction + curvature * square_yy_[k]};
        const double det = s.det();
        // q/2 = (S_yy e_x² − 2 S_xy e_x e_y + S_xx e_y²) / (2 det S).
        g.qxx[k - first] = 0.5 * s.yy / det;
        g.qxy[k - first] = -s.xy / det;
        g.qyy[k - first] = 0.5 * s.xx / det;
        // The Gaussian's normalisation 1/(2π √det S), over the mass the cut keeps.
        g.norm[k - first] = probability_[k] / (2.0 * pi * std::sqrt(det) * kept_mass_);
    }
    return g;
}

double KernelMixture::sum_gaussians(const Gaussians& g, const std::vector<KernelRun>& runs, double px, double py,
                                    double xi) const {
    const KernelArrays& kernels = index_->kernels();
    return sum_cut_gaussians(kernels.slope_x.data() + g.first, kernels.slope_y.data() + g.first, g.qxx.data(),
                             g.qxy.data(), g.qyy.data(), g.norm.data(), cut_, g.first, runs.data(), runs.size(), px, py,
                             xi);
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
    // Box–Muller with the radius cut at √(2 cut): r² = −2 ln(1 − rest · kept mass).
    const double radius = std::sqrt(-2.0 * std::log1p(-rest * kept_mass_));
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
    const KernelArrays& kernels = index_->kernels();
    const double dx = -omega_i.x - xi * kernels.slope_x[k] + l11 * z1;
    const double dy = -omega_i.y - xi * kernels.slope_y[k] + l21 * z1 + l22 * z2;
    if (!(dx * dx + dy * dy < 1.0)) return std::nullopt;
    return direction_from_disk(dx, dy);
}

DirectionSample KernelMixture::sample(Vec3 omega_i, double u1, double u2) const {
    const std::optional<Vec3> omega_o = draw(omega_i, u1, u2);
    if (!omega_o) return {};
    return {*omega_o, pdf(omega_i, *omega_o)};
}

const double* KernelMixture::shared_norms(std::size_t layer) const {
    return fixed_.empty() || phase_depends_on_outgoing(model_) ? nullptr : fixed_[layer].norm.data();
}

SlopeIndex::DiskReach KernelMixture::disk_reach(Vec3 omega_i, Vec3 omega_o, std::size_t layer, double margin2) const {
    // Kernel k's cut keeps eᵀS_k⁻¹e < 2 cut, which lies in the disk |e|² < 2 cut λ_max(S_k),
    // λ_max(S_k) = diffraction + curvature ρ(H''_k)², with e = d − μ_k = (ω_o + ω_i)_xy + ξ3 H'_k.
    const double scale = margin2 * 2.0 * cut_;
    return {omega_o.x + omega_i.x, omega_o.y + omega_i.y, sampling_xi3(omega_i),
            scale * diffraction_variance(wavelengths_um_[layer]), scale * curvature_scale(omega_i)};
}

double KernelMixture::pdf(Vec3 omega_i, Vec3 omega_o) const {
    constexpr double margin2 = SlopeIndex::kReachMargin * SlopeIndex::kReachMargin;
    // Reused by each thread: no allocation per call.
    thread_local std::vector<KernelRun> runs;
    double density = 0.0;
    for (std::size_t layer = 0; layer < wavelengths_um_.size(); ++layer) {
        runs.clear();
        index_->disk_runs(disk_reach(omega_i, omega_o, layer, margin2), runs);
        density += layer_density(omega_i, omega_o, layer, runs);
    }
    return pdf_of_density(density, omega_o);
}

const ChirpFactors* KernelMixture::split_runs(Vec3 omega_i, Vec3 omega_o, std::size_t layer,
                                              const TransformPoint& point, std::vector<KernelRun>& transform_runs,
                                              std::vector<KernelRun>& other_runs) const {
    // The disk circumscribes the point's boxes exactly (cut = kernel_sigmas²: gaussian_cut); widened
    // by the margin once more, rounding never leaves a cell that the transform sum keeps outside it.
    constexpr double m = SlopeIndex::kReachMargin;
    return index_->reaching_runs(point, disk_reach(omega_i, omega_o, layer, m * m * m * m), transform_runs,
                                 other_runs);
}

double KernelMixture::layer_density(Vec3 omega_i, Vec3 omega_o, std::size_t layer,
                                    const std::vector<KernelRun>& runs) const {
    const double xi = sampling_xi3(omega_i);
    // e = d − μ_k = (ω_o + ω_i)_xy + ξ3 H'_k.
    const double px = omega_o.x + omega_i.x, py = omega_o.y + omega_i.y;
    if (!fixed_.empty()) return sum_gaussians(fixed_[layer], runs, px, py, xi);
    // Covariances made per call: only for the kernels summed.
    const double curvature = curvature_scale(omega_i);
    double density = 0.0;
    for (const KernelRun& run : runs)
        density += sum_gaussians(gaussians(wavelengths_um_[layer], curvature, run.begin, run.end), {run}, px, py, xi);
    return density;
}

double KernelMixture::pdf_of_density(double density, Vec3 omega_o) const {
    // The mean over wavelengths, and dA = cosθ_o dω_o.
    return density / wavelengths_um_.size() * omega_o.z;
}

}  // namespace glintscope::gabor
