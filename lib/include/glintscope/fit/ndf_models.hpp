#pragma once
// Parametric normal distribution functions, normalised as every NDF of the library
// (conventions.md "Geometric NDFs"): ∫ D(m)(m·n) dω_m = 1, i.e. Σ D (2/N)² = 1 over an N×N
// projected-disk image of m (n = +z). Angles in radians.
#include "glintscope/core/geometry.hpp"

namespace glintscope {

// Dong 2015 §8: the normal distribution of an ellipsoid p with pᵀAᵀAp = const, A = S R,
// S = diag(α_x, α_y, 1), R = R_x(θ_x) R_y(θ_y) R_z(θ_z) (right-handed rotations about the frame
// axes). θ_z turns the anisotropy (the α_x axis lies along (cos θ_z, −sin θ_z) when θ_x = θ_y = 0);
// θ_x and θ_y tilt the peak away from n. R = I is GTR2aniso, and α_x = α_y then GGX.
struct EllipsoidNdf {
    double alpha_x = 0.1;
    double alpha_y = 0.1;
    double theta_x = 0.0;
    double theta_y = 0.0;
    double theta_z = 0.0;
};

// The same D with |θ_z| ≤ π/4: α_x and α_y then name the roughness along x and y as Beckmann's
// and GGX's do (a brushed surface's larger α along the same axis in every model).
EllipsoidNdf canonical_ellipsoid(EllipsoidNdf ndf);

// D(m) of Dong 2015 eq. 10; m a unit vector, 0 for m_z ≤ 0.
double ellipsoid_ndf(const EllipsoidNdf& ndf, Vec3 m);

// The shadowing or masking of one direction u (Dong 2015 eq. 14), in [0, 1].
double ellipsoid_g1(const EllipsoidNdf& ndf, Vec3 u);

// G(ω_i, ω_o) = G1(ω_i) G1(ω_o) (Dong 2015 eq. 13), for the geometric lobe. h is the half
// vector: a microfacet seen or lit from behind (ω·h ≤ 0) reflects nothing, so G is then 0.
double ellipsoid_shadowing_masking(const EllipsoidNdf& ndf, Vec3 omega_i, Vec3 omega_o, Vec3 h);

// Anisotropic Beckmann, axes along x and y (Dong 2015 Fig. 12's comparison):
// D = exp(−(m_x²/α_x² + m_y²/α_y²)/m_z²) / (π α_x α_y m_z⁴).
double beckmann_ndf(double alpha_x, double alpha_y, Vec3 m);

// Anisotropic GGX (GTR2aniso, Burley 2012 eq. 13), axes along x and y:
// D = 1 / (π α_x α_y m_z⁴ (1 + (m_x²/α_x² + m_y²/α_y²)/m_z²)²).
double ggx_ndf(double alpha_x, double alpha_y, Vec3 m);

}  // namespace glintscope
