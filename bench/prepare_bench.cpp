#include <benchmark/benchmark.h>

#include <limits>

#include "glintscope/prepare/prepare.hpp"

namespace {

// fill_missing on a 512² field with one valid point: a constant at once, not an iterative solve
// (the conjugate-gradient route took minutes; tests/lib/prepare/fill_degenerate_test.cpp).
void BM_FillOneValidPoint(benchmark::State& state) {
    for (auto _ : state) {
        state.PauseTiming();
        glintscope::Heightfield field =
            glintscope::make_heightfield(512, 512, 1.0, std::numeric_limits<float>::quiet_NaN());
        field.at(100, 321) = 0.375f;
        state.ResumeTiming();
        benchmark::DoNotOptimize(glintscope::fill_missing(field, glintscope::FillMethod::biharmonic, glintscope::Tiling::none));
    }
}
BENCHMARK(BM_FillOneValidPoint)->Unit(benchmark::kMillisecond);

}  // namespace
