// The BSDF contract (glintscope/bsdf/bsdf.hpp) on the isotropic builtin (1024² at 1 µm), σ_c = 10 µm,
// ω_i at 20°, two wavelengths: the footprint's table (make_bsdf), then eval and sample per call
// over random directions, from one thread.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/generate/generate.hpp"

namespace {

glintscope::LobeQuery builtin_query(int resolution) {
    static const glintscope::Heightfield field = glintscope::generate_builtin("isotropic");
    glintscope::LobeQuery query;
    glintscope::set_heightfield(query, field);
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = 10.0;
    query.wavelengths_um = {0.5};
    query.resolution = resolution;
    return query;
}

const glintscope::Vec3 kIncident = glintscope::direction_from_spherical(20.0 * glintscope::pi / 180.0, 0.3);

std::vector<glintscope::Vec3> random_directions(int count) {
    std::mt19937_64 rng(22);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<glintscope::Vec3> directions;
    while (static_cast<int>(directions.size()) < count) {
        const double x = 2.0 * u(rng) - 1.0, y = 2.0 * u(rng) - 1.0;
        if (x * x + y * y < 1.0) directions.push_back(glintscope::direction_from_disk(x, y));
    }
    return directions;
}

// The footprint's table, made by make_bsdf for every ω_i. Argument: the lobe image's N (dk's D_K
// table is 2N, geometric's NDF table ndf_oversampling·N = 4N).
void BM_BsdfTable(benchmark::State& state, const char* method) {
    const glintscope::LobeQuery query = builtin_query(static_cast<int>(state.range(0)));
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::make_bsdf(method, query));
}
BENCHMARK_CAPTURE(BM_BsdfTable, dk, "dk")->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_BsdfTable, geometric, "geometric")->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->UseRealTime();
// gabor's "table" is the footprint's slope index (its kernels gathered and sorted by slope cell).
BENCHMARK_CAPTURE(BM_BsdfTable, gabor, "gabor")->Arg(64)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_BsdfEval(benchmark::State& state, const char* method) {
    const glintscope::Bsdf bsdf = glintscope::make_bsdf(method, builtin_query(static_cast<int>(state.range(0))));
    const std::vector<glintscope::Vec3> directions = random_directions(4096);
    bsdf.eval(kIncident, directions[0]);  // a method answered from images makes its table of ω_i here
    std::size_t k = 0;
    for (auto _ : state) benchmark::DoNotOptimize(bsdf.eval(kIncident, directions[k++ & 4095]));
}
BENCHMARK_CAPTURE(BM_BsdfEval, dk, "dk")->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_BsdfEval, stam, "stam")->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_BsdfEval, geometric, "geometric")->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_BsdfEval, fft, "fft")->Arg(64)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_BsdfEval, gabor, "gabor")->Arg(64)->Unit(benchmark::kMicrosecond);
// Jakob 2014's count of the flakes (10⁶ in the footprint, Beckmann α = 0.2) reflecting ω_i into
// the cone about ω_o; N = 64's default cone is 1.0°.
BENCHMARK_CAPTURE(BM_BsdfEval, discrete, "discrete")->Arg(64)->Unit(benchmark::kMicrosecond);

// The pdf alone: for gabor the sum over the footprint's kernel mixture (gabor_sampling.hpp).
void BM_BsdfPdf(benchmark::State& state, const char* method) {
    const glintscope::Bsdf bsdf = glintscope::make_bsdf(method, builtin_query(static_cast<int>(state.range(0))));
    const std::vector<glintscope::Vec3> directions = random_directions(4096);
    std::size_t k = 0;
    for (auto _ : state) benchmark::DoNotOptimize(bsdf.pdf(kIncident, directions[k++ & 4095]));
}
BENCHMARK_CAPTURE(BM_BsdfPdf, gabor, "gabor")->Arg(64)->Unit(benchmark::kMicrosecond);
// The smooth density at 2α convolved with the cone: 32 evaluations of it (flake_sampling.hpp).
BENCHMARK_CAPTURE(BM_BsdfPdf, discrete, "discrete")->Arg(64)->Unit(benchmark::kMicrosecond);

void BM_BsdfSample(benchmark::State& state, const char* method) {
    const glintscope::Bsdf bsdf = glintscope::make_bsdf(method, builtin_query(static_cast<int>(state.range(0))));
    std::mt19937_64 rng(22);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    bsdf.sample(kIncident, 0.5, 0.5);
    for (auto _ : state) benchmark::DoNotOptimize(bsdf.sample(kIncident, u(rng), u(rng)));
}
BENCHMARK_CAPTURE(BM_BsdfSample, dk, "dk")->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_BsdfSample, stam_from_images, "stam")->Arg(256)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_BsdfSample, geometric, "geometric")->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_BsdfSample, gabor, "gabor")->Arg(64)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_BsdfSample, discrete, "discrete")->Arg(64)->Unit(benchmark::kMicrosecond);

}  // namespace
