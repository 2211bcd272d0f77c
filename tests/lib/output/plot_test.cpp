// Line plots: a series' points land where its axes put them, in its colour; bad series refused.
#include "glintscope/output/plot.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

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

// The largest distance (pixels) of the series' blue pixels left of the legend from the straight
// line through them, fitted over the mean blue row of each column.
double straightness(const std::string& path) {
    OIIO::ImageBuf picture(path);
    if (!picture.read()) return -1.0;
    std::vector<double> columns, rows;
    for (int x = 95; x < 640; ++x) {  // inside the plot area (90..650), off its frame
        double sum = 0.0;
        int count = 0;
        for (int y = 60; y < 415; ++y) {
            float p[3];
            picture.getpixel(x, y, p, 3);
            if (p[0] < 0.05f && std::abs(p[1] - 0.45f) < 0.05f && std::abs(p[2] - 0.70f) < 0.05f) sum += y, ++count;
        }
        if (count > 0) columns.push_back(x), rows.push_back(sum / count);
    }
    if (columns.size() < 2) return -1.0;
    double mx = 0.0, my = 0.0;
    for (std::size_t k = 0; k < columns.size(); ++k) mx += columns[k], my += rows[k];
    mx /= columns.size(), my /= columns.size();
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t k = 0; k < columns.size(); ++k)
        sxy += (columns[k] - mx) * (rows[k] - my), sxx += (columns[k] - mx) * (columns[k] - mx);
    double worst = 0.0;
    for (std::size_t k = 0; k < columns.size(); ++k)
        worst = std::max(worst, std::abs(rows[k] - (my + sxy / sxx * (columns[k] - mx))));
    return worst;
}

TEST(Plot, APowerLawIsStraightOnLogLogAxesOnly) {
    testing::TemporaryDirectory directory;
    PlotSeries power{"x^2", {}, {}};
    power.marks = false;
    for (int k = 0; k <= 30; ++k) power.x.push_back(std::pow(10.0, k / 10.0)), power.y.push_back(std::pow(10.0, k / 5.0));
    Plot plot{"power law", "x", "y", {}, {power}, /*log_y=*/true, /*log_x=*/true};
    write_plot(plot, directory.file("loglog.png"));
    const double log_log = straightness(directory.file("loglog.png"));
    EXPECT_GE(log_log, 0.0);
    EXPECT_LT(log_log, 3.0);
    plot.log_x = false;  // exponential in x on a log y axis: strongly curved
    write_plot(plot, directory.file("semilog.png"));
    EXPECT_GT(straightness(directory.file("semilog.png")), 30.0);
    // Stacked: two plots, each with its own axes, one above the other.
    write_plots({plot, plot}, directory.file("stacked.png"));
    OIIO::ImageBuf one(directory.file("semilog.png")), two(directory.file("stacked.png"));
    ASSERT_TRUE(one.read() && two.read());
    EXPECT_EQ(two.spec().height, 2 * one.spec().height - 8);  // the bottom margin once
}

}  // namespace
}  // namespace glintscope
