// glintscope compare, as a user runs it: exit status 0 alike, 1 above --fail-above, 2 on bad
// input (nothing written), and its report and picture.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "glintscope/output/figure.hpp"
#include "glintscope/output/lobe_output.hpp"

namespace glintscope {
namespace {

using testing::run_cli;
using testing::TemporaryDirectory;

class CompareCommand : public ::testing::Test {
protected:
    // A lobe of the isotropic builtin written by the tool.
    std::string lobe(const std::string& name, const std::vector<std::string>& extra = {}, const std::string& res = "32") {
        std::vector<std::string> arguments = {"--quiet", "lobe", "builtin:isotropic", "--res", res, "--supersample", "1",
                                              "-o", directory.file(name)};
        arguments.insert(arguments.end(), extra.begin(), extra.end());
        const auto result = run_cli(arguments);
        EXPECT_EQ(result.exit_code, 0) << result.output;
        return directory.file(name);
    }
    TemporaryDirectory directory;
};

TEST_F(CompareCommand, TheSameQueryTwiceIsExactAndExitsZero) {
    const auto result = run_cli({"compare", lobe("a.exr"), lobe("b.exr"), "--fail-above", "0"});
    EXPECT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find("0.0000%"), std::string::npos) << result.output;
}

TEST_F(CompareCommand, ScaledByOnePointOneReportsTenPercentAndFailAboveDecides) {
    const std::string b = lobe("b.exr");
    LobeImage scaled = load_lobe_exr(b);
    for (float& value : scaled.values) value *= 1.1f;
    const std::string a = directory.file("a.exr");
    write_lobe_exr(scaled, a, {});
    const std::string report = directory.file("report.json");
    const auto below = run_cli({"compare", a, b, "--fail-above", "0.1001", "--json", report});
    EXPECT_EQ(below.exit_code, 0) << below.output;
    const nlohmann::json json = nlohmann::json::parse(std::ifstream(report));
    const nlohmann::json& layer = json["layers"][0];
    EXPECT_NEAR(layer["relative_l2"].get<double>(), 0.1, 1e-6);
    EXPECT_NEAR(layer["energy_ratio"].get<double>(), 1.1, 1e-6);
    EXPECT_EQ(json["a"]["method"], "fft");
    EXPECT_EQ(json["a"]["query"]["heightfield"], "builtin:isotropic");

    const auto above = run_cli({"compare", a, b, "--fail-above", "0.0999"});
    EXPECT_EQ(above.exit_code, 1) << above.output;
    EXPECT_NE(above.output.find("layer 0.5 um: relative L2 0.1"), std::string::npos) << above.output;
    EXPECT_NE(above.output.find("exceeds --fail-above 0.0999"), std::string::npos) << above.output;
}

TEST_F(CompareCommand, MismatchedImagesAreRefusedInOneLineWithStatusTwoAndNothingWritten) {
    const std::string a = lobe("a.exr");
    const std::string small = lobe("small.exr", {}, "16");
    const std::string ndf = directory.file("ndf.exr");
    ASSERT_EQ(run_cli({"--quiet", "ndf", "builtin:isotropic", "--res", "32", "-o", ndf}).exit_code, 0);
    const int files = testing::count_entries(directory.path());
    for (const auto& [b, expected] : {std::pair{small, std::string("different sizes")},
                                      std::pair{ndf, std::string("different quantities")},
                                      std::pair{directory.file("missing.exr"), std::string("missing.exr")}}) {
        const auto result = run_cli({"compare", a, b, "--diff", directory.file("d.png"), "--json", directory.file("r.json")});
        EXPECT_EQ(result.exit_code, 2) << result.output;
        EXPECT_NE(result.output.find(expected), std::string::npos) << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_EQ(testing::count_entries(directory.path()), files);
    }
    const auto bad_path = run_cli({"compare", a, a, "--diff", directory.file("no/such/d.png")});
    EXPECT_EQ(bad_path.exit_code, 2) << bad_path.output;
    EXPECT_NE(bad_path.output.find("--diff"), std::string::npos) << bad_path.output;
}

TEST_F(CompareCommand, BadOutputsFailInOneLineBeforeReadingTheInputs) {
    // The inputs do not even exist: the outputs are judged first.
    const std::string a = directory.file("a.exr"), b = directory.file("b.exr");
    const std::vector<std::pair<std::vector<std::string>, std::string>> requests = {
        {{"--diff", directory.file("d.jpg")}, "--diff '" + directory.file("d.jpg") + "': the file name must end in .png"},
        {{"--diff", directory.file("no/d.png")}, "does not exist"},
        {{"--json", directory.file("r.csv")}, "must end in .json"},
        {{"--json", directory.file("no/r.json")}, "does not exist"},
        {{"--fail-above", "-1"}, "--fail-above: must be a number 0 or more, got '-1'"},
        {{"--threads", "nan"}, "--threads: must be a number 0 or more, got 'nan'"},
    };
    for (const auto& [extra, message] : requests) {
        std::vector<std::string> arguments = {"compare", a, b};
        arguments.insert(arguments.end(), extra.begin(), extra.end());
        const auto result = run_cli(arguments);
        EXPECT_EQ(result.exit_code, 2) << message;
        EXPECT_NE(result.output.find(message), std::string::npos) << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_EQ(testing::count_entries(directory.path()), 0) << message;
    }
}

TEST_F(CompareCommand, DiffPictureShowsBothInputsAndTheirDifference) {
    const std::string a = lobe("a.exr", {"--method", "gabor"});
    const std::string picture = directory.file("diff.png");
    const auto result = run_cli({"compare", a, lobe("b.exr"), "--diff", picture});
    EXPECT_EQ(result.exit_code, 0) << result.output;
    auto input = OIIO::ImageInput::open(picture);
    ASSERT_TRUE(input);
    EXPECT_GE(input->spec().width, 3 * panel_size(32));  // A | B | A - B side by side
    EXPECT_GE(input->spec().height, panel_size(32));
    EXPECT_LT(input->spec().height, 2 * panel_size(32));  // one row
}

}  // namespace
}  // namespace glintscope
