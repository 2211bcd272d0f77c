// ISO 16610-61 Gaussian filters against their transmission exp(−π (αλ/Λ)²), α = √(ln 2/π):
// a sinusoid of wavelength Λ = λ passes the S-filter at 50% and the L-filter at 50%, shorter
// and longer ones by the closed form; constants and planes pass a non-periodic S-filter
// unchanged up to its border, and missing points stay missing without biasing their neighbours.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "glintscope/core/error.hpp"
#include "glintscope/prepare/prepare.hpp"

namespace glintscope {
namespace {

constexpr double kPi = std::numbers::pi;

double transmission(double nesting, double wavelength) {
    return std::exp(-std::log(2.0) * nesting * nesting / (wavelength * wavelength));  // exp(−π (αλ/Λ)²)
}

// A periodic field holding `periods` whole periods of a sinusoid along x, amplitude 1.
Heightfield sinusoid(int periods, double texel = 0.5) {
    Heightfield field = make_heightfield(8, 256, texel);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c)
            field.at(r, c) = static_cast<float>(std::sin(2.0 * kPi * periods * sample_position(field, r, c).x / field.width_um()));
    return field;
}

double amplitude(const Heightfield& field) {
    double squares = 0.0;
    for (float h : field.heights_um) squares += double(h) * h;
    return std::sqrt(2.0 * squares / double(field.size()));
}

TEST(GaussianFilter, SinusoidsPassByTheTransmissionOfTheStandard) {
    const double wavelength = 256 * 0.5 / 4;  // 32 µm
    for (const double nesting : {wavelength, 0.25 * wavelength, 2.0 * wavelength}) {
        Heightfield smooth = sinusoid(4);
        apply_s_filter(smooth, nesting);
        EXPECT_NEAR(amplitude(smooth), transmission(nesting, wavelength), 2e-4) << nesting;
        Heightfield rough = sinusoid(4);
        apply_l_filter(rough, nesting);
        EXPECT_NEAR(amplitude(rough), 1.0 - transmission(nesting, wavelength), 2e-4) << nesting;
    }
    Heightfield recorded = sinusoid(4);
    apply_l_filter(recorded, 80.0);
    EXPECT_EQ(recorded.provenance.at("prepare.1"), "L-filter: ISO 16610-61 Gaussian, nesting index 80 um");
}

// Rectangular texels: a sinusoid along y on rows 2 µm apart (columns 0.5 µm) is filtered by its
// wavelength in µm, as the standard's transmission says.
TEST(GaussianFilter, RectangularTexelsFilterEachAxisInMicrometres) {
    const double wavelength = 32.0;
    Heightfield field = make_heightfield(64, 8, 0.5);  // 4 µm x 128 µm: 4 periods along y
    set_spacing(field, 0.5, 2.0);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c)
            field.at(r, c) = static_cast<float>(std::sin(2.0 * kPi * sample_position(field, r, c).y / wavelength));
    for (const double nesting : {wavelength, 0.5 * wavelength}) {
        Heightfield smooth = field;
        apply_s_filter(smooth, nesting);
        EXPECT_NEAR(amplitude(smooth), transmission(nesting, wavelength), 2e-4) << nesting;
    }
}

TEST(GaussianFilter, NonPeriodicPlanesPassAndMissingPointsStayMissing) {
    Heightfield plane = make_heightfield(60, 80, 1.0);
    plane.periodic = false;
    for (int r = 0; r < plane.rows; ++r)
        for (int c = 0; c < plane.cols; ++c) {
            const Point2 s = sample_position(plane, r, c);
            plane.at(r, c) = static_cast<float>(3.0 + 0.2 * s.x - 0.1 * s.y);
        }
    const double hole_height = plane.at(30, 40);
    plane.at(30, 40) = std::numeric_limits<float>::quiet_NaN();
    const Heightfield original = plane;
    const double nesting = 8.0;
    apply_s_filter(plane, nesting);
    EXPECT_TRUE(std::isnan(plane.at(30, 40)));
    // Away from the border (3αλ ≈ 11.3 µm) the full kernel of total weight S averages a plane to
    // itself; the hole removes its weight w from the average, which moves it by exactly
    // w (h − h_hole)/(S − w).
    const double width = std::sqrt(std::log(2.0) / kPi) * nesting;
    double line_sum = 0.0;
    for (int k = -12; k <= 12; ++k) line_sum += std::exp(-kPi * k * k / (width * width));
    const double total = line_sum * line_sum;
    for (int r = 12; r < plane.rows - 12; ++r)
        for (int c = 12; c < plane.cols - 12; ++c) {
            if (std::isnan(original.at(r, c))) continue;
            const double hole_weight = std::exp(-kPi * ((r - 30) * (r - 30) + (c - 40) * (c - 40)) / (width * width));
            const double expected =
                original.at(r, c) + hole_weight * (original.at(r, c) - hole_height) / (total - hole_weight);
            EXPECT_NEAR(plane.at(r, c), expected, 2e-5) << r << "," << c;
        }
    // A constant passes everywhere, border included (the normalised convolution).
    Heightfield constant = make_heightfield(20, 30, 1.0, 5.0f);
    constant.periodic = false;
    apply_l_filter(constant, 40.0);
    for (float h : constant.heights_um) EXPECT_NEAR(h, 0.0f, 1e-5);
}

TEST(GaussianFilter, BadNestingIndicesAreRefused) {
    Heightfield field = sinusoid(1);
    EXPECT_THROW(apply_s_filter(field, 0.0), Error);
    EXPECT_THROW(apply_l_filter(field, std::nan("")), Error);
    EXPECT_THROW(apply_l_filter(field, 1e9), Error);
}

}  // namespace
}  // namespace glintscope
