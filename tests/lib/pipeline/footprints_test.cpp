// The pipeline averages over the query's footprints: the mean of the single-footprint images.
#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "glintscope/generate/generate.hpp"
#include "glintscope/lobe/compare.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "mean_lobe.hpp"

namespace glintscope {
namespace {

LobeQuery brushed_ndf_query() {
    LobeQuery query = make_query({{"heightfield", "builtin:brushed"}, {"quantity", "ndf"}, {"res", "64"}});
    return query;
}

TEST(Footprints, AGridOfThreeIsTheMeanOfItsNineFootprintsAndDiffersFromOne) {
    LobeQuery query = brushed_ndf_query();
    query.footprints = parse_footprint_set("grid:3");
    const LobeImage averaged = compute_lobe("pndf", query);
    const std::vector<Point2> centres = footprint_centres(*query.field, query.footprint, query.footprints);
    ASSERT_EQ(centres.size(), 9u);
    const LobeImage expected = testing::mean_of_single_lobes("pndf", query, centres);
    for (std::size_t i = 0; i < expected.values.size(); ++i)
        EXPECT_NEAR(averaged.values[i], expected.values[i], 1e-6 * (1.0 + expected.values[i]));
    EXPECT_EQ(averaged.metadata.at("footprints.count"), "9");
    EXPECT_EQ(averaged.metadata.at("query.footprints"), "grid:3");

    LobeQuery single = brushed_ndf_query();
    const LobeImage one = compute_lobe("pndf", single);
    EXPECT_GT(compare_lobes(averaged, one).at(0).relative_l2, 0.05);
}

// One footprint reports its work pass by pass (core/parallel.hpp: ProgressScope): within a pass
// the chunks done rise to its total, a new pass starts from its first chunk, and the last report
// is the end of the last pass; the image is the one computed without progress.
TEST(Footprints, ASingleFootprintReportsEachPassRisingToItsEnd) {
    Heightfield field = make_heightfield(128, 128, 0.5);
    for (int r = 0; r < 128; ++r)
        for (int c = 0; c < 128; ++c) field.at(r, c) = float(0.3 * std::sin(0.3 * c) * std::cos(0.2 * r));
    for (const auto& [method, quantity, shape] : {std::tuple{"pndf", Quantity::ndf, FootprintShape::gaussian},
                                                  std::tuple{"pndf", Quantity::ndf, FootprintShape::whole},
                                                  std::tuple{"fft", Quantity::brdf, FootprintShape::gaussian}}) {
        LobeQuery query;
        set_heightfield(query, field);
        query.quantity = quantity;
        query.resolution = 64;
        query.footprint.shape = shape;
        query.footprint.centre_um = field.centre_um();
        query.footprint.sigma_um = 8.0;
        std::vector<std::pair<std::size_t, std::size_t>> calls;
        const LobeRun run = run_lobe(method, query, [&](std::size_t done, std::size_t total) { calls.emplace_back(done, total); });
        const std::string name = std::string(method) + (shape == FootprintShape::whole ? ", whole" : "");
        ASSERT_GE(calls.size(), 2u) << name;
        std::size_t passes = 1;
        for (std::size_t k = 1; k < calls.size(); ++k) {
            if (calls[k].first > calls[k - 1].first) {
                EXPECT_EQ(calls[k].second, calls[k - 1].second) << name << ": one pass, one total";
                continue;
            }
            EXPECT_EQ(calls[k - 1].first, calls[k - 1].second) << name << ": a pass ends at its total";
            ++passes;
        }
        EXPECT_EQ(calls.back().first, calls.back().second) << name;
        EXPECT_GE(passes, 2u) << name;  // the methods' several loops
        RecordProperty(name + " passes", int(passes));
        EXPECT_EQ(run.image.values, compute_lobe(method, query).values) << name;
    }
}

TEST(Footprints, RandomCentresOfAWaveLobeAverageTheirLobes) {
    LobeQuery query;
    Heightfield field = make_heightfield(64, 64, 1.0);
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 64; ++c) field.at(r, c) = float(0.3 * std::sin(0.5 * c) + 0.2 * std::cos(0.4 * r));
    field.periodic = true;
    set_heightfield(query, field);
    query.footprint.sigma_um = 4.0;
    query.resolution = 24;
    query.footprints = parse_footprint_set("3");
    const LobeImage mean = compute_lobe("fft", query);
    const LobeImage expected =
        testing::mean_of_single_lobes("fft", query, footprint_centres(*query.field, query.footprint, query.footprints));
    for (std::size_t i = 0; i < expected.values.size(); ++i)
        EXPECT_NEAR(mean.values[i], expected.values[i], 1e-6 * (1.0 + expected.values[i]));
    EXPECT_EQ(mean.metadata.at("footprints.count"), "3");
}

TEST(Footprints, TheRecordedQueryRerunsTheAverageExactly) {
    LobeQuery query = brushed_ndf_query();
    query.footprints = parse_footprint_set("grid:2");
    const LobeImage first = compute_lobe("pndf", query);
    const LobeImage again = compute_lobe("pndf", make_query(query_text_from_metadata(first.metadata)));
    EXPECT_EQ(again.values, first.values);
}

}  // namespace
}  // namespace glintscope
