#pragma once
// Runs the built glintscope executable, as a user would, for the command-line tests.
#include <filesystem>
#include <string>
#include <vector>

namespace glintscope::testing {

struct CliResult {
    int exit_code = -1;
    std::string output;  // stdout and stderr together
};

CliResult run_cli(const std::vector<std::string>& arguments);

// A shell command line (stdout and stderr together), and the executable's path, shell-quoted,
// for command lines that drive it through other tools (GNU parallel, ulimit, ...).
CliResult run_shell(std::string command);
std::string executable();

// text as one word of a shell command line, whatever it holds.
std::string shell_quote(const std::string& text);

// A fresh directory under the system temporary directory, removed when the object dies.
class TemporaryDirectory {
public:
    TemporaryDirectory();
    ~TemporaryDirectory();
    TemporaryDirectory(const TemporaryDirectory&) = delete;
    TemporaryDirectory& operator=(const TemporaryDirectory&) = delete;
    std::filesystem::path path() const { return path_; }
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    std::filesystem::path path_;
};

// The number of entries in a directory (to check that a failed command left no file behind).
int count_entries(const std::filesystem::path& directory);

// ../shared beside the checkout, where the conventions and test data live.
std::string shared_path(const std::string& relative);

}  // namespace glintscope::testing
