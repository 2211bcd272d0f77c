// Commands that would need more memory than their stated limits fail at once, with the estimate
// in one line and no output file.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "cli_runner.hpp"

namespace glintscope::testing {
namespace {

TEST(ResourceLimitsCommand, GenerateAndResampleBeyondTheirLimitsStateTheMemory) {
    const TemporaryDirectory directory;
    const CliResult generate = run_cli({"generate", "isotropic", "--size", "40000", "-o", directory.file("g.exr")});
    EXPECT_NE(generate.exit_code, 0);
    EXPECT_NE(generate.output.find("it would need about 12.8 GB"), std::string::npos) << generate.output;
    const CliResult resample =
        run_cli({"convert", "builtin:grating", directory.file("c.exr"), "--resample", "1nm"});
    EXPECT_NE(resample.exit_code, 0);
    EXPECT_NE(resample.output.find("GB)"), std::string::npos) << resample.output;
    const CliResult lobe = run_cli({"lobe", "builtin:grating", "--res", "100000", "-o", directory.file("l.exr")});
    EXPECT_NE(lobe.exit_code, 0);
    EXPECT_NE(lobe.output.find("would need 40 GB"), std::string::npos) << lobe.output;
    EXPECT_EQ(count_entries(directory.path()), 0);
}

}  // namespace
}  // namespace glintscope::testing

namespace glintscope::testing {
namespace {

TEST(ResourceLimitsCommand, ThreadsTheSystemRefusesAreDoneWithout) {
    // 1000 threads need 8 GB of stack address space; under a 1.5 GB limit most cannot start.
    const TemporaryDirectory directory;
    const CliResult result = run_shell("ulimit -v 1500000 && " + executable() +
                                       " --threads 1000 lobe builtin:grating --method fft --res 32 -o " +
                                       directory.file("lobe.exr"));
    EXPECT_EQ(result.exit_code, 0) << result.output;
    // The same lobe as with one thread: the summary line names its peak and albedo.
    const CliResult one = run_shell(executable() + " --threads 1 lobe builtin:grating --method fft --res 32 -o " +
                                    directory.file("one.exr"));
    ASSERT_EQ(one.exit_code, 0) << one.output;
    const auto summary = [](const std::string& output) {
        std::istringstream lines(output);
        for (std::string line; std::getline(lines, line);)
            if (line.find("albedo ") != std::string::npos) return line;
        return std::string();
    };
    EXPECT_FALSE(summary(one.output).empty()) << one.output;
    EXPECT_EQ(summary(result.output), summary(one.output));
}

}  // namespace
}  // namespace glintscope::testing
