// The paper-sized surfaces: generating an 8192² heightfield (target ≤ 10 s, ≤ 1.5 GB) and its
// statistics, alone and after loading it from EXR (target ≤ 3 s for loading + statistics).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "glintscope/generate/generate.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/surface/areal_parameters.hpp"
#include "glintscope/surface/statistics.hpp"

namespace {

using glintscope::Heightfield;

// heightfields/isotropic.recipe: the isotropic preset at 8192² and 1 µm.
glintscope::Recipe isotropic_8192() {
    glintscope::Recipe recipe = glintscope::default_recipe("isotropic");
    recipe.grid.rows = recipe.grid.cols = 8192;
    return recipe;
}

void BM_GenerateIsotropic8192(benchmark::State& state) {
    const glintscope::Recipe recipe = isotropic_8192();
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::generate(recipe).heights_um.data());
}
BENCHMARK(BM_GenerateIsotropic8192)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

void BM_GenerateBuiltin(benchmark::State& state, const std::string& kind) {
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::generate_builtin(kind).heights_um.data());
}
BENCHMARK_CAPTURE(BM_GenerateBuiltin, isotropic_1024, std::string("isotropic"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_GenerateBuiltin, scratched_1024, std::string("scratched"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_GenerateBuiltin, cd_1000, std::string("cd"))->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Statistics8192(benchmark::State& state) {
    const Heightfield field = glintscope::generate(isotropic_8192());
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_statistics(field));
}
BENCHMARK(BM_Statistics8192)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

// Each iteration loads the 8192² isotropic EXR (written once, as a file: a measured scan, so
// non-periodic) and computes `numbers` of it.
template <typename Numbers>
void load_8192_and(benchmark::State& state, const std::string& file, const Numbers& numbers) {
    const std::string path = (std::filesystem::temp_directory_path() / file).string();
    glintscope::save_heightfield(path, glintscope::generate(isotropic_8192()));
    for (auto _ : state) benchmark::DoNotOptimize(numbers(glintscope::load_heightfield(path)));
    std::filesystem::remove(path);
}

void BM_LoadAndStatistics8192(benchmark::State& state) {
    load_8192_and(state, "glintscope-bench-isotropic-8192.exr",
                  [](const Heightfield& field) { return glintscope::compute_statistics(field); });
}
BENCHMARK(BM_LoadAndStatistics8192)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

// Reading an X3P of 724² float64 heights (4.2 MB of data, 3.5 MB deflated; target ≤ 0.5 s).
void BM_ReadX3p4MB(benchmark::State& state) {
    const std::string path = (std::filesystem::temp_directory_path() / "glintscope-bench-724.x3p").string();
    glintscope::Recipe recipe = glintscope::default_recipe("isotropic");
    recipe.grid.rows = recipe.grid.cols = 724;
    glintscope::save_heightfield(path, glintscope::generate(recipe));
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::load_heightfield(path));
    std::filesystem::remove(path);
}
BENCHMARK(BM_ReadX3p4MB)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

// ISO 25178-2 parameters alone (the 2-D autocorrelation, rays and angular spectrum dominate).
void BM_ArealParameters8192(benchmark::State& state) {
    Heightfield field = glintscope::generate(isotropic_8192());
    field.periodic = false;  // as a measured scan: the zero-padded autocorrelation
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_areal_parameters(field));
}
BENCHMARK(BM_ArealParameters8192)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

// What `info` computes on the 8192² EXR (a measured scan: non-periodic): the load, the statistics
// and every ISO 25178-2 parameter from one autocorrelation (target for the whole `info` ≤ 3 s).
void BM_LoadAndSurfaceReport8192(benchmark::State& state) {
    load_8192_and(state, "glintscope-bench-report-8192.exr",
                  [](const Heightfield& field) { return glintscope::compute_surface_report(field); });
}
BENCHMARK(BM_LoadAndSurfaceReport8192)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(2);

}  // namespace
