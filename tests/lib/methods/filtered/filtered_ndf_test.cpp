// The filtered NDF (Dong 2015 §5.1): the Gaussian-smoothed surface's slope is the weighted
// least-squares plane fit's slope, the NDF narrows as σ_f grows, and σ_f → 0 is the P-NDF.
#include "methods/filtered/filtered_ndf.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "glintscope/generate/generate.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "disk_sums.hpp"
#include "glintscope/lobe/query.hpp"

namespace glintscope {
namespace {

using testing::second_moment;

Heightfield isotropic_field(int size) {
    Recipe recipe = default_recipe("isotropic");
    recipe.grid.rows = recipe.grid.cols = size;
    return generate(recipe);
}

LobeQuery whole_field_query(Heightfield field, int resolution) {
    LobeQuery query;
    query.resolution = resolution;
    query.footprint.shape = FootprintShape::whole;
    query.quantity = Quantity::ndf;
    set_heightfield(query, std::move(field));
    return query;
}

TEST(FilteredNdf, SmoothedSlopeIsTheGaussianWeightedPlaneFit) {
    // Direct weighted least squares at a few samples: with the window's odd moments zero, the
    // slope is Σ g (x − p_x) H / Σ g (x − p_x)² (and likewise in y).
    const Heightfield field = isotropic_field(128);
    const double sigma = 3.0;
    const BicubicInterpolant smoothed(gaussian_smoothed(field, sigma));
    for (const auto& [row, col] : {std::pair{20, 30}, std::pair{64, 100}, std::pair{110, 5}}) {
        double moment_x = 0.0, norm = 0.0;
        for (int dr = -16; dr <= 16; ++dr)
            for (int dc = -16; dc <= 16; ++dc) {
                const double g = std::exp(-0.5 * (dr * dr + dc * dc) / (sigma * sigma));
                const int r = (row + dr + 128) % 128, c = (col + dc + 128) % 128;
                moment_x += g * dc * field.at(r, c);
                norm += g * dc * dc;
            }
        const double fitted = moment_x / norm;
        const SurfacePoint p = smoothed.sample_point(col, 127 - row);
        EXPECT_NEAR(p.dh_dx, fitted, 0.03 * std::abs(fitted) + 2e-3) << row << "," << col;
    }
}

TEST(FilteredNdf, NarrowsAsTheFilterGrows) {
    LobeQuery query = whole_field_query(isotropic_field(256), 128);
    double previous = 1e9;
    for (const char* sigma : {"0.5", "1", "2", "4"}) {
        query.method_options["filter_sigma"] = sigma;
        const double moment = second_moment(compute_lobe("filtered", query));
        RecordProperty(std::string("second_moment_sigma_") + sigma, std::to_string(moment));
        EXPECT_LT(moment, previous) << "filter_sigma " << sigma;
        previous = moment;
    }
}

TEST(FilteredNdf, ZeroFilterIsThePatchNdf) {
    LobeQuery query = whole_field_query(isotropic_field(128), 64);
    const LobeImage reference = compute_lobe("pndf", query);
    query.method_options = {{"filter_sigma", "0"}};
    EXPECT_EQ(compute_lobe("filtered", query).values, reference.values);
    // A window far below a texel keeps every sample (its neighbour taps are e^{−50}).
    query.method_options = {{"filter_sigma", "0.1"}};
    const LobeImage tiny = compute_lobe("filtered", query);
    for (std::size_t k = 0; k < tiny.values.size(); ++k) ASSERT_NEAR(tiny.values[k], reference.values[k], 1e-6 * (1.0 + reference.values[k]));
}

}  // namespace
}  // namespace glintscope
