// The exact P-NDF, the filtered NDF, the geometric lobe and the Kirchhoff distribution on the isotropic surface of Yan 2018
// Fig. 8 (1024² builtin at 1 µm; 8192² from heightfields/isotropic.recipe for the whole-field NDF).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>

#include "glintscope/generate/generate.hpp"
#include "normal_density/normal_bounds_tree.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/query.hpp"

namespace {

glintscope::LobeQuery builtin_query(int resolution, glintscope::FootprintShape shape, glintscope::Quantity quantity) {
    static const glintscope::Heightfield field = glintscope::generate_builtin("isotropic");
    glintscope::LobeQuery query;
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = 10.0;
    query.footprint.shape = shape;
    query.resolution = resolution;
    query.quantity = quantity;
    glintscope::set_heightfield(query, field);
    return query;
}

void BM_Pndf256GaussianFootprint(benchmark::State& state) {
    const glintscope::LobeQuery query = builtin_query(256, glintscope::FootprintShape::gaussian, glintscope::Quantity::ndf);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("pndf", query));
}
BENCHMARK(BM_Pndf256GaussianFootprint)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Pndf1024Whole8192Field(benchmark::State& state) {
    glintscope::LobeQuery query;
    {
        glintscope::Recipe recipe = glintscope::load_recipe(GLINTSCOPE_SOURCE_DIR "/heightfields/isotropic.recipe");
        glintscope::set_heightfield(query, glintscope::generate(recipe));
    }
    query.footprint.shape = glintscope::FootprintShape::whole;
    query.quantity = glintscope::Quantity::ndf;
    query.resolution = 1024;
    // One undivided cell per texel: the whole field's default tolerance (0.1 pixel) subdivides
    // most texels of this surface at 1024² and takes 2.4 s per 1024² of field (~2.6 min here).
    query.method_options = {{"refinement", "1"}, {"tolerance", "0"}};
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("pndf", query));
}
BENCHMARK(BM_Pndf1024Whole8192Field)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

void BM_FilteredNdf256Whole1024Field(benchmark::State& state) {
    const glintscope::LobeQuery query = builtin_query(256, glintscope::FootprintShape::whole, glintscope::Quantity::ndf);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("filtered", query));
}
BENCHMARK(BM_FilteredNdf256Whole1024Field)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_GeometricLobe256(benchmark::State& state) {
    const glintscope::LobeQuery query = builtin_query(256, glintscope::FootprintShape::gaussian, glintscope::Quantity::brdf);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("geometric", query));
}
BENCHMARK(BM_GeometricLobe256)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_KirchhoffDistribution256(benchmark::State& state) {
    const glintscope::LobeQuery query = builtin_query(256, glintscope::FootprintShape::gaussian, glintscope::Quantity::ndf);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::compute_lobe("dk", query));
}
BENCHMARK(BM_KirchhoffDistribution256)->Unit(benchmark::kMillisecond)->UseRealTime();

// The normal-bounds tree of the whole 1024² builtin for a 256² image, and a point query of its
// D at random normals of the distribution's core (|h| ≤ 0.3, the isotropic surface's slopes: rms
// 0.17) for Gaussian footprints of σ_c = 20 µm at random centres, as a renderer's shading points
// ask. Argument: 1 for pndf's default adaptive subdivision (tolerance 0.02 pixel), 0 for one
// undivided cell per texel (tolerance 0).
glintscope::NormalDensitySettings tree_settings(bool adaptive) {
    return {1, adaptive ? 0.02 : 0.0, 0.0};
}

std::shared_ptr<const glintscope::BicubicInterpolant> builtin_surface() {
    static const auto surface =
        std::make_shared<const glintscope::BicubicInterpolant>(glintscope::generate_builtin("isotropic"));
    return surface;
}

void BM_NormalBoundsTreeBuild1024(benchmark::State& state) {
    for (auto _ : state)
        benchmark::DoNotOptimize(glintscope::make_normal_bounds_tree(builtin_surface(), tree_settings(state.range(0)), 256));
}
BENCHMARK(BM_NormalBoundsTreeBuild1024)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

// Times point queries of 1024 footprints at random centres over the field, each shaped by
// shape(footprint, uniform), at random normals of the distribution's core (|h| ≤ 0.3).
template <typename Shape>
void time_point_queries(benchmark::State& state, const glintscope::NormalBoundsTree& tree, unsigned seed, const Shape& shape) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const auto uniform = [&] { return u(rng); };
    std::vector<std::pair<glintscope::Footprint, glintscope::DiskPoint>> queries(1024);
    for (auto& [footprint, h] : queries) {
        footprint.centre_um = {1024.0 * uniform(), 1024.0 * uniform()};
        shape(footprint, uniform);
        const double r = 0.3 * std::sqrt(uniform()), phi = 2.0 * glintscope::pi * uniform();
        h = {r * std::cos(phi), r * std::sin(phi)};
    }
    std::size_t k = 0;
    for (auto _ : state) {
        const auto& [footprint, h] = queries[k++ % queries.size()];
        benchmark::DoNotOptimize(glintscope::point_normal_density(tree, footprint, h));
    }
}

void BM_PndfPointQuerySigma20(benchmark::State& state) {
    const glintscope::NormalBoundsTree tree =
        glintscope::make_normal_bounds_tree(builtin_surface(), tree_settings(state.range(0)), 256);
    time_point_queries(state, tree, 22, [](glintscope::Footprint& footprint, const auto&) { footprint.sigma_um = 20.0; });
}
BENCHMARK(BM_PndfPointQuerySigma20)->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);

// A geometric render's shading point at the Patch scene's image centre, 1280 × 720 × 4 spp: its
// cell on the patch is 37 × 53 µm (the longer side along the view's azimuth, +y). Argument 0: the
// cell itself as the rectangle it queries now (render.cpp), turned by a random angle; 1: the
// elliptical Gaussian of the same covariance it queried before 2026-11-26 (σ_c = √2 · 53/√12,
// σ_minor = √2 · 37/√12), cut at 6σ. Adaptive tree, random centres and |h| ≤ 0.3 as above.
void BM_PndfPointQueryPatchCell(benchmark::State& state) {
    const glintscope::NormalBoundsTree tree = glintscope::make_normal_bounds_tree(builtin_surface(), tree_settings(true), 256);
    const bool rectangle = state.range(0) == 0;
    time_point_queries(state, tree, 24, [rectangle](glintscope::Footprint& footprint, const auto& uniform) {
        footprint.axis_radians = glintscope::pi * uniform();
        if (rectangle) {
            footprint.shape = glintscope::FootprintShape::box;
            footprint.size_um = 53.0;
            footprint.size_y_um = 37.0;
        } else {
            footprint.sigma_um = std::sqrt(2.0 / 12.0) * 53.0;
            footprint.sigma_minor_um = std::sqrt(2.0 / 12.0) * 37.0;
        }
    });
}
BENCHMARK(BM_PndfPointQueryPatchCell)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

// The point query's sampler for one σ_c = 20 µm footprint (argument as above): range(1) = 0 times
// the making of its cumulative weights over the support; 1 times a draw of h from them.
void BM_PndfPointSamplerSigma20(benchmark::State& state) {
    const glintscope::NormalBoundsTree tree =
        glintscope::make_normal_bounds_tree(builtin_surface(), tree_settings(state.range(0)), 256);
    glintscope::Footprint footprint;
    footprint.centre_um = {300.0, 700.0};
    footprint.sigma_um = 20.0;
    if (state.range(1) == 0) {
        for (auto _ : state) benchmark::DoNotOptimize(glintscope::make_normal_sampler(tree, footprint));
        return;
    }
    const glintscope::NormalSampler sampler = glintscope::make_normal_sampler(tree, footprint);
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::sample_normal(tree, sampler, u(rng), u(rng)));
}
BENCHMARK(BM_PndfPointSamplerSigma20)->Args({1, 0})->Args({1, 1})->Args({0, 1})->Unit(benchmark::kMicrosecond);

}  // namespace
