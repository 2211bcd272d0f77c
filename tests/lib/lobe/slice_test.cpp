#include <gtest/gtest.h>

#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/lobe/slice.hpp"

namespace glintscope {
namespace {

// f = 1 + x + 2y at pixel centres: bilinear slices reproduce it exactly away from the border.
TEST(Slice, BilinearSlicesOfALinearFunctionAreExact) {
    const int n = 64;
    LobeImage image = make_lobe_image(n, {0.5}, Quantity::ndf);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, n);
            image.at(0, r, c) = float(1.0 + p.x + 2.0 * p.y);
        }
    for (const SlicePoint& point : image_slice(image, parse_slice_direction("x"), 40)) {
        if (std::fabs(point.position) < 0.95) {
            EXPECT_NEAR(point.values[0], 1.0 + point.position, 1e-5);
        }
    }
    for (const SlicePoint& point : image_slice(image, parse_slice_direction("y"), 40)) {
        if (std::fabs(point.position) < 0.95) {
            EXPECT_NEAR(point.values[0], 1.0 + 2.0 * point.position, 1e-5);
        }
    }
    for (const SlicePoint& point : image_slice(image, parse_slice_direction("45"), 40)) {
        if (std::fabs(point.position) < 0.9) {
            EXPECT_NEAR(point.values[0], 1.0 + 3.0 * point.position / std::sqrt(2.0), 1e-5);
        }
    }
    EXPECT_THROW(parse_slice_direction("diagonal"), Error);
}

}  // namespace
}  // namespace glintscope
