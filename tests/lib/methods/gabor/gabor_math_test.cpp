// The Gabor sums' own exp(−x) and e^{−i2πt} (gabor_math.hpp) against libm, over the ranges the sums
// use, in scalars and in both vector widths (the lanes must give the scalar's bits).
#pragma GCC diagnostic ignored "-Wpsabi"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "methods/gabor/gabor_math.hpp"

namespace glintscope {
namespace {

using gabor_math::Double4;
using gabor_math::Double8;

// Relative error of exp_neg over [0, 25] (the kernel cut's range, kernel truncation ≤ 5σ), densely
// sampled, is within the bound its comment states; at 0 it is exactly 1.
TEST(GaborMath, ExpNegWithinItsStatedErrorOverTheCutsRange) {
    double worst = 0.0;
    for (int i = 0; i <= 250000; ++i) {
        const double x = 25.0 * i / 250000.0;
        worst = std::max(worst, std::fabs(gabor_math::exp_neg(x) / std::exp(-x) - 1.0));
    }
    EXPECT_LT(worst, 1e-11);
    EXPECT_EQ(gabor_math::exp_neg(0.0), 1.0);
}

// cos(2πt) and sin(2πt) to 1e-13 absolute for turns from small to the 10⁴ that phases in µm over
// wavelengths reach, including the reduction's edges at half turns.
TEST(GaborMath, CosSinTurnsMatchLibmOverManyTurns) {
    double worst = 0.0;
    for (int i = -200000; i <= 200000; ++i) {
        const double t = i * 0.0123456789 + (i % 7) * 1e-3;
        double c = 0.0;
        double s = 0.0;
        gabor_math::cos_sin_turns(t, c, s);
        const double angle = 2.0 * std::numbers::pi * (t - std::nearbyint(t));  // libm's own reduction is exact
        worst = std::max({worst, std::fabs(c - std::cos(angle)), std::fabs(s - std::sin(angle))});
    }
    for (const double t : {0.5, -0.5, 0.25, -0.25, 0.125, 1e-9, 0.0}) {
        double c = 0.0;
        double s = 0.0;
        gabor_math::cos_sin_turns(t, c, s);
        worst = std::max({worst, std::fabs(c - std::cos(2.0 * std::numbers::pi * t)),
                          std::fabs(s - std::sin(2.0 * std::numbers::pi * t))});
    }
    EXPECT_LT(worst, 1e-13);
}

template <typename V>
void expect_lanes_equal_scalars() {
    constexpr std::size_t n = gabor_math::kLanes<V>;
    V x{};
    V t{};
    for (std::size_t lane = 0; lane < n; ++lane) {
        x[lane] = 3.1 * double(lane) + 0.37;
        t[lane] = 17.3 * double(lane) - 41.9;
    }
    const V e = gabor_math::exp_neg(x);
    V c{};
    V s{};
    gabor_math::cos_sin_turns(t, c, s);
    for (std::size_t lane = 0; lane < n; ++lane) {
        double scalar_c = 0.0;
        double scalar_s = 0.0;
        gabor_math::cos_sin_turns(t[lane], scalar_c, scalar_s);
        EXPECT_EQ(e[lane], gabor_math::exp_neg(x[lane])) << "lane " << lane;
        EXPECT_EQ(c[lane], scalar_c) << "lane " << lane;
        EXPECT_EQ(s[lane], scalar_s) << "lane " << lane;
    }
}

TEST(GaborMath, VectorLanesGiveTheScalarsBits) {
    expect_lanes_equal_scalars<Double4>();
    expect_lanes_equal_scalars<Double8>();
}

// The single-precision exp and cos/sin of the spectral sums (gabor_kernels.cpp): exp(−x) within
// 2e-7 relative over [0, 25], exactly 1 at 0; cos and sin of 2πt within 6e-7 over the fractions
// and the added Im q/2π those sums pass (a few turns either way), half turns included. Together
// with the products around them, the 2^−20 per term that gabor_kernels.hpp states.
TEST(GaborMath, SinglePrecisionFunctionsWithinTheirStatedErrors) {
    using gabor_math::Single8;
    double worst_exp = 0.0;
    double worst_phasor = 0.0;
    constexpr int kSteps = 250000;
    for (int first = 0; first <= kSteps; first += 8) {
        Single8 x{};
        Single8 t{};
        for (int lane = 0; lane < 8; ++lane) {
            x[lane] = static_cast<float>(25.0 * std::min(first + lane, kSteps) / kSteps);
            t[lane] = static_cast<float>(-8.0 + 16.0 * std::min(first + lane, kSteps) / kSteps);
        }
        const Single8 e = gabor_math::exp_neg_single(x);
        Single8 c{};
        Single8 s{};
        gabor_math::cos_sin_turns_single(t, c, s);
        for (int lane = 0; lane < 8; ++lane) {
            worst_exp = std::max(worst_exp, std::fabs(e[lane] / std::exp(-double(x[lane])) - 1.0));
            const double angle = 2.0 * std::numbers::pi * double(t[lane]);
            worst_phasor = std::max({worst_phasor, std::fabs(c[lane] - std::cos(angle)), std::fabs(s[lane] - std::sin(angle))});
        }
    }
    const Single8 edges{0.5f, -0.5f, 0.25f, -0.25f, 0.125f, 1e-9f, 0.0f, 2.5f};
    Single8 c{};
    Single8 s{};
    gabor_math::cos_sin_turns_single(edges, c, s);
    for (int lane = 0; lane < 8; ++lane) {
        const double angle = 2.0 * std::numbers::pi * double(edges[lane]);
        worst_phasor = std::max({worst_phasor, std::fabs(c[lane] - std::cos(angle)), std::fabs(s[lane] - std::sin(angle))});
    }
    EXPECT_LT(worst_exp, 2e-7);
    EXPECT_LT(worst_phasor, 6e-7);
    EXPECT_EQ(gabor_math::exp_neg_single(Single8{} + 0.0f)[0], 1.0f);
}

}  // namespace
}  // namespace glintscope
