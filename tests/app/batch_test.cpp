// The cluster path for real: GNU parallel runs two shards, a final run assembles the figure,
// which is the same, bit for bit, as one run's.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "cli_runner.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

std::string read_bytes(const std::string& path) {
    std::ifstream stream(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
}

void write_manifest(const TemporaryDirectory& directory) {
    std::ofstream(directory.file("m.toml")) << R"(title = "Shards"
output = "figure.png"
[defaults]
heightfield = "builtin:grating"
res = 24
sigma_c = "4um"
[[row]]
label = "normal"
[[row]]
label = "oblique"
incident = [25, 90]
[[column]]
label = "fft"
[[column]]
label = "gabor"
method = "gabor"
kernels_per_texel = 1
)";
}

TEST(BatchCommand, GnuParallelShardsAssembleTheFigureOfOneRun) {
    TemporaryDirectory single, sharded;
    write_manifest(single);
    write_manifest(sharded);
    const auto one = testing::run_cli({"batch", single.file("m.toml")});
    ASSERT_EQ(one.exit_code, 0) << one.output;
    EXPECT_NE(one.output.find("4 panels computed, 0 up to date"), std::string::npos) << one.output;

    const auto shards = testing::run_shell("parallel --will-cite " + testing::executable() + " batch '" +
                                           sharded.file("m.toml") + "' --shard {}/2 ::: 1 2");
    ASSERT_EQ(shards.exit_code, 0) << shards.output;
    const auto final_run = testing::run_cli({"batch", sharded.file("m.toml")});
    ASSERT_EQ(final_run.exit_code, 0) << final_run.output;
    EXPECT_NE(final_run.output.find("0 panels computed, 4 up to date"), std::string::npos) << final_run.output;
    EXPECT_EQ(read_bytes(sharded.file("figure.png")), read_bytes(single.file("figure.png")));
}

TEST(BatchCommand, AMalformedManifestComputesNothing) {
    TemporaryDirectory directory;
    std::ofstream(directory.file("bad.toml")) << "output = \"f.png\"\n[[row]]\nlabel = \"a\"\nheightfield = \"builtin:grating\"\n"
                                                 "[[column]]\nlabel = \"b\"\nsigma_c = \"ten\"\n";
    const auto result = testing::run_cli({"batch", directory.file("bad.toml")});
    EXPECT_NE(result.exit_code, 0);
    EXPECT_NE(result.output.find("bad.toml:7:"), std::string::npos) << result.output;  // where sigma_c is written
    EXPECT_NE(result.output.find("sigma_c"), std::string::npos) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 1);  // nothing but the manifest
}

TEST(BatchCommand, AFigureIntoAMissingFolderFailsBeforeComputingAnyPanel) {
    TemporaryDirectory directory;
    // 4096² FFT panels would take minutes: the output's folder is checked first.
    std::ofstream(directory.file("m.toml")) << "output = \"no/such/f.png\"\n[defaults]\nres = 4096\n[[row]]\nlabel = \"a\"\n"
                                               "heightfield = \"builtin:grating\"\n[[column]]\nlabel = \"b\"\n";
    const auto result = testing::run_cli({"batch", directory.file("m.toml")});
    EXPECT_NE(result.exit_code, 0);
    EXPECT_NE(result.output.find("output '" + directory.file("no/such/f.png") + "': directory"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("does not exist"), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 1);  // nothing but the manifest
}

// Three metals at three wavelengths (fft, R-OHS, 20 degrees, res 128): no false hot spot on the
// rim (the pipeline supersamples the panels as `lobe` does), and R-OHS's excess energy over what
// each metal's Fresnel factor lets through is said per panel, naming the model's term.
TEST(BatchCommand, MaterialPanelsPeakInsideTheLobeAndEnergyBeyondFresnelIsWarnedPerPanel) {
    TemporaryDirectory directory;
    std::ofstream(directory.file("m.toml")) << R"(title = "Materials"
output = "m.png"
[defaults]
heightfield = "builtin:isotropic"
method = "fft"
res = 128
incident = [20, 0]
[[row]]
label = "Ag"
material = "Ag"
[[row]]
label = "Au"
material = "Au"
[[row]]
label = "Cu"
material = "Cu"
[[column]]
label = "0.45"
lambda = "0.45um"
[[column]]
label = "0.55"
lambda = "0.55um"
[[column]]
label = "0.65"
lambda = "0.65um"
)";
    const auto run = testing::run_cli({"batch", directory.file("m.toml")});
    ASSERT_EQ(run.exit_code, 0) << run.output;
    for (const char* metal : {"Ag", "Au", "Cu"})
        for (const char* lambda : {"0.45", "0.55", "0.65"}) {
            const std::string panel = std::string(metal) + " / " + lambda;
            EXPECT_NE(run.output.find("warning: " + panel + ": albedo"), std::string::npos) << panel << "\n" << run.output;
        }
    EXPECT_NE(run.output.find("xi1"), std::string::npos) << run.output;
    for (int row = 1; row <= 3; ++row)
        for (int column = 1; column <= 3; ++column) {
            const std::string json = read_bytes(directory.file("m.panels/r" + std::to_string(row) + "-c" +
                                                               std::to_string(column) + ".json"));
            const auto at = json.find("\"peak_theta_deg\":");
            ASSERT_NE(at, std::string::npos) << json;
            EXPECT_LT(std::stod(json.substr(at + 17)), 80.0) << "r" << row << "-c" << column;
        }
}

}  // namespace
}  // namespace glintscope
