// fill_missing on degenerate data: one valid point, or valid points on one line.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/prepare/prepare.hpp"

namespace glintscope {
namespace {

constexpr float kMissing = std::numeric_limits<float>::quiet_NaN();

TEST(FillDegenerate, OneValidPointFillsTheFieldWithItsHeightAtOnce) {
    for (FillMethod method : {FillMethod::biharmonic, FillMethod::harmonic})
        for (Tiling tiling : {Tiling::none, Tiling::periodic}) {
            Heightfield field = make_heightfield(512, 512, 1.0, kMissing);
            field.at(100, 321) = 0.375f;
            const auto start = std::chrono::steady_clock::now();
            const FillReport report = fill_missing(field, method, tiling);
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            // A generous bound a loaded CI cannot trip: the conjugate-gradient route took minutes here
            // (the speed itself is bench/prepare_bench.cpp's FillOneValidPoint).
            EXPECT_LT(seconds, 20.0);
            EXPECT_EQ(report.filled_points, field.size() - 1);
            for (float h : field.heights_um) ASSERT_EQ(h, 0.375f);
        }
}

TEST(FillDegenerate, CollinearPointsAreRefusedForTheNonPeriodicThinPlate) {
    Heightfield field = make_heightfield(64, 64, 1.0, kMissing);
    for (int k = 0; k < 5; ++k) field.at(10 + 3 * k, 7 + 2 * k) = float(k);  // a diagonal line
    Heightfield copy = field;
    try {
        fill_missing(copy, FillMethod::biharmonic, Tiling::none);
        FAIL() << "collinear points accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("the 5 valid points lie on one line"), std::string::npos) << e.what();
    }
    // The membrane is determined: its fill stays within the valid heights (maximum principle).
    fill_missing(field, FillMethod::harmonic, Tiling::none);
    for (float h : field.heights_um) {
        ASSERT_GE(h, -1e-5f);
        ASSERT_LE(h, 4.0f + 1e-5f);
    }
}

TEST(FillDegenerate, ThreePointsOffALineAreFilledWithTheirPlane) {
    // Three non-collinear points determine a plane, which the thin plate carries exactly.
    Heightfield field = make_heightfield(48, 48, 1.0, kMissing);
    const auto plane = [](int r, int c) { return 0.5f + 0.25f * float(c) - 0.125f * float(r); };
    for (auto [r, c] : {std::pair{5, 5}, std::pair{5, 40}, std::pair{40, 20}}) field.at(r, c) = plane(r, c);
    fill_missing(field, FillMethod::biharmonic, Tiling::none);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) ASSERT_NEAR(field.at(r, c), plane(r, c), 1e-3) << r << "," << c;
}

}  // namespace
}  // namespace glintscope
