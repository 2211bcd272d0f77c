// A ProgressScope counts the chunks of the loops its thread starts (core/parallel.hpp): its
// reports rise, stay below 1 until finish(), and ignore loops nested in a body.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

TEST(ProgressScope, ReportsTheChunksDoneOfTheOuterLoopsRisingToOne) {
    const ThreadScope two(2);
    std::vector<double> reports;
    {
        ProgressScope scope([&](double fraction) { reports.push_back(fraction); });  // serialised by the scope
        parallel_for(10, 1, [](std::size_t, std::size_t) {});
        ASSERT_FALSE(reports.empty());
        EXPECT_EQ(reports.back(), 0.999);  // every started chunk done, but not finished
        // A second loop of 30 chunks, each starting a nested loop of 5 that does not count.
        parallel_for(30, 1, [](std::size_t, std::size_t) { parallel_for(5, 1, [](std::size_t, std::size_t) {}); });
        scope.finish();
        scope.finish();  // once
    }
    ASSERT_GE(reports.size(), 10u);
    for (std::size_t k = 1; k < reports.size(); ++k) EXPECT_GT(reports[k], reports[k - 1]) << k;
    EXPECT_EQ(reports.back(), 1.0);
    EXPECT_EQ(reports.front(), 0.1);  // one chunk of the first ten
    EXPECT_EQ(std::count(reports.begin(), reports.end(), 1.0), 1);
    // Outside the scope nothing is reported.
    const std::size_t before = reports.size();
    parallel_for(10, 1, [](std::size_t, std::size_t) {});
    EXPECT_EQ(reports.size(), before);
}

}  // namespace
}  // namespace glintscope
