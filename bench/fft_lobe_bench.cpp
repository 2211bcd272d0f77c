// The FFT ground truth on the isotropic surface of Yan 2018 Fig. 8 (1024² at 1 µm, rms slope
// 0.17), R-OHS, σ_c = 10 µm, normal incidence: one wavelength at 256², 16 wavelengths at 512².
#include <benchmark/benchmark.h>

#include <vector>

#include "methods/fft/fft_lobe.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace {

glintscope::LobeQuery isotropic_query(int resolution, std::vector<double> wavelengths_um) {
    static const glintscope::Heightfield field = glintscope::generate_builtin("isotropic");
    glintscope::LobeQuery query;
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = 10.0;
    query.model = glintscope::DiffractionModel::rohs;
    query.resolution = resolution;
    query.wavelengths_um = std::move(wavelengths_um);
    glintscope::set_heightfield(query, field);
    return query;
}

// Midpoints of 16 equal bins over 360–830 nm (conventions.md "Spectra and colour").
std::vector<double> sixteen_bins() {
    std::vector<double> wavelengths_um;
    for (int i = 0; i < 16; ++i) wavelengths_um.push_back(0.36 + (i + 0.5) * 0.47 / 16);
    return wavelengths_um;
}

void run(benchmark::State& state, const glintscope::LobeQuery& query) {
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("fft", query));
}

void BM_FftLobe256OneWavelength(benchmark::State& state) {
    const glintscope::LobeQuery query = isotropic_query(256, {0.5});
    run(state, query);
}
BENCHMARK(BM_FftLobe256OneWavelength)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FftLobe512SixteenWavelengths(benchmark::State& state) {
    const glintscope::LobeQuery query = isotropic_query(512, sixteen_bins());
    run(state, query);
}
BENCHMARK(BM_FftLobe512SixteenWavelengths)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
