// `glintscope generate`: writes the requested surface, and refuses absurd parameters with a
// one-line message, exit code 1 and no output file.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "cli_runner.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {
namespace {

using testing::run_cli;
using testing::TemporaryDirectory;

TEST(GenerateCommand, WritesTheRequestedSurface) {
    const TemporaryDirectory directory;
    const std::string output = directory.file("grating.exr");
    const auto result = run_cli({"generate", "grating", "--size", "64", "--texel", "250nm", "--period", "4um",
                                 "--amplitude", "100nm", "-o", output});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const Heightfield field = load_heightfield(output);
    EXPECT_EQ(field.rows, 64);
    EXPECT_EQ(field.cols, 64);
    EXPECT_DOUBLE_EQ(field.texel_um, 0.25);
    EXPECT_NEAR(compute_statistics(field).sq_um, 0.1 / std::sqrt(2.0), 1e-6);
    EXPECT_EQ(field.provenance.at("generator"), "grating");
    EXPECT_EQ(field.provenance.at("generator.period_um"), "4");
}

TEST(GenerateCommand, TexelYMakesRectangularTexels) {
    // A grating along y (period 4 µm) at 0.25 × 0.5 µm: the same 0.1 µm sinusoid in µm, its rms
    // slope along y that of central differences over 2dy = 1 µm.
    const TemporaryDirectory directory;
    const std::string output = directory.file("grating.exr");
    const auto result = run_cli({"generate", "grating", "--rows", "32", "--cols", "16", "--texel", "250nm",
                                 "--texel-y", "0.5um", "--angle", "90", "-o", output});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("250 nm x 500 nm (x by y)"), std::string::npos) << result.output;
    const Heightfield field = load_heightfield(output);
    EXPECT_DOUBLE_EQ(field.dx_um(), 0.25);
    EXPECT_DOUBLE_EQ(field.dy_um(), 0.5);
    EXPECT_EQ(field.provenance.at("generator.texel_y_um"), "0.5");
    const SurfaceStatistics stats = compute_statistics(field);
    EXPECT_NEAR(stats.sq_um, 0.1 / std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(stats.rms_slope_y, 0.1 * std::sin(2.0 * std::numbers::pi * 0.5 / 4.0) / (std::sqrt(2.0) * 0.5), 1e-5);
    const auto bad = run_cli({"generate", "grating", "--texel-y", "0", "-o", directory.file("bad.exr")});
    EXPECT_EQ(bad.exit_code, 1) << bad.output;
    EXPECT_NE(bad.output.find("texel_y: must be a positive length"), std::string::npos) << bad.output;
}

TEST(GenerateCommand, OptionsOverrideARecipe) {
    const TemporaryDirectory directory;
    const std::string recipe = directory.file("small.recipe");
    std::ofstream(recipe) << "kind = isotropic\nsize = 96\ncorrelation_length_x = 5um\ncorrelation_length_y = 5um\n";
    const std::string output = directory.file("small.exr");
    const auto result = run_cli({"generate", "--recipe", recipe, "--seed", "9", "--sigma-h", "0.5um", "-o", output});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const Heightfield field = load_heightfield(output);
    EXPECT_EQ(field.rows, 96);
    EXPECT_EQ(field.provenance.at("generator.preset"), "isotropic");
    EXPECT_EQ(field.provenance.at("generator.seed"), "9");
    EXPECT_EQ(field.provenance.at("generator.sigma_h_um"), "0.5");
    EXPECT_NEAR(compute_statistics(field).sq_um, 0.5, 1e-5);
}

TEST(GenerateCommand, BadParameterIsAOneLineErrorWithNoOutput) {
    const TemporaryDirectory directory;
    const auto result =
        run_cli({"generate", "isotropic", "--size", "64", "--sigma-h=-1um", "-o", directory.file("bad.exr")});
    EXPECT_EQ(result.exit_code, 1);
    EXPECT_EQ(result.output, "glintscope: error: sigma_h must be a positive length, got -1 um\n");
    EXPECT_EQ(testing::count_entries(directory.path()), 0);
    // The output's folder is checked before the surface is generated (the writer's own refusal,
    // after the work, would begin "cannot write").
    const std::string nowhere = directory.file("no/such/dir/big.exr");
    const auto refused = run_cli({"generate", "isotropic", "--size", "8192", "-o", nowhere});
    EXPECT_EQ(refused.exit_code, 1);
    EXPECT_EQ(refused.output, "glintscope: error: -o '" + nowhere + "': directory '" + directory.file("no/such/dir") +
                                  "' does not exist\n");
    const auto convert = run_cli({"convert", "builtin:isotropic", directory.file("no/out.exr")});
    EXPECT_NE(convert.output.find("-o '"), std::string::npos) << convert.output;
}

TEST(GenerateCommand, OptionOfAnotherKindIsRefused) {
    const TemporaryDirectory directory;
    const auto result = run_cli({"generate", "grating", "--seed", "3", "-o", directory.file("g.exr")});
    EXPECT_EQ(result.exit_code, 1);
    EXPECT_NE(result.output.find("seed does not apply to kind 'grating'"), std::string::npos) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 0);
}

TEST(GenerateCommand, UnknownKindIsRefused) {
    const TemporaryDirectory directory;
    const auto result = run_cli({"generate", "velvet", "-o", directory.file("v.exr")});
    EXPECT_EQ(result.exit_code, 1);
    EXPECT_NE(result.output.find("unknown heightfield kind 'velvet'"), std::string::npos) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 0);
}

TEST(GenerateCommand, HelpShowsUnitsAndDefaults) {
    const auto result = run_cli({"generate", "--help"});
    EXPECT_EQ(result.exit_code, 0);
    EXPECT_NE(result.output.find("--sigma-h LENGTH"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("isotropic: 1.2 um"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("--orientation DEGREES"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace glintscope
