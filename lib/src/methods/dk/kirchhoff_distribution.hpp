#pragma once
// The Kirchhoff distribution of Dong 2015 eq. 6, conventions.md "Geometric NDFs":
//   D_K(q) = |∫ (q·m(s)) e^{−i q·s} ds|² / (4π² A),   m ds = (−H_x, −H_y, 1) dx dy,
// s = (x, y, H) on the surface, the footprint's window w in the integrand and A = A_c = ∫|w|².
// With q = 2πψ/λ this is Yan 2018's Kirchhoff-model integral: q·m ds = (2π/λ) ψ_z ξ2 dx dy with
// ξ2 = 1 − ψ̄·H'/ψ_z and q·s = 2π(ψ̄·s + ψ_z H)/λ, so
//   D_K = ψ_z² |R̃*(ψ̄/λ)|² / (λ² A_c),   R* = w ξ2 e^{−i2π ψ_z H/λ},
// and the FFT method's transforms (methods/fft) evaluate it exactly. Over h on the projected
// disk with a fixed effective wavelength λ_q, q = 4πh/λ_q: ψ = 2h, λ = λ_q.
//
// quantity ndf: D_K(h) at λ_q (option lambda_q, default 0.555 µm, Dong's value). A flat patch
// gives the window's transform at h = n with Σ D_K (2/N)² = h_z² ≈ 1; a rough one loses the
// part of |R̃*|² that falls outside the disk (|h_xy| > 1) and weighs by h_z²: the image warns
// when the sum is off 1 by more than 2%.
// quantity brdf: Dong 2015 eq. 8, f_r = F(ω_i·h) D_K(4πh/λ_q) / (4 cosθ_i cosθ_o) (G = 1), D_K
// computed at ndf_oversampling × N and read bilinearly at each sub-pixel's h. With
// lambda_q=per-pixel, λ_q = 2λ/|ω_i + ω_o| (Dong 2015 eq. 5), q = 2π(ω_i + ω_o)/λ, and Dong 2015 eq. 7
// is the Kirchhoff integral itself: the lobe is the fft method's kirchhoff-model lobe.
// Method options: lambda_q, ndf_oversampling (1-4, default 2) and the fft method's grid options.
#include "lobe/method.hpp"

namespace glintscope {

MethodEntry dk_method();

}  // namespace glintscope
