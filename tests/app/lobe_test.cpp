// The lobe command as a user drives it: a flat mirror's albedo through the whole pipeline,
// the metadata that makes an output reproducible, and clean failures on bad input.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli_runner.hpp"
#include "glintscope/io/heightfield_io.hpp"

namespace glintscope {
namespace {

using testing::run_cli;
using testing::TemporaryDirectory;

std::string write_flat_field(const TemporaryDirectory& directory, float fill = 0.0f) {
    Heightfield field = make_heightfield(128, 128, 1.0, 0.0f);
    field.heights_um[1000] = fill;
    const std::string path = directory.file("flat.exr");
    save_heightfield(path, field);
    return path;
}

// "lambda 0.5 um: peak ... albedo A" → A
double printed_albedo(const std::string& output) {
    const auto at = output.find("albedo ");
    if (at == std::string::npos) return NAN;
    return std::stod(output.substr(at + 7));
}

TEST(LobeCommand, FlatMirrorAlbedoIsOneByBothMethods) {
    TemporaryDirectory directory;
    const std::string field = write_flat_field(directory);
    for (const std::string method : {"fft", "gabor"}) {
        const std::string exr = directory.file(method + ".exr");
        const auto result = run_cli({"lobe", field, "--method", method, "--sigma-c", "5um", "--lambda", "500nm",
                                     "--incident", "30,45", "--res", "128", "--supersample", "2", "-o", exr});
        ASSERT_EQ(result.exit_code, 0) << result.output;
        // Gabor's kernels blur the footprint: albedo σ_c²/(σ_c² + σ_k²) = 0.990 at the default one
        // kernel per texel (σ_k = 0.5 µm).
        const double expected = method == "gabor" ? 25.0 / 25.25 : 1.0;
        EXPECT_NEAR(printed_albedo(result.output), expected, 3e-3) << method << ": " << result.output;

        auto input = OIIO::ImageInput::open(exr);
        ASSERT_TRUE(input);
        const OIIO::ImageSpec& spec = input->spec();
        ASSERT_EQ(spec.nchannels, 1);
        EXPECT_EQ(spec.channelnames[0], "Y");
        EXPECT_EQ(spec.get_string_attribute("glintscope:method"), method);
        EXPECT_EQ(spec.get_string_attribute("glintscope:query.model"), "rohs");
        EXPECT_EQ(spec.get_string_attribute("glintscope:query.lambda"), "0.5");
        EXPECT_NEAR(std::stod(spec.get_string_attribute("glintscope:info.theta_i_deg")), 30.0, 1e-9);
        EXPECT_NEAR(std::stod(spec.get_string_attribute("glintscope:info.phi_i_deg")), 45.0, 1e-9);
    }
}

// λ/(2πσ_c) = 0.5/(2π·10) ≈ 0.008 against a pixel of 2/64 ≈ 0.031: point-sampled, the flat
// mirror's albedo would be far from 1. Unless told otherwise, the command supersamples (and says
// so); told --supersample 1, it warns.
TEST(LobeCommand, SupersamplesWhenTheCoherenceBlurIsSmallerThanAPixel) {
    TemporaryDirectory directory;
    const std::string field = write_flat_field(directory);
    const auto automatic = run_cli({"lobe", field, "--res", "64", "-o", directory.file("a.exr")});
    ASSERT_EQ(automatic.exit_code, 0) << automatic.output;
    EXPECT_NE(automatic.output.find("note: supersampled 6x6"), std::string::npos) << automatic.output;
    EXPECT_NEAR(printed_albedo(automatic.output), 1.0, 0.01) << automatic.output;
    const auto point = run_cli({"lobe", field, "--res", "64", "--supersample", "1", "-o", directory.file("b.exr")});
    ASSERT_EQ(point.exit_code, 0) << point.output;
    EXPECT_NE(point.output.find("warning: the coherence blur"), std::string::npos) << point.output;
    const auto resolved = run_cli({"lobe", field, "--res", "64", "--sigma-c", "1um", "-o", directory.file("c.exr")});
    ASSERT_EQ(resolved.exit_code, 0) << resolved.output;
    EXPECT_EQ(resolved.output.find("warning"), std::string::npos);
    EXPECT_EQ(resolved.output.find("note"), std::string::npos);
}

struct BadRequest {
    std::vector<std::string> arguments;
    std::string message;
};

TEST(LobeCommand, BadInputFailsInOneLineAndWritesNothing) {
    TemporaryDirectory directory;
    const std::string field = write_flat_field(directory);
    const std::string holes = directory.file("holes.exr");
    {
        Heightfield with_nan = make_heightfield(16, 16, 1.0, 0.0f);
        with_nan.heights_um[5] = NAN;
        save_heightfield(holes, with_nan);
    }
    const std::string out = directory.file("out.exr");
    const std::vector<BadRequest> requests = {
        {{"lobe", directory.file("missing.exr"), "-o", out}, "missing.exr"},
        {{"lobe", holes, "-o", out}, "missing (NaN)"},
        {{"lobe", field, "--method", "raytrace", "-o", out}, "unknown method 'raytrace'"},
        {{"lobe", field, "--res", "0", "-o", out}, "lobe resolution must be between 4 and 8192"},
        {{"lobe", field, "--sigma-c", "-1um", "-o", out}, "coherence sigma"},
        {{"lobe", field, "--sigma-c", "ten", "-o", out}, "'ten' is not a length"},
        {{"lobe", field, "--res", "many", "-o", out}, "query key res"},
        {{"lobe", field, "--incident", "95,0", "-o", out}, "theta must be in [0, 90)"},
        {{"lobe", field, "--lambda", "0", "-o", out}, "wavelength 0 um is outside"},
        {{"lobe", field, "--model", "mie", "-o", out}, "unknown diffraction model 'mie'"},
        {{"lobe", field, "--material", "Unobtainium", "-o", out}, "Unobtainium"},
        {{"lobe", field, "--method", "fft", "--option", "step=-1um", "-o", out}, "step"},
        {{"lobe", field, "--method", "gabor", "--option", "colour=blue", "-o", out}, "has no option 'colour'"},
        {{"lobe", field, "-o", directory.file("no/such/dir/out.exr")}, "does not exist"},
        {{"lobe", field, "--colormap", "rainbow", "-o", out}, "unknown lobe colour map 'rainbow'"},
        {{"lobe", field, "--colour-space", "nonsense", "-o", out}, "nonsense"},
        {{"lobe", field, "--ocio-config", directory.file("none.ocio"), "-o", out}, "none.ocio"},
        {{"lobe", field, "--lamda", "0.5um", "-o", out}, "did you mean '--lambda' for '--lamda'?"},
        {{"lobe", field, "--supersampel=2", "-o", out}, "did you mean '--supersample'"},
    };
    for (const BadRequest& request : requests) {
        const int before = testing::count_entries(directory.path());
        const auto result = run_cli(request.arguments);
        EXPECT_NE(result.exit_code, 0) << request.message;
        EXPECT_NE(result.output.find(request.message), std::string::npos) << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_EQ(testing::count_entries(directory.path()), before) << request.message;
    }
}

}  // namespace
}  // namespace glintscope
