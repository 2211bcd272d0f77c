// Rectangular texels read natively: one analytic surface sampled at 1 × 1 µm and at 1 × 2 µm
// (rows 2 µm apart, half as many) gives the same interpolant, statistics and ISO 25178
// parameters, with no resampling anywhere.
#include <gtest/gtest.h>

#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/surface/areal_parameters.hpp"
#include "glintscope/surface/heightfield.hpp"
#include "glintscope/surface/interpolant.hpp"
#include "glintscope/surface/statistics.hpp"
#include "sampled_field.hpp"

namespace glintscope {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Periodic on 64 × 64 µm: waves of 32 µm along x, 64 µm along y and a diagonal one; ≥ 16 samples
// per period along y even at dy = 2 µm.
double surface(double x, double y) {
    return 0.5 * std::sin(2 * kPi * x / 32.0) * std::cos(2 * kPi * y / 64.0) +
           0.15 * std::cos(2 * kPi * (x / 64.0 + y / 32.0));
}

Heightfield sampled(double dy_um) {
    return testing::sampled_field(static_cast<int>(std::lround(64.0 / dy_um)), 64, 1.0, dy_um, surface);
}

TEST(RectangularTexels, SpacingAccessorsKeepSquareTheDefault) {
    Heightfield field = make_heightfield(4, 8, 0.5);
    EXPECT_TRUE(field.square_texels());
    EXPECT_EQ(field.dy_um(), 0.5);
    field.texel_um = 0.25;  // code that sets only dx keeps square texels
    EXPECT_EQ(field.dy_um(), 0.25);
    set_spacing(field, 0.25, 1.0);
    EXPECT_FALSE(field.square_texels());
    EXPECT_EQ(field.width_um(), 2.0);
    EXPECT_EQ(field.height_um(), 4.0);
    EXPECT_EQ(sample_position(field, 0, 1).y, 3.5);  // row 0 is the top, rows dy apart
    EXPECT_EQ(texel_text(field), "250 nm x 1 um (x by y)");
    EXPECT_THROW(set_spacing(field, 1.0, -1.0), Error);
}

TEST(RectangularTexels, InterpolantReadsEachAxisAtItsOwnSpacing) {
    const BicubicInterpolant fine(sampled(1.0)), coarse(sampled(2.0));
    EXPECT_EQ(coarse.texel_y_um(), 2.0);
    double height = 0.0, slope_x = 0.0, slope_y = 0.0;
    for (int k = 0; k < 200; ++k) {
        const double x = std::fmod(7.31 * k, 64.0), y = std::fmod(3.77 * k + 0.4, 64.0);
        const SurfacePoint a = fine.evaluate(x, y), b = coarse.evaluate(x, y);
        height = std::fmax(height, std::fabs(a.height - b.height));
        slope_x = std::fmax(slope_x, std::fabs(a.dh_dx - b.dh_dx));
        slope_y = std::fmax(slope_y, std::fabs(a.dh_dy - b.dh_dy));
        // The rectangular interpolant against the surface itself (Catmull–Rom's error at 32
        // samples per period of the 0.15 wave along y).
        EXPECT_NEAR(b.height, surface(x, y), 2e-3) << x << "," << y;
    }
    // Heights ~0.5, slopes ~0.1: the 1 × 2 sampling errs at the level of its interpolation error.
    EXPECT_LT(height, 2e-3);
    EXPECT_LT(slope_x, 2e-3);
    EXPECT_LT(slope_y, 3e-3);
    // The grid evaluation and the curvature use dy along y too.
    SurfacePoint grid[4];
    coarse.evaluate_grid(3.0, 5.0, 0.5, 1.5, 2, 2, grid);
    const SurfacePoint direct = coarse.evaluate(3.5, 6.5);
    EXPECT_DOUBLE_EQ(grid[3].height, direct.height);
    EXPECT_DOUBLE_EQ(grid[3].dh_dy, direct.dh_dy);
    const double d2y_fine = fine.curvature(10.3, 20.7).d2h_dy2, d2y_coarse = coarse.curvature(10.3, 20.7).d2h_dy2;
    EXPECT_NEAR(d2y_coarse, d2y_fine, 0.05 * std::fabs(d2y_fine) + 2e-3);
}

TEST(RectangularTexels, StatisticsAndIsoParametersAgreeWithTheSquareSampling) {
    const Heightfield square = sampled(1.0), rectangular = sampled(2.0);
    const SurfaceStatistics a = compute_statistics(square), b = compute_statistics(rectangular);
    EXPECT_NEAR(b.sq_um / a.sq_um, 1.0, 1e-3);
    EXPECT_NEAR(b.rms_slope_x / a.rms_slope_x, 1.0, 1e-3);
    // Central differences over 2dy = 4 µm lose (2π·4/32)²/6 ≈ 10% of the 32 µm wave's slope; over
    // 2 µm, 2.6%: the rms y slopes differ by the difference of those truncation errors.
    EXPECT_NEAR(b.rms_slope_y / a.rms_slope_y, 1.0, 0.06);
    EXPECT_NEAR(b.correlation_length_x_um / a.correlation_length_x_um, 1.0, 1e-2);
    EXPECT_NEAR(b.correlation_length_y_um / a.correlation_length_y_um, 1.0, 2e-2);

    const ArealParameters p = compute_areal_parameters(square, 0.2), q = compute_areal_parameters(rectangular, 0.2);
    EXPECT_NEAR(q.sq_um / p.sq_um, 1.0, 1e-3);
    EXPECT_NEAR(q.sa_um / p.sa_um, 1.0, 2e-3);
    EXPECT_NEAR(q.ssk, p.ssk, 1e-2);
    EXPECT_NEAR(q.sku / p.sku, 1.0, 1e-2);
    EXPECT_NEAR(q.sdq / p.sdq, 1.0, 0.04);
    EXPECT_NEAR(q.sal_um / p.sal_um, 1.0, 2e-2);
    EXPECT_NEAR(q.str, p.str, 2e-2);
    EXPECT_NEAR(q.max_lag_y_um, p.max_lag_y_um, 2.0);
}

// A random anisotropic field (c1, T 40 × 4 µm, its long axis at 30° from +x) on 1 µm texels, and
// the same field with every other row dropped: exactly its 1 × 2 µm sampling, aliasing at most
// e^−13 of the power (the spectrum along y dies as exp(−π²T_y²k²)). The lay, the autocorrelation
// decay and its anisotropy are read the same from both.
TEST(RectangularTexels, AnisotropicRandomFieldGivesTheSameSpatialParameters) {
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {128, 128, 1.0};
    recipe.gaussian.correlation_length_x_um = 40.0;
    recipe.gaussian.correlation_length_y_um = 4.0;
    recipe.gaussian.orientation_rad = kPi / 6.0;
    const Heightfield square = generate(recipe);
    Heightfield rectangular = make_heightfield(64, 128, 1.0);
    set_spacing(rectangular, 1.0, 2.0);
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 128; ++c) rectangular.at(r, c) = square.at(2 * r + 1, c);  // same y positions
    const ArealParameters p = compute_areal_parameters(square, 0.2), q = compute_areal_parameters(rectangular, 0.2);
    EXPECT_NEAR(p.std_deg, 30.0, 5.0);  // the lay runs along the long correlation axis
    EXPECT_NEAR(q.std_deg, p.std_deg, 2.0);
    EXPECT_NEAR(q.sal_um / p.sal_um, 1.0, 0.05);
    EXPECT_NEAR(q.str / p.str, 1.0, 0.05);
    EXPECT_NEAR(q.sq_um / p.sq_um, 1.0, 0.02);
    // Sdq's central differences span 2dy = 4 µm, one T_y: they miss more of the short-axis slope
    // than over 2 µm (measured 10% less), a sampling effect, not a texel-shape one.
    EXPECT_NEAR(q.sdq / p.sdq, 0.9, 0.05);
}

}  // namespace
}  // namespace glintscope
