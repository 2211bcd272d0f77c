// A ProgressScope reports the loops its thread starts pass by pass (core/parallel.hpp): each
// pass's chunks done rise to its total; loops nested in a body are not passes.
#include <gtest/gtest.h>

#include <tuple>
#include <vector>

#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

TEST(ProgressScope, ReportsEachOuterLoopAsAPassWhoseChunksRiseToItsTotal) {
    const ThreadScope two(2);
    std::vector<std::tuple<std::size_t, std::size_t, std::size_t>> reports;  // pass, done, total
    {
        const ProgressScope scope([&](std::size_t pass, std::size_t done, std::size_t total) {
            reports.emplace_back(pass, done, total);  // serialised by the scope
        });
        parallel_for(10, 1, [](std::size_t, std::size_t) {});
        // A second loop of 30 chunks, each starting a nested loop of 5 that is no pass.
        parallel_for(30, 1, [](std::size_t, std::size_t) { parallel_for(5, 1, [](std::size_t, std::size_t) {}); });
        parallel_for(3000, 1, [](std::size_t, std::size_t) {});  // reported per thousandth, not per chunk
    }
    const std::vector<std::size_t> totals = {10, 30, 3000};
    std::size_t k = 0;
    for (std::size_t pass = 1; pass <= 3; ++pass) {
        std::size_t previous = 0, count = 0;
        for (; k < reports.size() && std::get<0>(reports[k]) == pass; ++k, ++count) {
            EXPECT_EQ(std::get<2>(reports[k]), totals[pass - 1]);
            EXPECT_GT(std::get<1>(reports[k]), previous) << "pass " << pass;
            previous = std::get<1>(reports[k]);
        }
        EXPECT_EQ(previous, totals[pass - 1]) << "pass " << pass << " ends at its total";
        EXPECT_EQ(count, pass == 3 ? 1000u : totals[pass - 1]) << "pass " << pass;
    }
    EXPECT_EQ(k, reports.size());  // three passes, no more
    // Outside the scope nothing is reported.
    parallel_for(10, 1, [](std::size_t, std::size_t) {});
    EXPECT_EQ(k, reports.size());
}

}  // namespace
}  // namespace glintscope
