// Threads are the caller's (core/parallel.hpp): a ThreadScope sets the count of the loops its
// own thread starts, which their workers inherit, and no other thread's.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>

#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

// The distinct threads that run the chunks of a parallel_for of 64 chunks, each chunk sleeping
// long enough for every worker to take one.
std::size_t threads_used() {
    std::mutex mutex;
    std::set<std::thread::id> ids;
    parallel_for(64, 1, [&](std::size_t, std::size_t) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        const std::lock_guard lock(mutex);
        ids.insert(std::this_thread::get_id());
    });
    return ids.size();
}

TEST(ThreadScope, SetsTheCallingThreadsLoopsOnlyAndWorkersInheritIt) {
    const ThreadScope three(3);
    EXPECT_EQ(thread_count(), 3);
    std::size_t other_used = 0;
    int other_count = 0;
    std::thread([&] {
        const ThreadScope one(1);
        other_count = thread_count();
        other_used = threads_used();
    }).join();
    EXPECT_EQ(other_count, 1);
    EXPECT_EQ(other_used, 1u);  // the other thread's loop ran on that thread alone
    EXPECT_EQ(thread_count(), 3);
    {
        const ThreadScope two(2);
        EXPECT_EQ(threads_used(), 2u);
    }
    EXPECT_EQ(threads_used(), 3u);
    std::atomic<int> not_inherited{0};
    parallel_for(16, 1, [&](std::size_t, std::size_t) {
        if (thread_count() != 3) ++not_inherited;
    });
    EXPECT_EQ(not_inherited.load(), 0);
}

}  // namespace
}  // namespace glintscope
