// Rendering the Patch scene (Yan 2018 Table 1, render.hpp) on the isotropic builtin (1024² at 1 µm,
// tiled): gabor, one kernel per texel, σ_c = 10 µm, 4 spp, the default camera and light, at the
// image size of the argument's height (16:9), single wavelength (0.4 µm, the paper's) and 8 bins,
// and a 16-frame light sweep; and discrete's flakes over each shading point's footprint.
#include <benchmark/benchmark.h>

#include <string>

#include "glintscope/generate/generate.hpp"
#include "glintscope/optics/spectrum.hpp"
#include "glintscope/render/render.hpp"

namespace {

glintscope::Scene patch_scene(int height, bool spectral, const std::string& method = "gabor") {
    static const glintscope::Heightfield field = glintscope::generate_builtin("isotropic");
    glintscope::Scene scene;
    glintscope::set_heightfield(scene.query, field);
    scene.query.wavelengths_um = spectral ? glintscope::spectral_bin_centres_um(8) : std::vector<double>{0.4};
    scene.camera.height = height;
    scene.camera.width = height * 16 / 9;
    scene.method = method;
    return scene;
}

void BM_RenderPatch(benchmark::State& state, bool spectral) {
    const glintscope::Scene scene = patch_scene(static_cast<int>(state.range(0)), spectral);
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::render(scene, glintscope::RenderSettings{4, 0}));
    state.counters["shading_points"] = double(scene.camera.width) * scene.camera.height * 4;
}
BENCHMARK_CAPTURE(BM_RenderPatch, single_wavelength, false)->Arg(90)->Arg(720)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
// Jakob 2014's flakes (discrete's defaults: Beckmann α = 0.2, 1e6 flakes per σ_c = 10 µm footprint)
// counted over each shading point's footprint on the patch (render.md "the pixel's footprint").
void BM_RenderPatchDiscrete(benchmark::State& state) {
    const glintscope::Scene scene = patch_scene(static_cast<int>(state.range(0)), false, "discrete");
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::render(scene, glintscope::RenderSettings{4, 0}));
    state.counters["shading_points"] = double(scene.camera.width) * scene.camera.height * 4;
}
BENCHMARK(BM_RenderPatchDiscrete)->Arg(90)->Arg(720)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
// Yan 2018's video: 16 frames of the light moving across the patch side (render_light_sweep, as
// the CLI's --light-sweep 16), single wavelength, kernels of order state.range(1): each shading
// point's BSDF evaluates all frames' lights in one call (Bsdf::eval_incident).
void BM_RenderLightSweep(benchmark::State& state) {
    glintscope::Scene scene = patch_scene(static_cast<int>(state.range(0)), false);
    scene.query.method_options["order"] = std::to_string(state.range(1));
    for (auto _ : state)
        benchmark::DoNotOptimize(
            glintscope::render_light_sweep(scene, 16, scene.patch_um, glintscope::RenderSettings{4, 0}));
    state.counters["shading_points"] = double(scene.camera.width) * scene.camera.height * 4;
}
BENCHMARK(BM_RenderLightSweep)->Args({90, 1})->Args({90, 2})->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_RenderPatch, spectral_8, true)->Arg(90)->Arg(720)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace
