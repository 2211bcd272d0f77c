// Preparing measured heightfields: filling drop-outs, form removal, cropping and resampling
// (lib/src/fill_missing.cpp, form_removal.cpp, crop.cpp, resample.cpp, prepare.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/prepare/prepare.hpp"

#include "sampled_field.hpp"

namespace glintscope {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kTwoPi = 2.0 * std::numbers::pi;

using HeightFunction = std::function<double(double x, double y)>;

using testing::sampled_field;

void punch_disk(Heightfield& field, double row, double col, double radius) {
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c)
            if ((r - row) * (r - row) + (c - col) * (c - col) <= radius * radius) field.at(r, c) = kNaN;
}

void punch_rectangle(Heightfield& field, int first_row, int first_col, int rows, int cols) {
    for (int r = first_row; r < first_row + rows; ++r)
        for (int c = first_col; c < first_col + cols; ++c) field.at(r, c) = kNaN;
}

// Holes of many shapes, all at least three samples from the border of a 96×130 field.
void punch_interior_holes(Heightfield& field) {
    punch_disk(field, 40.0, 60.0, 9.0);
    punch_rectangle(field, 70, 10, 3, 45);  // a long thin scratch
    punch_rectangle(field, 12, 100, 20, 20);
    for (int k = 0; k < 40; ++k) field.at(5 + (k * 37) % 86, 5 + (k * 53) % 120) = kNaN;  // isolated drop-outs
}

// Every valid point of `before` is bit for bit the same in `after`, and `after` has no NaN.
void expect_valid_points_kept(const Heightfield& before, const Heightfield& after) {
    ASSERT_EQ(before.size(), after.size());
    EXPECT_EQ(count_missing(after), 0u);
    for (std::size_t k = 0; k < before.size(); ++k) {
        if (std::isnan(before.heights_um[k])) continue;
        ASSERT_EQ(std::memcmp(&before.heights_um[k], &after.heights_um[k], sizeof(float)), 0) << "point " << k;
    }
}

// The largest |filled − truth| over the points that were missing.
double fill_error(const Heightfield& holes, const Heightfield& filled, const Heightfield& truth) {
    double worst = 0.0;
    for (std::size_t k = 0; k < holes.size(); ++k)
        if (std::isnan(holes.heights_um[k]))
            worst = std::fmax(worst, std::fabs(static_cast<double>(filled.heights_um[k]) - truth.heights_um[k]));
    return worst;
}

// ---- fill_missing ---------------------------------------------------------------------------

TEST(FillMissing, BiharmonicCarriesACubicThroughInteriorHolesExactly) {
    // The thin-plate equations are the 13-point Δ² stencil, which annihilates every cubic.
    const HeightFunction cubic = [](double x, double y) {
        const double u = x / 60.0 - 1.0;
        const double v = y / 50.0 - 1.0;
        return 0.3 + 0.5 * u - 0.2 * v + 0.7 * u * v - 0.4 * u * u * u + 0.25 * u * v * v + 0.6 * v * v * v;
    };
    const Heightfield truth = sampled_field(96, 130, 1.0, cubic);
    Heightfield field = truth;
    punch_interior_holes(field);
    const Heightfield holes = field;
    fill_missing(field, FillMethod::biharmonic);
    expect_valid_points_kept(holes, field);
    EXPECT_LT(fill_error(holes, field, truth), 1e-6);  // float rounding of O(1) heights
}

TEST(FillMissing, HarmonicCarriesAHarmonicFunctionThroughInteriorHolesExactly) {
    // x² − y² and xy satisfy the 5-point Laplace equation exactly.
    const HeightFunction harmonic = [](double x, double y) {
        const double u = x / 60.0 - 1.0;
        const double v = y / 60.0 - 1.0;
        return 0.2 + 0.4 * u - 0.3 * v + 0.5 * (u * u - v * v) + 0.8 * u * v;
    };
    const Heightfield truth = sampled_field(96, 130, 1.0, harmonic);
    Heightfield field = truth;
    punch_interior_holes(field);
    const Heightfield holes = field;
    fill_missing(field, FillMethod::harmonic);
    expect_valid_points_kept(holes, field);
    EXPECT_LT(fill_error(holes, field, truth), 1e-6);
}

TEST(FillMissing, BiharmonicContinuesAPlaneIntoHolesAtTheBorder) {
    // The thin plate's free boundary: a plane costs no energy, so border holes stay on it.
    const HeightFunction plane = [](double x, double y) { return 1.5 + 0.02 * x - 0.035 * y; };
    const Heightfield truth = sampled_field(60, 83, 0.5, plane);
    Heightfield field = truth;
    punch_rectangle(field, 0, 0, 12, 9);     // the top-left corner
    punch_rectangle(field, 20, 78, 15, 5);   // along the right border
    punch_rectangle(field, 55, 30, 5, 20);   // along the bottom border
    const Heightfield holes = field;
    const FillReport report = fill_missing(field);
    EXPECT_EQ(report.method, FillMethod::biharmonic);
    EXPECT_EQ(report.filled_points, 12u * 9 + 15 * 5 + 5 * 20);
    expect_valid_points_kept(holes, field);
    EXPECT_LT(fill_error(holes, field, truth), 1e-6);
}

TEST(FillMissing, SmoothFieldIsReproducedCloselyAndBiharmonicBeatsHarmonic) {
    // A smooth non-polynomial surface, 20 samples per shortest wavelength, with holes up to 18
    // samples across, some touching the border.
    const HeightFunction smooth = [](double x, double y) {
        return std::sin(kTwoPi * x / 40.0) * std::cos(kTwoPi * y / 55.0) + 0.4 * std::sin(kTwoPi * (x + 2 * y) / 70.0);
    };
    const Heightfield truth = sampled_field(96, 130, 0.5, smooth);
    Heightfield holes = truth;
    punch_interior_holes(holes);
    punch_rectangle(holes, 0, 40, 4, 12);
    punch_rectangle(holes, 80, 0, 10, 3);
    Heightfield harmonic = holes;
    Heightfield biharmonic = holes;
    fill_missing(harmonic, FillMethod::harmonic);
    fill_missing(biharmonic, FillMethod::biharmonic);
    expect_valid_points_kept(holes, harmonic);
    expect_valid_points_kept(holes, biharmonic);
    const double harmonic_error = fill_error(holes, harmonic, truth);
    const double biharmonic_error = fill_error(holes, biharmonic, truth);
    // Amplitude 1.4: the thin plate continues the curvature (error < 2% of it), the membrane
    // cannot (about 20%).
    EXPECT_LT(biharmonic_error, 0.025);
    EXPECT_LT(harmonic_error, 0.35);
    EXPECT_LT(biharmonic_error, 0.2 * harmonic_error);
}

TEST(FillMissing, LargeHoleIsSmoothAndHarmonicStaysWithinItsRim) {
    // A 70-sample-wide hole (multigrid path) in a tilted sinusoid.
    const HeightFunction surface = [](double x, double y) {
        return 0.01 * x + 0.3 * std::sin(kTwoPi * x / 50.0) * std::sin(kTwoPi * y / 45.0);
    };
    const Heightfield truth = sampled_field(150, 170, 1.0, surface);
    Heightfield holes = truth;
    punch_disk(holes, 75.0, 85.0, 35.0);
    for (FillMethod method : {FillMethod::harmonic, FillMethod::biharmonic}) {
        Heightfield field = holes;
        const FillReport report = fill_missing(field, method);
        EXPECT_EQ(report.holes, 1u);
        EXPECT_GT(report.largest_hole, 3000u);
        EXPECT_LE(report.relative_residual, 1e-9);
        expect_valid_points_kept(holes, field);
        // Smoothness: no seam at the rim or inside, the largest jump between neighbours
        // anywhere stays that of the data (slope ≤ 0.01 + 0.3·2π/45 ≈ 0.05 per sample).
        double steepest = 0.0;
        for (int r = 0; r < field.rows; ++r)
            for (int c = 0; c + 1 < field.cols; ++c)
                steepest = std::fmax(steepest, std::fabs(field.at(r, c + 1) - field.at(r, c)));
        EXPECT_LT(steepest, 0.06) << to_string(method);
        if (method == FillMethod::harmonic) {
            // Maximum principle: never beyond the range of the hole's rim (here: of all data).
            float low = std::numeric_limits<float>::infinity(), high = -low;
            for (float h : holes.heights_um)
                if (!std::isnan(h)) low = std::fmin(low, h), high = std::fmax(high, h);
            for (float h : field.heights_um) {
                EXPECT_GE(h, low);
                EXPECT_LE(h, high);
            }
        }
    }
}

TEST(FillMissing, PeriodicTilingFillsAcrossTheWrap) {
    // A hole straddling the left/right border of a periodic field is filled from both sides.
    const HeightFunction periodic = [](double x, double y) {
        return std::sin(kTwoPi * x / 64.0) + 0.5 * std::cos(kTwoPi * y / 48.0);
    };
    const Heightfield truth = sampled_field(48, 64, 1.0, periodic);
    Heightfield holes = truth;
    punch_rectangle(holes, 10, 0, 12, 4);
    punch_rectangle(holes, 10, 60, 12, 4);
    Heightfield wrapped = holes;
    const FillReport report = fill_missing(wrapped, FillMethod::biharmonic, Tiling::periodic);
    EXPECT_EQ(report.holes, 1u);  // one hole once the borders join
    expect_valid_points_kept(holes, wrapped);
    Heightfield open = holes;
    EXPECT_EQ(fill_missing(open, FillMethod::biharmonic, Tiling::none).holes, 2u);
    // 8 samples across, on a wavelength of 64: within 0.3% of the amplitude 1.5 when the two
    // halves see each other, several times worse when each is extrapolated from one side.
    const double wrapped_error = fill_error(holes, wrapped, truth);
    EXPECT_LT(wrapped_error, 5e-3);
    EXPECT_GT(fill_error(holes, open, truth), 3.0 * wrapped_error);
}

TEST(FillMissing, ResultIsIdenticalForAnyThreadCount) {
    // One hole above the parallel chunk size (40 000 unknowns) and many small ones.
    const HeightFunction surface = [](double x, double y) { return std::sin(0.05 * x) * std::cos(0.07 * y); };
    Heightfield holes = sampled_field(260, 300, 1.0, surface);
    punch_rectangle(holes, 20, 30, 200, 200);
    for (int k = 0; k < 200; ++k) punch_disk(holes, (k * 71) % 260, 240 + (k * 13) % 60, 1.5);
    std::vector<Heightfield> results;
    for (int threads : {1, 2, 3}) {
        const ThreadScope scope(threads);
        Heightfield field = holes;
        fill_missing(field);
        results.push_back(field);
    }
    for (std::size_t k = 1; k < results.size(); ++k)
        EXPECT_EQ(std::memcmp(results[0].heights_um.data(), results[k].heights_um.data(),
                              results[0].size() * sizeof(float)),
                  0);
}

TEST(FillMissing, CsafeScanWithDropOutsIsFilledCompletely) {
    Heightfield scan = load_heightfield(testing::shared_path("data/csafe-logo.x3p"));
    std::mt19937 random(7);
    std::uniform_int_distribution<int> row(0, scan.rows - 1), col(0, scan.cols - 1);
    for (int k = 0; k < 3000; ++k) scan.at(row(random), col(random)) = kNaN;
    punch_disk(scan, 200.0, 370.0, 40.0);
    punch_rectangle(scan, 0, 0, scan.rows, 6);  // a lost strip along the left border
    const Heightfield holes = scan;
    float low = std::numeric_limits<float>::infinity(), high = -low;
    for (float h : holes.heights_um)
        if (!std::isnan(h)) low = std::fmin(low, h), high = std::fmax(high, h);
    for (FillMethod method : {FillMethod::biharmonic, FillMethod::harmonic}) {
        Heightfield field = holes;
        const FillReport report = fill_missing(field, method);
        EXPECT_EQ(report.filled_points, count_missing(holes));
        expect_valid_points_kept(holes, field);
        // The logo is a two-level relief; the fill may overshoot its steps only modestly.
        const double margin = method == FillMethod::harmonic ? 0.0 : 0.5 * (high - low);
        for (float h : field.heights_um) {
            ASSERT_TRUE(std::isfinite(h));
            EXPECT_GE(h, low - margin);
            EXPECT_LE(h, high + margin);
        }
    }
}

TEST(FillMissing, RecordsItsStepAndRejectsHopelessInput) {
    Heightfield field = sampled_field(8, 11, 1.0, [](double x, double) { return x; });
    field.at(3, 4) = kNaN;
    const FillReport report = fill_missing(field);
    EXPECT_EQ(report.filled_points, 1u);
    ASSERT_EQ(field.provenance.count("prepare.1"), 1u);
    EXPECT_EQ(field.provenance["prepare.1"], describe(report));
    EXPECT_EQ(describe(report).rfind("fill_missing: 1 points", 0), 0u) << describe(report);

    Heightfield empty = make_heightfield(4, 5, 1.0, kNaN);
    EXPECT_THROW(fill_missing(empty), Error);
    Heightfield infinite = make_heightfield(4, 5, 1.0);
    infinite.at(1, 1) = std::numeric_limits<float>::infinity();
    EXPECT_THROW(fill_missing(infinite), Error);
    EXPECT_EQ(parse_fill_method("harmonic"), FillMethod::harmonic);
    EXPECT_THROW(parse_fill_method("nearest"), Error);
}

// ---- remove_form ----------------------------------------------------------------------------

TEST(RemoveForm, ExactPlaneLeavesZero) {
    // A tilted plane on a non-square grid with drop-outs; y is map-view (up).
    const HeightFunction plane = [](double x, double y) { return 3.0 + 0.01 * x - 0.02 * y; };
    Heightfield field = sampled_field(37, 53, 0.7, plane);
    field.at(5, 7) = kNaN;
    field.at(30, 50) = kNaN;
    const FormReport report = remove_form(field, 1);
    EXPECT_EQ(report.terms.size(), 3u);
    EXPECT_EQ(report.fitted_points, 37u * 53 - 2);
    EXPECT_NEAR(report.slope_x, 0.01, 1e-9);
    EXPECT_NEAR(report.slope_y, -0.02, 1e-9);
    EXPECT_TRUE(std::isnan(field.at(5, 7)));
    for (float h : field.heights_um) {
        if (std::isnan(h)) continue;
        EXPECT_LE(std::fabs(h), 1e-6);  // float rounding of heights near 3
    }
    // Σ over a uniform grid of a plane: rms about the mean = √(b_x² Var x + b_y² Var y) with
    // Var = dx² (n² − 1)/12 (two missing points shift it by < 0.1%).
    const double var_x = 0.7 * 0.7 * (53.0 * 53.0 - 1.0) / 12.0;
    const double var_y = 0.7 * 0.7 * (37.0 * 37.0 - 1.0) / 12.0;
    EXPECT_NEAR(report.rms_removed_um, std::sqrt(0.01 * 0.01 * var_x + 0.02 * 0.02 * var_y), 1e-3);
    EXPECT_LE(report.rms_residual_um, 1e-6);
    EXPECT_EQ(field.provenance["prepare.1"].rfind("remove_form: plane", 0), 0u);

    // Rectangular texels (rows 1.9 µm apart): the slopes come out in µm per µm along each axis.
    Heightfield rectangular = sampled_field(37, 53, 0.7, 1.9, plane);
    const FormReport rectangular_report = remove_form(rectangular, 1);
    EXPECT_NEAR(rectangular_report.slope_x, 0.01, 1e-9);
    EXPECT_NEAR(rectangular_report.slope_y, -0.02, 1e-9);
    EXPECT_LE(rectangular_report.rms_residual_um, 1e-6);
}

TEST(RemoveForm, PolynomialOfOrderNIsRemovedByOrderNButNotByOrderNMinusOne) {
    for (int order = 2; order <= kMaxFormOrder; ++order) {
        std::mt19937 random(static_cast<unsigned>(order));
        std::uniform_real_distribution<double> coefficient(-1.0, 1.0);
        std::vector<double> a;
        for (int i = 0; i <= order; ++i)
            for (int j = 0; i + j <= order; ++j) a.push_back(coefficient(random));
        // Monomials in plain µm (not the fit's basis), scaled so that heights stay O(1).
        const HeightFunction polynomial = [&](double x, double y) {
            double sum = 0.0;
            std::size_t k = 0;
            for (int i = 0; i <= order; ++i)
                for (int j = 0; i + j <= order; ++j) sum += a[k++] * std::pow(x / 40.0, i) * std::pow(y / 30.0, j);
            return sum;
        };
        const Heightfield original = sampled_field(48, 64, 1.0, polynomial);
        Heightfield exact = original;
        const FormReport report = remove_form(exact, order);
        EXPECT_EQ(report.terms.size(), static_cast<std::size_t>((order + 1) * (order + 2) / 2));
        EXPECT_LT(report.rms_residual_um, 1e-5 * report.rms_removed_um) << "order " << order;
        Heightfield short_of_it = original;
        const FormReport lower = remove_form(short_of_it, order - 1);
        EXPECT_GT(lower.rms_residual_um, 1e-3 * report.rms_removed_um) << "order " << order;
    }
}

TEST(RemoveForm, KeepsTheMicrogeometry) {
    // A checkerboard ±0.1 µm on a plane: removing the plane leaves the checkerboard.
    Heightfield field = sampled_field(40, 50, 1.0, [](double x, double y) { return 2.0 + 0.05 * x + 0.01 * y; });
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) field.at(r, c) += (r + c) % 2 ? 0.1f : -0.1f;
    const FormReport report = remove_form(field, 1);
    EXPECT_NEAR(report.slope_x, 0.05, 1e-6);
    EXPECT_NEAR(report.rms_residual_um, 0.1, 1e-5);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) EXPECT_NEAR(field.at(r, c), (r + c) % 2 ? 0.1 : -0.1, 1e-5);
}

TEST(RemoveForm, RejectsBadOrdersAndUndeterminedFits) {
    Heightfield field = sampled_field(10, 12, 1.0, [](double x, double y) { return x + y; });
    EXPECT_THROW(remove_form(field, -1), Error);
    EXPECT_THROW(remove_form(field, kMaxFormOrder + 1), Error);
    // Only one row of valid points: no slope in y can be fitted.
    Heightfield one_row = field;
    for (int r = 1; r < one_row.rows; ++r)
        for (int c = 0; c < one_row.cols; ++c) one_row.at(r, c) = kNaN;
    EXPECT_THROW(remove_form(one_row, 1), Error);
    EXPECT_NO_THROW(remove_form(one_row, 0));
    EXPECT_EQ(parse_form_order("mean"), 0);
    EXPECT_EQ(parse_form_order("plane"), 1);
    EXPECT_EQ(parse_form_order("poly:4"), 4);
    for (const char* bad : {"poly:7", "poly:", "poly:-1", "poly:2x", "cubic", ""})
        EXPECT_THROW(parse_form_order(bad), Error) << bad;
}

// ---- crop -----------------------------------------------------------------------------------

TEST(Crop, SamplesGiveTheExactSubGridAtShiftedPositions) {
    const Heightfield original = sampled_field(23, 31, 0.4, [](double x, double y) { return x * 100.0 + y; });
    Heightfield field = original;
    const CropReport report = crop_samples(field, 5, 7, 11, 13);
    ASSERT_EQ(field.rows, 11);
    ASSERT_EQ(field.cols, 13);
    EXPECT_EQ(field.texel_um, original.texel_um);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            EXPECT_EQ(field.at(r, c), original.at(5 + r, 7 + c));
            const Point2 cropped = sample_position(field, r, c);
            const Point2 before = sample_position(original, 5 + r, 7 + c);
            EXPECT_NEAR(cropped.x + report.origin_um.x, before.x, 1e-12);
            EXPECT_NEAR(cropped.y + report.origin_um.y, before.y, 1e-12);
        }
    EXPECT_NEAR(report.origin_um.x, 7 * 0.4, 1e-12);
    EXPECT_NEAR(report.origin_um.y, (23 - 5 - 11) * 0.4, 1e-12);
    EXPECT_EQ(field.provenance["prepare.1"], describe(report));
}

TEST(Crop, MicrometreRegionIsMeasuredFromTheLowerLeftCorner) {
    // 741×419 samples of 0.645 µm, like the CSAFE scan.
    const Heightfield original = sampled_field(419, 741, 0.645, [](double x, double y) { return x - 2.0 * y; });
    Heightfield field = original;
    const CropReport report = crop(field, {10.0, 20.0, 100.0, 50.0});
    // Edges snap to texel boundaries: round(10/0.645) = 16, round(110/0.645) = 171, etc.
    EXPECT_EQ(report.first_col, 16);
    EXPECT_EQ(field.cols, 171 - 16);
    EXPECT_EQ(field.rows, 109 - 31);           // y from round(20/0.645) = 31 to round(70/0.645) = 109
    EXPECT_EQ(report.first_row, 419 - 109);  // rows count down from the top
    for (int r = 0; r < field.rows; r += 7)
        for (int c = 0; c < field.cols; c += 7) {
            const Point2 s = sample_position(field, r, c);
            const double x = s.x + report.origin_um.x;
            const double y = s.y + report.origin_um.y;
            EXPECT_NEAR(field.at(r, c), x - 2.0 * y, 1e-3);
            EXPECT_GE(x, 10.0 - 0.645);
            EXPECT_LE(x, 110.0 + 0.645);
            EXPECT_GE(y, 20.0 - 0.645);
            EXPECT_LE(y, 70.0 + 0.645);
        }
    // The whole field, to the last rounding, is allowed.
    Heightfield whole = original;
    EXPECT_NO_THROW(crop(whole, {0.0, 0.0, 741 * 0.645, 419 * 0.645}));
    EXPECT_EQ(whole.heights_um, original.heights_um);
}

TEST(Crop, RejectsRegionsOutsideOrSmallerThanATexel) {
    const Heightfield original = make_heightfield(20, 30, 1.0);
    const std::vector<CropRegion> bad = {
        {-1.0, 0.0, 10.0, 10.0},  {0.0, -0.5, 10.0, 10.0}, {25.0, 0.0, 10.0, 10.0}, {0.0, 15.0, 10.0, 10.0},
        {0.0, 0.0, 0.0, 10.0},    {0.0, 0.0, 10.0, -2.0},  {0.0, 0.0, 0.3, 10.0},   {std::nan(""), 0.0, 1.0, 1.0},
        {0.0, 0.0, 1e300, 1e300}, {0.0, 0.0, std::numeric_limits<double>::infinity(), 1.0}};
    for (const CropRegion& region : bad) {
        Heightfield field = original;
        EXPECT_THROW(crop(field, region), Error) << region.x0_um << "," << region.y0_um << "," << region.width_um
                                                 << "," << region.height_um;
        EXPECT_EQ(field.rows, 20);  // untouched on failure
    }
    Heightfield field = original;
    EXPECT_THROW(crop_samples(field, 15, 0, 10, 5), Error);
    EXPECT_THROW(crop_samples(field, 0, 0, 0, 5), Error);
    EXPECT_THROW(crop_samples(field, -1, 0, 2, 5), Error);
    EXPECT_THROW(crop_samples(field, 0, 2147483000, 2, 5000), Error);
    try {
        crop(field, {25.0, 0.0, 10.0, 10.0});
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("outside the field"), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos);
    }
}

// ---- resample -------------------------------------------------------------------------------

// A smooth surface that tiles a 64 × 48 µm field: wavelengths 32 and 24 µm and a diagonal.
constexpr double kWidth = 64.0;
constexpr double kHeight = 48.0;
double periodic_surface(double x, double y) {
    return std::sin(kTwoPi * x / 32.0) * std::cos(kTwoPi * y / 24.0) +
           0.5 * std::cos(kTwoPi * (x / kWidth + y / kHeight));
}

// The mean of periodic_surface over the square of side a centred on (x, y): each Fourier
// component is multiplied by sinc(k_x a/2)·sinc(k_y a/2).
double periodic_surface_area_mean(double x, double y, double a) {
    const auto sinc = [](double t) { return t == 0.0 ? 1.0 : std::sin(t) / t; };
    const double kx1 = kTwoPi / 32.0, ky1 = kTwoPi / 24.0, kx2 = kTwoPi / kWidth, ky2 = kTwoPi / kHeight;
    return std::sin(kx1 * x) * std::cos(ky1 * y) * sinc(kx1 * a / 2) * sinc(ky1 * a / 2) +
           0.5 * std::cos(kx2 * x + ky2 * y) * sinc(kx2 * a / 2) * sinc(ky2 * a / 2);
}

// The largest |field − surface| over the field's samples.
double largest_deviation(const Heightfield& field, const HeightFunction& surface) {
    double worst = 0.0;
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            worst = std::fmax(worst, std::fabs(field.at(r, c) - surface(s.x, s.y)));
        }
    return worst;
}

TEST(Resample, UpsamplingMatchesTheAnalyticSurface) {
    Heightfield field = sampled_field(48, 64, 1.0, periodic_surface);
    const ResampleReport report = resample(field, 0.4, Tiling::periodic);
    EXPECT_FALSE(report.prefiltered);
    ASSERT_EQ(field.cols, 160);
    ASSERT_EQ(field.rows, 120);
    const double worst = largest_deviation(field, periodic_surface);
    // Catmull–Rom with 24 samples per shortest wavelength: within 0.1% of the amplitude 1.5.
    EXPECT_LT(worst, 1.5e-3);
}

TEST(Resample, DownsamplingGivesTheAreaMeanOfTheSurface) {
    Heightfield field = sampled_field(96, 128, 0.5, periodic_surface);
    const ResampleReport report = resample(field, 2.0, Tiling::periodic);
    EXPECT_TRUE(report.prefiltered);
    ASSERT_EQ(field.cols, 32);
    ASSERT_EQ(field.rows, 24);
    const double worst =
        largest_deviation(field, [](double x, double y) { return periodic_surface_area_mean(x, y, 2.0); });
    // Within 0.5% of the amplitude of the mean over each new 2 µm texel.
    EXPECT_LT(worst, 0.0075);
}

TEST(Resample, DownsamplingDoesNotAliasDetailTheCoarseGridCannotHold) {
    // A checkerboard at the old Nyquist frequency: point samples at every other texel would all
    // read +1 (aliased to a constant); the area mean is 0.
    Heightfield field = make_heightfield(40, 60, 1.0);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) field.at(r, c) = (r + c) % 2 ? 1.0f : -1.0f;
    resample(field, 2.0, Tiling::periodic);
    ASSERT_EQ(field.cols, 30);
    for (float h : field.heights_um) EXPECT_NEAR(h, 0.0, 1e-6);
}

TEST(Resample, KeepsTheExtentCentredAndTheSurfaceInPlace) {
    // A ramp h = x − 0.5 y on the CSAFE grid (741×419 of 0.645 µm) to 1 µm: 478×270 samples,
    // each within half a texel of the old extent, and the ramp read at the right positions.
    Heightfield field = sampled_field(419, 741, 0.645, [](double x, double y) { return x - 0.5 * y; });
    const double width = field.width_um(), height = field.height_um();
    const ResampleReport report = resample(field, 1.0);
    EXPECT_EQ(report.tiling, Tiling::none);
    EXPECT_EQ(field.cols, 478);
    EXPECT_EQ(field.rows, 270);
    EXPECT_EQ(field.texel_um, 1.0);
    EXPECT_LE(std::fabs(field.width_um() - width), 0.5);
    EXPECT_LE(std::fabs(field.height_um() - height), 0.5);
    const double x0 = 0.5 * (width - field.width_um()), y0 = 0.5 * (height - field.height_um());
    // Box means and Catmull–Rom reproduce a ramp exactly, and so does the point-reflected
    // continuation at the borders (heights up to 478 µm: float steps of 3e-5).
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            ASSERT_NEAR(field.at(r, c), (x0 + s.x) - 0.5 * (y0 + s.y), 3e-4) << r << "," << c;
        }
    EXPECT_NE(field.provenance["prepare.1"].find("478x270"), std::string::npos);
}

TEST(Resample, OpenBordersContinueTheTrendInsteadOfWrapping) {
    // A non-periodic ramp: wrapping mixes the high right edge into the low left one, point
    // reflection about the border samples continues the ramp.
    const Heightfield ramp = sampled_field(20, 50, 1.0, [](double x, double) { return x; });
    Heightfield open = ramp;
    Heightfield wrapped = ramp;
    resample(open, 0.5, Tiling::none);
    resample(wrapped, 0.5, Tiling::periodic);
    for (int r = 0; r < open.rows; ++r) {
        EXPECT_NEAR(open.at(r, 0), 0.25, 1e-5);  // the first new sample, at x = 0.25 µm
        EXPECT_NEAR(open.at(r, 99), 49.75, 1e-5);
        EXPECT_GT(wrapped.at(r, 0), 5.0);
    }
}

TEST(Resample, SameTexelKeepsTheSamples) {
    const Heightfield original = sampled_field(33, 47, 0.8, [](double x, double y) { return std::sin(x) * std::cos(y); });
    Heightfield field = original;
    resample(field, 0.8);
    ASSERT_EQ(field.size(), original.size());
    for (std::size_t k = 0; k < field.size(); ++k) EXPECT_NEAR(field.heights_um[k], original.heights_um[k], 1e-6);
}

// Rectangular texels: crop snaps each axis to its own spacing and keeps both; resample makes
// square texels from rectangular ones, on the same surface.
TEST(Crop, RectangularTexelsSnapEachAxisToItsOwnSpacing) {
    Heightfield field = sampled_field(40, 100, 0.5, 2.0, [](double x, double y) { return x - 2.0 * y; });
    const CropReport report = crop(field, {10.0, 20.0, 30.0, 40.0});
    EXPECT_EQ(field.cols, 60);  // x from 10/0.5 = 20 to 40/0.5 = 80
    EXPECT_EQ(field.rows, 20);  // y from 20/2 = 10 to 60/2 = 30
    EXPECT_EQ(field.dx_um(), 0.5);
    EXPECT_EQ(field.dy_um(), 2.0);
    EXPECT_EQ(report.origin_um.y, 20.0);
    for (int r = 0; r < field.rows; r += 3)
        for (int c = 0; c < field.cols; c += 7) {
            const Point2 s = sample_position(field, r, c);
            EXPECT_FLOAT_EQ(field.at(r, c), (s.x + report.origin_um.x) - 2.0 * (s.y + report.origin_um.y));
        }
    EXPECT_NE(describe(report).find("y 20..60 um"), std::string::npos) << describe(report);
}

TEST(Resample, RectangularTexelsBecomeSquareOnTheSameSurface) {
    Heightfield field = sampled_field(72, 64, 1.0, 2.0 / 3.0, periodic_surface);  // 64 x 48 um
    const ResampleReport report = resample(field, 0.8, Tiling::periodic);
    EXPECT_TRUE(report.prefiltered);  // y grows from 2/3 to 0.8 um: box over 1.2 rows
    EXPECT_EQ(report.original_texel_y_um, 2.0 / 3.0);
    ASSERT_EQ(field.cols, 80);
    ASSERT_EQ(field.rows, 60);
    EXPECT_TRUE(field.square_texels());
    const double worst = largest_deviation(field, periodic_surface);
    // The 1.2-row box along y damps the 24 µm wave by 1 − sinc(π·0.8/24) ≈ 0.2%, and the
    // interpolation errs by ~0.1% of the amplitude 1.5.
    EXPECT_LT(worst, 8e-3);
    EXPECT_NE(describe(report).find("1 x 0.666667 um"), std::string::npos) << describe(report);
}

TEST(Resample, RejectsBadTexelsAndMissingPoints) {
    const Heightfield original = make_heightfield(10, 12, 1.0);
    for (double texel : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity(), 1e-9}) {
        Heightfield field = original;
        EXPECT_THROW(resample(field, texel), Error) << texel;
        EXPECT_EQ(field.cols, 12);
    }
    Heightfield holes = original;
    holes.at(2, 3) = kNaN;
    try {
        resample(holes, 0.5);
        FAIL() << "resampling a field with NaN must throw";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("fill"), std::string::npos) << e.what();
    }
}

// ---- the steps together ----------------------------------------------------------------------

TEST(Prepare, StepsAreNumberedInTheOrderApplied) {
    Heightfield field = sampled_field(40, 60, 1.0, [](double x, double y) { return 0.1 * x + 0.2 * y; });
    field.at(20, 30) = kNaN;
    crop_samples(field, 2, 3, 30, 40);
    fill_missing(field);
    remove_form(field, 1);
    resample(field, 2.0);
    ASSERT_EQ(field.provenance.size(), 4u);
    EXPECT_EQ(field.provenance["prepare.1"].rfind("crop:", 0), 0u);
    EXPECT_EQ(field.provenance["prepare.2"].rfind("fill_missing:", 0), 0u);
    EXPECT_EQ(field.provenance["prepare.3"].rfind("remove_form:", 0), 0u);
    EXPECT_EQ(field.provenance["prepare.4"].rfind("resample:", 0), 0u);
    EXPECT_EQ(field.cols, 20);
    EXPECT_EQ(field.rows, 15);
}

}  // namespace
}  // namespace glintscope
