#pragma once
// Point queries of wave-optics lobes from Gabor kernels, for renderers (Yan, Hašan, Walter,
// Marschner, Ramamoorthi 2018, §4–5): f_r(ω_i, ω_o, λ) of one footprint at a time, pruned by a
// hierarchy over the kernel grid. Whole images come from compute_lobe("gabor", query) (pipeline.hpp),
// which shares these definitions.
//
// The reflection function R*(s) = w(s − x_c) ξ2 e^{−i2π ξ3 H(s)/λ} is approximated by one Gabor
// kernel per cell of a regular grid of spacing l = dx/K (K = kernels per texel along each axis),
// centred at the cell centre m_k, of width σ_k = l/2, with H(m_k) and H'(m_k) from the shared
// BicubicInterpolant (Yan 2018 eq. 9–15). Each kernel's Fourier transform is a Gaussian times a
// plane wave, so the BRDF is a short sum (Yan 2018 eq. 16–17):
//   f_r(ω_i, ω_o) ≈ ξ1/A_c |Σ_k w_k C_k F[g_k](ψ̄/λ)|²,   ξ1 including F/λ².
#include <cstddef>
#include <memory>
#include <vector>

#include "glintscope/optics/diffraction_model.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/surface/interpolant.hpp"
#include "glintscope/lobe/query.hpp"

namespace glintscope {

namespace gabor {
class KernelArrays;
struct Hierarchy;  // the pruning quadtree (gabor_surface.cpp)
}

// ---- Settings shared by images and point queries -----------------------------------------

struct GaborSettings {
    // K: kernel spacing l = dx/K. With `order` the default is the cheapest setting whose R-OHS lobes
    // stay within 3% relative L2 of the FFT ground truth on the builtins and a held-out surface:
    // second order at K = 1 (0.3–0.9%; first order needs K = 4 for that, 2 gives 2–6%; docs/gabor.md).
    int kernels_per_texel = 1;
    // Kernels farther than this many σ_c from x_c are dropped (Gaussian footprint only). Against
    // 3.5σ_c, the paper's 3σ_c adds 0.4% relative L2 at K = 4, 3.25σ_c 0.06% (docs/gabor.md).
    double footprint_sigmas = 3.25;
    // Each kernel's transform is zero outside |v + a_k| ≤ kernel_sigmas/(2πσ_k) per axis. The
    // paper's 3 standard deviations: 4 or 5 change the lobe by < 0.05% relative L2.
    double kernel_sigmas = 3.0;
    // 1: H expanded to first order in each kernel (Yan 2018 eq. 12–15); 2: to second order, each
    // kernel a chirped Gaussian whose transform widens to kernel_sigmas·√(1 + ε²)/(2πσ_k),
    // ε = 2πσ_k² ξ3 ρ(H'')/λ (docs/gabor.md "Second order").
    int order = 2;
};

// Throws Error naming the setting when it is out of range (K in 1..16, footprint truncation in
// 1..8, kernel truncation in 1..5, order 1 or 2).
void validate(const GaborSettings& settings);

// ---- Point queries for renderers ----------------------------------------------------------

struct GaborPointQuery {
    Footprint footprint;                 // x_c and the coherence window
    Vec3 omega_i{0.0, 0.0, 1.0};         // toward the light
    Vec3 omega_o{0.0, 0.0, 1.0};         // toward the viewer
    DiffractionModel model = DiffractionModel::rohs;
    MaterialChoice material;
};

struct GaborQueryStatistics {
    std::size_t nodes_visited = 0;       // hierarchy nodes tested
    std::size_t kernels_evaluated = 0;   // kernels whose H, H' were read (K = 1) or interpolated
    std::size_t kernels_summed = 0;      // kernels passed to the sum, added up over wavelengths
};

// A heightfield prepared for point queries: a mip-style quadtree over the kernel grid whose
// nodes hold the range of H' over their kernels (Yan 2018 §5). A query visits the nodes that
// overlap the footprint and whose directional box ξ3 H'/λ ± kernel_sigmas/(2πσ_k) can reach
// −ψ̄/λ, then tests each kernel of the surviving leaves and sums the transforms of those that
// pass. With one kernel per texel the kernels are the samples and the test reads their central
// differences directly; with more, the leaves also hold each kernel's H' quantised to 8 bits per
// axis within the leaf's range, so that only leaves with passing codes are interpolated.
// Pruning drops only kernels whose truncated transform is zero at the query, so it does not
// change f_r. The structure is immutable after construction; queries may run concurrently.
class GaborSurface {
public:
    explicit GaborSurface(std::shared_ptr<const BicubicInterpolant> surface, GaborSettings settings = {});

    // f_r in sr⁻¹; 0 when ω_i or ω_o is below the horizon. Throws Error for a non-finite query
    // or wavelength. At second order the terms are single precision, each within 2^−20 of its
    // size (docs/gabor.md); first order sums in double.
    double f_r(const GaborPointQuery& query, double lambda_um, GaborQueryStatistics* statistics = nullptr) const;

    // f_r at several wavelengths: the hierarchy is traversed and the kernels interpolated once,
    // at the longest wavelength, whose directional reach in slope space is the widest; each
    // wavelength then sums the survivors that reach it (Yan 2018 §5 "Spectral rendering"). At
    // second order the terms are single precision, as above.
    std::vector<double> f_r(const GaborPointQuery& query, const std::vector<double>& wavelengths_um,
                            GaborQueryStatistics* statistics = nullptr) const;

    // f_r at several incident directions (query.omega_i unused), direction-major: value
    // [d · wavelengths + w] is f_r(query with omegas_i[d], wavelengths_um[w]), equal bit for bit to
    // f_r of each direction alone. One walk of the hierarchy serves all directions: the nodes are
    // pruned against the union of their reaches, and each direction then tests and sums the
    // kernels of its own surviving leaves (renderers' light sweeps: one footprint, many lights).
    std::vector<double> f_r(const GaborPointQuery& query, const std::vector<Vec3>& omegas_i,
                            const std::vector<double>& wavelengths_um) const;

    const GaborSettings& settings() const { return settings_; }
    std::size_t memory_bytes() const;  // of the hierarchy (the interpolant is shared)

private:
    template <typename Aims>
    struct Collector;  // one footprint's walk for one or several directions (gabor_surface.cpp)

    // Appends the kernels that survive pruning at `prune_lambda_um`, heights relative to H(x_c).
    void collect(const GaborPointQuery& query, double prune_lambda_um, gabor::KernelArrays& kernels,
                 GaborQueryStatistics* statistics) const;
    // The same for each of omegas_i[0 … count) (query.omega_i unused) into *kernels[d], in one
    // walk per 64 directions.
    void collect(const GaborPointQuery& query, const Vec3* omegas_i, std::size_t count, double prune_lambda_um,
                 gabor::KernelArrays* const* kernels, GaborQueryStatistics* statistics) const;

    std::shared_ptr<const BicubicInterpolant> surface_;
    GaborSettings settings_;
    // The quadtree's layout stays out of this header, so that it can change without changing this
    // class's; immutable, so copies share it.
    std::shared_ptr<const gabor::Hierarchy> hierarchy_;
};

}  // namespace glintscope
