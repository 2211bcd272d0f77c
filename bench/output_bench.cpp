// Writing a 1024² NDF as a labelled PNG (colour map, legend, caption): the display path reads each
// pixel a constant number of times (it once scanned the whole image per pixel: 238 s at 1024²).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "glintscope/generate/generate.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/output/lobe_output.hpp"

namespace {

void BM_WriteNdfPng1024(benchmark::State& state) {
    glintscope::LobeQuery query;
    glintscope::set_heightfield(query, glintscope::generate_builtin("isotropic"));
    query.footprint.shape = glintscope::FootprintShape::whole;
    query.quantity = glintscope::Quantity::ndf;
    query.resolution = 1024;
    query.method_options = {{"refinement", "1"}, {"tolerance", "0"}};
    const glintscope::LobeImage ndf = glintscope::compute_lobe("pndf", query);
    const std::string path = (std::filesystem::temp_directory_path() / "glintscope-bench-ndf.png").string();
    for (auto _ : state) benchmark::DoNotOptimize(glintscope::write_lobe_png(ndf, path, {}));
    std::filesystem::remove(path);
}
BENCHMARK(BM_WriteNdfPng1024)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
