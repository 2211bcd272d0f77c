// The glints command on bad input: one line naming the problem, a non-zero exit, no file written.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "cli_runner.hpp"

namespace glintscope {
namespace {

using testing::run_cli;
using testing::TemporaryDirectory;

TEST(GlintsCommand, BadInputFailsInOneLineAndWritesNothing) {
    TemporaryDirectory directory;
    const std::string out = directory.file("map.png");
    const std::vector<std::pair<std::vector<std::string>, std::string>> requests = {
        {{"glints", "--outgoing", "10,0", "--size", "0", "-o", out}, "size must be 1 to 4096"},
        {{"glints", "--outgoing", "95,0", "-o", out}, "theta below 90"},
        {{"glints", "--outgoing", "10,0", "--spacing", "-1um", "-o", out}, "spacing must be above 0"},
        {{"glints", "--outgoing", "10,0", "--footprint", "whole", "-o", out}, "needs a finite footprint"},
        {{"glints", "--outgoing", "10,0", "--kernels-per-texel", "2", "-o", out}, "has no option 'kernels_per_texel'"},
        {{"glints", "--outgoing", "10,0", "--flakes", "nan", "-o", out}, "flakes"},
        {{"glints", "--outgoing", "10,0", "-o", directory.file("map.exr")}, "must end in .png"},
        {{"glints", "--outgoing", "10,0", "-o", directory.file("no/such/map.png")}, "does not exist"},
    };
    for (const auto& [arguments, message] : requests) {
        const int before = testing::count_entries(directory.path());
        const auto result = run_cli(arguments);
        EXPECT_NE(result.exit_code, 0) << message;
        EXPECT_NE(result.output.find(message), std::string::npos) << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_EQ(testing::count_entries(directory.path()), before) << message;
    }
}

}  // namespace
}  // namespace glintscope
