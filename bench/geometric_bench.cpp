// The exact P-NDF, the filtered NDF, the geometric lobe and the Kirchhoff distribution on the isotropic surface of Yan 2018
// Fig. 8 (1024² builtin at 1 µm; 8192² from heightfields/isotropic.recipe for the whole-field NDF).
#include <benchmark/benchmark.h>

#include "glintscope/generate/generate.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/query.hpp"

namespace {

glintscope::LobeQuery builtin_query(int resolution, glintscope::FootprintShape shape, glintscope::Quantity quantity) {
    static const glintscope::Heightfield field = glintscope::generate_builtin("isotropic");
    glintscope::LobeQuery query;
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = 10.0;
    query.footprint.shape = shape;
    query.resolution = resolution;
    query.quantity = quantity;
    glintscope::set_heightfield(query, field);
    return query;
}

void BM_Pndf256GaussianFootprint(benchmark::State& state) {
    const glintscope::LobeQuery query = builtin_query(256, glintscope::FootprintShape::gaussian, glintscope::Quantity::ndf);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("pndf", query));
}
BENCHMARK(BM_Pndf256GaussianFootprint)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Pndf1024Whole8192Field(benchmark::State& state) {
    glintscope::LobeQuery query;
    {
        glintscope::Recipe recipe = glintscope::load_recipe(GLINTSCOPE_SOURCE_DIR "/heightfields/isotropic.recipe");
        glintscope::set_heightfield(query, glintscope::generate(recipe));
    }
    query.footprint.shape = glintscope::FootprintShape::whole;
    query.quantity = glintscope::Quantity::ndf;
    query.resolution = 1024;
    // One undivided cell per texel: the whole field's default tolerance (0.1 pixel) subdivides
    // most texels of this surface at 1024² and takes 2.4 s per 1024² of field (~2.6 min here).
    query.method_options = {{"refinement", "1"}, {"tolerance", "0"}};
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("pndf", query));
}
BENCHMARK(BM_Pndf1024Whole8192Field)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

void BM_FilteredNdf256Whole1024Field(benchmark::State& state) {
    const glintscope::LobeQuery query = builtin_query(256, glintscope::FootprintShape::whole, glintscope::Quantity::ndf);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("filtered", query));
}
BENCHMARK(BM_FilteredNdf256Whole1024Field)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GeometricLobe256(benchmark::State& state) {
    const glintscope::LobeQuery query = builtin_query(256, glintscope::FootprintShape::gaussian, glintscope::Quantity::brdf);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("geometric", query));
}
BENCHMARK(BM_GeometricLobe256)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_KirchhoffDistribution256(benchmark::State& state) {
    const glintscope::LobeQuery query = builtin_query(256, glintscope::FootprintShape::gaussian, glintscope::Quantity::ndf);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("dk", query));
}
BENCHMARK(BM_KirchhoffDistribution256)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
