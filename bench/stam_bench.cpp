// Stam's expected lobe of a Gaussian random field (C1, σ_h = 0.1 µm, T = 2 µm, so g ≈ 6.3 and
// ~50 series terms per direction), R-OHS, σ_c = 10 µm, normal incidence, one wavelength, 256².
#include <benchmark/benchmark.h>

#include "glintscope/generate/generate.hpp"
#include "methods/stam/stam_lobe.hpp"

namespace {

glintscope::LobeQuery gaussian_query(int resolution) {
    glintscope::Recipe recipe = glintscope::default_recipe("gaussian");
    recipe.grid = {256, 256, 0.5};
    recipe.gaussian.sigma_h_um = 0.1;
    recipe.gaussian.correlation_length_x_um = 2.0;
    recipe.gaussian.correlation_length_y_um = 2.0;
    static const glintscope::Heightfield field = glintscope::generate(recipe);
    glintscope::LobeQuery query;
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = 10.0;
    query.model = glintscope::DiffractionModel::rohs;
    query.resolution = resolution;
    query.wavelengths_um = {0.5};
    glintscope::set_heightfield(query, field);
    return query;
}

void StamLobe256GaussianField(benchmark::State& state) {
    const glintscope::LobeQuery query = gaussian_query(256);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::stam_lobe(query));
}
BENCHMARK(StamLobe256GaussianField)->Unit(benchmark::kMillisecond);

}  // namespace
