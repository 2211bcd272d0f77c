// glintscope convert: crop, fill, form removal and resampling of a measured heightfield, in
// that order, printed and recorded in the output; bad requests fail with one line, exit code 1
// and no output file.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/io/heightfield_io.hpp"

namespace glintscope {
namespace {

using testing::count_entries;
using testing::run_cli;
using testing::CliResult;
using testing::run_cli;
using testing::TemporaryDirectory;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A tilted 60×80 scan with a sinusoidal texture and drop-outs, written as NPY (no units: the
// tests give --texel 0.5um).
std::string write_scan(const TemporaryDirectory& directory) {
    Heightfield field = make_heightfield(60, 80, 0.5);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            field.at(r, c) = static_cast<float>(5.0 + 0.02 * s.x - 0.01 * s.y + 0.1 * std::sin(s.x) * std::cos(s.y));
        }
    for (int r = 20; r < 26; ++r)
        for (int c = 30; c < 37; ++c) field.at(r, c) = std::numeric_limits<float>::quiet_NaN();
    field.at(40, 50) = std::numeric_limits<float>::quiet_NaN();
    const std::string path = directory.file("scan.npy");
    save_heightfield(path, field);
    return path;
}

TEST(ConvertCommand, AppliesTheStepsInTheDocumentedOrder) {
    TemporaryDirectory directory;
    const std::string input = write_scan(directory);
    const std::string output = directory.file("prepared.exr");
    // Options given in another order than the steps run.
    const auto result = run_cli({"convert", input, output, "--resample", "1um", "--remove-form", "plane", "--fill",
                                 "--crop", "2um,3um,30um,20um", "--texel", "0.5um"});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const std::size_t crop = result.output.find("crop:");
    const std::size_t fill = result.output.find("fill_missing:");
    const std::size_t form = result.output.find("remove_form: plane");
    const std::size_t resample = result.output.find("resample:");
    ASSERT_NE(resample, std::string::npos) << result.output;
    EXPECT_LT(crop, fill);
    EXPECT_LT(fill, form);
    EXPECT_LT(form, resample);
    EXPECT_TRUE(contains(result.output, "fill_missing: 43 points")) << result.output;  // 6·7 + 1, all inside the crop

    const Heightfield prepared = load_heightfield(output);
    EXPECT_EQ(prepared.cols, 30);  // 60 × 40 samples of 0.5 µm, resampled to 1 µm
    EXPECT_EQ(prepared.rows, 20);
    EXPECT_EQ(prepared.texel_um, 1.0);
    EXPECT_EQ(count_missing(prepared), 0u);
    double sum = 0.0, peak = 0.0;
    for (float h : prepared.heights_um) {
        sum += h;
        peak = std::fmax(peak, std::fabs(h));
    }
    // The 5 µm offset and the tilt are gone; the ±0.1 µm texture remains.
    EXPECT_LT(std::fabs(sum / static_cast<double>(prepared.size())), 0.01);
    EXPECT_LT(peak, 0.15);
    ASSERT_EQ(prepared.provenance.count("prepare.4"), 1u);
    EXPECT_EQ(prepared.provenance.at("prepare.1").rfind("crop:", 0), 0u);
    EXPECT_EQ(prepared.provenance.at("prepare.2").rfind("fill_missing:", 0), 0u);
    EXPECT_EQ(prepared.provenance.at("prepare.3").rfind("remove_form:", 0), 0u);
    EXPECT_EQ(prepared.provenance.at("prepare.4").rfind("resample:", 0), 0u);
}

TEST(ConvertCommand, FillsTheCsafeScanIntoX3p) {
    TemporaryDirectory directory;
    const std::string output = directory.file("logo.x3p");
    const auto result = run_cli({"convert", testing::shared_path("data/csafe-logo.x3p"), output, "--remove-form",
                                 "poly:2", "--fill-method", "harmonic", "--fill"});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const Heightfield converted = load_heightfield(output);
    EXPECT_EQ(converted.cols, 741);
    EXPECT_EQ(converted.rows, 419);
    EXPECT_NEAR(converted.texel_um, 0.645, 1e-9);
    EXPECT_TRUE(contains(converted.provenance.at("prepare.2"), "polynomial order 2")) << result.output;
}

TEST(ConvertCommand, BadRequestsFailWithOneLineAndNoOutput) {
    TemporaryDirectory directory;
    const std::string input = write_scan(directory);
    const std::string output = directory.file("out.exr");
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"--crop", "30um,0um,20um,10um"}, "crop: the region x 30 um to 50 um"},  // the field is 40 µm wide
        {{"--crop=-1um,0,10um,10um"}, "lies outside the field"},
        {{"--crop", "1,2,3"}, "--crop: expected X0,Y0,W,H"},
        {{"--crop", "1,2,3,4furlong"}, "--crop: '4furlong' has an unknown unit suffix"},
        {{"--remove-form", "poly:9"}, "--remove-form: 'poly:9' is not a form"},
        {{"--resample", "1um"}, "fill them first (convert --fill)"},
        {{"--fill", "--resample", "0"}, "resample: the texel size must be a positive length"},
    };
    for (const auto& [options, message] : cases) {
        std::vector<std::string> arguments = {"convert", input, output, "--texel", "0.5um"};
        arguments.insert(arguments.end(), options.begin(), options.end());
        const auto result = run_cli(arguments);
        EXPECT_EQ(result.exit_code, 1) << result.output;
        EXPECT_TRUE(contains(result.output, "glintscope: error: ")) << result.output;
        EXPECT_TRUE(contains(result.output, message)) << message << "\n" << result.output;
        EXPECT_EQ(result.output.find('\n'), result.output.size() - 1) << result.output;
        EXPECT_EQ(count_entries(directory.path()), 1) << "left an output behind: " << message;
    }
}

TEST(ConvertCommand, HelpShowsUnitsDefaultsAndOrder) {
    const auto result = run_cli({"convert", "--help"});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    for (const std::string part : {"crop, fill, form removal, resample", "--crop X0,Y0,W,H", "lower-left corner",
                                   "10um,5um,100um,50um", "=biharmonic", "poly:N", "--resample", "bare numbers are um",
                                   "--periodic", "--texel", "--height-unit"})
        EXPECT_TRUE(contains(result.output, part)) << part << "\n" << result.output;
}

TEST(ConvertCommand, NpyOutputSaysHowToGetTheTexelBack) {
    // NPY has no texel field: convert prints the --texel that restores it, and that round trip
    // gives back the same sample spacing and heights.
    TemporaryDirectory directory;
    const CliResult result = run_cli({"convert", "builtin:grating", directory.file("g.npy"), "--crop", "0,0,20um,20um"});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const std::string flag = "--texel ";
    const std::size_t at = result.output.find(flag);
    ASSERT_NE(at, std::string::npos) << result.output;
    const std::string texel = result.output.substr(at + flag.size(), result.output.find(' ', at + flag.size()) - at - flag.size());
    EXPECT_EQ(texel, "0.25um");
    LoadOptions options;
    options.texel_um = 0.25;
    const Heightfield back = load_heightfield(directory.file("g.npy"), options);
    const Heightfield original = generate_builtin("grating");
    EXPECT_EQ(back.texel_um, original.texel_um);
    EXPECT_EQ(back.cols, 80);
}

}  // namespace
}  // namespace glintscope
