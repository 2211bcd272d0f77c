#include <gtest/gtest.h>

#include <cmath>

#include "glintscope/error.hpp"
#include "glintscope/geometry.hpp"
#include "glintscope/lobe.hpp"
#include "glintscope/slice.hpp"

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

TEST(MeanLobe, IsThePixelMeanOfTheFootprintsLobes) {
    LobeQuery query;
    Heightfield field = make_heightfield(64, 64, 1.0);
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 64; ++c) field.at(r, c) = float(0.3 * std::sin(0.5 * c) + 0.2 * std::cos(0.4 * r));
    set_heightfield(query, field);
    query.footprint.sigma_um = 4.0;
    query.resolution = 24;
    const std::vector<Point2> centres = {{20.0, 20.0}, {40.0, 30.0}, {25.0, 44.0}};
    const LobeImage mean = compute_mean_lobe("fft", query, centres);
    std::vector<double> expected(mean.values.size(), 0.0);
    for (const Point2& centre : centres) {
        LobeQuery one = query;
        one.footprint.centre_um = centre;
        const LobeImage image = compute_lobe("fft", one);
        for (std::size_t i = 0; i < expected.size(); ++i) expected[i] += image.values[i] / 3.0;
    }
    for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(mean.values[i], expected[i], 1e-6 * (1.0 + expected[i]));
    EXPECT_EQ(mean.metadata.at("footprints.count"), "3");
}

}  // namespace
}  // namespace glintscope
