// glintscope info: size, texel, units, statistics and provenance of a file, as text or JSON,
// and one-line errors with exit code 1 for bad files.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "glintscope/io/heightfield_io.hpp"

namespace glintscope {
namespace {

using testing::run_cli;
using testing::TemporaryDirectory;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The text line that starts with `name` ("" if none).
std::string line_of(const std::string& output, const std::string& name) {
    const std::size_t start = output.find("\n" + name);
    if (start == std::string::npos) return output.rfind(name, 0) == 0 ? output.substr(0, output.find('\n')) : "";
    return output.substr(start + 1, output.find('\n', start + 1) - start - 1);
}

// ±1 µm in a checkerboard: mean 0, Sq = Sa = 1 µm, exactly.
Heightfield checkerboard() {
    Heightfield field = make_heightfield(4, 6, 0.5);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 6; ++c) field.at(r, c) = (r + c) % 2 ? 1.0f : -1.0f;
    field.provenance["generator"] = "checkerboard \"quoted\"";
    return field;
}

TEST(InfoCommand, DescribesTheCsafeX3p) {
    const auto result = run_cli({"info", testing::shared_path("data/csafe-logo.x3p")});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_TRUE(contains(result.output, "741 x 419 samples")) << result.output;
    EXPECT_TRUE(contains(result.output, "645 nm")) << result.output;
    EXPECT_TRUE(contains(result.output, "477.945 um x 270.255 um")) << result.output;
    EXPECT_TRUE(contains(result.output, "from the file")) << result.output;
    EXPECT_FALSE(contains(result.output, "ASSUMED")) << result.output;
    EXPECT_TRUE(contains(result.output, "x3p:creator: Heike Hofmann, CSAFE")) << result.output;
    EXPECT_TRUE(contains(line_of(result.output, "missing points:"), " 0 (0%)")) << result.output;
}

TEST(InfoCommand, JsonCarriesTheSameContent) {
    TemporaryDirectory directory;
    const std::string path = directory.file("checker.exr");
    save_heightfield(path, checkerboard());
    const auto result = run_cli({"info", path, "--json"});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const nlohmann::json json = nlohmann::json::parse(result.output);  // nothing but one JSON object
    EXPECT_EQ(json["cols"], 6);
    EXPECT_EQ(json["rows"], 4);
    EXPECT_EQ(json["texel_um"], 0.5);
    EXPECT_EQ(json["width_um"], 3.0);
    EXPECT_EQ(json["units_assumed"], false);
    const nlohmann::json& statistics = json["statistics"];
    EXPECT_EQ(statistics["mean_um"], 0.0);
    EXPECT_EQ(statistics["sq_um"], 1.0);
    EXPECT_EQ(statistics["sa_um"], 1.0);
    EXPECT_EQ(statistics["min_um"], -1.0);
    EXPECT_EQ(statistics["max_um"], 1.0);
    EXPECT_EQ(json["missing_count"], 0);
    EXPECT_EQ(json["provenance"], nlohmann::json({{"generator", "checkerboard \"quoted\""}}));
}

TEST(InfoCommand, SaysWhenUnitsWereAssumedAndTakesLoadingOptions) {
    TemporaryDirectory directory;
    const std::string path = directory.file("checker.npy");
    save_heightfield(path, checkerboard());
    const auto assumed = run_cli({"info", path});
    ASSERT_EQ(assumed.exit_code, 0) << assumed.output;
    EXPECT_TRUE(contains(assumed.output, "ASSUMED")) << assumed.output;
    EXPECT_TRUE(contains(line_of(assumed.output, "texel:"), " 1 um")) << assumed.output;

    const auto given =
        run_cli({"info", path, "--texel", "250nm", "--height-unit", "nm", "--height-scale", "-2", "--json"});
    ASSERT_EQ(given.exit_code, 0) << given.output;
    const nlohmann::json json = nlohmann::json::parse(given.output);
    EXPECT_EQ(json["texel_um"], 0.25);
    EXPECT_EQ(json["units_assumed"], false);
    EXPECT_NEAR(json["statistics"]["max_um"].get<double>(), 0.002, 1e-9);  // 1 nm · 2
}

TEST(InfoCommand, BadFilesFailWithOneLineAndExitCodeOne) {
    TemporaryDirectory directory;
    const std::string corrupt = directory.file("corrupt.x3p");
    std::ofstream(corrupt) << "not a zip";
    const std::string empty = directory.file("empty.npy");
    std::ofstream{empty};
    const std::string nan_only = directory.file("nan.npy");
    {
        std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 2), }";
        header.append((64 - (10 + header.size() + 1) % 64) % 64, ' ');
        header += '\n';
        const float nan = std::numeric_limits<float>::quiet_NaN();
        std::ofstream out(nan_only, std::ios::binary);
        const auto length = static_cast<std::uint16_t>(header.size());
        out.write("\x93NUMPY\x01\x00", 8).write(reinterpret_cast<const char*>(&length), 2);
        out << header;
        out.write(reinterpret_cast<const char*>(&nan), 4).write(reinterpret_cast<const char*>(&nan), 4);
    }
    const std::string exr = directory.file("field.exr");
    save_heightfield(exr, checkerboard());

    const std::pair<std::vector<std::string>, std::string> cases[] = {
        {{"info", directory.file("absent.exr")}, "absent.exr': no such file"},
        {{"info", corrupt}, "corrupt.x3p': not a valid X3P file"},
        {{"info", empty}, "empty.npy': the file is empty"},
        {{"info", nan_only}, "nan.npy': every height is missing (NaN)"},
        {{"info", exr, "--channel", "R"}, "no channel 'R' (available: 0:Z)"},
    };
    for (const auto& [arguments, message] : cases) {
        const auto result = run_cli(arguments);
        EXPECT_EQ(result.exit_code, 1) << result.output;
        EXPECT_TRUE(contains(result.output, "glintscope: error: cannot read '")) << result.output;
        EXPECT_TRUE(contains(result.output, message)) << message << "\n" << result.output;
        EXPECT_EQ(result.output.find('\n'), result.output.size() - 1) << result.output;
    }
}

TEST(InfoCommand, HelpShowsUnitsAndDefaults) {
    const auto result = run_cli({"info", "--help"});
    EXPECT_EQ(result.exit_code, 0);
    for (const std::string part : {"--texel", "LENGTH", "500nm", "Default", "1 um", "--height-unit", "texel",
                                   "--height-scale", "--channel", "Z, Y, R", "--json"})
        EXPECT_TRUE(contains(result.output, part)) << part << "\n" << result.output;
}

}  // namespace
}  // namespace glintscope
