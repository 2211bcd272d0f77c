// Methods on rectangular texels: one analytic surface sampled at 1 × 1 µm and at 1 × 2 µm gives the
// same FFT lobe and the same P-NDF (both read dx ≠ dy natively), and gabor, which wants square
// texels, gets the field resampled by the pipeline and says so in the image's metadata.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "glintscope/lobe/query.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/surface/square_texels.hpp"
#include "relative_l2.hpp"
#include "sampled_field.hpp"

namespace glintscope {
namespace {

using testing::relative_l2;

constexpr double kPi = 3.14159265358979323846;

// Periodic on 48 × 48 µm, slopes up to ~0.1: waves of 24 µm along x and 48 µm along y, and a
// diagonal one; at dy = 2 µm still 12 samples per period of the shortest wave along y.
Heightfield sampled(double dy_um) {
    return testing::sampled_field(static_cast<int>(std::lround(48.0 / dy_um)), 48, 1.0, dy_um, [](double x, double y) {
        return 0.3 * std::sin(2 * kPi * x / 24.0) * std::cos(2 * kPi * y / 48.0) +
               0.1 * std::cos(2 * kPi * (x / 48.0 + y / 24.0));
    });
}

LobeQuery query_for(Heightfield field, Quantity quantity) {
    LobeQuery query;
    set_heightfield(query, std::move(field));
    query.quantity = quantity;
    query.footprint.centre_um = {24.0, 24.0};
    query.footprint.sigma_um = 6.0;
    if (quantity == Quantity::ndf) query.footprint.shape = FootprintShape::whole;
    query.omega_i = {0.0, 0.0, 1.0};
    query.wavelengths_um = {0.5};
    query.resolution = 32;
    query.supersample = 1;
    return query;
}

std::vector<double> values(const LobeImage& image) { return {image.values.begin(), image.values.end()}; }

TEST(RectangularTexels, FftLobeOfTheOneByTwoSamplingMatchesTheSquareOne) {
    const LobeImage square = compute_lobe("fft", query_for(sampled(1.0), Quantity::brdf));
    const LobeImage rectangular = compute_lobe("fft", query_for(sampled(2.0), Quantity::brdf));
    // The two interpolants differ by ~1e-3 µm in height (Catmull–Rom at 12 samples per period):
    // a phase of 4π·1e-3/0.5 ≈ 0.03 rad, a few percent of the lobe.
    EXPECT_LT(relative_l2(values(rectangular), values(square)), 0.05);
    EXPECT_EQ(rectangular.metadata.count("heightfield.square_texels"), 0u);  // read as it is
    EXPECT_EQ(rectangular.metadata.at("heightfield.texel_y_um"), "2");
}

TEST(RectangularTexels, PndfOfTheOneByTwoSamplingMatchesTheSquareOne) {
    const LobeImage square = compute_lobe("pndf", query_for(sampled(1.0), Quantity::ndf));
    const LobeImage rectangular = compute_lobe("pndf", query_for(sampled(2.0), Quantity::ndf));
    EXPECT_LT(relative_l2(values(rectangular), values(square)), 0.05);
    double sum = 0.0;  // both normalised: Σ D (2/N)² = 1 (conventions.md)
    for (float v : rectangular.values) sum += v * (2.0 / 32) * (2.0 / 32);
    EXPECT_NEAR(sum, 1.0, 1e-3);
    EXPECT_EQ(rectangular.metadata.count("heightfield.square_texels"), 0u);
}

TEST(RectangularTexels, GaborResamplesToSquareTexelsAndRecordsIt) {
    const LobeImage lobe = compute_lobe("gabor", query_for(sampled(2.0), Quantity::brdf));
    const std::string& record = lobe.metadata.at("heightfield.square_texels");
    EXPECT_NE(record.find("rows 24 -> 48"), std::string::npos) << record;
    EXPECT_NE(record.find("largest round-trip change"), std::string::npos) << record;
    EXPECT_NE(record.find("method gabor needs square texels"), std::string::npos) << record;
    EXPECT_EQ(lobe.metadata.at("heightfield.texel_um"), "1");
    EXPECT_EQ(lobe.metadata.count("heightfield.texel_y_um"), 0u);
    // What gabor computed is exactly the lobe of the field made square beforehand.
    Heightfield squared = sampled(2.0);
    make_texels_square(squared, std::size_t{1} << 20, "test");
    const LobeImage expected = compute_lobe("gabor", query_for(squared, Quantity::brdf));
    EXPECT_EQ(lobe.values, expected.values);
    // And close to the lobe of the square sampling of the same surface.
    const LobeImage square = compute_lobe("gabor", query_for(sampled(1.0), Quantity::brdf));
    EXPECT_LT(relative_l2(values(lobe), values(square)), 0.05);
    const LobePlan plan = plan_lobe("gabor", query_for(sampled(2.0), Quantity::brdf));
    ASSERT_FALSE(plan.notes.empty());
    EXPECT_NE(plan.notes.front().find("gabor needs square texels"), std::string::npos);
}

}  // namespace
}  // namespace glintscope
