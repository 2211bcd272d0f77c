// Ellipsoid fit (Dong 2015 §8) of a 256² NDF image: a skewed ellipsoid's own image (the solver
// from the moments' start to 1e-9), and the exact P-NDF of a 32 µm patch of a brushed field.
#include <benchmark/benchmark.h>

#include "glintscope/generate/generate.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/fit/ndf_fit.hpp"

namespace {

void EllipsoidFit256Skewed(benchmark::State& state) {
    const glintscope::LobeImage ndf =
        glintscope::model_ndf_image({glintscope::NdfModelKind::ellipsoid, {0.35, 0.15, -0.12, 0.08, -0.7}}, 256);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::fit_ndf(ndf, glintscope::NdfModelKind::ellipsoid));
}

void EllipsoidFit256BrushedPatch(benchmark::State& state) {
    glintscope::Recipe recipe = glintscope::default_recipe("brushed");
    recipe.grid.rows = recipe.grid.cols = 256;
    recipe.gaussian.correlation_length_x_um = 64.0;
    glintscope::LobeQuery query;
    glintscope::set_heightfield(query, glintscope::generate(recipe));
    query.quantity = glintscope::Quantity::ndf;
    query.footprint = {{100.0, 100.0}, 10.0, glintscope::FootprintShape::box, 32.0};
    query.resolution = 256;
    const glintscope::LobeImage ndf = glintscope::compute_lobe("pndf", query);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::fit_ndf(ndf, glintscope::NdfModelKind::ellipsoid));
}

}  // namespace

BENCHMARK(EllipsoidFit256Skewed)->Unit(benchmark::kMillisecond);
BENCHMARK(EllipsoidFit256BrushedPatch)->Unit(benchmark::kMillisecond);
