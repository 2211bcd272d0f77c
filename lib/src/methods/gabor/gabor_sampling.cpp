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

// Σ_k norm_k e^{−q_k/2} over the Gaussians' q_k = (e − μ_k)ᵀ S_k⁻¹ (e − μ_k) < 2 kCut, with
// e − μ_k = (px, py) + ξ3 H'_k, over the kernels of the runs, indices from `first` (where the
// arrays start; the tail's lanes may read kernels before a run).
__attribute__((target_clones("arch=x86-64-v3", "default")))
double sum_cut_gaussians(const double* slope_x, const double* slope_y, const double* qxx, const double* qxy,
                         const double* qyy, const double* norm, std::size_t first, const KernelRun* runs,
                         std::size_t run_count, double px, double py, double xi) {
    const auto add = [&](std::size_t k, auto& sum, auto&, auto&) __attribute__((always_inline)) {
        using T = std::decay_t<decltype(sum)>;
        const T ex = px + xi * gabor_math::lanes<T>(slope_x + k);
        const T ey = py + xi * gabor_math::lanes<T>(slope_y + k);
        const T half_q = gabor_math::lanes<T>(qxx + k) * ex * ex + gabor_math::lanes<T>(qxy + k) * ex * ey + gabor_math::lanes<T>(qyy + k) * ey * ey;
        const T kept = half_q < kCut ? gabor_math::lanes<T>(norm + k) : T{} * 0.0;
        sum += kept * gabor_math::exp_neg(half_q < kCut ? half_q : T{} + kCut);
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

// The square of the distance from 0 to the box [x_min, x_max] × [y_min, y_max].
double distance2_to_box(double x_min, double x_max, double y_min, double y_max) {
    const double x = x_min > 0.0 ? x_min : x_max < 0.0 ? x_max : 0.0;
    const double y = y_min > 0.0 ? y_min : y_max < 0.0 ? y_max : 0.0;
    return x * x + y * y;
}

// Calls add(b, e) for the parts of [begin, end) outside the runs (sorted, disjoint).
template <typename Add>
void for_each_part_outside(std::size_t begin, std::size_t end, const std::vector<KernelRun>& runs, const Add& add) {
    for (const auto& [run_begin, run_end] : runs) {
        if (run_end <= begin) continue;
        if (run_begin >= end) break;
        if (run_begin > begin) add(begin, run_begin);
        begin = run_end;
        if (begin >= end) return;
    }
    if (begin < end) add(begin, end);
}

}  // namespace

KernelMixture::KernelMixture(std::shared_ptr<const SlopeIndex> index, DiffractionModel model,
                             std::vector<double> wavelengths_um)
    : index_(std::move(index)),
      model_(model),
      wavelengths_um_(std::move(wavelengths_um)),
      sigma_um_(index_->grid().sigma_um),
      chirped_(index_->grid().order == 2) {
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
        g.norm[k - first] = probability_[k] / (2.0 * pi * std::sqrt(det) * kKeptMass);
    }
    return g;
}

double KernelMixture::sum_gaussians(const Gaussians& g, const std::vector<KernelRun>& runs, double px, double py,
                                    double xi) const {
    const KernelArrays& kernels = index_->kernels();
    return sum_cut_gaussians(kernels.slope_x.data() + g.first, kernels.slope_y.data() + g.first, g.qxx.data(),
                             g.qxy.data(), g.qyy.data(), g.norm.data(), g.first, runs.data(), runs.size(), px, py, xi);
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

double KernelMixture::pdf(Vec3 omega_i, Vec3 omega_o) const { return pdf_completing(omega_i, omega_o, {}, {}); }

double KernelMixture::pdf_completing(Vec3 omega_i, Vec3 omega_o, const std::vector<double>& summed_density,
                                     const std::vector<std::vector<KernelRun>>& summed) const {
    const double xi = sampling_xi3(omega_i);
    // e = d − μ_k = (ω_o + ω_i)_xy + ξ3 H'_k.
    const double px = omega_o.x + omega_i.x, py = omega_o.y + omega_i.y;
    const double curvature = curvature_scale(omega_i);
    double density = 0.0;
    for (std::size_t layer = 0; layer < wavelengths_um_.size(); ++layer) {
        const double lambda = wavelengths_um_[layer];
        // Kernel k's cut keeps eᵀS_k⁻¹e < 2 kCut, which lies in the disk |e|² < 2 kCut λ_max(S_k),
        // λ_max(S_k) = diffraction + curvature ρ(H''_k)²; so a cell can hold a kernel that reaches
        // d only if its slope box, mapped to e, meets the disk of its largest ρ(H'').
        const double diffraction = diffraction_variance(lambda);
        const auto reach2 = [&](double radius) {
            constexpr double margin2 = SlopeIndex::kReachMargin * SlopeIndex::kReachMargin;
            return margin2 * 2.0 * kCut * (diffraction + curvature * radius * radius);
        };
        const auto keep = [&](const SlopeIndex::CellBounds& b, std::size_t) {
            return distance2_to_box(px + xi * b.x_min, px + xi * b.x_max, py + xi * b.y_min, py + xi * b.y_max) <=
                   reach2(b.radius);
        };
        // The kernels to sum, as runs (parts of the reaching cells' runs that `summed` leaves).
        thread_local std::vector<KernelRun> parts;
        parts.clear();
        const auto add_part = [&](std::size_t begin, std::size_t end) { parts.push_back({begin, end}); };
        const auto add_run = [&](std::size_t begin, std::size_t end) {
            if (summed.empty())
                add_part(begin, end);
            else
                for_each_part_outside(begin, end, summed[layer], add_part);
        };
        const double widest = std::sqrt(reach2(index_->largest_radius()));
        if (index_->within_reach_of_all(px, py, xi, widest))
            add_run(0, index_->kernels().size());
        else
            index_->for_each_run(px, py, xi, widest, keep, add_run, true);
        if (!summed_density.empty()) density += summed_density[layer];
        if (!fixed_.empty()) {
            density += sum_gaussians(fixed_[layer], parts, px, py, xi);
            continue;
        }
        // Covariances made per call: only for the kernels summed.
        for (const KernelRun& part : parts)
            density += sum_gaussians(gaussians(lambda, curvature, part.begin, part.end), {part}, px, py, xi);
    }
    // The mean over wavelengths, and dA = cosθ_o dω_o.
    return density / wavelengths_um_.size() * omega_o.z;
}

}  // namespace glintscope::gabor
