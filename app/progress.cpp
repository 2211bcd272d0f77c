#include "progress.hpp"

#include <cstdio>
#include <unistd.h>

namespace glintscope::cli {

Verbosity& verbosity() {
    static Verbosity settings;
    return settings;
}

ProgressBar::ProgressBar(std::string title)
    : title_(std::move(title)), shown_(!verbosity().quiet && ::isatty(STDERR_FILENO)), start_(std::chrono::steady_clock::now()) {}

ProgressBar::~ProgressBar() {
    if (drawn_) std::fputc('\n', stderr);
}

void ProgressBar::restart() { start_ = std::chrono::steady_clock::now(); }

void ProgressBar::update(std::size_t done, std::size_t total, const std::string& what) {
    if (!shown_ || total == 0) return;
    constexpr int kWidth = 24;
    const double fraction = double(done) / double(total);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(filled, '=');
    bar.resize(kWidth, ' ');
    char eta[32] = "";
    if (done > 0 && done < total) std::snprintf(eta, sizeof eta, "  ETA %.0f s", elapsed / fraction - elapsed);
    // \r and clear-to-end redraw the line; the text is cut so that it stays on one line.
    std::fprintf(stderr, "\r\033[K%s [%s] %zu/%zu%s  %.60s", title_.c_str(), bar.c_str(), done, total, eta, what.c_str());
    std::fflush(stderr);
    drawn_ = true;
}

}  // namespace glintscope::cli
