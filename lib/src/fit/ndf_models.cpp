#include "glintscope/fit/ndf_models.hpp"

#include "fit/ellipsoid_frame.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace glintscope {
namespace {

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 multiply(const Mat3& a, const Mat3& b) {
    Mat3 product{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) product[i][j] += a[i][k] * b[k][j];
    return product;
}

Vec3 apply(const Mat3& a, Vec3 v) {
    return {a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z, a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
            a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z};
}

// R = R_x(θ_x) R_y(θ_y) R_z(θ_z) (Dong 2015 eq. 12).
Mat3 rotation(const EllipsoidNdf& ndf) {
    const double cx = std::cos(ndf.theta_x), sx = std::sin(ndf.theta_x);
    const double cy = std::cos(ndf.theta_y), sy = std::sin(ndf.theta_y);
    const double cz = std::cos(ndf.theta_z), sz = std::sin(ndf.theta_z);
    const Mat3 rx{{{1, 0, 0}, {0, cx, -sx}, {0, sx, cx}}};
    const Mat3 ry{{{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}}};
    const Mat3 rz{{{cz, -sz, 0}, {sz, cz, 0}, {0, 0, 1}}};
    return multiply(multiply(rx, ry), rz);
}

// S v with S = diag(α_x, α_y, 1) (Dong 2015 eq. 11).
Vec3 scale(const EllipsoidNdf& ndf, Vec3 v) { return {ndf.alpha_x * v.x, ndf.alpha_y * v.y, v.z}; }

// The angles of R = R_x(θ_x) R_y(θ_y) R_z(θ_z): its first row is (cos θ_y cos θ_z,
// −cos θ_y sin θ_z, sin θ_y) and its last column (sin θ_y, −sin θ_x cos θ_y, cos θ_x cos θ_y)ᵀ.
EllipsoidNdf with_rotation(EllipsoidNdf ndf, const Mat3& r) {
    ndf.theta_y = std::asin(std::clamp(r[0][2], -1.0, 1.0));
    ndf.theta_z = std::atan2(-r[0][1], r[0][0]);
    ndf.theta_x = std::atan2(-r[1][2], r[2][2]);
    return ndf;
}

}  // namespace

EllipsoidNdf canonical_ellipsoid(EllipsoidNdf ndf) {
    // D depends on A = S R only through |A|, ‖A n‖ and ‖A⁻ᵀ m‖ (Dong 2015 eq. 10), so Q A gives the
    // same D for any rotation Q. Q = R_z(q), q = ±π/2, turns S into S' (α_x, α_y swapped):
    // Q S R = S' (Q R). Choosing q against θ_z brings θ_z within ±π/4, so α_x is the roughness
    // along x as Beckmann's and GGX's are.
    ndf.theta_z = std::remainder(ndf.theta_z, 2.0 * pi);
    for (int turns = 0; turns < 3 && std::abs(ndf.theta_z) > 0.25 * pi; ++turns) {
        const double q = -std::copysign(0.5 * pi, ndf.theta_z);
        const Mat3 turn{{{std::cos(q), -std::sin(q), 0}, {std::sin(q), std::cos(q), 0}, {0, 0, 1}}};
        std::swap(ndf.alpha_x, ndf.alpha_y);
        ndf = with_rotation(ndf, multiply(turn, rotation(ndf)));
    }
    return ndf;
}

EllipsoidFrame ellipsoid_frame(const EllipsoidNdf& ndf) {
    EllipsoidFrame frame{ndf, rotation(ndf), {}};
    frame.a_n = scale(ndf, apply(frame.r, {0, 0, 1}));
    return frame;
}

double ellipsoid_ndf(const EllipsoidFrame& frame, Vec3 m) {
    if (m.z <= 0.0) return 0.0;  // χ⁺(m·n): only the upper half of the ellipsoid
    // A⁻ᵀ m = S⁻¹ R m, since R⁻ᵀ = R.
    const Vec3 rm = apply(frame.r, m);
    const Vec3 a_inv_t_m{rm.x / frame.ndf.alpha_x, rm.y / frame.ndf.alpha_y, rm.z};
    const double q = dot(a_inv_t_m, a_inv_t_m);
    // Dong 2015 eq. 10, with |A| = |S| = α_x α_y.
    return 1.0 / (pi * frame.ndf.alpha_x * frame.ndf.alpha_y * length(frame.a_n) * q * q);
}

double ellipsoid_ndf(const EllipsoidNdf& ndf, Vec3 m) { return ellipsoid_ndf(ellipsoid_frame(ndf), m); }

double ellipsoid_g1(const EllipsoidNdf& ndf, Vec3 u) {
    const EllipsoidFrame frame = ellipsoid_frame(ndf);
    const Vec3 a_n = frame.a_n;
    const Vec3 a_u = scale(ndf, apply(frame.r, u));
    const double a_n_length = length(a_n);
    const double denominator = length(a_u) * a_n_length + dot(a_u, a_n);
    if (denominator <= 0.0) return 0.0;  // u opposite the ellipsoid's mean normal: fully shadowed
    return std::min(1.0, 2.0 * a_n_length * a_n_length * std::abs(u.z) / denominator);  // Dong 2015 eq. 14
}

double ellipsoid_shadowing_masking(const EllipsoidNdf& ndf, Vec3 omega_i, Vec3 omega_o, Vec3 h) {
    if (dot(omega_i, h) <= 0.0 || dot(omega_o, h) <= 0.0) return 0.0;
    return ellipsoid_g1(ndf, omega_i) * ellipsoid_g1(ndf, omega_o);  // Dong 2015 eq. 13
}

double beckmann_ndf(double alpha_x, double alpha_y, Vec3 m) {
    if (m.z <= 0.0) return 0.0;
    const double z2 = m.z * m.z;
    const double slope2 = (m.x * m.x / (alpha_x * alpha_x) + m.y * m.y / (alpha_y * alpha_y)) / z2;
    return std::exp(-slope2) / (pi * alpha_x * alpha_y * z2 * z2);
}

double ggx_ndf(double alpha_x, double alpha_y, Vec3 m) {
    if (m.z <= 0.0) return 0.0;
    const double z2 = m.z * m.z;
    const double t = 1.0 + (m.x * m.x / (alpha_x * alpha_x) + m.y * m.y / (alpha_y * alpha_y)) / z2;
    return 1.0 / (pi * alpha_x * alpha_y * z2 * z2 * t * t);  // Burley 2012 eq. 13
}

}  // namespace glintscope
