// The chirp-z transform equals the direct sum Σ_n x_n e^{−i2π n h (v0 + m Δv)} at arbitrary
// (non-FFT) frequencies, including decreasing ones, and so does its folded path on commensurate
// grids (|h Δv| = 1/F).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "numerics/chirp_z.hpp"

namespace glintscope {
namespace {

std::vector<Complex> direct_sum(const std::vector<Complex>& input, int outputs, double step, double first,
                                double delta) {
    std::vector<Complex> result(outputs);
    for (int m = 0; m < outputs; ++m)
        for (std::size_t n = 0; n < input.size(); ++n)
            result[m] += input[n] * std::polar(1.0, -2.0 * std::numbers::pi * double(n) * step * (first + m * delta));
    return result;
}

void expect_matches_direct_sum(int inputs, int outputs, double step, double first, double delta,
                               int expected_fold = 0) {
    std::vector<Complex> input(inputs);
    for (int n = 0; n < inputs; ++n) input[n] = {std::sin(0.7 * n + 0.3), std::cos(1.3 * n * n + 0.1)};
    const ChirpZ transform(inputs, outputs, step, first, delta);
    EXPECT_EQ(transform.fold_size(), expected_fold);
    auto workspace = transform.make_workspace();
    std::vector<Complex> output(outputs);
    transform.transform(input.data(), output.data(), workspace.get());
    const std::vector<Complex> expected = direct_sum(input, outputs, step, first, delta);
    double scale = 0.0;
    for (const Complex& value : expected) scale = std::max(scale, std::abs(value));
    for (int m = 0; m < outputs; ++m) EXPECT_NEAR(std::abs(output[m] - expected[m]) / scale, 0.0, 1e-12) << m;
}

TEST(ChirpZ, MatchesDirectSumOnIncreasingGrid) { expect_matches_direct_sum(301, 128, 0.137, -3.1, 0.0421); }

TEST(ChirpZ, MatchesDirectSumOnDecreasingGridWithMoreOutputsThanInputs) {
    expect_matches_direct_sum(57, 200, 0.41, 2.3, -0.0173);
}

// F = 1/(h Δv) = 120 bins: 301 inputs fold about 2.5 times onto them, and the 256 outputs wrap
// round the 120 bins twice; Δv < 0 takes the opposite sign of the DFT.
TEST(ChirpZ, FoldedPathMatchesDirectSumOnCommensurateGrids) {
    const double step = 0.137;
    expect_matches_direct_sum(301, 256, step, -3.1, 1.0 / (120 * step), 120);
    expect_matches_direct_sum(301, 256, step, 2.3, -1.0 / (120 * step), 120);
    expect_matches_direct_sum(57, 40, step, 0.7, 1.0 / (64 * step), 64);  // fewer inputs than bins
}

// A bin count that is not a fast FFT size, or not smaller than the convolution, keeps chirp-z.
TEST(ChirpZ, FoldsOnlyOntoFastSizesSmallerThanTheConvolution) {
    const double step = 0.137;
    expect_matches_direct_sum(301, 128, step, -3.1, 1.0 / (127 * step));         // 127 is prime
    expect_matches_direct_sum(57, 40, step, 0.7, 1.0 / (1000 * step));           // 1000 > 96 = P
    expect_matches_direct_sum(301, 128, step, -3.1, 1.0 / (120.001 * step));     // not commensurate
    EXPECT_EQ(commensurate_fold(0.25, 0.5), 8);
    EXPECT_EQ(commensurate_fold(0.25, -0.5), 8);
    EXPECT_EQ(commensurate_fold(0.3, 0.5), 0);
}

TEST(ChirpZ, SmoothSizesHaveOnlySmallPrimeFactors) {
    EXPECT_EQ(smooth_fft_size(1), 1);
    EXPECT_EQ(smooth_fft_size(11), 12);
    EXPECT_EQ(smooth_fft_size(121), 125);
    EXPECT_EQ(smooth_fft_size(1031), 1050);
}

}  // namespace
}  // namespace glintscope
