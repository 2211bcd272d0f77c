// glintscope info: size, texel, units, statistics and provenance of a file, as text or JSON,
// and one-line errors with exit code 1 for bad files.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <numbers>
#include <regex>
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

TEST(InfoCommand, DeclaredRectangularSpacingIsSaidToBeDeclared) {
    TemporaryDirectory directory;
    const std::string npy = directory.file("checker.npy");
    save_heightfield(npy, checkerboard());
    const auto text = run_cli({"info", npy, "--texel", "1x2um"});
    ASSERT_EQ(text.exit_code, 0) << text.output;
    EXPECT_TRUE(contains(line_of(text.output, "texel:"), "1 um x 2 um (x by y)")) << text.output;
    EXPECT_TRUE(contains(line_of(text.output, "spacing:"), "DECLARED with --texel, not read from the file; the file "
                                                           "states none"))
        << text.output;
    EXPECT_TRUE(contains(line_of(text.output, "extent:"), "6 um x 8 um")) << text.output;
    const auto json = nlohmann::json::parse(run_cli({"info", npy, "--texel", "1x2um", "--json"}).output);
    EXPECT_EQ(json["texel_um"], 1.0);
    EXPECT_EQ(json["texel_y_um"], 2.0);
    EXPECT_EQ(json["spacing_declared"], true);
    // An EXR's own spacing is named when a declaration overrides it.
    const std::string exr = directory.file("checker.exr");
    save_heightfield(exr, checkerboard());
    const auto overridden = run_cli({"info", exr, "--texel", "2um"});
    ASSERT_EQ(overridden.exit_code, 0) << overridden.output;
    EXPECT_TRUE(contains(line_of(overridden.output, "spacing:"), "the file states 500 nm, overridden"))
        << overridden.output;
    EXPECT_EQ(line_of(run_cli({"info", exr}).output, "spacing:"), "");
    const auto bad = run_cli({"info", npy, "--texel", "1x0um"});
    EXPECT_NE(bad.exit_code, 0) << bad.output;
    EXPECT_TRUE(contains(bad.output, "--texel")) << bad.output;
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

// The number after `key` in JSON output (NaN if absent).
double json_value(const std::string& output, const std::string& key) {
    const std::size_t at = output.find("\"" + key + "\": ");
    if (at == std::string::npos) return std::numeric_limits<double>::quiet_NaN();
    return std::stod(output.substr(at + key.size() + 4));
}

// builtin:grating is A sin(2π x/Λ) with A = 0.1 µm, Λ = 4 µm, 0.25 µm texels, periodic.
TEST(InfoCommand, IsoParametersOfTheGratingAndWhatEachFlagChanges) {
    const double amplitude = 0.1, wavelength = 4.0;
    const auto plain = run_cli({"info", "builtin:grating", "--json"});
    ASSERT_EQ(plain.exit_code, 0) << plain.output;
    EXPECT_NEAR(json_value(plain.output, "Sq_um"), amplitude / std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(json_value(plain.output, "Sku"), 1.5, 1e-4);
    // Central differences over 16 texels a period: A sin(2π/16)/Δ/√2, 2.6% below √2 πA/Λ.
    EXPECT_NEAR(json_value(plain.output, "Sdq"), amplitude * std::sin(2.0 * std::numbers::pi / 16.0) / 0.25 / std::sqrt(2.0),
                1e-6);
    EXPECT_NEAR(json_value(plain.output, "Sal_um"), wavelength * std::acos(0.2) / (2.0 * std::numbers::pi), 0.01);
    EXPECT_NEAR(json_value(plain.output, "Std_deg"), 90.0, 0.5);
    EXPECT_TRUE(contains(plain.output, "\"Str_is_upper_bound\": true")) << plain.output;
    EXPECT_TRUE(contains(plain.output, "\"surface\": \"as read (not levelled, no S- or L-filter)\"")) << plain.output;

    // s = 0.5: cos(2π t/Λ) = 0.5 at t = Λ/6.
    const auto threshold = run_cli({"info", "builtin:grating", "--json", "--acf-threshold", "0.5"});
    EXPECT_NEAR(json_value(threshold.output, "Sal_um"), wavelength / 6.0, 0.01) << threshold.output;
    // The Gaussian filters pass a sinusoid of their nesting index at 50%.
    for (const char* filter : {"--s-filter", "--l-filter"}) {
        const auto filtered = run_cli({"info", "builtin:grating", "--json", filter, "4um"});
        ASSERT_EQ(filtered.exit_code, 0) << filtered.output;
        EXPECT_NEAR(json_value(filtered.output, "Sq_um"), 0.5 * amplitude / std::sqrt(2.0), 1e-4) << filter;
        EXPECT_TRUE(contains(filtered.output, "nesting index 4 um")) << filtered.output;
    }
}

TEST(InfoCommand, LevellingRemovesATilt) {
    TemporaryDirectory directory;
    Heightfield tilted = make_heightfield(64, 64, 1.0);
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 64; ++c) {
            const Point2 s = sample_position(tilted, r, c);
            tilted.at(r, c) = static_cast<float>(0.05 * s.x + 0.2 * std::sin(2.0 * std::numbers::pi * s.y / 16.0));
        }
    const std::string path = directory.file("tilted.exr");
    save_heightfield(path, tilted);
    const auto raw = run_cli({"info", path, "--json"});
    const auto level = run_cli({"info", path, "--json", "--level"});
    ASSERT_EQ(level.exit_code, 0) << level.output;
    // The sinusoid's gradient alone, in y: 0.2·sin(2π/16)/√2 with central differences.
    const double sinusoid_sdq = 0.2 * std::sin(2.0 * std::numbers::pi / 16.0) / std::sqrt(2.0);
    EXPECT_NEAR(json_value(raw.output, "Sdq"), std::hypot(0.05, sinusoid_sdq), 1e-3);
    EXPECT_NEAR(json_value(level.output, "Sdq"), sinusoid_sdq, 1e-3);
    EXPECT_TRUE(contains(level.output, "levelled (least-squares plane removed)")) << level.output;
}

TEST(InfoCommand, NoNaNEvenWhereACorrelationOutlastsTheField) {
    // The grating never decorrelates along y; a constant field has no ISO parameters at all.
    TemporaryDirectory directory;
    const std::string flat = directory.file("flat.exr");
    save_heightfield(flat, make_heightfield(8, 8, 1.0, 3.0f));
    for (const std::vector<std::string>& arguments :
         {std::vector<std::string>{"info", "builtin:grating"}, {"info", "builtin:grating", "--json"}, {"info", flat},
          {"info", flat, "--json"}}) {
        const auto result = run_cli(arguments);
        ASSERT_EQ(result.exit_code, 0) << result.output;
        EXPECT_FALSE(std::regex_search(result.output, std::regex("\\b(nan|null|inf)\\b", std::regex::icase)))
            << result.output;
    }
    const auto grating = run_cli({"info", "builtin:grating"});
    EXPECT_TRUE(contains(line_of(grating.output, "correlation length:"),
                         "y longer than 128 um (half the field; autocorrelation still 1 there)"))
        << grating.output;
    EXPECT_TRUE(contains(run_cli({"info", flat}).output, "not defined: the heights do not vary"));
}

TEST(InfoCommand, HelpShowsUnitsAndDefaults) {
    const auto result = run_cli({"info", "--help"});
    EXPECT_EQ(result.exit_code, 0);
    for (const std::string part : {"--texel", "LENGTH", "500nm", "Default", "1 um", "--height-unit", "texel",
                                   "--height-scale", "--channel", "Z, Y, R", "--json"})
        EXPECT_TRUE(contains(result.output, part)) << part << "\n" << result.output;
}

// A builtin says what it is, that its units are exact, and its zero mean reads 0 (the float sum's
// rounding noise, ~1e-9 um, is not a height).
TEST(InfoCommand, ABuiltinSaysWhatItIsAndItsZeroMeanIsZero) {
    const auto result = run_cli({"info", "builtin:brushed"});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_TRUE(contains(line_of(result.output, "surface:"), "brushed metal, grooves along x")) << result.output;
    EXPECT_TRUE(contains(line_of(result.output, "units:"), "exact")) << result.output;
    EXPECT_FALSE(contains(result.output, "from the file")) << result.output;
    EXPECT_EQ(line_of(result.output, "mean height:"), "mean height:           0 um") << result.output;
}

}  // namespace
}  // namespace glintscope
