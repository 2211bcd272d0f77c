#include <benchmark/benchmark.h>

#include <cmath>

#include "glintscope/surface/interpolant.hpp"

namespace {

void BM_InterpolantEvaluate(benchmark::State& state) {
    glintscope::Heightfield field = glintscope::make_heightfield(256, 256, 1.0);
    for (std::size_t i = 0; i < field.size(); ++i) field.heights_um[i] = static_cast<float>(std::sin(0.37 * i));
    const glintscope::BicubicInterpolant surface(field);
    double x = 0.1;
    for (auto _ : state) {
        benchmark::DoNotOptimize(surface.evaluate(x, 0.7 * x));
        x += 0.013;
    }
}
BENCHMARK(BM_InterpolantEvaluate);

}  // namespace

BENCHMARK_MAIN();
