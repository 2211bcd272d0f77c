// parallel_for when the system refuses threads: it must finish on the threads it has, with the
// same result, instead of ending in std::terminate.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <vector>

#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

// Σ k² for k < count, summed per chunk and then in chunk order.
double chunked_sum_of_squares(std::size_t count) {
    std::vector<double> partial((count + 99) / 100, 0.0);
    parallel_for(count, 100, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) partial[begin / 100] += double(k) * double(k);
    });
    double sum = 0.0;
    for (double p : partial) sum += p;
    return sum;
}

// The virtual memory in use now, from /proc/self/statm (pages).
long virtual_bytes() {
    long pages = 0;
    std::FILE* statm = std::fopen("/proc/self/statm", "r");
    if (statm) {
        if (std::fscanf(statm, "%ld", &pages) != 1) pages = 0;
        std::fclose(statm);
    }
    return pages * sysconf(_SC_PAGESIZE);
}

TEST(ParallelLimits, RefusedThreadsFallBackToFewerWithTheSameResult) {
    const std::size_t count = 100000;
    const double expected = chunked_sum_of_squares(count);  // closed form: (n−1)n(2n−1)/6, exact here
    ASSERT_EQ(expected, double(count - 1) * double(count) * double(2 * count - 1) / 6.0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        // 2 MB above the current use: a thread's 8 MB stack cannot be mapped, so every
        // std::thread the call asks for fails.
        const rlimit limit{static_cast<rlim_t>(virtual_bytes() + (2l << 20)), RLIM_INFINITY};
        if (setrlimit(RLIMIT_AS, &limit) != 0) _exit(3);
        const ThreadScope threads(64);
        _exit(chunked_sum_of_squares(count) == expected ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status)) << "child ended by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 0);
}

}  // namespace
}  // namespace glintscope
