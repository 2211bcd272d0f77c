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

// Yan 2018 eq. 6 at one direction over the footprint grid (fft_point), one wavelength, ω_i at
// 20°, ω_o near its mirror direction; the grid of ω_i (its rows' spectra) is made before the timing.
void BM_FftPointEval(benchmark::State& state) {
    glintscope::LobeQuery query = isotropic_query(64, {0.5});
    const glintscope::Vec3 omega_i = glintscope::direction_from_spherical(20.0 * glintscope::pi / 180.0, 0.3);
    const glintscope::PointAnswers point = glintscope::fft_point(query);
    std::vector<glintscope::Vec3> directions;
    for (int k = 0; k < 64; ++k) directions.push_back(glintscope::direction_from_spherical(0.35 + 0.002 * k, 0.3 + 0.05 * k));
    point.eval(omega_i, directions[0]);
    std::size_t k = 0;
    for (auto _ : state) benchmark::DoNotOptimize(point.eval(omega_i, directions[k++ & 63]));
}
BENCHMARK(BM_FftPointEval)->Unit(benchmark::kMicrosecond);

// The same at an ω_i not seen before: its grid (heights and R* over the footprint, the rows'
// spectra) made, then one eval. Real time: making the grid runs on the library's threads.
void BM_FftPointNewIncidence(benchmark::State& state) {
    glintscope::LobeQuery query = isotropic_query(64, {0.5});
    const glintscope::PointAnswers point = glintscope::fft_point(query);
    int k = 0;
    for (auto _ : state) {
        const glintscope::Vec3 omega_i = glintscope::direction_from_spherical(0.35, 0.01 * k++);
        benchmark::DoNotOptimize(point.eval(omega_i, glintscope::direction_from_spherical(0.35, 0.01 * k + 3.0)));
    }
}
BENCHMARK(BM_FftPointNewIncidence)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
