// Rectangular texels made square (for the methods that need them): the same analytic surface
// sampled at 1 × 1 µm and at 1 × 2 µm (rows 2 µm apart) gives the same field, statistics and ISO
// parameters once the 1 × 2 sampling is resampled along y.
#include "glintscope/surface/square_texels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "glintscope/core/error.hpp"
#include "glintscope/surface/areal_parameters.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {
namespace {

constexpr double kPi = 3.14159265358979323846;

// h = A sin(2πx/Λx) cos(2πy/Λy) + 0.3 A cos(2π(x + y)/Λd) on `rows` × 64 samples, columns 1 µm
// apart and rows dy apart, one period of every term (periodic).
Heightfield waves(int rows, double dy_um) {
    Heightfield field = make_heightfield(rows, 64, 1.0);
    set_spacing(field, 1.0, dy_um);
    const double height = rows * dy_um;  // 64 µm
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < 64; ++c) {
            const double x = c + 0.5, y = (rows - r - 0.5) * dy_um;
            field.at(r, c) = static_cast<float>(0.5 * std::sin(2 * kPi * x / 32.0) * std::cos(2 * kPi * y / height) +
                                                0.15 * std::cos(2 * kPi * (x / 64.0 + y / height)));
        }
    return field;
}

TEST(SquareTexels, TwoToOneSamplingEqualsTheSquareSamplingOfTheSameSurface) {
    const Heightfield square = waves(64, 1.0);
    Heightfield rectangular = waves(32, 2.0);
    const SquareTexelReport report = make_texels_square(rectangular, 1u << 20, "test");
    ASSERT_EQ(rectangular.rows, 64);
    ASSERT_EQ(rectangular.cols, 64);
    EXPECT_EQ(rectangular.texel_um, 1.0);
    EXPECT_EQ(report.period_change, 0.0);
    double largest = 0.0;
    for (std::size_t i = 0; i < square.size(); ++i)
        largest = std::max(largest, std::fabs(double(square.heights_um[i]) - rectangular.heights_um[i]));
    // Catmull–Rom on a wave of 32 samples per period errs by about (2π/32)³/… of its amplitude.
    EXPECT_LT(largest, 2e-3);
    EXPECT_LT(report.round_trip_max_um, 2e-3);

    const SurfaceStatistics a = compute_statistics(square), b = compute_statistics(rectangular);
    EXPECT_NEAR(b.sq_um / a.sq_um, 1.0, 1e-3);
    const ArealParameters p = compute_areal_parameters(square, 0.2), q = compute_areal_parameters(rectangular, 0.2);
    EXPECT_NEAR(q.sq_um / p.sq_um, 1.0, 1e-3);
    EXPECT_NEAR(q.sdq / p.sdq, 1.0, 5e-3);
    EXPECT_NEAR(q.sal_um / p.sal_um, 1.0, 1e-2);
}

TEST(SquareTexels, NearlySquareSpacingKeepsTheGridAndSaysHowMuchChanged) {
    Heightfield field = waves(64, 1.0);
    set_spacing(field, 1.0, 1.0005);
    field.periodic = false;
    const Heightfield before = field;
    const SquareTexelReport report = make_texels_square(field, 1u << 20, "test");
    EXPECT_EQ(field.rows, 64);  // round(64 · 1.0005) = 64
    EXPECT_EQ(field.texel_um, 1.0);
    // Rows move by at most 32 × 0.0005 texel: the heights by about that times the slope (≤ 0.1).
    double largest = 0.0;
    for (std::size_t i = 0; i < field.size(); ++i)
        largest = std::max(largest, std::fabs(double(field.heights_um[i]) - before.heights_um[i]));
    EXPECT_GT(largest, 0.0);
    EXPECT_LT(largest, 0.1 * 32 * 0.0005 * 1.5);
    EXPECT_GT(report.round_trip_max_um, 0.0);
    EXPECT_NE(describe(report, field).find("rows 64 -> 64"), std::string::npos);
}

TEST(SquareTexels, MissingPointsStayMissingOnlyWhereTheKernelReadsThem) {
    Heightfield field = waves(32, 2.0);
    field.periodic = false;
    field.at(10, 5) = std::numeric_limits<float>::quiet_NaN();
    make_texels_square(field, 1u << 20, "test");
    int missing = 0;
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c)
            if (std::isnan(field.at(r, c))) {
                ++missing;
                EXPECT_EQ(c, 5);
            }
    // New rows at source positions k/2 − ¼: those within two source rows of row 10 read it.
    EXPECT_GE(missing, 3);
    EXPECT_LE(missing, 8);
}

TEST(SquareTexels, AbsurdAspectsAndSizesAreRefusedInOneLine) {
    Heightfield field = waves(32, 2.0);
    EXPECT_THROW(make_texels_square(field, 1000, "test"), Error);
    field.texel_y_um = 20.0;
    EXPECT_THROW(make_texels_square(field, 1u << 20, "test"), Error);
    field.texel_y_um = std::nan("");
    EXPECT_THROW(make_texels_square(field, 1u << 20, "test"), Error);
}

}  // namespace
}  // namespace glintscope
