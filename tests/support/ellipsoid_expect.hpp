#pragma once
// A fitted ellipsoid NDF against the truth: α within 1%, angles within 1% (1e-6 rad at 0).
#include <gtest/gtest.h>

#include <cmath>

#include "glintscope/fit/ndf_models.hpp"

namespace glintscope::testing {

inline void expect_within_percent(const EllipsoidNdf& fitted, const EllipsoidNdf& truth) {
    EXPECT_NEAR(fitted.alpha_x, truth.alpha_x, 0.01 * truth.alpha_x);
    EXPECT_NEAR(fitted.alpha_y, truth.alpha_y, 0.01 * truth.alpha_y);
    EXPECT_NEAR(fitted.theta_x, truth.theta_x, 0.01 * std::abs(truth.theta_x) + 1e-6);
    EXPECT_NEAR(fitted.theta_y, truth.theta_y, 0.01 * std::abs(truth.theta_y) + 1e-6);
    EXPECT_NEAR(fitted.theta_z, truth.theta_z, 0.01 * std::abs(truth.theta_z) + 1e-6);
}

}  // namespace glintscope::testing
