#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_runner.hpp"

namespace glintscope {
namespace {

using testing::run_cli;
using testing::TemporaryDirectory;

TEST(ValidateCommand, ReportsAndFailAboveFlipsTheExitCode) {
    TemporaryDirectory directory;
    const std::string report = directory.file("report.json");
    const std::vector<std::string> common = {"validate", "builtin:isotropic", "--res", "64", "--supersample", "2",
                                             "--kernels-per-texel", "2", "--report", report};
    auto passing = common;
    passing.insert(passing.end(), {"--fail-above", "0.2"});
    const auto ok = run_cli(passing);
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    std::ifstream stream(report);
    const nlohmann::json json = nlohmann::json::parse(stream);
    const double error = json["rows"][0]["relative_l2"].get<double>();
    EXPECT_GT(error, 0.0);
    EXPECT_LT(error, 0.06);  // the K = 2 bound of docs/gabor.md on this surface's centre

    auto failing = common;
    failing.insert(failing.end(), {"--fail-above", std::to_string(error / 2)});
    const auto fails = run_cli(failing);
    EXPECT_NE(fails.exit_code, 0);
    EXPECT_NE(fails.output.find("exceeds --fail-above"), std::string::npos) << fails.output;
}

// --footprints grid:2 means 2 x 2 footprints, a row and a picture each; --images makes its folder.
TEST(ValidateCommand, AGridOfTwoValidatesFourFootprintsIntoANewImagesFolder) {
    TemporaryDirectory directory;
    const std::string images = directory.file("new/pairs");
    const auto result = run_cli({"validate", "builtin:isotropic", "--res", "32", "--kernels-per-texel", "1", "--footprints",
                                 "grid:2", "--report", directory.file("r.json"), "--images", images});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    std::ifstream stream(directory.file("r.json"));
    EXPECT_EQ(nlohmann::json::parse(stream)["rows"].size(), 4u);
    for (int k = 1; k <= 4; ++k) EXPECT_TRUE(std::filesystem::exists(images + "/pair-" + std::to_string(k) + ".png")) << k;
    EXPECT_FALSE(std::filesystem::exists(images + "/pair-5.png"));
}

TEST(ValidateCommand, AMissingReportDirectoryFailsBeforeComputing) {
    const auto result = run_cli({"validate", "builtin:isotropic", "--report", "/no/such/dir/r.json"});
    EXPECT_NE(result.exit_code, 0);
    EXPECT_NE(result.output.find("does not exist"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace glintscope
