// The cluster path for real: GNU parallel runs two shards, a final run assembles the figure,
// which is the same, bit for bit, as one run's.
#include <gtest/gtest.h>

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
    EXPECT_NE(result.output.find("bad.toml:5:"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("sigma_c"), std::string::npos) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 1);  // nothing but the manifest
}

}  // namespace
}  // namespace glintscope
