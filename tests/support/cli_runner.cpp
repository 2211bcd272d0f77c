#include "cli_runner.hpp"

#include <array>
#include <atomic>
#include <cstdio>
#include <random>
#include <sys/wait.h>
#include <unistd.h>

namespace glintscope::testing {

std::string shell_quote(const std::string& text) {
    std::string quoted = "'";
    for (char ch : text) {
        if (ch == '\'')
            quoted += "'\\''";
        else
            quoted += ch;
    }
    return quoted + "'";
}

CliResult run_cli(const std::vector<std::string>& arguments) {
    std::string command = shell_quote(GLINTSCOPE_EXE);
    for (const auto& argument : arguments) {
        command += ' ';
        command += shell_quote(argument);
    }
    return run_shell(command);
}

std::string executable() { return shell_quote(GLINTSCOPE_EXE); }

CliResult run_shell(std::string command) {
    command += " 2>&1";
    CliResult result;
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe) return result;
    std::array<char, 4096> buffer{};
    while (std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) result.output.append(buffer.data(), n);
    const int status = ::pclose(pipe);
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return result;
}

TemporaryDirectory::TemporaryDirectory() {
    static std::atomic<unsigned> counter{0};
    std::random_device entropy;
    path_ = std::filesystem::temp_directory_path() /
            ("glintscope-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + "-" +
             std::to_string(entropy()));
    std::filesystem::create_directories(path_);
}

TemporaryDirectory::~TemporaryDirectory() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

int count_entries(const std::filesystem::path& directory) {
    int n = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(directory)) ++n;
    return n;
}

std::string shared_path(const std::string& relative) {
    return (std::filesystem::path(GLINTSCOPE_SHARED_DIR) / relative).string();
}

}  // namespace glintscope::testing
