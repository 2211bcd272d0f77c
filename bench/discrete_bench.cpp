// Jakob 2014's discrete microfacets: a 256² lobe (one cone query per pixel, the default cone of
// one centre pixel), Beckmann α = 0.2, Gaussian footprint σ_c = 10 µm holding N flakes, normal
// incidence. The target: N = 1e8 within 1 s.
#include <benchmark/benchmark.h>

#include <string>

#include "glintscope/lobe/query.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace {

glintscope::LobeQuery flake_query(const std::string& flakes) {
    glintscope::Heightfield flat;  // the method reads no heightfield
    flat.rows = flat.cols = 64;
    flat.heights_um.assign(64 * 64, 0.0f);
    glintscope::LobeQuery query;
    glintscope::set_heightfield(query, flat);
    query.footprint.centre_um = {32.0, 32.0};
    query.resolution = 256;
    query.method_options.insert_or_assign("flakes", flakes);
    return query;
}

void DiscreteLobe256(benchmark::State& state) {
    const glintscope::LobeQuery query = flake_query("1e" + std::to_string(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("discrete", query));
}
BENCHMARK(DiscreteLobe256)->Arg(4)->Arg(6)->Arg(8)->Arg(10)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
