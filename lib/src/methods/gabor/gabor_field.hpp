#pragma once
// The Gabor kernels' sum in space, R*(s) ≈ Σ_k C_k g(s; m_k, σ_k, a_k) (Yan 2018 eq. 13–15), on
// the FFT method's footprint grid, so that a whole Gabor image costs the FFT's transforms plus
// the kernels' splatting: the same lobe as the closed-form sum of their transforms (Yan 2018
// eq. 16–17), without its per-kernel spectral cut.
#include "gabor_kernels.hpp"
#include "methods/fft/fft_lobe.hpp"

namespace glintscope::gabor {

// A source for scattering_layers: each kernel adds w_k l² G_2D(s − m_k; σ_k)
// e^{−i2π ξ3 (H(m_k) − H̄ + H'(m_k)·(s − m_k))/λ} at the grid points within kSplatSigmas σ_k of
// m_k (m_k = centre + p_k; H(m_k) = reference_height + the kernel's relative height), and for
// Kirchhoff the same times H'_x and H'_y. Its spectral reach beyond ξ3 H'/λ is the Gaussian's,
// kSplatSigmas/(2πσ_k), plus `chirp_bandwidth`. Second order (grid.order 2): the phase also holds
// ½ ξ3 (s − m_k)ᵀH''(m_k)(s − m_k)/λ, whose local frequency departs from ξ3 H'(m_k)/λ by
// ξ3 |H'' d|/λ at d from the centre; the caller bounds that in chirp_bandwidth. The kernels must
// outlive the source.
ReflectionSource kernel_field_source(const KernelArrays& kernels, const KernelGrid& grid, Point2 centre_um,
                                     double reference_height_um, bool kirchhoff, double chirp_bandwidth);

constexpr double kSplatSigmas = 4.0;  // e^{−8} ≈ 3e-4 of a kernel's peak is cut, in space and spectrum

}  // namespace glintscope::gabor
