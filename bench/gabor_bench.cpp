// Speed of the Gabor-kernel lobe (Yan 2018 §4–5) on the canonical isotropic surface (1024² at
// 1 µm, rms slope 0.17 per axis), σ_c = 10 µm, R-OHS: whole images, point queries, and the
// pruning hierarchy of an 8192² field.
#include <benchmark/benchmark.h>

#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "methods/gabor/gabor.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace {

using namespace glintscope;

const LobeQuery& isotropic_query() {
    static const LobeQuery query = [] {
        LobeQuery q;
        set_heightfield(q, generate_builtin("isotropic"));
        q.footprint.centre_um = {512.3, 498.7};
        q.footprint.sigma_um = 10.0;
        q.omega_i = direction_from_spherical(20.0 * std::numbers::pi / 180.0, 0.0);
        return q;
    }();
    return query;
}

// Midpoints of 16 equal bins over 360–830 nm (Yan 2018 §5 "Spectral rendering").
std::vector<double> visible_bins(int count) {
    std::vector<double> wavelengths;
    for (int i = 0; i < count; ++i) wavelengths.push_back(0.36 + (i + 0.5) * (0.83 - 0.36) / count);
    return wavelengths;
}

void BM_GaborImage256SingleWavelengthOneKernelPerTexel(benchmark::State& state) {
    LobeQuery query = isotropic_query();
    query.resolution = 256;
    query.wavelengths_um = {0.5};
    query.method_options = {{"kernels_per_texel", "1"}};
    for (auto _ : state) benchmark::DoNotOptimize(gabor_lobe(query));
}
BENCHMARK(BM_GaborImage256SingleWavelengthOneKernelPerTexel)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GaborImage512SixteenWavelengthsDefaultDensity(benchmark::State& state) {
    LobeQuery query = isotropic_query();
    query.resolution = 512;
    query.wavelengths_um = visible_bins(16);
    for (auto _ : state) benchmark::DoNotOptimize(gabor_lobe(query));
}
BENCHMARK(BM_GaborImage512SixteenWavelengthsDefaultDensity)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

// Gabor against the FFT per diffraction model (range(0): ohs, ghs, rohs, rghs, kirchhoff;
// range(1): 0 gabor, 1 fft), 256², one wavelength, 2×2 supersampling: GHS, R-GHS and Kirchhoff
// go through ξ3 nodes in both methods.
void BM_GaborVsFftPerModel256(benchmark::State& state) {
    LobeQuery query = isotropic_query();
    query.resolution = 256;
    query.supersample = 2;
    query.model = std::vector{DiffractionModel::ohs, DiffractionModel::ghs, DiffractionModel::rohs,
                              DiffractionModel::rghs, DiffractionModel::kirchhoff}[state.range(0)];
    const char* method = state.range(1) == 0 ? "gabor" : "fft";
    state.SetLabel(to_string(query.model) + " " + method);
    for (auto _ : state) benchmark::DoNotOptimize(compute_lobe(method, query));
}
BENCHMARK(BM_GaborVsFftPerModel256)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

// Point queries at random footprint centres and outgoing directions over the whole hemisphere;
// state.range(0) wavelengths per query (1: 0.5 µm; 8, a render's `--spectral 8`, or 16 visible
// bins), state.range(1) kernels per texel, state.range(2) the order (1: Yan 2018's kernels, 2: chirped). "per_omega_lambda" is the mean time per (ω_o, λ) pair.
// The isotropic surface's pruning hierarchy at K = density and the order, built once.
const GaborSurface& point_query_surface(int density, int order) {
    const auto surface_for = [](int density, int order) {
        GaborSettings settings;
        settings.kernels_per_texel = density;
        settings.order = order;
        return GaborSurface(isotropic_query().surface, settings);
    };
    static const GaborSurface surfaces[2][2] = {{surface_for(1, 1), surface_for(1, 2)},
                                                 {surface_for(2, 1), surface_for(2, 2)}};
    return surfaces[density - 1][order - 1];
}

// 4096 queries at ω_i of the isotropic query, ω_o uniform on the projected disk, footprint
// centres uniform over [origin, origin + spread)² µm.
std::vector<GaborPointQuery> random_point_queries(double origin, double spread) {
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<GaborPointQuery> queries(4096);
    for (GaborPointQuery& query : queries) {
        query.footprint.centre_um = {origin + spread * uniform(random), origin + spread * uniform(random)};
        query.omega_i = isotropic_query().omega_i;
        const double r = std::sqrt(uniform(random));
        const double phi = 2.0 * std::numbers::pi * uniform(random);
        query.omega_o = direction_from_disk(r * std::cos(phi), r * std::sin(phi));
    }
    return queries;
}

void BM_GaborPointQuery(benchmark::State& state) {
    const GaborSurface& surface =
        point_query_surface(static_cast<int>(state.range(1)), static_cast<int>(state.range(2)));
    const std::vector<double> wavelengths =
        state.range(0) == 1 ? std::vector<double>{0.5} : visible_bins(static_cast<int>(state.range(0)));
    const std::vector<GaborPointQuery> queries = random_point_queries(0.0, 1024.0);
    std::size_t next = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(surface.f_r(queries[next], wavelengths));
        next = (next + 1) % queries.size();
    }
    state.counters["per_omega_lambda"] = benchmark::Counter(
        double(state.iterations()) * wavelengths.size(), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_GaborPointQuery)
    ->ArgsProduct({{1, 8, 16}, {1, 2}, {1, 2}})
    ->Unit(benchmark::kMicrosecond);

// GaborPointQuery/1/1/2 with every footprint centre in a square of side state.range(0) µm, its
// samples and hierarchy nodes in cache: how much of the one-off query is waiting on memory.
void BM_GaborPointQueryWarm(benchmark::State& state) {
    const GaborSurface& surface = point_query_surface(1, 2);
    const std::vector<double> wavelengths{0.5};
    const std::vector<GaborPointQuery> queries = random_point_queries(512.0, double(state.range(0)));
    std::size_t next = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(surface.f_r(queries[next], wavelengths));
        next = (next + 1) % queries.size();
    }
}
BENCHMARK(BM_GaborPointQueryWarm)->Arg(0)->Arg(2)->Unit(benchmark::kMicrosecond);

// A renderer's shading points inside the lobe (Yan 2018 Fig. 12's Patch scene at λ 0.4 µm):
// footprint centres 0.7 µm apart along rows, ω_o within ±0.3 per axis on the projected disk of
// ω_i's mirror direction (the lobe's width: twice the rms slope 0.17), where a good part of each
// footprint's kernels reach, unlike most of GaborPointQuery's directions; K = 1, state.range(0)
// the order.
void BM_GaborPointQueryInTheLobe(benchmark::State& state) {
    const GaborSurface& surface = point_query_surface(1, static_cast<int>(state.range(0)));
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-0.3, 0.3);
    const Vec3 omega_i = isotropic_query().omega_i;
    std::vector<GaborPointQuery> queries(4096);
    for (std::size_t k = 0; k < queries.size(); ++k) {
        GaborPointQuery& query = queries[k];
        query.footprint.centre_um = {200.0 + 0.7 * double(k % 512), 300.0 + 0.7 * double(k / 512)};
        query.footprint.sigma_um = isotropic_query().footprint.sigma_um;
        query.omega_i = omega_i;
        query.omega_o = direction_from_disk(-omega_i.x + uniform(random), -omega_i.y + uniform(random));
    }
    std::size_t next = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(surface.f_r(queries[next], 0.4));
        next = (next + 1) % queries.size();
    }
}
BENCHMARK(BM_GaborPointQueryInTheLobe)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

// Whole images by order and density (state.range(0) order, state.range(1) kernels per texel):
// 256², one wavelength, 2×2 supersampling, R-OHS, the default grid evaluation.
void BM_GaborImage256ByOrder(benchmark::State& state) {
    LobeQuery query = isotropic_query();
    query.resolution = 256;
    query.supersample = 2;
    query.wavelengths_um = {0.5};
    query.method_options = {{"order", std::to_string(state.range(0))},
                            {"kernels_per_texel", std::to_string(state.range(1))}};
    for (auto _ : state) benchmark::DoNotOptimize(gabor_lobe(query));
}
BENCHMARK(BM_GaborImage256ByOrder)
    ->ArgsProduct({{1, 2}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The pruning hierarchy of an 8192² field (Yan 2018 §5: 8K × 8K maps at 1 µm), K = 1.
void BM_GaborSurfaceBuild8192(benchmark::State& state) {
    static const auto surface = [] {
        Recipe recipe = default_recipe("isotropic");
        recipe.grid.rows = recipe.grid.cols = 8192;
        return std::make_shared<const BicubicInterpolant>(generate(recipe));
    }();
    GaborSettings settings;
    settings.kernels_per_texel = static_cast<int>(state.range(0));
    std::size_t bytes = 0;
    for (auto _ : state) {
        const GaborSurface built(surface, settings);
        bytes = built.memory_bytes();
    }
    state.counters["hierarchy_MB"] = double(bytes) / (1 << 20);
}
BENCHMARK(BM_GaborSurfaceBuild8192)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
