#pragma once
// Wave-optics lobes from Gabor kernels (Yan, Hašan, Walter, Marschner, Ramamoorthi 2018, §4–5).
//
// The reflection function R*(s) = w(s − x_c) ξ2 e^{−i2π ξ3 H(s)/λ} is approximated by one Gabor
// kernel per cell of a regular grid of spacing l = dx/K (K = kernels per texel along each axis),
// centred at the cell centre m_k, of width σ_k = l/2, with H(m_k) and H'(m_k) from the shared
// BicubicInterpolant (Yan 2018 eq. 9–15). Each kernel's Fourier transform is a Gaussian times a plane
// wave, so the BRDF is a short sum (Yan 2018 eq. 16–17):
//   f_r(ω_i, ω_o) ≈ ξ1/A_c |Σ_k w_k C_k F[g_k](ψ̄/λ)|²,   ξ1 including F/λ².
// Kernels are kept within `footprint_sigmas` σ_c of x_c (a box footprint keeps the kernels
// inside the box), and each kernel's transform is cut to the box |v + a_k| ≤ kernel_sigmas ·
// 1/(2πσ_k) in each axis (Yan 2018 §5 "Acceleration by pruning").
//
// Two evaluators share these definitions: gabor_lobe (whole images; a lobe-method table entry)
// and GaborSurface (point queries for renderers, with the pruning hierarchy of §5).
#include <complex>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "glintscope/optics/diffraction_model.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/surface/interpolant.hpp"
#include "glintscope/methods/gabor/gabor_surface.hpp"
#include "glintscope/lobe/query.hpp"
#include "lobe/method.hpp"

namespace glintscope {

// ---- One Gabor kernel (Yan 2018 §4.1) -----------------------------------------------------

// A symmetric 2 × 2 matrix B (cycles/µm²): the chirp rate of a second-order kernel.
struct Chirp {
    double xx = 0.0;
    double xy = 0.0;
    double yy = 0.0;
};

// g(s; μ, σ, a, B) = G_2D(s; μ, σ) e^{−i2π (a·s + ½ (s − μ)ᵀ B (s − μ))}, G_2D the normalised
// isotropic Gaussian: Yan 2018 eq. 7 when B = 0 (first order), a chirped kernel otherwise.
struct GaborKernel {
    Point2 centre_um;         // μ
    double sigma_um = 0.5;    // σ
    Point2 frequency;         // a, cycles/µm
    Chirp chirp;              // B
};

// g(s) (Yan 2018 eq. 7, times the chirp).
std::complex<double> gabor_kernel_value(const GaborKernel& kernel, Point2 s_um);

// F[g](v) = ∫ g(s) e^{−i2π s·v} ds. First order: e^{−i2π μ·(v + a)} e^{−2π²σ²|v + a|²}, Yan 2018 eq. 8
// with the centre μ in the phase (the paper prints a·(v + a), a misprint: conventions.md).
// Chirped: with u = v + a and M = I + i2πσ²B,
//   F[g](v) = e^{−i2π μ·u} det(M)^{−1/2} e^{−2π²σ² uᵀM⁻¹u}
// (Folland 1989 App. A Thm. 1, the Gaussian integral for a complex symmetric matrix with positive
// definite real part; the principal square root: docs/gabor.md "Second order").
std::complex<double> gabor_kernel_transform(const GaborKernel& kernel, Point2 v);

// The kernel that stands for the cell of side l centred at m (Yan 2018 eq. 13–15): R_k(s) ≈ C_k g(s; m, l/2, a_k)
// with C_k = l² ξ2 e^{−i2π ξ3 (H(m) − H'(m)·m)/λ} (Yan 2018 eq. 14) and a_k = ξ3 H'(m)/λ (Yan 2018 eq. 15).
struct GaborCellKernel {
    std::complex<double> coefficient;  // C_k
    GaborKernel kernel;
};
GaborCellKernel gabor_cell_kernel(Point2 centre_um, double cell_um, const SurfacePoint& surface_at_centre,
                                  double xi2, double xi3, double lambda_um);
// The second-order kernel of the same cell: H expanded to second order about m, so the kernel also
// carries the chirp B = ξ3 H''(m)/λ (a paraboloid is represented exactly).
GaborCellKernel gabor_cell_kernel(Point2 centre_um, double cell_um, const SurfacePoint& surface_at_centre,
                                  const SurfaceCurvature& curvature_at_centre, double xi2, double xi3,
                                  double lambda_um);

// ---- Settings from a query -----------------------------------------------------------------

// The settings a lobe query asks for, from its method options "kernels_per_texel" (an integer),
// "footprint_truncation" and "kernel_truncation" (in σ), each defaulting as above. Throws Error
// for unknown options or bad values.
GaborSettings gabor_settings(const LobeQuery& query);

namespace gabor {
struct KernelGrid;  // gabor_kernels.hpp
}

// Refuses (Error) a Gaussian footprint narrower than the kernels, σ_c (or its minor σ) < σ_k:
// they cannot resolve its window, whose lobe would not be the footprint's (docs/gabor.md "Flat
// mirror"). Images, BSDFs and render fields alike, before any work.
void check_footprint_width(const Footprint& footprint, const gabor::KernelGrid& grid);

// What the kernels' own blur costs a Gaussian footprint, as its images' "gabor.warning" and its
// point answers' warning say it: empty while the blur factor f (docs/gabor.md "Flat mirror") is at
// least 0.98, else f, the albedo lost and the kernels_per_texel that brings f to 0.99.
std::string kernel_blur_warning(const Footprint& footprint, const gabor::KernelGrid& grid);

// ---- Whole lobe images --------------------------------------------------------------------

// The lobe image of the query. OHS and R-OHS (ξ3 = 2) are evaluated as a banded complex matrix
// product over the footprint's kernels (each kernel's transform is separable in v_x and v_y);
// GHS, R-GHS and Kirchhoff (ξ3 = ψ·n) pixel by pixel over pruned kernel blocks. The metadata
// records the kernel grid, count, truncations and evaluation scheme under "gabor.*".
LobeImage gabor_lobe(const LobeQuery& query);

// Point answers at any footprint of the query's heightfield (lobe/point_answers.hpp): eval by
// GaborSurface, sample and pdf by the footprint's kernel mixture (gabor_sampling.hpp).
PointAnswersAt gabor_point_field(const LobeQuery& query);
// Point answers at the query's footprint, for make_bsdf: eval through the footprint's kernels
// sorted by slope (gabor_slope_index.hpp), sample and pdf as above.
PointAnswers gabor_point_answers(const LobeQuery& query);

// The method-table entry: "gabor", Yan 2018 §4-5, brdf, the options of gabor_settings.
MethodEntry gabor_method();

}  // namespace glintscope
