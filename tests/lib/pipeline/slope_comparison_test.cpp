// The whole field's slope distribution against its whole-field P-NDF (ndf method pndf), which
// reads the interpolant's continuous gradient instead of the samples' central differences: on a
// smooth generated field the two densities of normals agree.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "glintscope/generate/generate.hpp"
#include "glintscope/lobe/image.hpp"
#include "glintscope/pipeline/slope_comparison.hpp"
#include "relative_l2.hpp"

namespace glintscope {
namespace {

TEST(SlopeComparison, AgreesWithTheWholeFieldPndfOnASmoothField) {
    // Stam's C1 field, T = 12 texels, rms slope √2 σ_h/T ≈ 0.24: the central differences see
    // sin(kΔ)/Δ instead of k, a ~1% narrower spread at these wavelengths, and 256² samples
    // histogrammed into 48² pixels add counting noise of a few per cent where the density is high.
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {256, 256, 1.0};
    recipe.seed = 3;
    recipe.gaussian.sigma_h_um = 2.0;
    recipe.gaussian.correlation_length_x_um = recipe.gaussian.correlation_length_y_um = 12.0;
    const int n = 48;
    const SlopeComparison comparison = compare_slopes_with_pndf(generate(recipe), n);
    const std::vector<double> slopes(comparison.slopes.values.begin(), comparison.slopes.values.end());
    const std::vector<double> pndf(comparison.pndf.values.begin(), comparison.pndf.values.end());
    EXPECT_NEAR(disk_sum(comparison.slopes), 1.0, 1e-5);
    const double error = testing::relative_l2(slopes, pndf);
    RecordProperty("relative_l2", std::to_string(error));
    EXPECT_LT(error, 0.08);
}

}  // namespace
}  // namespace glintscope
