// Footprints and the sets of footprints a request averages over.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/lobe/footprint.hpp"

namespace glintscope {
namespace {

// An ellipse's minor σ lies in (0, σ_c], its axis is finite, and only a Gaussian has one; σ_minor
// equal to σ_c is the circle.
TEST(Footprint, BadEllipsesAreRefusedInOneLine) {
    Footprint ellipse;
    ellipse.sigma_minor_um = 4.0;
    ellipse.axis_radians = 0.3;
    EXPECT_NO_THROW(validate(ellipse));
    EXPECT_TRUE(is_elliptical(ellipse));
    ellipse.sigma_minor_um = ellipse.sigma_um;
    EXPECT_FALSE(is_elliptical(ellipse));
    const auto message = [](Footprint footprint) {
        try {
            validate(footprint);
        } catch (const Error& error) {
            return std::string(error.what());
        }
        return std::string();
    };
    for (const double minor : {-1.0, 12.0, std::nan("")}) {
        Footprint bad;
        bad.sigma_minor_um = minor;
        EXPECT_NE(message(bad).find("minor sigma"), std::string::npos) << minor;
    }
    Footprint turned;
    turned.sigma_minor_um = 4.0;
    turned.axis_radians = std::numeric_limits<double>::infinity();
    EXPECT_NE(message(turned).find("axis"), std::string::npos);
    Footprint box;
    set_box(box, "70um");
    box.sigma_minor_um = 4.0;
    EXPECT_NE(message(box).find("only a Gaussian"), std::string::npos);
}

// A box may be rotated (its width's axis from +x): a finite axis; its reach is its bounding
// rectangle's; the whole field has no axis.
TEST(Footprint, ARotatedBoxReachesItsBoundingRectangle) {
    Footprint box;
    set_box(box, "20x10um");
    EXPECT_FALSE(is_rotated_box(box));
    box.axis_radians = pi / 6.0;
    EXPECT_NO_THROW(validate(box));
    EXPECT_TRUE(is_rotated_box(box));
    const Point2 reach = footprint_support_um(box);
    EXPECT_NEAR(reach.x, 10.0 * std::cos(pi / 6.0) + 5.0 * std::sin(pi / 6.0), 1e-12);
    EXPECT_NEAR(reach.y, 10.0 * std::sin(pi / 6.0) + 5.0 * std::cos(pi / 6.0), 1e-12);
    box.axis_radians = std::numeric_limits<double>::infinity();
    EXPECT_THROW(validate(box), Error);
    Footprint whole;
    whole.shape = FootprintShape::whole;
    whole.axis_radians = 0.2;
    EXPECT_THROW(validate(whole), Error);
}

TEST(FootprintSet, CentresStayClearOfTheEdgesAndAreReproducible) {
    const Heightfield field = make_heightfield(200, 300, 1.0);
    Footprint footprint;
    footprint.sigma_um = 10.0;
    const std::vector<Point2> random = footprint_centres(field, footprint, {50, false, 7});
    EXPECT_EQ(random.size(), 50u);
    for (const Point2& p : random) {
        EXPECT_GE(p.x, 32.5);
        EXPECT_LE(p.x, 300.0 - 32.5);
        EXPECT_GE(p.y, 32.5);
        EXPECT_LE(p.y, 200.0 - 32.5);
    }
    const std::vector<Point2> again = footprint_centres(field, footprint, {50, false, 7});
    EXPECT_EQ(again.front().x, random.front().x);
    const std::vector<Point2> grid = footprint_centres(field, footprint, parse_footprint_set("grid:3"));
    ASSERT_EQ(grid.size(), 9u);
    EXPECT_DOUBLE_EQ(grid[4].x, 150.0);  // the middle cell's centre is the field's
    EXPECT_DOUBLE_EQ(grid[4].y, 100.0);
}

TEST(FootprintSet, GridNMeansNByNAndTextReadsBack) {
    const Heightfield field = make_heightfield(100, 100, 1.0);
    const Footprint footprint;
    for (int n = 1; n <= 5; ++n) {
        const FootprintSet set = parse_footprint_set("grid:" + std::to_string(n));
        EXPECT_EQ(footprint_centres(field, footprint, set).size(), std::size_t(n * n));
        EXPECT_EQ(to_string(set), "grid:" + std::to_string(n));
        EXPECT_EQ(to_string(parse_footprint_set(to_string(set))), to_string(set));
    }
    EXPECT_EQ(footprint_centres(field, footprint, parse_footprint_set("grid")).size(), 9u);
    EXPECT_EQ(footprint_centres(field, footprint, parse_footprint_set("7")).size(), 7u);
    EXPECT_TRUE(parse_footprint_set("1").single());
    for (const char* bad : {"0", "grid:0", "grid:x", "lots", "grid3", "-2"})
        EXPECT_THROW(parse_footprint_set(bad), Error) << bad;
}

}  // namespace
}  // namespace glintscope
