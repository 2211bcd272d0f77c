// Interrupting a run leaves no file behind and ends the process with the signal.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <thread>

#include "cli_runner.hpp"

namespace glintscope::testing {
namespace {

namespace fs = std::filesystem;

// Whether `directory` holds a temporary directory with a file in it: the output is being written.
bool writing(const fs::path& directory) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(directory, ec))
        if (entry.is_directory() && !fs::is_empty(entry.path(), ec)) return true;
    return false;
}

TEST(Interrupt, SigintWhileWritingLeavesTheDirectoryClean) {
    const TemporaryDirectory directory;
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        if (::chdir(directory.path().c_str()) != 0) _exit(126);
        ::execl(GLINTSCOPE_EXE, GLINTSCOPE_EXE, "generate", "isotropic", "--size", "2048", "-o", "out.x3p",
                static_cast<char*>(nullptr));
        _exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (!writing(directory.path()) && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    const bool caught = writing(directory.path());
    ::kill(child, SIGINT);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(caught) << "the temporary never appeared";
    ASSERT_TRUE(WIFSIGNALED(status)) << "exit status " << WEXITSTATUS(status);
    EXPECT_EQ(WTERMSIG(status), SIGINT);
    EXPECT_EQ(count_entries(directory.path()), 0);
}

}  // namespace
}  // namespace glintscope::testing
