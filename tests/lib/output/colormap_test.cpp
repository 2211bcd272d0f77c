// Colour maps reproduce the published matplotlib tables, and the PNG writer draws each value in
// its colour, missing values in grey, in map-view orientation, with a legend.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "cli_runner.hpp"
#include "glintscope/output/colormap.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

void expect_color(const SrgbColor& color, double r, double g, double b, double tolerance) {
    EXPECT_NEAR(color.r, r, tolerance);
    EXPECT_NEAR(color.g, g, tolerance);
    EXPECT_NEAR(color.b, b, tolerance);
}

TEST(Colormap, EndpointsAreThePublishedColours) {
    // matplotlib _cm_listed.py, entries 0 and 255 (OpenImageIO stores them linearised, in float:
    // the round trip keeps them within 1e-5, far below an 8-bit step).
    expect_color(map_color(ColorMap::viridis, 0.0), 0.267004, 0.004874, 0.329415, 1e-5);
    expect_color(map_color(ColorMap::viridis, 1.0), 0.993248, 0.906157, 0.143936, 1e-5);
    expect_color(map_color(ColorMap::inferno, 0.0), 0.001462, 0.000466, 0.013866, 1e-5);
    expect_color(map_color(ColorMap::inferno, 1.0), 0.988362, 0.998364, 0.644924, 1e-5);
    // Out-of-range values clamp to the ends.
    expect_color(map_color(ColorMap::viridis, -3.0), 0.267004, 0.004874, 0.329415, 1e-5);
    expect_color(map_color(ColorMap::inferno, 7.0), 0.988362, 0.998364, 0.644924, 1e-6);
}

TEST(Colormap, InteriorMatchesPublishedEntriesWithinAnEightBitStep) {
    // Entries 63 and 128 of the 256-entry tables are not among the tabulated control points.
    const double step = 1.0 / 255.0;
    expect_color(map_color(ColorMap::viridis, 63.0 / 255.0), 0.231674, 0.318106, 0.544834, step);
    expect_color(map_color(ColorMap::viridis, 128.0 / 255.0), 0.127568, 0.566949, 0.550556, step);
    expect_color(map_color(ColorMap::inferno, 63.0 / 255.0), 0.335217, 0.060060, 0.428524, step);
    expect_color(map_color(ColorMap::inferno, 128.0 / 255.0), 0.735683, 0.215906, 0.330245, step);
}

double relative_luminance(const SrgbColor& color) {
    auto linear = [](double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); };
    return 0.2126 * linear(color.r) + 0.7152 * linear(color.g) + 0.0722 * linear(color.b);
}

TEST(Colormap, LuminanceRisesMonotonically) {
    for (ColorMap map : {ColorMap::viridis, ColorMap::inferno}) {
        double previous = -1.0;
        for (int i = 0; i <= 200; ++i) {
            const double luminance = relative_luminance(map_color(map, i / 200.0));
            EXPECT_GT(luminance, previous) << to_string(map) << " at " << i / 200.0;
            previous = luminance;
        }
    }
}

TEST(Colormap, NamesParse) {
    EXPECT_EQ(parse_colormap("viridis"), ColorMap::viridis);
    EXPECT_EQ(parse_colormap("inferno"), ColorMap::inferno);
    EXPECT_EQ(to_string(ColorMap::inferno), "inferno");
    EXPECT_THROW(parse_colormap("jet"), Error);
}

struct Picture {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;
};

Picture read_png(const std::string& path) {
    Picture picture;
    auto input = OIIO::ImageInput::open(path);
    if (!input) return picture;
    EXPECT_EQ(input->spec().nchannels, 3);
    EXPECT_EQ(input->spec().format, OIIO::TypeDesc::UINT8);
    picture.width = input->spec().width;
    picture.height = input->spec().height;
    picture.rgb.resize(static_cast<std::size_t>(picture.width) * picture.height * 3);
    input->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, picture.rgb.data());
    return picture;
}

struct Region {
    long count = 0;
    double mean_x = 0.0;
    double mean_y = 0.0;
};

// Pixels within one 8-bit step of `color`, and where they lie.
Region find_color(const Picture& picture, const SrgbColor& color) {
    const int target[3] = {static_cast<int>(std::lround(color.r * 255)), static_cast<int>(std::lround(color.g * 255)),
                           static_cast<int>(std::lround(color.b * 255))};
    Region region;
    for (int y = 0; y < picture.height; ++y)
        for (int x = 0; x < picture.width; ++x) {
            const std::uint8_t* p = &picture.rgb[(static_cast<std::size_t>(y) * picture.width + x) * 3];
            if (std::abs(p[0] - target[0]) <= 1 && std::abs(p[1] - target[1]) <= 1 && std::abs(p[2] - target[2]) <= 1) {
                ++region.count;
                region.mean_x += x;
                region.mean_y += y;
            }
        }
    if (region.count > 0) {
        region.mean_x /= region.count;
        region.mean_y /= region.count;
    }
    return region;
}

TEST(Colormap, PngShowsEachValueInItsColourAndMissingInGrey) {
    TemporaryDirectory directory;
    const std::string path = directory.file("plot.png");
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const ScalarImage image{2, 3, {0.0f, 1.0f, 2.0f, 3.0f, nan, 5.0f}};
    write_colormapped_png(path, image, {0.0, 5.0, "height [um]", ColorMap::inferno});
    const Picture picture = read_png(path);
    ASSERT_GT(picture.width, 0);

    // The 3-column image is enlarged 85 times to reach 256 pixels: each sample is an 85 x 85 square.
    const long square = 85 * 85;
    std::vector<Region> regions;
    for (float value : {0.0f, 1.0f, 2.0f, 3.0f, 5.0f}) {
        regions.push_back(find_color(picture, map_color(ColorMap::inferno, value / 5.0)));
        EXPECT_GE(regions.back().count, square) << "value " << value;
    }
    // (A few grey edge pixels of the anti-aliased text may match too.)
    const Region grey = find_color(picture, {kMissingGrey, kMissingGrey, kMissingGrey});
    EXPECT_GE(grey.count, square);
    EXPECT_LT(grey.count, square + 200);
    // Row 0 is drawn at the top, column 0 at the left.
    EXPECT_LT(regions[0].mean_x + 80, regions[2].mean_x);
    EXPECT_LT(regions[0].mean_y + 80, regions[3].mean_y);
    EXPECT_NEAR(grey.mean_x, regions[1].mean_x, 5.0);
    EXPECT_NEAR(grey.mean_y, regions[1].mean_y + 85, 5.0);

    // The label is written above the picture: dark text pixels in the top band.
    long dark = 0;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < picture.width; ++x)
            if (picture.rgb[(static_cast<std::size_t>(y) * picture.width + x) * 3] < 100) ++dark;
    EXPECT_GT(dark, 20);
}

// Rectangular texels are drawn at their true aspect: each row of a 1 x 2 um field twice, so that a
// pixel is as tall as it is wide in um; a 2 x 1 field repeats its columns instead.
TEST(Colormap, RectangularTexelsAreDrawnAtTheirTrueAspect) {
    const ScalarImage image{2, 3, {1, 2, 3, 4, 5, 6}};
    const ScalarImage tall = at_true_aspect(image, 3.0, 4.0);  // dx 1, dy 2
    ASSERT_EQ(tall.rows, 4);
    ASSERT_EQ(tall.cols, 3);
    EXPECT_EQ(tall.values, (std::vector<float>{1, 2, 3, 1, 2, 3, 4, 5, 6, 4, 5, 6}));
    const ScalarImage wide = at_true_aspect(image, 6.0, 2.0);  // dx 2, dy 1
    ASSERT_EQ(wide.rows, 2);
    ASSERT_EQ(wide.cols, 6);
    EXPECT_EQ(wide.values, (std::vector<float>{1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6}));
    EXPECT_EQ(at_true_aspect(image, 3.0, 2.0).values, image.values);  // square: unchanged
}

TEST(Colormap, PngRejectsBadInputWithoutLeavingAFile) {
    TemporaryDirectory directory;
    const ScalarImage image{1, 2, {0.0f, 1.0f}};
    EXPECT_THROW(write_colormapped_png(directory.file("plot.jpg"), image, {0.0, 1.0, "x", ColorMap::viridis}), Error);
    EXPECT_THROW(write_colormapped_png(directory.file("plot.png"), image, {1.0, 0.0, "x", ColorMap::viridis}), Error);
    EXPECT_THROW(write_colormapped_png(directory.file("plot.png"), image,
                                       {0.0, std::numeric_limits<double>::infinity(), "x", ColorMap::viridis}),
                 Error);
    EXPECT_THROW(write_colormapped_png(directory.file("plot.png"), ScalarImage{2, 2, {0.0f}}, {}), Error);
    EXPECT_THROW(write_colormapped_png(directory.file("plot.png"), ScalarImage{}, {}), Error);
    EXPECT_EQ(testing::count_entries(directory.path()), 0);
}

}  // namespace
}  // namespace glintscope
