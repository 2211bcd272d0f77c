// The projected disk as a piecewise-constant distribution (numerics/disk_distribution.hpp); the
// BSDF conformance suite (tests/lib/bsdf) tests its sampling through every method.
#include <gtest/gtest.h>

#include "glintscope/core/geometry.hpp"
#include "numerics/disk_distribution.hpp"

namespace glintscope {
namespace {

TEST(DiskDistribution, PixelAreasInsideTheDiskAddUpToPi) {
    for (int n : {7, 40, 256}) {
        const double side = 2.0 / n;
        double total = 0.0;
        for (int row = 0; row < n; ++row)
            for (int col = 0; col < n; ++col)
                total += area_inside_disk(-1.0 + col * side, -1.0 + (col + 1) * side, 1.0 - (row + 1) * side,
                                          1.0 - row * side);
        EXPECT_NEAR(total, pi, 1e-12) << n;
    }
}

TEST(DiskDistribution, AreasOfSquaresCutByTheRimMatchTheirClosedForms) {
    // A quarter disk in the unit square, a half disk in [−1, 1] × [0, 1], a square inside.
    EXPECT_NEAR(area_inside_disk(0.0, 1.0, 0.0, 1.0), pi / 4.0, 1e-14);
    EXPECT_NEAR(area_inside_disk(-1.0, 1.0, 0.0, 1.0), pi / 2.0, 1e-14);
    EXPECT_DOUBLE_EQ(area_inside_disk(0.1, 0.3, 0.2, 0.4), 0.04);
    EXPECT_EQ(area_inside_disk(0.9, 1.0, 0.9, 1.0), 0.0);
    // The segment x > 0.8 of the disk: acos(0.8) − 0.8·0.6.
    EXPECT_NEAR(area_inside_disk(0.8, 1.0, -1.0, 1.0), std::acos(0.8) - 0.8 * 0.6, 1e-14);
}

}  // namespace
}  // namespace glintscope
