// Line plots: a series' points land where its axes put them, in its colour; bad series refused.
#include "glintscope/output/plot.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include <OpenImageIO/imagebuf.h>

#include "glintscope/core/error.hpp"
#include "cli_runner.hpp"

namespace glintscope {
namespace {

TEST(Plot, AFlatSeriesIsDrawnAsOneHorizontalLineAndBadSeriesAreRefused) {
    testing::TemporaryDirectory directory;
    const std::string path = directory.file("plot.png");
    // y = 0.5 at every x, on a linear axis: one row of the picture holds the whole line.
    write_plot({"flat", "x", "y", {"caption"}, {{"half", {0.0, 1.0, 2.0}, {0.5, 0.5, 0.5}}}}, path);
    OIIO::ImageBuf picture(path);
    ASSERT_TRUE(picture.read()) << picture.geterror();
    const OIIO::ROI roi = picture.roi();
    int best_row = -1, best_count = 0;
    for (int y = roi.ybegin; y < roi.yend; ++y) {
        int count = 0;  // pixels of the series' blue (0, 0.45, 0.70)
        for (int x = roi.xbegin; x < roi.xend; ++x) {
            float p[3];
            picture.getpixel(x, y, p, 3);
            if (p[0] < 0.05f && std::abs(p[1] - 0.45f) < 0.05f && std::abs(p[2] - 0.70f) < 0.05f) ++count;
        }
        if (count > best_count) best_count = count, best_row = y;
    }
    EXPECT_GT(best_count, 400);  // the plot area is 560 pixels wide; the legend's sample adds 28
    EXPECT_GT(best_row, 0);
    EXPECT_THROW(write_plot({"bad", "x", "y", {}, {{"s", {0.0, 1.0}, {1.0}}}}, directory.file("bad.png")), Error);
    EXPECT_THROW(write_plot({"empty", "x", "y", {}, {}}, directory.file("empty.png")), Error);
    EXPECT_THROW(write_plot({"log", "x", "y", {}, {{"s", {0.0}, {-1.0}}}, true}, directory.file("log.png")), Error);
}

}  // namespace
}  // namespace glintscope
