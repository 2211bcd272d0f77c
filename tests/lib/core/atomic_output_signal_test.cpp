// An interrupted write leaves neither the output nor its temporary behind, and the process still
// ends with the signal's status.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>

#include "glintscope/core/atomic_output.hpp"

namespace glintscope {
namespace {

namespace fs = std::filesystem;

// A child starts writing `directory`/out.txt, reports once its temporary holds data, and hangs
// until `signal_number` arrives; returns the child's wait status.
int interrupted_write_status(const fs::path& directory, int signal_number) {
    int ready[2];
    if (::pipe(ready) != 0) return -1;
    const pid_t child = ::fork();
    if (child < 0) return -1;
    if (child == 0) {
        ::close(ready[0]);
        write_atomically((directory / "out.txt").string(), [&](const std::string& temporary) {
            std::ofstream(temporary) << "partial";
            const char byte = 1;
            if (::write(ready[1], &byte, 1) != 1) _exit(4);
            for (;;) ::pause();
        });
        _exit(5);
    }
    ::close(ready[1]);
    char byte = 0;
    const bool started = ::read(ready[0], &byte, 1) == 1;
    ::close(ready[0]);
    ::kill(child, started ? signal_number : SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    return status;
}

TEST(AtomicOutputSignal, InterruptRemovesTheTemporaryAndEndsWithTheSignal) {
    for (int signal_number : {SIGINT, SIGTERM}) {
        const fs::path directory =
            fs::temp_directory_path() / ("glintscope-signal-" + std::to_string(::getpid()) + "-" +
                                         std::to_string(signal_number));
        fs::create_directories(directory);
        const int status = interrupted_write_status(directory, signal_number);
        ASSERT_TRUE(WIFSIGNALED(status)) << "status " << status;
        EXPECT_EQ(WTERMSIG(status), signal_number);
        EXPECT_TRUE(fs::is_empty(directory)) << "left behind: " << fs::directory_iterator(directory)->path();
        fs::remove_all(directory);
    }
}

}  // namespace
}  // namespace glintscope
