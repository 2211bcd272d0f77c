// The pndf method: one identical, normalised NDF layer per wavelength, equal to the exact
// normal density of the query's footprint; its options are checked and recorded.
#include "methods/pndf/pndf.hpp"

#include <gtest/gtest.h>

#include "glintscope/error.hpp"
#include "glintscope/lobe.hpp"
#include "glintscope/generate.hpp"

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
    double total = 0.0;
    for (std::size_t k = 0; k < density.size(); ++k) {
        EXPECT_EQ(image.values[k], static_cast<float>(density[k]));
        EXPECT_EQ(image.values[density.size() + k], image.values[k]);
        total += image.values[k];
    }
    EXPECT_NEAR(total * disk_pixel_area(64), 1.0, 1e-5);
    EXPECT_EQ(image.metadata.at("pndf.intrinsic_roughness_rad"), "0.02");
}

TEST(Pndf, RejectsUnknownAndOutOfRangeOptions) {
    LobeQuery query = isotropic_query(32);
    query.method_options = {{"refinement", "0"}};
    EXPECT_THROW(compute_lobe("pndf", query), Error);
    query.method_options = {{"step", "1"}};
    EXPECT_THROW(compute_lobe("pndf", query), Error);
}

}  // namespace
}  // namespace glintscope
