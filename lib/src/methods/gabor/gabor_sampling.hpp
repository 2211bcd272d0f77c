#pragma once
// Importance sampling of a Gabor lobe as Yan 2018 §5 ("Importance sampling") describes it, pick a
// kernel by its weight, then a direction from that kernel's directional Gaussian, but with the
// exact pdf of that mixture, so that the weight f_r cosθ_o / pdf is honest (the paper set it to 1).
// docs/gabor.md "Sampling" derives the densities.
#include <memory>
#include <optional>
#include <vector>

#include "gabor_kernels.hpp"
#include "gabor_slope_index.hpp"
#include "lobe/point_answers.hpp"

namespace glintscope::gabor {

// One footprint's kernels as a mixture of Gaussians over d, the xy part of ω_o (the projected
// disk). A sample picks a wavelength of the query uniformly, a kernel k with probability
// w_k / Σ w (w_k the coherence window at m_k), then d from the Gaussian that is the magnitude of
// the kernel's transform, |F[g_k](v)| at v = (ω̄_i + d)/λ:
//   mean −ω̄_i − ξ3 H'_k,   covariance λ²/(4π²σ_k²) I + σ_k² ξ3² (H''_k)²
// (H'' = 0 at first order; ξ3 of the model at ω_i's mirror direction), cut where it falls to
// e^{−cut()} of its peak. The pdf per solid angle is cosθ_o times the mixture's density in d, a
// sum over the kernels whose cut Gaussian holds d: those of the cells of the footprint's slope
// index (which orders the kernels by H'_k, so by their means) that can reach d; d outside the
// unit disk is no direction (pdf 0).
class KernelMixture {
public:
    // The kernels of the index, in its order (gather_kernels' weights, all positive).
    KernelMixture(std::shared_ptr<const SlopeIndex> index, DiffractionModel model, std::vector<double> wavelengths_um);

    DirectionSample sample(Vec3 omega_i, double u1, double u2) const;
    // sample()'s direction without its pdf: none outside the disk.
    std::optional<Vec3> draw(Vec3 omega_i, double u1, double u2) const;
    double pdf(Vec3 omega_i, Vec3 omega_o) const;

    // Where the Gaussians' exponents are the kernels' transforms' Re q at the query's wavelength
    // `layer` (OHS, R-OHS: fixed ξ3 and covariances; sum_transforms_and_density), the Gaussians'
    // norm_k (in the index's order) that turn them into this layer's density; else null.
    const double* shared_norms(std::size_t layer) const;
    // Each Gaussian is cut where its exponent ½eᵀS⁻¹e reaches this: kernel_sigmas² where the
    // sampler's ξ3 is the model's (OHS, R-OHS; the cut then holds each kernel's box), else 25.
    double cut() const { return cut_; }
    // For a sample that computes f_r too (gabor_point.cpp), where shared_norms(layer): the slope
    // index's reaching_runs of the layer's transform point at ω_o (returning its chirp factors)
    // and, from the same scan of the cells, the runs of the other kernels whose Gaussians pdf()
    // sums at ω_o.
    const ChirpFactors* split_runs(Vec3 omega_i, Vec3 omega_o, std::size_t layer, const TransformPoint& point,
                                   std::vector<KernelRun>& transform_runs, std::vector<KernelRun>& other_runs) const;
    // Σ_k norm_k e^{−½q_k} of the query's wavelength `layer` at ω_o over the kernels of the runs.
    double layer_density(Vec3 omega_i, Vec3 omega_o, std::size_t layer, const std::vector<KernelRun>& runs) const;
    // The pdf per solid angle of ω_o whose layers' densities sum to `density`.
    double pdf_of_density(double density, Vec3 omega_o) const;

private:
    // Per kernel of [first, first + size), the Gaussian of one wavelength and curvature scale:
    // q/2 = qxx e_x² + qxy e_x e_y + qyy e_y² with e = d − μ_k, and its weight w_k/Σw over its
    // normalisation.
    struct Gaussians {
        std::size_t first = 0;
        std::vector<double> qxx, qxy, qyy, norm;
    };
    Gaussians gaussians(double lambda_um, double curvature, std::size_t first, std::size_t end) const;
    // Σ over the kernels of the runs (inside g's range) of their Gaussians at d = μ_k + e,
    // e = (px, py) + ξ3 H'_k.
    double sum_gaussians(const Gaussians& g, const std::vector<KernelRun>& runs, double px, double py,
                         double xi) const;
    // The disk of e = d − μ_k that holds every cut Gaussian reaching ω_o at the layer's
    // wavelength, its squared radius widened by margin2.
    SlopeIndex::DiskReach disk_reach(Vec3 omega_i, Vec3 omega_o, std::size_t layer, double margin2) const;
    // ξ3 at ω_i's mirror direction, which places the Gaussians.
    double sampling_xi3(Vec3 omega_i) const;
    // σ_k² ξ3² (0 at first order) and λ²/(4π²σ_k²): kernel k's covariance is
    // diffraction · I + curvature · (H''_k)².
    double curvature_scale(Vec3 omega_i) const;
    double diffraction_variance(double lambda_um) const;

    std::shared_ptr<const SlopeIndex> index_;
    DiffractionModel model_;
    std::vector<double> wavelengths_um_;
    double sigma_um_;
    bool chirped_ = false;
    double cut_;
    double kept_mass_;  // 1 − e^{−cut}: each cut Gaussian's mass
    std::vector<double> probability_;  // w_k / Σ w
    std::vector<double> cumulative_;   // Σ_{j ≤ k} probability_j
    std::vector<double> square_xx_;    // (H''_k)², symmetric: xx, xy, yy
    std::vector<double> square_xy_;
    std::vector<double> square_yy_;
    // One per wavelength when the covariances do not depend on ω_i (first order, or ξ3 = 2);
    // otherwise (second order with GHS, R-GHS, Kirchhoff) made per call for the reached kernels.
    std::vector<Gaussians> fixed_;
};

}  // namespace glintscope::gabor
