// The slope distribution (ISO 25178-2:2021 §4.6) on the projected disk: a plane puts all of its
// mass in the pixel of its normal, the density sums to 1, and bad input is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <span>

#include "glintscope/core/error.hpp"
#include "glintscope/lobe/image.hpp"
#include "glintscope/surface/slope_distribution.hpp"

namespace glintscope {
namespace {

TEST(SlopeDistribution, PlanePutsAllItsMassInThePixelOfItsNormal) {
    // A measured (non-periodic) plane h = a x + b y, so no wrap-around step.
    const double a = 0.3, b = -0.2, texel = 0.5;
    Heightfield field = make_heightfield(32, 48, texel);
    field.periodic = false;
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            field.at(r, c) = static_cast<float>(a * s.x + b * s.y);
        }
    const int n = 64;
    const std::vector<float> density = slope_distribution(field, n);
    const double norm = std::sqrt(1.0 + a * a + b * b);
    const int col = static_cast<int>(std::floor((-a / norm + 1.0) * 0.5 * n));
    const int row = static_cast<int>(std::floor((1.0 + b / norm) * 0.5 * n));
    EXPECT_NEAR(density[row * n + col] * 4.0 / (n * n), 1.0, 1e-6);
    EXPECT_NEAR(disk_sum(std::span<const float>(density), n), 1.0, 1e-6);
}

TEST(SlopeDistribution, RefusesAFieldWithoutSlopes) {
    Heightfield field = make_heightfield(2, 2, 1.0);
    field.periodic = false;
    EXPECT_THROW(slope_distribution(field, 64), Error);
    EXPECT_THROW(slope_distribution(make_heightfield(8, 8, 1.0), 1), Error);
}

}  // namespace
}  // namespace glintscope
