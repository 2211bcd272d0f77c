// Procedural heightfields: each generator delivers the statistics it was asked for, the same
// bits on any thread count, and a one-line Error for absurd parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstring>
#include <filesystem>
#include <numbers>

#include "generate/correlation_spectrum.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {
namespace {

constexpr double kPi = std::numbers::pi;

Recipe gaussian_recipe(CorrelationFunction correlation, double tx, double ty, std::uint64_t seed = 1) {
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {1024, 1024, 1.0};
    recipe.gaussian = {correlation, 0.05, tx, ty, 0.0};
    recipe.seed = seed;
    return recipe;
}

bool same_bits(const Heightfield& a, const Heightfield& b) {
    return a.size() == b.size() && std::memcmp(a.heights_um.data(), b.heights_um.data(), a.size() * sizeof(float)) == 0;
}

std::string error_message(const std::function<void()>& action) {
    try {
        action();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

// ---- The folded power spectrum ------------------------------------------------------------

double correlation(CorrelationFunction kind, const GaussianFieldParameters& p, double x, double y) {
    const double c = std::cos(p.orientation_rad);
    const double s = std::sin(p.orientation_rad);
    const double u = (c * x + s * y) / p.correlation_length_x_um;
    const double v = (-s * x + c * y) / p.correlation_length_y_um;
    switch (kind) {
        case CorrelationFunction::c1: return std::exp(-u * u - v * v);
        case CorrelationFunction::c2: return std::exp(-std::sqrt(u * u + v * v));
        case CorrelationFunction::c3: return std::exp(-std::fabs(u) - std::fabs(v));
    }
    return 0.0;
}

// Poisson summation: Σ_(m,n) S(kx + m/dx, ky + n/dy) = dx dy Σ_(q,p) C_periodic(q dx, p dy)
// e^{−i2π(kx q dx + ky p dy)}. The right side is computed by brute force (C summed over periodic
// images, then a direct DFT) and compared with the generator's filter over all bins. The relative
// L1 error Σ|ΔS|/ΣS bounds the error of the synthesised field's covariance at every lag, as a
// fraction of σ_h².
double folded_spectrum_error(const GaussianFieldParameters& p, const GridSpec& grid = {20, 24, 0.8}) {
    const double width = grid.width_um();
    const double height = grid.height_um();
    std::vector<double> periodic(static_cast<std::size_t>(grid.rows) * grid.cols, 0.0);
    const auto signed_index = [](int index, int count) { return index <= count / 2 ? index : index - count; };
    for (int p_row = 0; p_row < grid.rows; ++p_row)
        for (int q = 0; q < grid.cols; ++q)
            for (int a = -12; a <= 12; ++a)
                for (int b = -12; b <= 12; ++b)
                    periodic[p_row * grid.cols + q] += correlation(
                        p.correlation, p, signed_index(q, grid.cols) * grid.dx_um() + a * width,
                        -signed_index(p_row, grid.rows) * grid.dy_um() + b * height);
    const SampledPowerSpectrum spectrum(p, grid);
    double error = 0.0;
    double total = 0.0;
    for (int i = 0; i < grid.rows; ++i)
        for (int j = 0; j < grid.cols; ++j) {
            std::complex<double> dft = 0.0;
            for (int p_row = 0; p_row < grid.rows; ++p_row)
                for (int q = 0; q < grid.cols; ++q)
                    dft += periodic[p_row * grid.cols + q] *
                           std::polar(1.0, -2.0 * kPi * (static_cast<double>(i * p_row) / grid.rows +
                                                         static_cast<double>(j * q) / grid.cols));
            const double expected = grid.dx_um() * grid.dy_um() * dft.real();
            error += std::fabs(spectrum.aliased(i, j) - expected);
            total += expected;
        }
    return error / total;
}

TEST(CorrelationSpectrum, SeparableFoldingIsExact) {
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c1, 1.0, 1.5, 0.9, 0.0}), 1e-12);
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c3, 1.0, 1.5, 0.9, 0.0}), 1e-12);
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c1, 1.0, 2.0, 0.9, 0.4}), 1e-12);  // rotated C1
}

TEST(CorrelationSpectrum, FoldingIsPerAxisOnRectangularTexels) {
    // dy = 2 dx: the reciprocal lattice is (m/dx, n/dy), the DFT bins j/(cols dx), i/(rows dy).
    const GridSpec rectangular{20, 24, 0.6, 1.2};
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c1, 1.0, 1.5, 1.8, 0.0}, rectangular), 1e-12);
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c3, 1.0, 1.5, 1.8, 0.0}, rectangular), 1e-12);
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c1, 1.0, 2.0, 1.8, 0.4}, rectangular), 1e-12);
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c2, 1.0, 2.4, 3.2, 0.7}, rectangular), 5e-3);
}

TEST(CorrelationSpectrum, NonSeparableFoldingIsCloseToExact) {
    // C2 and rotated C3 sum the nearest 3×3 images exactly and the far ones approximately.
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c2, 1.0, 2.4, 1.6, 0.0}), 5e-3);
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c2, 1.0, 2.4, 1.6, 0.7}), 5e-3);
    EXPECT_LT(folded_spectrum_error({CorrelationFunction::c3, 1.0, 2.4, 1.6, 0.4}), 2e-2);
}

// ---- Gaussian random fields ---------------------------------------------------------------

void expect_statistics(const Recipe& recipe, double tx_expected, double ty_expected) {
    const Heightfield field = generate(recipe);
    const SurfaceStatistics stats = compute_statistics(field);
    EXPECT_NEAR(stats.mean_um, 0.0, 1e-6);
    EXPECT_NEAR(stats.sq_um / recipe.gaussian.sigma_h_um, 1.0, 0.02);
    EXPECT_NEAR(stats.correlation_length_x_um / tx_expected, 1.0, 0.05);
    EXPECT_NEAR(stats.correlation_length_y_um / ty_expected, 1.0, 0.05);
}

TEST(GaussianRandomField, C1HasRequestedSqAndCorrelationLength) {
    expect_statistics(gaussian_recipe(CorrelationFunction::c1, 5.0, 5.0), 5.0, 5.0);
}

TEST(GaussianRandomField, C2HasRequestedSqAndCorrelationLength) {
    expect_statistics(gaussian_recipe(CorrelationFunction::c2, 5.0, 5.0), 5.0, 5.0);
}

TEST(GaussianRandomField, C3HasRequestedSqAndCorrelationLength) {
    expect_statistics(gaussian_recipe(CorrelationFunction::c3, 5.0, 5.0), 5.0, 5.0);
}

TEST(GaussianRandomField, AnisotropicCorrelationLengths) {
    expect_statistics(gaussian_recipe(CorrelationFunction::c1, 5.0, 15.0), 5.0, 15.0);
    expect_statistics(gaussian_recipe(CorrelationFunction::c3, 4.0, 8.0, 2), 4.0, 8.0);
}

TEST(GaussianRandomField, OrientationTurnsTheCorrelationEllipse) {
    // T_x along +y: the measured x and y lengths swap.
    Recipe recipe = gaussian_recipe(CorrelationFunction::c1, 12.0, 4.0);
    recipe.gaussian.orientation_rad = kPi / 2.0;
    expect_statistics(recipe, 4.0, 12.0);
}

TEST(GaussianRandomField, RmsSlopeOfC1) {
    // Central differences of a C1 field: E[(H(x+dx) − H(x−dx))²]/(2dx)² = σ²(1 − e^{−4dx²/T²})/(2dx²).
    Recipe recipe = default_recipe("brushed");
    const SurfaceStatistics stats = compute_statistics(generate(recipe));
    const auto rms_slope = [&](double t) {
        return recipe.gaussian.sigma_h_um * std::sqrt((1.0 - std::exp(-4.0 / (t * t))) / 2.0);
    };
    EXPECT_NEAR(stats.rms_slope_y / rms_slope(recipe.gaussian.correlation_length_y_um), 1.0, 0.03);
    EXPECT_NEAR(stats.rms_slope_x / rms_slope(recipe.gaussian.correlation_length_x_um), 1.0, 0.2);
}

TEST(GaussianRandomField, IsotropicPresetHasRmsSlopeNearPointSeventeen) {
    const SurfaceStatistics stats = compute_statistics(generate_builtin("isotropic"));
    EXPECT_NEAR(stats.rms_slope_x, 0.17, 0.17 * 0.05);
    EXPECT_NEAR(stats.rms_slope_y, 0.17, 0.17 * 0.05);
}

TEST(GaussianRandomField, NonSquareOddSizes) {
    Recipe recipe = gaussian_recipe(CorrelationFunction::c2, 3.0, 3.0);
    recipe.grid = {301, 171, 0.5};
    const Heightfield field = generate(recipe);
    ASSERT_EQ(field.rows, 301);
    ASSERT_EQ(field.cols, 171);
    const SurfaceStatistics stats = compute_statistics(field);
    EXPECT_NEAR(stats.sq_um, 0.05, 1e-6);
    EXPECT_NEAR(stats.correlation_length_x_um / 3.0, 1.0, 0.1);
    EXPECT_NEAR(stats.correlation_length_y_um / 3.0, 1.0, 0.1);
}

// ---- Determinism --------------------------------------------------------------------------

Heightfield generate_with_threads(const Recipe& recipe, int threads) {
    return with_threads(threads, [&] { return generate(recipe); });
}

TEST(Generate, SameSeedGivesSameBitsOnAnyThreadCount) {
    for (const std::string kind : {"gaussian", "scratched", "cd"}) {
        Recipe recipe = default_recipe(kind);
        recipe.grid.rows = 200;
        recipe.grid.cols = 330;
        if (kind != "cd") recipe.gaussian.correlation = CorrelationFunction::c2;
        if (kind != "cd") recipe.gaussian.orientation_rad = 0.3;
        recipe.scratches.density_per_mm2 = 2000.0;
        EXPECT_TRUE(same_bits(generate_with_threads(recipe, 1), generate_with_threads(recipe, 2))) << kind;
    }
}

TEST(Generate, DifferentSeedsGiveDifferentSurfaces) {
    for (const std::string kind : {"gaussian", "scratched", "cd"}) {
        Recipe recipe = default_recipe(kind);
        recipe.grid.rows = recipe.grid.cols = 128;
        recipe.scratches.density_per_mm2 = 2000.0;
        const Heightfield first = generate(recipe);
        recipe.seed = 2;
        const Heightfield second = generate(recipe);
        std::size_t differing = 0;
        for (std::size_t i = 0; i < first.size(); ++i) differing += first.heights_um[i] != second.heights_um[i];
        EXPECT_GT(differing, first.size() / 10) << kind;
    }
}

// ---- Grating ------------------------------------------------------------------------------

TEST(Grating, StatisticsAreExact) {
    Recipe recipe = default_recipe("grating");
    recipe.grid = {48, 400, 0.25};
    recipe.grating = {5.0, 0.2, 0.0};  // 20 samples per period, 20 periods across
    EXPECT_EQ(seamless_warning(recipe), "");
    const SurfaceStatistics stats = compute_statistics(generate(recipe));
    EXPECT_NEAR(stats.mean_um, 0.0, 1e-7);
    EXPECT_NEAR(stats.sq_um, 0.2 / std::sqrt(2.0), 1e-6);
    const double k = 2.0 * kPi / 5.0;
    EXPECT_NEAR(stats.rms_slope_x, 0.2 * std::sin(k * 0.25) / (std::sqrt(2.0) * 0.25), 1e-5);
    EXPECT_NEAR(stats.rms_slope_y, 0.0, 1e-9);
    // ACF cos(k·lag): crossing 1/e at acos(1/e)/k, to within the linear interpolation between texels.
    EXPECT_NEAR(stats.correlation_length_x_um, std::acos(kCorrelationThreshold) / k, 0.01);
}

TEST(Grating, AngleTurnsTheGrooves) {
    Recipe recipe = default_recipe("grating");
    recipe.grid = {400, 40, 0.25};
    recipe.grating = {5.0, 0.2, kPi / 2.0};
    const SurfaceStatistics stats = compute_statistics(generate(recipe));
    EXPECT_NEAR(stats.sq_um, 0.2 / std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(stats.rms_slope_x, 0.0, 1e-6);
    EXPECT_NEAR(stats.rms_slope_y, 0.2 * std::sin(2.0 * kPi / 20.0) / (std::sqrt(2.0) * 0.25), 1e-5);
}

TEST(Grating, WarnsWhenNotSeamless) {
    Recipe recipe = default_recipe("grating");
    recipe.grating.period_um = 3.0;  // 256 µm is not a whole number of 3 µm periods
    EXPECT_NE(seamless_warning(recipe).find("not seamless"), std::string::npos);
    recipe.grid.rows = recipe.grid.cols = 64;
    EXPECT_NE(generate(recipe).provenance.count("generator.warning"), 0u);
}

// ---- CD tracks ----------------------------------------------------------------------------

TEST(CdTracks, BoxFilterConservesEveryBumpsVolume) {
    for (BumpShape shape : {BumpShape::flat, BumpShape::ramp}) {
        Recipe recipe = default_recipe("cd");
        recipe.grid = {333, 200, 0.1};  // 8 tracks; the texels do not line up with the bump edges
        recipe.cd.shape = shape;
        const Heightfield field = generate(recipe);
        const std::size_t bumps = place_cd_bumps(recipe.grid, recipe.cd, recipe.seed).size();
        double volume = 0.0;
        for (float h : field.heights_um) volume += h * field.texel_um * field.texel_um;
        const CdParameters& cd = recipe.cd;
        // ∫ g over a bump: a·b for g⁰ = 1, a·b/2 for the ramp g¹ = 1/2 + x/a.
        const double bump_volume = cd.bump_height_um * cd.bump_width_um * cd.bump_length_um * (shape == BumpShape::flat ? 1.0 : 0.5);
        EXPECT_NEAR(volume / (bumps * bump_volume), 1.0, 1e-5);
    }
}

// The union of a track's bumps, measured directly on the periodic track from the bump centres.
double covered_length(const std::vector<double>& centres, double length, double height) {
    const int samples = 200000;
    int covered = 0;
    for (int k = 0; k < samples; ++k) {
        const double y = (k + 0.5) * height / samples;
        for (double centre : centres) {
            const double d = std::remainder(y - centre, height);
            if (std::fabs(d) < 0.5 * length) {
                ++covered;
                break;
            }
        }
    }
    return covered * height / samples;
}

TEST(CdTracks, MergedBumpsArePitsOfOneHeight) {
    Recipe recipe = default_recipe("cd");
    recipe.grid = {300, 50, 0.1};  // 2 tracks of 30 µm: about 15 bumps each, several overlapping
    recipe.cd.overlap = BumpOverlap::merge;
    const Heightfield field = generate(recipe);
    const SurfaceStatistics stats = compute_statistics(field);
    EXPECT_LE(stats.max_um, recipe.cd.bump_height_um * (1.0 + 1e-6));
    // Volume = h0 · a · (length of the union of each track's bumps, wrapping round the tile).
    const std::vector<Point2> bumps = place_cd_bumps(recipe.grid, recipe.cd, recipe.seed);
    double expected = 0.0;
    for (double x : {1.25, 3.75}) {
        std::vector<double> centres;
        for (const Point2& bump : bumps)
            if (bump.x == x) centres.push_back(bump.y);
        expected += recipe.cd.bump_height_um * recipe.cd.bump_width_um * covered_length(centres, 1.0, 30.0);
    }
    double volume = 0.0;
    for (float h : field.heights_um) volume += h * 0.01;
    EXPECT_NEAR(volume / expected, 1.0, 1e-3);
    recipe.cd.overlap = BumpOverlap::add;
    EXPECT_GT(compute_statistics(generate(recipe)).max_um, 1.5 * recipe.cd.bump_height_um);  // some bumps stack
}

TEST(CdTracks, FillFractionMatchesStamTable1) {
    const Recipe recipe = default_recipe("cd");
    const Heightfield field = generate(recipe);
    const SurfaceStatistics stats = compute_statistics(field);
    const CdParameters& cd = recipe.cd;
    // Mean height / h0 = a·b·ν_y/Δx = 0.1 for Table 1; 2000 bumps expected, so ±8 % is about 3.5σ.
    EXPECT_NEAR(stats.mean_um / cd.bump_height_um / (cd.bump_width_um * cd.bump_length_um * cd.bump_density_per_um / cd.track_spacing_um), 1.0, 0.08);
    EXPECT_GE(stats.min_um, 0.0);
    const std::vector<Point2> bumps = place_cd_bumps(recipe.grid, cd, recipe.seed);
    EXPECT_NEAR(bumps.size() / (cd.bump_density_per_um * field.height_um() * 40.0), 1.0, 0.08);
    for (const Point2& bump : bumps) {
        const double track = bump.x / cd.track_spacing_um - 0.5;
        EXPECT_NEAR(track, std::round(track), 1e-9);
        EXPECT_GE(bump.y, 0.0);
        EXPECT_LT(bump.y, field.height_um());
    }
}

// ---- Scratches ----------------------------------------------------------------------------

TEST(Scratches, PlacementHonoursCountAndRanges) {
    const Recipe recipe = default_recipe("scratched");
    const std::vector<Scratch> scratches = place_scratches(recipe.grid, recipe.scratches, recipe.seed);
    const double area_mm2 = 1.024 * 1.024;
    EXPECT_EQ(scratches.size(), static_cast<std::size_t>(std::llround(recipe.scratches.density_per_mm2 * area_mm2)));
    const ScratchParameters& s = recipe.scratches;
    int profiles[3] = {0, 0, 0};
    for (const Scratch& scratch : scratches) {
        EXPECT_GE(scratch.depth_um, s.depth_min_um);
        EXPECT_LE(scratch.depth_um, s.depth_max_um);
        EXPECT_GE(scratch.width_um, s.width_min_um);
        EXPECT_LE(scratch.width_um, s.width_max_um);
        EXPECT_GE(scratch.length_um, s.length_min_um);
        EXPECT_LE(scratch.length_um, s.length_max_um);
        ASSERT_NE(scratch.profile, ScratchProfile::mixed);
        ++profiles[static_cast<int>(scratch.profile)];
    }
    for (int count : profiles) EXPECT_GT(count, 0);  // "mixed" uses every cross-section
}

TEST(Scratches, GroovesHaveTheirDepthAndVolumeAcrossTileEdges) {
    // One groove on a 256 µm tile with no base noise. Its volume is depth × cross-section area
    // factor × width × effective length (the smoothstep tapers over 10 % at each end average 1/2,
    // so 0.9 ℓ), wherever it lies: a groove leaving one edge continues at the opposite one.
    const std::pair<ScratchProfile, double> profiles[] = {
        {ScratchProfile::parabolic, 2.0 / 3.0}, {ScratchProfile::v, 0.5}, {ScratchProfile::rounded, kPi / 4.0}};
    for (const auto& [profile, area_factor] : profiles) {
        for (std::uint64_t seed = 1; seed <= 3; ++seed) {
            Recipe recipe = default_recipe("scratched");
            recipe.grid = {256, 256, 1.0};
            recipe.seed = seed;
            recipe.gaussian.sigma_h_um = 0.0;
            recipe.scratches = {1.0 / (0.256 * 0.256), 0.3, 0.3, 6.0, 6.0, 200.0, 200.0, profile};
            const Heightfield field = generate(recipe);
            ASSERT_EQ(place_scratches(recipe.grid, recipe.scratches, seed).size(), 1u);
            double volume = 0.0;
            for (float h : field.heights_um) volume -= h;
            EXPECT_NEAR(volume / (0.3 * area_factor * 6.0 * 0.9 * 200.0), 1.0, 0.02);
            const SurfaceStatistics stats = compute_statistics(field);
            EXPECT_LE(stats.max_um, 0.0);
            EXPECT_GE(stats.min_um, -0.3 - 1e-6);
            EXPECT_LE(stats.min_um, -0.85 * 0.3);
        }
    }
}

// ---- Recipes and validation ---------------------------------------------------------------

TEST(Recipe, ParsesKeysWithUnits) {
    const Recipe recipe = parse_recipe_text(
        "# a comment\nkind = gaussian\nsize = 300\ncols = 200\ntexel = 500nm\nseed = 7\ncorrelation = c3\n"
        "sigma_h = 50 nm  # trailing comment\ncorrelation_length_x = 0.004mm\norientation = 30\n",
        "test.recipe");
    EXPECT_EQ(recipe.kind, "gaussian");
    EXPECT_EQ(recipe.grid.rows, 300);
    EXPECT_EQ(recipe.grid.cols, 200);
    EXPECT_NEAR(recipe.grid.texel_um, 0.5, 1e-15);
    EXPECT_EQ(recipe.seed, 7u);
    EXPECT_EQ(recipe.gaussian.correlation, CorrelationFunction::c3);
    EXPECT_NEAR(recipe.gaussian.sigma_h_um, 0.05, 1e-15);
    EXPECT_NEAR(recipe.gaussian.correlation_length_x_um, 4.0, 1e-14);
    EXPECT_DOUBLE_EQ(recipe.gaussian.correlation_length_y_um, default_recipe("gaussian").gaussian.correlation_length_y_um);
    EXPECT_NEAR(recipe.gaussian.orientation_rad, kPi / 6.0, 1e-15);
    EXPECT_EQ(recipe_value(recipe, "orientation"), "30");
}

TEST(Recipe, ParseErrorsNameTheLine) {
    const auto parse = [](const std::string& text) { return error_message([&] { parse_recipe_text(text, "r.recipe"); }); };
    EXPECT_EQ(parse("sigma_h = 1\n"), "r.recipe: no 'kind = ...' line");
    EXPECT_NE(parse("kind = marble\n").find("r.recipe line 1: unknown heightfield kind 'marble'"), std::string::npos);
    EXPECT_EQ(parse("kind = gaussian\nfoo = 1\n"), "r.recipe line 2: unknown key 'foo'");
    EXPECT_EQ(parse("kind = gaussian\nseed = 1\nseed = 2\n"), "r.recipe line 3: 'seed' is set twice");
    EXPECT_EQ(parse("kind = gaussian\nperiod = 3\n"),
              "r.recipe line 2: period does not apply to kind 'gaussian' (only to grating)");
    EXPECT_NE(parse("kind = gaussian\nsigma_h = 3 parsecs\n").find("r.recipe line 2: sigma_h: "), std::string::npos);
    EXPECT_EQ(parse("kind = gaussian\ncorrelation = c4\n"),
              "r.recipe line 2: correlation: 'c4' is not one of c1, c2, c3");
    EXPECT_EQ(parse("kind = gaussian\njust words\n"), "r.recipe line 2: expected 'key = value', got 'just words'");
    EXPECT_EQ(parse("kind = gaussian\nrows = 0\n"), "r.recipe line 2: rows: '0' is not a grid size between 1 and 65536");
}

TEST(Recipe, AbsurdParametersAreOneLineErrors) {
    struct Case {
        std::string kind;
        std::function<void(Recipe&)> change;
        std::string message;
    };
    const Case cases[] = {
        {"gaussian", [](Recipe& r) { r.gaussian.sigma_h_um = -0.1; }, "sigma_h must be a positive length"},
        {"gaussian", [](Recipe& r) { r.gaussian.sigma_h_um = std::nan(""); }, "sigma_h must be a positive length"},
        {"gaussian", [](Recipe& r) { r.gaussian.correlation_length_x_um = 0.0; }, "correlation_length_x must be"},
        {"gaussian", [](Recipe& r) { r.gaussian.correlation_length_y_um = 2000.0; }, "exceed the 1.024 mm x 1.024 mm tile"},
        {"gaussian", [](Recipe& r) { r.grid.texel_um = 0.0; }, "texel must be a positive length"},
        {"gaussian", [](Recipe& r) { r.grid.rows = 40000; r.grid.cols = 40000; }, "more than 2^30 samples"},
        {"gaussian", [](Recipe& r) { r.grid.cols = -3; }, "rows and cols must be between 1 and 65536"},
        {"scratched", [](Recipe& r) { r.scratches.depth_min_um = 1.0; }, "scratch_depth_min (1 um) is larger than scratch_depth_max"},
        {"scratched", [](Recipe& r) { r.scratches.width_max_um = -1.0; }, "scratch_width_max must be a positive length"},
        {"scratched", [](Recipe& r) { r.scratches.density_per_mm2 = 1e9; }, "more than 10^6 scratches"},
        {"grating", [](Recipe& r) { r.grating.period_um = 0.3; }, "period (300 nm) is shorter than two texels"},
        {"grating", [](Recipe& r) { r.grating.amplitude_um = std::numeric_limits<double>::infinity(); }, "amplitude must be"},
        {"cd", [](Recipe& r) { r.cd.bump_width_um = 3.0; }, "bump_width (3 um) is wider than track_spacing (2.5 um)"},
        {"cd", [](Recipe& r) { r.cd.bump_density_per_um = 0.0; }, "bump_density must be a positive number"},
        {"cd", [](Recipe& r) { r.kind = "velvet"; }, "unknown heightfield kind 'velvet'"},
    };
    for (const Case& c : cases) {
        Recipe recipe = default_recipe(c.kind);
        c.change(recipe);
        const std::string message = error_message([&] { generate(recipe); });
        EXPECT_NE(message.find(c.message), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos);
    }
}

TEST(Recipe, ProvenanceRecordsEveryParameter) {
    Recipe recipe = default_recipe("isotropic");
    recipe.grid.rows = recipe.grid.cols = 128;
    const Provenance provenance = generate(recipe).provenance;
    EXPECT_EQ(provenance.at("generator"), "gaussian");
    EXPECT_EQ(provenance.at("generator.preset"), "isotropic");
    EXPECT_EQ(provenance.at("generator.sigma_h_um"), "1.2");
    EXPECT_EQ(provenance.at("generator.correlation_length_x_um"), "10");
    EXPECT_EQ(provenance.at("generator.orientation_deg"), "0");
    EXPECT_EQ(provenance.at("generator.correlation"), "c1");
    EXPECT_EQ(provenance.at("generator.seed"), "1");
    EXPECT_EQ(provenance.at("generator.rows"), "128");
    EXPECT_EQ(provenance.at("generator.texel_um"), "1");
    EXPECT_EQ(provenance.count("generator.period_um"), 0u);
    const Provenance cd = generate_builtin("cd").provenance;
    EXPECT_EQ(cd.at("generator"), "cd");
    EXPECT_EQ(cd.at("generator.bump_density_per_um"), "0.5");
    EXPECT_EQ(cd.at("generator.bump_shape"), "flat");
    EXPECT_EQ(cd.at("generator.bump_overlap"), "add");
}

TEST(Recipe, BuiltinsHaveDocumentedSizes) {
    for (const std::string kind : {"isotropic", "brushed", "scratched", "gaussian"}) {
        const Recipe recipe = default_recipe(kind);
        EXPECT_EQ(recipe.grid.rows, 1024);
        EXPECT_EQ(recipe.grid.cols, 1024);
        EXPECT_EQ(recipe.grid.texel_um, 1.0);
        EXPECT_EQ(seamless_warning(recipe), "");
    }
    EXPECT_EQ(default_recipe("grating").grid.texel_um, 0.25);
    EXPECT_EQ(seamless_warning(default_recipe("grating")), "");
    EXPECT_EQ(default_recipe("cd").grid.rows, 1000);
    EXPECT_EQ(seamless_warning(default_recipe("cd")), "");
}

TEST(Recipe, CanonicalRecipeFilesDescribeThePaperSurfaces) {
    const std::filesystem::path directory = std::filesystem::path(GLINTSCOPE_SOURCE_DIR) / "heightfields";
    for (const std::string kind : {"isotropic", "brushed", "scratched"}) {
        const Recipe recipe = load_recipe((directory / (kind + ".recipe")).string());
        EXPECT_EQ(recipe.kind, kind);
        EXPECT_EQ(recipe.grid.rows, 8192);
        EXPECT_EQ(recipe.grid.cols, 8192);
        EXPECT_EQ(recipe.grid.texel_um, 1.0);
        EXPECT_NO_THROW(validate_recipe(recipe));
    }
    EXPECT_NE(error_message([&] { load_recipe((directory / "missing.recipe").string()); }).find("no such file"),
              std::string::npos);
}

}  // namespace
}  // namespace glintscope
