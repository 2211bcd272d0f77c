#pragma once
// Importance sampling of a Gabor lobe as Yan 2018 §5 ("Importance sampling") describes it, pick a
// kernel by its weight, then a direction from that kernel's directional Gaussian, but with the
// exact pdf of that mixture, so that the weight f_r cosθ_o / pdf is honest (the paper set it to 1).
// docs/gabor.md "Sampling" derives the densities.
#include <optional>
#include <vector>

#include "gabor_kernels.hpp"
#include "lobe/point_answers.hpp"

namespace glintscope::gabor {

// One footprint's kernels as a mixture of Gaussians over d, the xy part of ω_o (the projected
// disk). A sample picks a wavelength of the query uniformly, a kernel k with probability
// w_k / Σ w (w_k the coherence window at m_k), then d from the Gaussian that is the magnitude of
// the kernel's transform, |F[g_k](v)| at v = (ω̄_i + d)/λ:
//   mean −ω̄_i − ξ3 H'_k,   covariance λ²/(4π²σ_k²) I + σ_k² ξ3² (H''_k)²
// (H'' = 0 at first order; ξ3 of the model at ω_i's mirror direction), cut where it falls to
// e^{−25} of its peak. The pdf per solid angle is cosθ_o times the mixture's density in d, a
// sum over every kernel of the footprint; d outside the unit disk is no direction (pdf 0).
class KernelMixture {
public:
    KernelMixture(const KernelArrays& kernels, const KernelGrid& grid, DiffractionModel model,
                  std::vector<double> wavelengths_um);

    DirectionSample sample(Vec3 omega_i, double u1, double u2) const;
    // sample()'s direction without its pdf (a sum over every kernel): none outside the disk.
    std::optional<Vec3> draw(Vec3 omega_i, double u1, double u2) const;
    double pdf(Vec3 omega_i, Vec3 omega_o) const;

private:
    // Per kernel, the Gaussian of one wavelength and curvature scale: q/2 = qxx e_x² + qxy e_x e_y
    // + qyy e_y² with e = d − μ_k, and its weight w_k/Σw over its normalisation.
    struct Gaussians {
        std::vector<double> qxx, qxy, qyy, norm;
    };
    Gaussians gaussians(double lambda_um, double curvature) const;
    // ξ3 at ω_i's mirror direction, which places the Gaussians.
    double sampling_xi3(Vec3 omega_i) const;
    // σ_k² ξ3² (0 at first order) and λ²/(4π²σ_k²): kernel k's covariance is
    // diffraction · I + curvature · (H''_k)².
    double curvature_scale(Vec3 omega_i) const;
    double diffraction_variance(double lambda_um) const;

    DiffractionModel model_;
    std::vector<double> wavelengths_um_;
    double sigma_um_;
    bool chirped_ = false;
    std::vector<double> probability_;  // w_k / Σ w
    std::vector<double> cumulative_;   // Σ_{j ≤ k} probability_j
    std::vector<double> slope_x_;      // H'_k
    std::vector<double> slope_y_;
    std::vector<double> square_xx_;    // (H''_k)², symmetric: xx, xy, yy
    std::vector<double> square_xy_;
    std::vector<double> square_yy_;
    // One per wavelength when the covariances do not depend on ω_i (first order, or ξ3 = 2);
    // otherwise (second order with GHS, R-GHS, Kirchhoff) made per call.
    std::vector<Gaussians> fixed_;
};

}  // namespace glintscope::gabor
