// Generation with rectangular texels: every generator works in µm per axis, so one recipe at
// 1 × 1 µm and at 1 × 2 µm describes the same surface, sampled twice as coarsely along y.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/surface/areal_parameters.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {
namespace {

constexpr double kPi = std::numbers::pi;

std::string error_message(const Recipe& recipe) {
    try {
        generate(recipe);
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(RectangularTexels, GratingIsTheSameSinusoidInMicrometres) {
    // Λ = 8 µm at dx = 0.5, dy = 1 µm, along y, along x and obliquely: every sample is
    // A sin(2π u/Λ) at its own position ((c + 0.5)dx, (R − r − 0.5)dy) to float precision.
    for (const double angle : {0.0, kPi / 2.0, kPi / 6.0}) {
        Recipe recipe = default_recipe("grating");
        recipe.grid = {40, 64, 0.5, 1.0};
        recipe.grating = {8.0, 0.2, angle};
        const Heightfield field = generate(recipe);
        ASSERT_DOUBLE_EQ(field.dx_um(), 0.5);
        ASSERT_DOUBLE_EQ(field.dy_um(), 1.0);
        double largest_error = 0.0;
        for (int r = 0; r < field.rows; ++r)
            for (int c = 0; c < field.cols; ++c) {
                const Point2 p = sample_position(field, r, c);
                const double expected = 0.2 * std::sin(2.0 * kPi / 8.0 * (p.x * std::cos(angle) + p.y * std::sin(angle)));
                largest_error = std::max(largest_error, std::fabs(field.at(r, c) - expected));
            }
        EXPECT_LT(largest_error, 1e-7) << "angle " << angle;
    }
}

TEST(RectangularTexels, GratingAlongYHasTheSlopeOfItsSpacing) {
    // Central differences over 2dy of A sin(2πy/Λ): rms slope A sin(2π dy/Λ)/(√2 dy).
    Recipe recipe = default_recipe("grating");
    recipe.grid = {40, 16, 0.25, 0.5};  // 20 µm tall: 4 periods of 5 µm
    recipe.grating = {5.0, 0.2, kPi / 2.0};
    EXPECT_EQ(seamless_warning(recipe), "");
    const SurfaceStatistics stats = compute_statistics(generate(recipe));
    EXPECT_NEAR(stats.sq_um, 0.2 / std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(stats.rms_slope_y, 0.2 * std::sin(2.0 * kPi * 0.5 / 5.0) / (std::sqrt(2.0) * 0.5), 1e-5);
}

TEST(RectangularTexels, IsotropicRecipeKeepsItsStatisticsAtOneByTwo) {
    // The isotropic preset (C1, T = 10 µm) on the same 512 µm square tile at 1 × 1 µm and
    // 1 × 2 µm, four seeds each: one tile's Sal scatters by about 6 %, the mean of four by 3 %.
    constexpr int kSeeds = 4;
    double sal_square = 0.0, sal_rectangular = 0.0, str_square = 0.0, str_rectangular = 0.0;
    for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
        Recipe square = default_recipe("isotropic");
        square.grid = {512, 512, 1.0};
        square.seed = seed;
        Recipe rectangular = square;
        rectangular.grid = {256, 512, 1.0, 2.0};
        const Heightfield a = generate(square);
        const Heightfield b = generate(rectangular);
        ASSERT_DOUBLE_EQ(b.height_um(), a.height_um());
        const ArealParameters pa = compute_areal_parameters(a);
        const ArealParameters pb = compute_areal_parameters(b);
        EXPECT_NEAR(pa.sq_um, 1.2, 1e-5);
        EXPECT_NEAR(pb.sq_um, 1.2, 1e-5);
        sal_square += pa.sal_um / kSeeds;
        sal_rectangular += pb.sal_um / kSeeds;
        str_square += pa.str / kSeeds;
        str_rectangular += pb.str / kSeeds;
    }
    // C1 reaches s = 0.2 at T √ln 5 = 12.7 µm in every direction: Sal ≈ 12.7 µm and Str ≈ 1 (a
    // little below: the fastest and slowest of 360 noisy directions).
    const double sal = 10.0 * std::sqrt(std::log(5.0));
    EXPECT_NEAR(sal_square / sal, 1.0, 0.08);
    EXPECT_NEAR(sal_rectangular / sal, 1.0, 0.08);
    EXPECT_NEAR(sal_rectangular / sal_square, 1.0, 0.08);
    EXPECT_NEAR(str_square, 0.93, 0.07);
    EXPECT_NEAR(str_rectangular, 0.93, 0.07);
    EXPECT_NEAR(str_rectangular - str_square, 0.0, 0.06);
    // The spectrum is per axis: central differences over 2d of a C1 field have the rms slope
    // σ √((1 − e^{−4d²/T²})/(2d²)) for d = dx along x and d = dy along y.
    Recipe recipe = default_recipe("isotropic");
    recipe.grid = {256, 512, 1.0, 2.0};
    const SurfaceStatistics stats = compute_statistics(generate(recipe));
    const auto rms_slope = [](double d) { return 1.2 * std::sqrt((1.0 - std::exp(-4.0 * d * d / 100.0)) / (2.0 * d * d)); };
    EXPECT_NEAR(stats.rms_slope_x / rms_slope(1.0), 1.0, 0.06);
    EXPECT_NEAR(stats.rms_slope_y / rms_slope(2.0), 1.0, 0.06);
    EXPECT_NEAR(stats.correlation_length_y_um / 10.0, 1.0, 0.1);
}

TEST(RectangularTexels, CdBumpsKeepTheirVolume) {
    // Bumps 0.5 × 1 µm on a 0.1 × 0.3 µm grid: the area average keeps Σ h dx dy = N h0 a b.
    Recipe recipe = default_recipe("cd");
    recipe.grid = {111, 200, 0.1, 0.3};
    const Heightfield field = generate(recipe);
    const std::size_t bumps = place_cd_bumps(recipe.grid, recipe.cd, recipe.seed).size();
    double volume = 0.0;
    for (float h : field.heights_um) volume += h * 0.1 * 0.3;
    EXPECT_NEAR(volume / (bumps * 0.15 * 0.5 * 1.0), 1.0, 1e-5);
    for (const Point2& bump : place_cd_bumps(recipe.grid, recipe.cd, recipe.seed)) EXPECT_LT(bump.y, 111 * 0.3);
}

TEST(RectangularTexels, ScratchKeepsItsVolume) {
    // One 200 µm groove, 6 µm wide and 0.3 µm deep (parabolic: area factor 2/3, tapers 0.9 ℓ) on
    // a 256 × 256 µm tile sampled at 1 × 2 µm.
    Recipe recipe = default_recipe("scratched");
    recipe.grid = {128, 256, 1.0, 2.0};
    recipe.gaussian.sigma_h_um = 0.0;
    recipe.scratches = {1.0 / (0.256 * 0.256), 0.3, 0.3, 6.0, 6.0, 200.0, 200.0, ScratchProfile::parabolic};
    const Heightfield field = generate(recipe);
    ASSERT_EQ(place_scratches(recipe.grid, recipe.scratches, recipe.seed).size(), 1u);
    double volume = 0.0;
    for (float h : field.heights_um) volume -= h * 1.0 * 2.0;
    EXPECT_NEAR(volume / (0.3 * 2.0 / 3.0 * 6.0 * 0.9 * 200.0), 1.0, 0.03);
}

TEST(RectangularTexels, RecipeKeyRoundTripsAndRecordsProvenance) {
    const Recipe recipe = parse_recipe_text("kind = gaussian\nsize = 64\ntexel = 0.5um\ntexel_y = 750nm\n", "r.recipe");
    EXPECT_DOUBLE_EQ(recipe.grid.dx_um(), 0.5);
    EXPECT_DOUBLE_EQ(recipe.grid.dy_um(), 0.75);
    EXPECT_EQ(recipe_value(recipe, "texel_y"), "0.75");
    std::string text = "kind = gaussian\n";
    for (const RecipeKey& key : recipe_keys())
        if (std::find(key.kinds.begin(), key.kinds.end(), "gaussian") != key.kinds.end())
            text += key.name + " = " + recipe_value(recipe, key.name) + "\n";
    const Recipe again = parse_recipe_text(text, "again.recipe");
    EXPECT_DOUBLE_EQ(again.grid.dx_um(), 0.5);
    EXPECT_DOUBLE_EQ(again.grid.dy_um(), 0.75);
    // Without texel_y the texels stay square and follow texel.
    EXPECT_EQ(recipe_value(parse_recipe_text("kind = gaussian\ntexel = 2\n", "s.recipe"), "texel_y"), "2");
    Recipe small = recipe;
    small.gaussian.correlation_length_x_um = small.gaussian.correlation_length_y_um = 4.0;
    const Heightfield field = generate(small);
    EXPECT_DOUBLE_EQ(field.dy_um(), 0.75);
    EXPECT_EQ(field.provenance.at("generator.texel_y_um"), "0.75");
}

TEST(RectangularTexels, AbsurdSpacingsAreOneLineErrors) {
    const auto parse_error = [](const std::string& text) {
        try {
            parse_recipe_text("kind = gaussian\n" + text, "r.recipe");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    EXPECT_EQ(parse_error("texel_y = 0\n"), "r.recipe line 2: texel_y: must be a positive length, got '0'");
    EXPECT_EQ(parse_error("texel_y = -1um\n"), "r.recipe line 2: texel_y: must be a positive length, got '-1um'");
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {64, 64, 1.0, 20.0};
    EXPECT_EQ(error_message(recipe), "texel 1 um and texel_y 20 um differ by more than 16 times");
    recipe.grid.texel_y_um = std::nan("");
    EXPECT_NE(error_message(recipe).find("texel_y must be a positive length"), std::string::npos);
    // A grating along y must have two samples per period along y.
    Recipe grating = default_recipe("grating");
    grating.grid = {64, 64, 0.25, 1.0};
    grating.grating = {1.5, 0.1, kPi / 2.0};
    EXPECT_NE(error_message(grating).find("period (1.5 um) is shorter than two texels (2 um)"), std::string::npos);
    grating.grating.angle_rad = 0.0;  // along x, 0.25 µm texels sample it
    EXPECT_EQ(error_message(grating), "(no error)");
}

}  // namespace
}  // namespace glintscope
