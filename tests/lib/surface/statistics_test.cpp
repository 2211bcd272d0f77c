// Surface statistics against analytic fields: a sampled sinusoid has known Sq, Sa, slopes and
// autocorrelation; missing points must not bias any of them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr float kMissing = std::numeric_limits<float>::quiet_NaN();

// H = A sin(2π x/Λ) + offset on a grid holding whole periods along x; constant along y.
Heightfield sinusoid_along_x(int rows, int cols, double texel, double amplitude, double period, double offset = 0.0) {
    Heightfield field = make_heightfield(rows, cols, texel);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
            field.at(r, c) = static_cast<float>(offset + amplitude * std::sin(2.0 * kPi * sample_position(field, r, c).x / period));
    return field;
}

// The lag at which cos(2π lag/Λ) first falls to 1/e, interpolated linearly between whole texels
// exactly as the statistics do (the sampled ACF of a sinusoid over whole periods is exactly cos).
double interpolated_cosine_crossing(double period_texels, double texel) {
    const auto rho = [&](int lag) { return std::cos(2.0 * kPi * lag / period_texels); };
    int lag = 1;
    while (rho(lag) > kCorrelationThreshold) ++lag;
    const double fraction = (rho(lag - 1) - kCorrelationThreshold) / (rho(lag - 1) - rho(lag));
    return (lag - 1 + fraction) * texel;
}

TEST(Statistics, SinusoidMatchesAnalyticMoments) {
    const double amplitude = 0.3;
    const double texel = 0.5;
    const double period = 32.0;  // 64 samples per period, 4 periods across
    const Heightfield field = sinusoid_along_x(16, 256, texel, amplitude, period, 2.0);
    const SurfaceStatistics stats = compute_statistics(field);
    EXPECT_NEAR(stats.mean_um, 2.0, 1e-6);
    EXPECT_NEAR(stats.sq_um, amplitude / std::sqrt(2.0), 1e-6);
    // The midpoint rule for |sin| has an O(1/N²) error with 64 samples per period.
    EXPECT_NEAR(stats.sa_um, 2.0 * amplitude / kPi, 2e-4);
    // Samples sit half a texel off the crest: max = 2 + A cos(π/64).
    EXPECT_NEAR(stats.max_um, 2.0 + amplitude * std::cos(kPi / 64.0), 1e-6);
    EXPECT_NEAR(stats.min_um, 2.0 - amplitude * std::cos(kPi / 64.0), 1e-6);
    // Central differences of A sin(kx): A cos(kx)·sin(k dx)/dx, whose rms is A sin(k dx)/(√2 dx).
    const double k = 2.0 * kPi / period;
    EXPECT_NEAR(stats.rms_slope_x, amplitude * std::sin(k * texel) / (std::sqrt(2.0) * texel), 1e-6);
    EXPECT_NEAR(stats.rms_slope_y, 0.0, 1e-9);
    EXPECT_EQ(stats.missing_count, 0u);
    EXPECT_DOUBLE_EQ(stats.correlation_threshold, kCorrelationThreshold);
}

TEST(Statistics, SinusoidAutocorrelationIsACosine) {
    const double texel = 0.5;
    const Heightfield field = sinusoid_along_x(16, 256, texel, 0.3, 32.0);
    const SurfaceStatistics stats = compute_statistics(field);
    EXPECT_NEAR(stats.correlation_length_x_um, interpolated_cosine_crossing(64.0, texel), 1e-9);
    // Along y the field never decorrelates: NaN, with the autocorrelation still 1 at half the field.
    EXPECT_TRUE(std::isnan(stats.correlation_length_y_um));
    EXPECT_NEAR(stats.autocorrelation_at_half_y, 1.0, 1e-9);
    EXPECT_TRUE(std::isnan(stats.autocorrelation_at_half_x));  // x did decay
}

TEST(Statistics, RowsRunAlongMinusY) {
    // H = A sin(2π y/Λ): the y slope and correlation carry it, not x.
    const double amplitude = 0.2;
    const double period = 16.0;
    Heightfield field = make_heightfield(128, 8, 1.0);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c)
            field.at(r, c) = static_cast<float>(amplitude * std::sin(2.0 * kPi * sample_position(field, r, c).y / period));
    const SurfaceStatistics stats = compute_statistics(field);
    EXPECT_NEAR(stats.rms_slope_y, amplitude * std::sin(2.0 * kPi / period) / std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(stats.rms_slope_x, 0.0, 1e-9);
    EXPECT_NEAR(stats.correlation_length_y_um, interpolated_cosine_crossing(period, 1.0), 1e-9);
    EXPECT_TRUE(std::isnan(stats.correlation_length_x_um));
}

TEST(Statistics, MomentsIgnoreMissingPoints) {
    Heightfield field = make_heightfield(10, 10, 1.0, 3.0f);
    for (int c = 0; c < 10; ++c) field.at(4, c) = kMissing;
    field.at(7, 7) = 5.0f;
    const SurfaceStatistics stats = compute_statistics(field);
    EXPECT_EQ(stats.missing_count, 10u);
    EXPECT_DOUBLE_EQ(stats.missing_fraction, 0.1);
    const double mean = (89.0 * 3.0 + 5.0) / 90.0;
    EXPECT_NEAR(stats.mean_um, mean, 1e-12);
    EXPECT_NEAR(stats.sq_um, std::sqrt((89.0 * (3.0 - mean) * (3.0 - mean) + (5.0 - mean) * (5.0 - mean)) / 90.0), 1e-12);
    EXPECT_DOUBLE_EQ(stats.max_um, 5.0);
    EXPECT_DOUBLE_EQ(stats.min_um, 3.0);
}

TEST(Statistics, SlopesSkipPointsWithAMissingNeighbour) {
    const double amplitude = 0.3;
    const double period = 16.0;
    Heightfield field = sinusoid_along_x(4, 64, 1.0, amplitude, period);
    const int hole = 10;
    for (int r = 0; r < field.rows; ++r) field.at(r, hole) = kMissing;
    // Expected: the rms of the exact central differences over the columns whose two neighbours
    // are valid (all but hole − 1 and hole + 1).
    const double k = 2.0 * kPi / period;
    double sum = 0.0;
    int count = 0;
    for (int c = 0; c < field.cols; ++c) {
        if (c == hole - 1 || c == hole + 1) continue;
        const double slope = amplitude * std::cos(k * (c + 0.5)) * std::sin(k);
        sum += slope * slope;
        ++count;
    }
    const SurfaceStatistics stats = compute_statistics(field);
    EXPECT_NEAR(stats.rms_slope_x, std::sqrt(sum / count), 1e-6);
}

TEST(Statistics, MaskedAutocorrelationIsUnbiasedByMissingPoints) {
    // A field with a cosine ACF along x and y. Knocking out 30 % of the points at random would
    // pull a zero-filled autocorrelation down by the factor 0.7 at every non-zero lag, and its
    // 1/e crossing far inwards; the masked estimator must not move.
    const int n = 256;
    const double period = 64.0;
    Heightfield field = make_heightfield(n, n, 1.0);
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const Point2 s = sample_position(field, r, c);
            field.at(r, c) = static_cast<float>(std::sin(2.0 * kPi * s.x / period) + std::cos(2.0 * kPi * s.y / period));
        }
    const SurfaceStatistics full = compute_statistics(field);
    std::uint64_t state = 12345;
    std::size_t removed = 0;
    for (float& h : field.heights_um) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        if ((state >> 33) % 10 < 3) {
            h = kMissing;
            ++removed;
        }
    }
    const SurfaceStatistics masked = compute_statistics(field);
    EXPECT_EQ(masked.missing_count, removed);
    EXPECT_NEAR(masked.correlation_length_x_um / full.correlation_length_x_um, 1.0, 0.01);
    EXPECT_NEAR(masked.correlation_length_y_um / full.correlation_length_y_um, 1.0, 0.01);
    EXPECT_NEAR(masked.sq_um / full.sq_um, 1.0, 0.01);
    EXPECT_NEAR(masked.rms_slope_x / full.rms_slope_x, 1.0, 0.02);
}

// The normalised autocorrelation at `lag` along x (along_x) or y, summed directly over the pairs
// of valid points `lag` apart: inside the field, or wrapping around on a periodic one.
double direct_autocorrelation(const Heightfield& field, double mean, int lag, bool along_x, bool wrap) {
    const auto product_sum = [&](int l, double& pairs) {
        double sum = 0.0;
        pairs = 0.0;
        for (int r = 0; r < field.rows; ++r)
            for (int c = 0; c < field.cols; ++c) {
                int r2 = along_x ? r : r + l, c2 = along_x ? c + l : c;
                if (wrap) {
                    r2 %= field.rows;
                    c2 %= field.cols;
                }
                if (r2 >= field.rows || c2 >= field.cols) continue;
                const float a = field.at(r, c), b = field.at(r2, c2);
                if (std::isnan(a) || std::isnan(b)) continue;
                sum += (a - mean) * (b - mean);
                pairs += 1.0;
            }
        return sum / pairs;
    };
    double pairs = 0.0;
    return product_sum(lag, pairs) / product_sum(0, pairs);
}

// Its first fall to 1/e, interpolated between lags as the statistics do (µm).
double direct_crossing(const Heightfield& field, double mean, bool along_x, bool wrap) {
    const double texel = along_x ? field.dx_um() : field.dy_um();
    double previous = 1.0;
    for (int lag = 1;; ++lag) {
        const double rho = direct_autocorrelation(field, mean, lag, along_x, wrap);
        if (rho <= kCorrelationThreshold)
            return (lag - 1 + (previous - kCorrelationThreshold) / (previous - rho)) * texel;
        previous = rho;
    }
}

TEST(Statistics, NonPeriodicAutocorrelationSumsThePairsInsideTheField) {
    // A scan's borders are edges: each lag averages the products of the valid pairs inside the
    // field (ISO 25178-2's integral over the definition area), as the areal parameters' Sal does;
    // wrapping around would pair the opposite edges. Heights: noise averaged over 5 x 3 samples
    // (a triangular autocorrelation crossing 1/e between lags) on a slope, with drop-outs.
    Heightfield field = make_heightfield(40, 64, 0.5);
    field.periodic = false;
    set_spacing(field, 0.5, 0.8);
    std::uint64_t state = 99;
    std::vector<double> noise(field.size());
    for (double& value : noise) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        value = double(state >> 11) / double(1ULL << 53) - 0.5;
    }
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            double sum = 0.0;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 5; ++j) sum += noise[((r + i) % field.rows) * field.cols + (c + j) % field.cols];
            field.at(r, c) = static_cast<float>(sum + 0.01 * c);
        }
    for (std::size_t i = 0; i < field.size(); i += 23) field.heights_um[i] = kMissing;
    const SurfaceStatistics stats = compute_statistics(field);
    for (const bool along_x : {true, false}) {
        const double inside = direct_crossing(field, stats.mean_um, along_x, /*wrap=*/false);
        const double wrapped = direct_crossing(field, stats.mean_um, along_x, /*wrap=*/true);
        const double measured = along_x ? stats.correlation_length_x_um : stats.correlation_length_y_um;
        EXPECT_NEAR(measured, inside, 1e-5 * inside) << (along_x ? "x" : "y");
        EXPECT_GT(std::fabs(wrapped - inside), 1e-3 * inside) << "the wrapped estimator differs";
    }
    field.periodic = true;  // the same heights as one tile: circular
    const SurfaceStatistics tile = compute_statistics(field);
    EXPECT_NEAR(tile.correlation_length_x_um, direct_crossing(field, tile.mean_um, true, true), 1e-5);
    EXPECT_NEAR(tile.correlation_length_y_um, direct_crossing(field, tile.mean_um, false, true), 1e-5);
}

TEST(Statistics, SameBitsOnAnyThreadCount) {
    Heightfield field = make_heightfield(300, 170, 0.7);
    for (std::size_t i = 0; i < field.size(); ++i)
        field.heights_um[i] = i % 97 == 0 ? kMissing : static_cast<float>(std::sin(0.37 * i) + 0.01 * (i % 13));
    const SurfaceStatistics one = with_threads(1, [&] { return compute_statistics(field); });
    const SurfaceStatistics two = with_threads(2, [&] { return compute_statistics(field); });
    EXPECT_EQ(std::memcmp(&one, &two, sizeof one), 0);
}

TEST(Statistics, RejectsEmptyOrAllMissingFields) {
    EXPECT_THROW(compute_statistics(Heightfield{}), Error);
    EXPECT_THROW(compute_statistics(make_heightfield(4, 4, 1.0, kMissing)), Error);
}

}  // namespace
}  // namespace glintscope
