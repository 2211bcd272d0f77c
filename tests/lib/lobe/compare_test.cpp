#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>

#include "glintscope/lobe/compare.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"

namespace glintscope {
namespace {

// A Gaussian spot centred on pixel (row, col), zero outside the disk.
LobeImage spot(int n, int row, int col, double scale) {
    LobeImage image = make_lobe_image(n, {0.5});
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
            if (inside_unit_disk(disk_pixel_point(r, c, n)))
                image.at(0, r, c) = float(scale * std::exp(-((r - row) * (r - row) + (c - col) * (c - col)) / 8.0));
    return image;
}

TEST(CompareLobes, ScalingByOnePointOneIsTenPercentAndMovesNoPeak) {
    const LobeImage reference = spot(32, 16, 16, 1.0);
    const LayerComparison same = compare_lobes(reference, reference).at(0);
    EXPECT_EQ(same.relative_l2, 0.0);
    EXPECT_EQ(same.max_abs_difference, 0.0);
    const LayerComparison scaled = compare_lobes(spot(32, 16, 16, 1.1), reference).at(0);
    EXPECT_NEAR(scaled.relative_l2, 0.1, 1e-6);
    EXPECT_NEAR(scaled.test_sum / scaled.reference_sum, 1.1, 1e-6);
    EXPECT_NEAR(scaled.max_abs_difference, 0.1, 1e-6);  // at the peak, where the value is 1
    EXPECT_EQ(scaled.max_row, 16);
    EXPECT_EQ(scaled.max_col, 16);
    EXPECT_EQ(scaled.peak_offset_pixels, 0.0);
    EXPECT_NEAR(scaled.peak_relative_error, 0.1, 1e-6);
    EXPECT_NEAR(scaled.log_rms_error, std::log10(1.1), 1e-6);  // the same ratio at every pixel
    EXPECT_NEAR(scaled.energy_ratio(), 1.1, 1e-6);
}

TEST(CompareLobes, SumsAreDiskIntegralsAndPeakOffsetsAreInPixels) {
    const LobeImage reference = spot(32, 16, 16, 1.0);
    const LayerComparison moved = compare_lobes(spot(32, 19, 12, 1.0), reference).at(0);
    EXPECT_DOUBLE_EQ(moved.peak_offset_pixels, 5.0);
    // Σ value (2/N)² of a Gaussian of variance 4 px² (well inside the disk): 2π·4·(2/32)².
    EXPECT_NEAR(moved.reference_sum, 2.0 * pi * 4.0 * std::pow(2.0 / 32, 2), 1e-3);
}

TEST(CompareLobes, RefusesImagesOfDifferentShapeOrQuantity) {
    EXPECT_THROW(compare_lobes(spot(16, 8, 8, 1.0), spot(32, 16, 16, 1.0)), Error);
    LobeImage ndf = spot(32, 16, 16, 1.0);
    ndf.quantity = Quantity::ndf;
    EXPECT_THROW(compare_lobes(ndf, spot(32, 16, 16, 1.0)), Error);
}

TEST(CompareLobes, OneLayerComparesAsTheImageDoes) {
    LobeImage reference = make_lobe_image(32, {0.45, 0.55});
    LobeImage test = reference;
    const LobeImage first = spot(32, 16, 16, 1.0), second = spot(32, 12, 20, 2.0);
    const std::size_t pixels = 32 * 32;
    std::copy(first.values.begin(), first.values.end(), reference.values.begin());
    std::copy(second.values.begin(), second.values.end(), reference.values.begin() + pixels);
    std::copy(second.values.begin(), second.values.end(), test.values.begin());
    std::copy(first.values.begin(), first.values.end(), test.values.begin() + pixels);
    const std::vector<LayerComparison> whole = compare_lobes(test, reference);
    const std::span<const float> t(test.values), r(reference.values);
    for (std::size_t layer = 0; layer < 2; ++layer) {
        const LayerComparison one = compare_layer(t.subspan(layer * pixels, pixels), r.subspan(layer * pixels, pixels), 32);
        EXPECT_EQ(one.relative_l2, whole[layer].relative_l2);
        EXPECT_EQ(one.energy_ratio(), whole[layer].energy_ratio());
        EXPECT_EQ(one.peak_offset_pixels, std::hypot(4.0, 4.0));
        EXPECT_EQ(one.log_rms_error, whole[layer].log_rms_error);
        EXPECT_EQ(one.wavelength_um, 0.0);
        EXPECT_EQ(whole[layer].wavelength_um, reference.wavelengths_um[layer]);
    }
    EXPECT_THROW(compare_layer(t.subspan(0, pixels - 1), r.subspan(0, pixels), 32), Error);
}

TEST(CompareLobes, DifferenceIsTestMinusReferenceAndNamesBothMethods) {
    LobeImage test = spot(16, 8, 8, 1.5), reference = spot(16, 8, 8, 1.0);
    test.metadata["method"] = "gabor";
    reference.metadata["method"] = "fft";
    const LobeImage difference = difference_image(test, reference);
    for (std::size_t i = 0; i < difference.values.size(); ++i)
        EXPECT_EQ(difference.values[i], test.values[i] - reference.values[i]);
    EXPECT_EQ(difference.metadata.at("method"), "gabor - fft");
    EXPECT_TRUE(difference.metadata.contains("difference"));  // drawn signed although every value is ≥ 0
    EXPECT_THROW(difference_image(spot(16, 8, 8, 1.0), spot(32, 8, 8, 1.0)), Error);
}

}  // namespace
}  // namespace glintscope
