#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>

#include "glintscope/core/geometry.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/validate/validate.hpp"

namespace glintscope {
namespace {

TEST(Validate, AFlatMirrorAgreesToTheKernelBlurAndEveryRowIsReported) {
    ValidationPlan plan;
    set_heightfield(plan.base, make_heightfield(64, 64, 1.0));
    plan.base.footprint.sigma_um = 5.0;
    plan.base.resolution = 64;
    plan.base.supersample = 2;
    plan.base.wavelengths_um = {0.45, 0.6};
    // The mirror direction −ω̄_i at the centre of pixel (31, 40) of 64, so the peak is one pixel.
    plan.base.omega_i = direction_from_disk(-(40.5 / 32 - 1), -(1 - 31.5 / 32));
    plan.base.footprints = parse_footprint_set("grid:2");
    plan.models = {DiffractionModel::rohs, DiffractionModel::kirchhoff};
    plan.kernels_per_texel = {2};
    const std::vector<ValidationRow> rows = run_validation(plan);
    ASSERT_EQ(rows.size(), 4u * 2u * 2u);  // centres × models × wavelengths
    for (const ValidationRow& row : rows) {
        // Gabor blurs the window by σ_k = 1/4 µm: energy σ_c²/(σ_c² + σ_k²) = 0.9975 of the FFT's.
        EXPECT_NEAR(row.comparison.energy_ratio(), 25.0 / (25.0 + 0.0625), 2e-3);
        EXPECT_LT(row.comparison.relative_l2, 0.01);
        EXPECT_EQ(row.comparison.peak_offset_pixels, 0.0);
        EXPECT_EQ(row.kernels_per_texel, 2);
        EXPECT_EQ(row.order, 2);  // not asked for: the row names the default that ran
    }
    const nlohmann::json report = nlohmann::json::parse(validation_json(plan, rows, "glintscope validate ..."));
    EXPECT_EQ(report["rows"].size(), rows.size());
    EXPECT_TRUE(report["rows"][0]["relative_l2"].is_number());
    EXPECT_EQ(report["footprint_centres_um"].size(), 4u);
    EXPECT_EQ(report["models"].size(), 2u);
    EXPECT_EQ(report["command_line"], "glintscope validate ...");

    // The summary is the mean and the worst of its rows over the footprints.
    const std::vector<ValidationSummary> summary = summarize_validation(rows);
    ASSERT_EQ(summary.size(), 2u * 2u);  // models × wavelengths (one K)
    EXPECT_EQ(report["summary"].size(), summary.size());
    for (const ValidationSummary& s : summary) {
        double sum = 0.0, worst = 0.0, energy = 0.0;
        int count = 0;
        for (const ValidationRow& row : rows)
            if (row.model == s.model && row.comparison.wavelength_um == s.wavelength_um) {
                sum += row.comparison.relative_l2;
                worst = std::max(worst, row.comparison.relative_l2);
                energy += row.comparison.energy_ratio();
                ++count;
            }
        EXPECT_EQ(count, 4);
        EXPECT_EQ(s.footprints, 4u);
        EXPECT_NEAR(s.mean_relative_l2, sum / count, 1e-15);
        EXPECT_EQ(s.worst_relative_l2, worst);
        EXPECT_NEAR(s.mean_energy_ratio, energy / count, 1e-15);
    }
}

// The summary figure plots what the summary says: per model, at each K, the mean over the
// wavelengths of the footprints' mean relative L2, in %, computed here from the rows themselves.
TEST(Validate, TheSummaryFiguresSeriesAreTheSummaryTablesMeans) {
    ValidationPlan plan;
    plan.base.wavelengths_um = {0.45, 0.6};
    std::vector<ValidationRow> rows;
    for (DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::kirchhoff})
        for (int k : {1, 2, 4})
            for (int footprint = 0; footprint < 3; ++footprint)
                for (double lambda : plan.base.wavelengths_um) {
                    ValidationRow row;
                    row.centre_um = {10.0 * footprint, 0.0};
                    row.model = model;
                    row.kernels_per_texel = k;
                    row.comparison.wavelength_um = lambda;
                    // Distinct errors per model, K, footprint and wavelength.
                    row.comparison.relative_l2 = (model == DiffractionModel::rohs ? 0.2 : 0.1) / k + 0.01 * footprint + lambda / 10;
                    rows.push_back(row);
                }
    const Plot plot = error_against_k_plot(plan, summarize_validation(rows));
    ASSERT_EQ(plot.series.size(), 2u);
    EXPECT_EQ(plot.series[0].label, "rohs");
    EXPECT_EQ(plot.series[1].label, "kirchhoff");
    for (const PlotSeries& series : plot.series) {
        ASSERT_EQ(series.x, (std::vector<double>{1, 2, 4}));
        for (std::size_t i = 0; i < series.x.size(); ++i) {
            double sum = 0.0;
            int count = 0;
            for (const ValidationRow& row : rows)
                if (to_string(row.model) == series.label && row.kernels_per_texel == series.x[i])
                    sum += row.comparison.relative_l2, ++count;
            EXPECT_EQ(count, 6);  // 3 footprints × 2 wavelengths
            EXPECT_NEAR(series.y[i], 100.0 * sum / count, 1e-12) << series.label << " K " << series.x[i];
        }
    }
    EXPECT_NE(plot.caption.at(0).find("the mean over 3 footprints and 2 wavelengths"), std::string::npos);
}

TEST(Validate, GaborMeetsItsDocumentedBoundOnTheIsotropicBuiltin) {
    ValidationPlan plan;
    set_heightfield(plan.base, generate_builtin("isotropic"));
    plan.base.footprint.centre_um = plan.base.field->centre_um();
    plan.base.resolution = 128;
    plan.base.supersample = 2;
    plan.kernels_per_texel = {1, 4};
    plan.orders = {1};  // the paper's kernels
    const std::vector<ValidationRow> rows = run_validation(plan);
    ASSERT_EQ(rows.size(), 2u);
    // docs/gabor.md: K = 1 ~ 13-20%, K = 4 ≤ 1.5% at the canonical footprint; error falls with K.
    EXPECT_LT(rows[1].comparison.relative_l2, 0.015);
    EXPECT_GT(rows[0].comparison.relative_l2, 4.0 * rows[1].comparison.relative_l2);
}

// Geometric optics is the λ → 0 limit of the Kirchhoff wave lobe, not of R-OHS's. The speckle
// hides it from the plain relative L2; the smoothed one (one-pixel blur) shows it. A small
// footprint (σ_c = 2 µm over a field of T = 1.4 µm) keeps the FFT quick and the diffraction blur
// λ/(2πσ_c) several pixels wide at 0.5 µm, so that λ visibly matters; at 30° incidence, where
// R-OHS's lobe (shift-invariant in direction cosines) is not the half-vector mapping of the slopes.
TEST(Validate, GeometricAgainstTheKirchhoffWaveLobeConvergesAsTheWavelengthShrinks) {
    Recipe recipe = default_recipe("gaussian");  // Stam's smooth C1, rms slope 0.1 per axis
    recipe.grid = {128, 128, 0.25};
    recipe.gaussian.correlation = CorrelationFunction::c1;
    recipe.gaussian.correlation_length_x_um = recipe.gaussian.correlation_length_y_um = 1.414;
    recipe.gaussian.sigma_h_um = 0.1;
    ValidationPlan plan;
    set_heightfield(plan.base, generate(recipe));
    plan.base.footprint.centre_um = plan.base.field->centre_um();
    plan.base.footprint.sigma_um = 2.0;
    plan.base.resolution = 48;
    plan.base.wavelengths_um = {0.5, 0.25, 0.1};
    plan.base.omega_i = direction_from_spherical(pi / 6.0, 0.0);  // 30°: R-OHS's shifted lobe parts from the rest
    plan.test_method = "geometric";
    ASSERT_EQ(validation_models(plan), std::vector{DiffractionModel::kirchhoff});
    EXPECT_EQ(validation_notes(plan).size(), 1u);
    plan.models = {DiffractionModel::kirchhoff, DiffractionModel::rohs};
    EXPECT_TRUE(validation_notes(plan).empty());
    const std::vector<ValidationRow> rows = run_validation(plan);
    ASSERT_EQ(rows.size(), 6u);  // models × wavelengths
    for (const ValidationRow& row : rows)
        RecordProperty(to_string(row.model) + "_" + shortest_text(row.comparison.wavelength_um),
                       shortest_text(row.comparison.smoothed_relative_l2) + " (plain " +
                           shortest_text(row.comparison.relative_l2) + ")");
    EXPECT_LT(rows[1].comparison.smoothed_relative_l2, 0.5 * rows[0].comparison.smoothed_relative_l2);
    EXPECT_LT(rows[2].comparison.smoothed_relative_l2, 0.5 * rows[1].comparison.smoothed_relative_l2);
    EXPECT_LT(rows[2].comparison.smoothed_relative_l2, 0.08);
    EXPECT_GT(rows[5].comparison.smoothed_relative_l2, 2.0 * rows[2].comparison.smoothed_relative_l2);  // R-OHS
}

}  // namespace
}  // namespace glintscope
