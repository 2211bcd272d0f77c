#pragma once
// The ellipsoid NDF's matrices computed once per parameter set, so that images and fits
// evaluate D at many normals without repeating the trigonometry.
#include <array>

#include "glintscope/fit/ndf_models.hpp"

namespace glintscope {

struct EllipsoidFrame {
    EllipsoidNdf ndf;
    std::array<std::array<double, 3>, 3> r{};  // R = R_x(θ_x) R_y(θ_y) R_z(θ_z), Dong 2015 eq. 12
    Vec3 a_n;                                  // A n = S R n, Dong 2015 eq. 11
};

EllipsoidFrame ellipsoid_frame(const EllipsoidNdf& ndf);

double ellipsoid_ndf(const EllipsoidFrame& frame, Vec3 m);

}  // namespace glintscope
