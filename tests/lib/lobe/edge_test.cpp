// Footprints on non-periodic (measured) heightfields: refused where they cross the border,
// with the valid range of centres; accepted on periodic fields.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/prepare/prepare.hpp"
#include "lobe_queries.hpp"

namespace glintscope {
namespace {

// A 64 µm square field; σ_c = 4 µm reaches 13 µm, so centres 13 … 51 µm fit.
LobeQuery query_at(Point2 centre, bool periodic) {
    Heightfield field = make_heightfield(64, 64, 1.0);
    field.periodic = periodic;
    LobeQuery query;
    set_heightfield(query, std::move(field));
    query.footprint.sigma_um = 4.0;
    query.footprint.centre_um = centre;
    query.resolution = 8;
    return query;
}

using testing::compute_error;

TEST(FootprintEdge, NonPeriodicFieldRefusesACrossingFootprintWithTheValidRange) {
    const std::string message = compute_error("fft", query_at({2.0, 2.0}, false));
    EXPECT_NE(message.find("crosses the edge of the non-periodic heightfield (64 um x 64 um)"), std::string::npos)
        << message;
    EXPECT_NE(message.find("centres must lie in x 13 um to 51 um, y 13 um to 51 um"), std::string::npos) << message;
    // Both ends of the stated range are accepted, a step beyond either is not.
    for (const Point2 c : {Point2{13.0, 13.0}, Point2{51.0, 51.0}, Point2{13.0, 51.0}})
        EXPECT_NO_THROW(check_footprint_inside(query_at(c, false)));
    for (const Point2 c : {Point2{12.99, 32.0}, Point2{32.0, 51.01}})
        EXPECT_THROW(check_footprint_inside(query_at(c, false)), Error);
}

TEST(FootprintEdge, PeriodicFieldAndTheWholeFieldFootprintAreAccepted) {
    EXPECT_EQ(compute_error("fft", query_at({2.0, 2.0}, true)), "");
    LobeQuery whole = query_at({2.0, 2.0}, false);
    whole.footprint.shape = FootprintShape::whole;
    EXPECT_NO_THROW(check_footprint_inside(whole));
}

TEST(FootprintEdge, BoxSupportIsHalfItsSideAndATooLargeFootprintFitsNowhere) {
    LobeQuery box = query_at({10.0, 32.0}, false);
    box.footprint.shape = FootprintShape::box;
    box.footprint.size_um = 20.0;
    EXPECT_NO_THROW(check_footprint_inside(box));
    box.footprint.centre_um.x = 9.5;
    EXPECT_THROW(check_footprint_inside(box), Error);
    LobeQuery wide = query_at({32.0, 32.0}, false);
    wide.footprint.sigma_um = 10.0;  // 65 µm across
    try {
        check_footprint_inside(wide);
        FAIL() << "a footprint wider than the field was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no centre fits"), std::string::npos) << e.what();
    }
}

TEST(FootprintEdge, ARectangularBoxReachesHalfOfEachSide) {
    LobeQuery box = query_at({32.0, 10.0}, false);  // the 64 µm square field
    box.footprint.shape = FootprintShape::box;
    box.footprint.size_um = 60.0;    // reaches 30 µm along x: fits at x = 32
    box.footprint.size_y_um = 20.0;  // reaches 10 µm along y: fits at y = 10, not below
    EXPECT_NO_THROW(check_footprint_inside(box));
    box.footprint.centre_um.y = 9.5;
    try {
        check_footprint_inside(box);
        FAIL() << "a box crossing the lower edge was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("y 10 um to 54 um"), std::string::npos) << e.what();
    }
}

TEST(FootprintEdge, PreparationEndsPeriodicityOnlyWhereTheFieldStopsTiling) {
    Heightfield field = make_heightfield(16, 16, 1.0);
    ASSERT_TRUE(field.periodic);
    fill_missing(field);
    orient(field, {true, false, 90});
    remove_form(field, 0);
    EXPECT_TRUE(field.periodic);
    const CropReport report = crop_samples(field, 0, 0, 8, 16);
    EXPECT_FALSE(field.periodic);
    EXPECT_TRUE(report.ended_periodicity);
    EXPECT_NE(describe(report).find("no longer periodic"), std::string::npos);
}

}  // namespace
}  // namespace glintscope

namespace glintscope {
namespace {

TEST(FootprintEdge, FftTruncationLosesTheWindowMassCutByTheEdge) {
    // Flat mirror: by Parseval the albedo is proportional to ∫|w|² over what is sampled, so cutting
    // the window at x = 0 scales it by the kept mass [erf((W − c)/σ_c) + erf(c/σ_c)]/2. Centres a
    // fraction of a grid step apart meet the edge between samples or on one (x = 4 µm: a sample
    // at x = 0); each sample counts the part of its cell inside, so the ratio does not jump.
    for (const double cx : {4.0, 4.1, 4.2, 4.3}) {
        LobeQuery truncated = query_at({cx, 32.0}, false);
        truncated.resolution = 64;
        truncated.supersample = 8;
        truncated.method_options["edge"] = "truncate";
        LobeQuery whole = query_at({cx, 32.0}, true);
        whole.resolution = 64;
        whole.supersample = 8;
        const LobeImage cut = compute_lobe("fft", truncated);
        const double kept = 0.5 * (std::erf((64.0 - cx) / 4.0) + std::erf(cx / 4.0)) * std::erf(32.0 / 4.0);
        EXPECT_NEAR(std::stod(cut.metadata.at("fft.edge_energy_kept")), kept, 1e-6);
        // Measured +0.36%, +0.53%, +1.21%, +0.79% at the four centres (+2.6% to +1.05% while a
        // sample counted whole or not at all): the cut's spectral tails fold a little energy back.
        const double ratio = disk_sum(cut) / disk_sum(compute_lobe("fft", whole));
        EXPECT_NEAR(ratio, kept, 0.015 * kept) << cx;
    }
}

TEST(FootprintEdge, TruncationIsRefusedByMethodsWithoutIt) {
    LobeQuery query = query_at({4.0, 32.0}, false);
    query.method_options["edge"] = "truncate";
    const std::string message = compute_error("gabor", query);
    EXPECT_NE(message.find("has no option 'edge'"), std::string::npos) << message;
}

}  // namespace
}  // namespace glintscope
