// The C++ side of the Python module's overhead (docs/performance.md "Python module";
// scripts/python-bench.py times the same calls from Python): a small lobe through run_lobe, whose
// compute is short enough that a per-call cost shows, and BSDF eval per direction pair.
#include <benchmark/benchmark.h>

#include <vector>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace {

// python: glintscope.generate("gaussian", size=64, sigma_h=0.05, correlation_length_x=4, correlation_length_y=4)
glintscope::LobeQuery small_query() {
    glintscope::Recipe recipe = glintscope::default_recipe("gaussian");
    for (const auto& [key, value] : {std::pair{"size", "64"}, {"sigma_h", "0.05"}, {"correlation_length_x", "4"},
                                     {"correlation_length_y", "4"}})
        glintscope::set_recipe_value(recipe, key, value);
    const glintscope::Heightfield field = glintscope::generate(recipe);
    glintscope::LobeQuery query;
    glintscope::set_heightfield(query, field);
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = 2.0;
    query.resolution = 16;
    query.supersample = 1;
    return query;
}

// python: glintscope.lobe(field, "fft", sigma_c=2, res=16, supersample=1)
void BM_SmallLobeFromCpp(benchmark::State& state) {
    const glintscope::LobeQuery query = small_query();
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::run_lobe("fft", query));
}
BENCHMARK(BM_SmallLobeFromCpp)->Unit(benchmark::kMicrosecond)->UseRealTime();

// python: glintscope.bsdf(builtin isotropic, "gabor", sigma_c=10, res=256, kernels_per_texel=1).eval(wi, wo),
// one ω_i at 20°, wo spread over the disk; one thread; per pair.
void BM_BsdfEvalGaborOneKernelPerTexel(benchmark::State& state) {
    static const glintscope::Heightfield field = glintscope::generate_builtin("isotropic");
    glintscope::LobeQuery query;
    glintscope::set_heightfield(query, field);
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = 10.0;
    query.resolution = 256;
    query.method_options["kernels_per_texel"] = "1";
    const glintscope::Bsdf bsdf = glintscope::make_bsdf("gabor", query);
    const glintscope::Vec3 wi = glintscope::direction_from_spherical(20.0 * glintscope::pi / 180.0, 0.0);
    std::vector<glintscope::Vec3> wo;
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j) {
            const double x = (i + 0.5) / 32.0 - 1.0, y = (j + 0.5) / 32.0 - 1.0;
            if (x * x + y * y < 1.0) wo.push_back(glintscope::direction_from_disk(x, y));
        }
    bsdf.eval(wi, wo.front());  // the table of wi
    for (auto _ : state)
        for (const glintscope::Vec3& direction : wo) benchmark::DoNotOptimize(bsdf.eval(wi, direction));
    state.SetItemsProcessed(state.iterations() * static_cast<long>(wo.size()));
}
BENCHMARK(BM_BsdfEvalGaborOneKernelPerTexel)->Unit(benchmark::kMicrosecond);

}  // namespace
