#pragma once
// A progress line on stderr for long work: "[=====     ] 12/40  ETA 8 s  gabor, centre ...",
// redrawn in place, only when stderr is a terminal and --quiet was not given.
#include <chrono>
#include <cstddef>
#include <string>

namespace glintscope::cli {

// Set from the main command's --quiet / --verbose.
struct Verbosity {
    bool quiet = false;
    bool verbose = false;
};
Verbosity& verbosity();

class ProgressBar {
public:
    explicit ProgressBar(std::string title);
    ~ProgressBar();  // ends the line if one was drawn
    ProgressBar(const ProgressBar&) = delete;
    ProgressBar& operator=(const ProgressBar&) = delete;

    void update(std::size_t done, std::size_t total, const std::string& what);
    void restart();  // a new stage of the work: the ETA counts from now

private:
    std::string title_;
    bool shown_ = false;
    bool drawn_ = false;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace glintscope::cli
