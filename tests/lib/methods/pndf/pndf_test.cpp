// The pndf method: one identical, normalised NDF layer per wavelength, equal to the exact
// normal density of the query's footprint; its options are checked and recorded.
#include "methods/pndf/pndf.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/surface/statistics.hpp"
#include "glintscope/generate/generate.hpp"

namespace glintscope {
namespace {

LobeQuery isotropic_query(int resolution) {
    Recipe recipe = default_recipe("isotropic");
    recipe.grid.rows = recipe.grid.cols = 128;
    LobeQuery query;
    query.resolution = resolution;
    query.quantity = Quantity::ndf;
    set_heightfield(query, generate(recipe));
    query.footprint.centre_um = query.field->centre_um();
    return query;
}

TEST(Pndf, EveryWavelengthLayerIsTheNormalisedNormalDensity) {
    LobeQuery query = isotropic_query(64);
    query.wavelengths_um = {0.4, 0.7};
    query.method_options["intrinsic_roughness"] = "0.02";
    const LobeImage image = compute_lobe("pndf", query);
    NormalDensitySettings settings;
    settings.intrinsic_roughness = 0.02;
    const std::vector<double> density = normal_density(*query.surface, query.footprint, 64, settings);
    for (std::size_t k = 0; k < density.size(); ++k) {
        EXPECT_EQ(image.values[k], static_cast<float>(density[k]));
        EXPECT_EQ(image.values[density.size() + k], image.values[k]);
    }
    EXPECT_NEAR(disk_sum(image), 1.0, 1e-5);
    EXPECT_EQ(image.metadata.at("pndf.intrinsic_roughness_rad"), "0.02");
}

TEST(Pndf, RejectsUnknownAndOutOfRangeOptions) {
    LobeQuery query = isotropic_query(32);
    query.method_options = {{"refinement", "0"}};
    EXPECT_THROW(compute_lobe("pndf", query), Error);
    query.method_options = {{"step", "1"}};
    EXPECT_THROW(compute_lobe("pndf", query), Error);
}

TEST(Pndf, WholeGaussianRandomFieldApproachesBeckmann) {
    // A C1 (Gaussian-correlated) field has Gaussian slopes: its large-area NDF is Beckmann's,
    // D(h) = exp(−tan²θ/α²)/(π α² cos⁴θ) with α = √2·σ_slope (per-axis rms slope 0.1 here).
    // 1024² samples, T = 8 texels: ~16,000 correlation cells.
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {1024, 1024, 1.0};
    recipe.gaussian.correlation = CorrelationFunction::c1;
    recipe.gaussian.correlation_length_x_um = recipe.gaussian.correlation_length_y_um = 8.0;
    recipe.gaussian.sigma_h_um = 0.1 * 8.0 / std::sqrt(2.0);
    const Heightfield field = generate(recipe);
    const SurfaceStatistics statistics = compute_statistics(field);
    const double alpha = std::sqrt(2.0) * std::sqrt(0.5 * (statistics.rms_slope_x * statistics.rms_slope_x +
                                                           statistics.rms_slope_y * statistics.rms_slope_y));
    LobeQuery query;
    query.quantity = Quantity::ndf;
    query.resolution = 64;
    query.footprint.shape = FootprintShape::whole;
    set_heightfield(query, field);
    const LobeImage image = compute_lobe("pndf", query);
    double difference = 0.0, norm = 0.0;
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 64; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, 64);
            if (!inside_unit_disk(p)) continue;
            const double cos2 = 1.0 - p.x * p.x - p.y * p.y;
            const double tan2 = (p.x * p.x + p.y * p.y) / cos2;
            const double beckmann = std::exp(-tan2 / (alpha * alpha)) / (pi * alpha * alpha * cos2 * cos2);
            difference += std::pow(image.at(0, r, c) - beckmann, 2);
            norm += beckmann * beckmann;
        }
    RecordProperty("alpha", std::to_string(alpha));
    RecordProperty("relative_l2", std::to_string(std::sqrt(difference / norm)));
    EXPECT_LT(std::sqrt(difference / norm), 0.05);
}

}  // namespace
}  // namespace glintscope
