// The shared interpolant: passes through the samples and its analytic gradient converges to
// the true gradient at second order in dx (issue: foundation, "Heightfield model").
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/surface/interpolant.hpp"

namespace glintscope {
namespace {

constexpr double kPeriod = 64.0;  // µm; the field tiles, so the test function must too

double smooth_height(double x, double y) {
    const double k = 2.0 * std::numbers::pi / kPeriod;
    return std::sin(k * x) * std::cos(2.0 * k * y) + 0.5 * std::cos(k * (x + y));
}

Point2 smooth_gradient(double x, double y) {
    const double k = 2.0 * std::numbers::pi / kPeriod;
    return {k * std::cos(k * x) * std::cos(2.0 * k * y) - 0.5 * k * std::sin(k * (x + y)),
            -2.0 * k * std::sin(k * x) * std::sin(2.0 * k * y) - 0.5 * k * std::sin(k * (x + y))};
}

Heightfield sampled(int n) {
    Heightfield field = make_heightfield(n, n, kPeriod / n);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const Point2 s = sample_position(field, r, c);
            field.at(r, c) = static_cast<float>(smooth_height(s.x, s.y));
        }
    return field;
}

// RMS over a dense low-discrepancy set of points, so every fractional position within a texel
// is represented equally at every resolution.
double rms_gradient_error(int n) {
    const BicubicInterpolant surface(sampled(n));
    constexpr int kPoints = 4096;
    double sum = 0.0;
    for (int i = 0; i < kPoints; ++i) {
        const double x = std::fmod(0.7548776662 * i, 1.0) * kPeriod;
        const double y = std::fmod(0.5698402910 * i, 1.0) * kPeriod;
        const SurfacePoint p = surface.evaluate(x, y);
        const Point2 g = smooth_gradient(x, y);
        sum += (p.dh_dx - g.x) * (p.dh_dx - g.x) + (p.dh_dy - g.y) * (p.dh_dy - g.y);
    }
    return std::sqrt(sum / kPoints);
}

TEST(BicubicInterpolant, ReproducesEverySample) {
    const Heightfield field = sampled(48);
    const BicubicInterpolant surface(field);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            EXPECT_NEAR(surface.height(s.x, s.y), field.at(r, c), 1e-6);
        }
}

TEST(BicubicInterpolant, GradientConvergesAtSecondOrder) {
    const double coarse = rms_gradient_error(32);
    const double fine = rms_gradient_error(64);
    const double finer = rms_gradient_error(128);
    // Halving dx divides the error by 4 at second order (measured 4.01 and 4.05).
    EXPECT_NEAR(coarse / fine, 4.0, 0.3);
    EXPECT_NEAR(fine / finer, 4.0, 0.3);
    EXPECT_LT(finer, 1e-4);
}

TEST(BicubicInterpolant, TilesPeriodically) {
    const BicubicInterpolant surface(sampled(40));
    for (double x : {0.3, 11.7, 40.1})
        for (double y : {0.9, 25.2}) {
            EXPECT_NEAR(surface.height(x, y), surface.height(x + kPeriod, y - 2 * kPeriod), 1e-5);
            EXPECT_NEAR(surface.evaluate(x, y).dh_dx, surface.evaluate(x - kPeriod, y).dh_dx, 1e-5);
        }
}

TEST(BicubicInterpolant, ReproducesAPlaneExactly) {
    Heightfield field = make_heightfield(8, 12, 0.5);
    // A plane is not periodic, but away from the wrap seam the stencil sees only the plane.
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            field.at(r, c) = static_cast<float>(0.25 * s.x - 0.125 * s.y);
        }
    const BicubicInterpolant surface(field);
    const SurfacePoint p = surface.evaluate(2.8, 2.1);
    EXPECT_NEAR(p.height, 0.25 * 2.8 - 0.125 * 2.1, 1e-6);
    EXPECT_NEAR(p.dh_dx, 0.25, 1e-6);
    EXPECT_NEAR(p.dh_dy, -0.125, 1e-6);
}

// The batch evaluations are evaluate() computed with shared taps: bit-identical values, for grids
// wider than one column block, crossing the periodic seam, and at the samples themselves.
TEST(BicubicInterpolant, GridAndSampleEvaluationsMatchPointwise) {
    const BicubicInterpolant surface(sampled(40));  // dx = 1.6 µm
    const double dx = kPeriod / 40;
    std::vector<SurfacePoint> grid(150 * 7);
    surface.evaluate_grid(-3.3, 60.1, 0.7, 150, 7, grid.data());
    std::vector<SurfacePoint> samples(90 * 5);
    surface.evaluate_samples(-7, 38, 90, 5, samples.data());
    for (int j = 0; j < 7; ++j)
        for (int i = 0; i < 150; ++i) {
            const SurfacePoint expected = surface.evaluate(-3.3 + i * 0.7, 60.1 + j * 0.7);
            const SurfacePoint& got = grid[j * 150 + i];
            EXPECT_EQ(got.height, expected.height);
            EXPECT_EQ(got.dh_dx, expected.dh_dx);
            EXPECT_EQ(got.dh_dy, expected.dh_dy);
        }
    for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 90; ++i) {
            const SurfacePoint expected = surface.evaluate((i - 7 + 0.5) * dx, (j + 38 + 0.5) * dx);
            const SurfacePoint& got = samples[j * 90 + i];
            EXPECT_NEAR(got.height, expected.height, 1e-12);
            EXPECT_NEAR(got.dh_dx, expected.dh_dx, 1e-12);
            EXPECT_NEAR(got.dh_dy, expected.dh_dy, 1e-12);
        }
}

// Single samples, on the seams too, take exactly the block evaluation's values (the block
// evaluation is built on them; this pins the wrapping of both).
TEST(BicubicInterpolant, SamplePointMatchesBlock) {
    const BicubicInterpolant surface(sampled(40));
    std::vector<SurfacePoint> block(40 * 40);
    surface.evaluate_samples(0, 0, 40, 40, block.data());
    for (int j = 0; j < 40; ++j)
        for (int c = 0; c < 40; ++c) {
            const SurfacePoint expected = block[j * 40 + c];
            const SurfacePoint got = surface.sample_point(c, j);
            EXPECT_EQ(got.height, expected.height);
            EXPECT_EQ(got.dh_dx, expected.dh_dx);
            EXPECT_EQ(got.dh_dy, expected.dh_dy);
            EXPECT_EQ(surface.sample_row(j)[c], got.height);
        }
}

TEST(BicubicInterpolant, RefusesMissingPoints) {
    Heightfield field = make_heightfield(4, 4, 1.0);
    field.at(1, 2) = std::nanf("");
    EXPECT_THROW(BicubicInterpolant{field}, Error);
}

}  // namespace
}  // namespace glintscope
