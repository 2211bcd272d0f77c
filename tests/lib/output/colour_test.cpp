// Lobes to colour: white point, hues of spectral spikes, exposure, and config handling.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

#include "cli_runner.hpp"
#include "scoped_ocio.hpp"
#include "core/embedded_data.hpp"
#include "glintscope/output/colour.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"

namespace glintscope {
namespace {

constexpr int kResolution = 32;

bool inside(int row, int col) {
    const DiskPoint p = disk_pixel_point(row, col, kResolution);
    return p.x * p.x + p.y * p.y <= 1.0;
}

// A lobe whose every in-disk pixel holds `spectrum` (one value per wavelength).
LobeImage uniform_lobe(const std::vector<double>& wavelengths, const std::vector<double>& spectrum) {
    LobeImage lobe = make_lobe_image(kResolution, wavelengths);
    for (std::size_t layer = 0; layer < wavelengths.size(); ++layer)
        for (int row = 0; row < kResolution; ++row)
            for (int col = 0; col < kResolution; ++col)
                if (inside(row, col)) lobe.at(layer, row, col) = float(spectrum[layer]);
    return lobe;
}

std::size_t centre_pixel() { return (std::size_t(kResolution / 2) * kResolution + kResolution / 2) * 3; }

// The tests use the built-in config unless they set $OCIO themselves.
class Colour : public ::testing::Test {
protected:
    testing::ScopedOcio no_ocio{std::nullopt};
};

TEST_F(Colour, WavelengthIndependentLobeIsNeutralGrey) {
    const std::vector<double> wavelengths = spectral_bin_centres_um(8);
    const double value = 0.37;
    const LobeImage lobe = uniform_lobe(wavelengths, std::vector<double>(8, value));
    for (Illuminant illuminant : {Illuminant::d65, Illuminant::e})
        for (const char* space : {"lin_rec709", "lin_rec2020", "ACEScg"}) {
            ColourSettings settings;
            settings.illuminant = illuminant;
            settings.output_space = space;
            const std::vector<float> rgb = lobe_to_rgb(lobe, settings);
            const float* pixel = &rgb[centre_pixel()];
            EXPECT_NEAR(pixel[0] / pixel[1], 1.0, 1e-4) << space;
            EXPECT_NEAR(pixel[2] / pixel[1], 1.0, 1e-4) << space;
            EXPECT_NEAR(pixel[1], value, 1e-4 * value) << space;  // white is R = G = B = Y
        }
    const std::vector<float> xyz = lobe_to_xyz(lobe, Illuminant::d65);
    EXPECT_NEAR(xyz[centre_pixel() + 1], value, 1e-6);
}

TEST_F(Colour, SingleWavelengthLobeIsAchromatic) {
    const LobeImage lobe = uniform_lobe({0.5}, {2.5});
    const std::vector<float> rgb = lobe_to_rgb(lobe, ColourSettings{});
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[centre_pixel() + c], 2.5, 2.5e-5);
    EXPECT_EQ(rgb[0], 0.0f);  // the corner pixel lies outside the disk
}

TEST_F(Colour, SpectralSpikeHasTheHueOfItsWavelength) {
    const std::vector<double> wavelengths = spectral_bin_centres_um(47);  // 10 nm bins
    struct Case {
        int bin;
        int dominant;  // the largest linear Rec.709 channel
    };
    for (const Case c : {Case{9, 2}, Case{24, 0}}) {  // 450-460 nm: blue; 600-610 nm: red/orange
        std::vector<double> spectrum(47, 0.0);
        spectrum[c.bin] = 1.0;
        const LobeImage lobe = uniform_lobe(wavelengths, spectrum);
        const std::vector<float> xyz = lobe_to_xyz(lobe, Illuminant::d65);
        const Chromaticity colour =
            chromaticity({xyz[centre_pixel()], xyz[centre_pixel() + 1], xyz[centre_pixel() + 2]});
        const Chromaticity locus = chromaticity(cie_1931_cmf(wavelengths[c.bin]));
        EXPECT_NEAR(colour.x, locus.x, 3e-3) << wavelengths[c.bin];
        EXPECT_NEAR(colour.y, locus.y, 3e-3) << wavelengths[c.bin];
        const std::vector<float> rgb = lobe_to_rgb(lobe, ColourSettings{});
        const float* pixel = &rgb[centre_pixel()];
        for (int other = 0; other < 3; ++other) {
            if (other == c.dominant) continue;
            EXPECT_GT(pixel[c.dominant], pixel[other] + 0.01f) << wavelengths[c.bin];
        }
    }
    // Orange, not magenta: at 605 nm green exceeds blue.
    std::vector<double> orange(47, 0.0);
    orange[24] = 1.0;
    const std::vector<float> rgb = lobe_to_rgb(uniform_lobe(wavelengths, orange), ColourSettings{});
    EXPECT_GT(rgb[centre_pixel() + 1], rgb[centre_pixel() + 2]);
}

TEST_F(Colour, BradfordAdaptationMapsTheSourceWhiteToD65) {
    const XYZ source = spectral_weights(8, Illuminant::e).white;
    const XYZ adapted = adapt_to_d65(source, source);
    const XYZ d65 = d65_white_xyz();
    EXPECT_NEAR(adapted.X, d65.X, 1e-12);
    EXPECT_NEAR(adapted.Y, 1.0, 1e-12);
    EXPECT_NEAR(adapted.Z, d65.Z, 1e-12);
}

TEST_F(Colour, AutoExposureMapsThePercentileToWhite) {
    // 2.0 over most of the disk: the 99.5th percentile is 2, EV = −1, and 2 shows as 255;
    // a pixel of 1 shows as the sRGB encoding of 0.5, 0.7354 → 188.
    LobeImage lobe = uniform_lobe({0.5}, {2.0});
    lobe.at(0, kResolution / 2, kResolution / 2 + 1) = 1.0f;
    const DisplayImage display = lobe_to_display(lobe, ColourSettings{});
    EXPECT_DOUBLE_EQ(display.exposure.ev, -1.0);
    EXPECT_NE(display.exposure.rule.find("99.5th percentile"), std::string::npos) << display.exposure.rule;
    EXPECT_EQ(display.pixels[centre_pixel()], 255);
    EXPECT_EQ(display.pixels[centre_pixel() + 3], 188);
    EXPECT_EQ(display.pixels[centre_pixel() + 4], 188);
    EXPECT_EQ(display.pixels[0], 0);  // outside the disk
}

// A thin highlight in a dark render: 400 of 100 000 pixels lit (0.4%), so the 99.5th percentile
// of the image is 0. The same percentile of the lit pixels maps to white (398 of 1 … 399 and
// one caustic spike of 10⁶), not the spike, which would leave the highlight black.
TEST_F(Colour, AutoExposureOfASparseImageUsesThePercentileOfItsLitPixels) {
    std::vector<float> xyz(3 * 100000, 0.0f);
    for (int k = 1; k < 400; ++k) xyz[3 * std::size_t(k) * 200 + 1] = float(k);
    xyz[3 * 7 + 1] = 1e6f;
    const DisplayExposure exposure = xyz_exposure(xyz, ColourSettings{});
    EXPECT_DOUBLE_EQ(exposure.white_level, 398.0);
    EXPECT_NE(exposure.rule.find("percentile of the lit pixels"), std::string::npos) << exposure.rule;
    // An image lit over more than 0.5% keeps the percentile of all its pixels.
    for (int k = 400; k < 1000; ++k) xyz[3 * std::size_t(k) * 100 + 4] = 1.0f;  // Y of pixel 100k + 1
    EXPECT_DOUBLE_EQ(xyz_exposure(xyz, ColourSettings{}).white_level, 1.0);
}

TEST_F(Colour, GivenExposureScalesByPowerOfTwo) {
    ColourSettings settings;
    settings.exposure_ev = 1.0;
    const DisplayImage display = lobe_to_display(uniform_lobe({0.5}, {0.25}), settings);
    EXPECT_EQ(display.exposure.rule, "given");
    EXPECT_DOUBLE_EQ(display.exposure.white_level, 0.5);
    EXPECT_EQ(display.pixels[centre_pixel()], 188);  // 0.25 · 2¹ = 0.5
}

TEST_F(Colour, LogScaleSpansTheGivenDecades) {
    ColourSettings settings;
    settings.exposure_ev = 0.0;  // white level 1
    settings.log_scale = true;
    settings.log_decades = 4.0;
    LobeImage lobe = uniform_lobe({0.5}, {1.0});
    lobe.at(0, kResolution / 2, kResolution / 2 + 1) = 1e-2f;  // two of four decades below white → 0.5
    lobe.at(0, kResolution / 2, kResolution / 2 + 2) = 1e-5f;  // below the range → black
    const DisplayImage display = lobe_to_display(lobe, settings);
    EXPECT_EQ(display.pixels[centre_pixel()], 255);
    EXPECT_EQ(display.pixels[centre_pixel() + 3], 188);
    EXPECT_EQ(display.pixels[centre_pixel() + 6], 0);
    // Auto on a log scale puts the maximum, not the percentile, at the top.
    lobe.at(0, kResolution / 2 + 1, kResolution / 2) = 8.0f;
    settings.exposure_ev.reset();
    EXPECT_DOUBLE_EQ(display_exposure(lobe, settings).white_level, 8.0);
    settings.log_scale = false;
    EXPECT_DOUBLE_EQ(display_exposure(lobe, settings).white_level, 1.0);
}

TEST_F(Colour, ConfigComesFromTheArgumentThenOcioThenBuiltIn) {
    EXPECT_EQ(colour_config_name(ColourSettings{}), "built-in data/ocio/config.ocio");
    testing::TemporaryDirectory directory;
    const std::string copy = directory.file("copy.ocio");
    std::ofstream(copy) << embedded_data("ocio/config.ocio");
    const testing::ScopedOcio ocio(directory.file("missing.ocio"));
    try {
        colour_space_names(ColourSettings{});
        FAIL() << "a missing $OCIO config was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("missing.ocio"), std::string::npos) << e.what();
    }
    ColourSettings settings;
    settings.config_path = copy;  // the argument wins over $OCIO
    const std::vector<std::string> names = colour_space_names(settings);
    EXPECT_NE(std::find(names.begin(), names.end(), "CIE-XYZ-D65"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "sRGB"), names.end());
}

TEST_F(Colour, RejectsBadConfigsAndUnknownSpaces) {
    const LobeImage lobe = uniform_lobe(spectral_bin_centres_um(4), {1, 1, 1, 1});
    ColourSettings missing;
    missing.config_path = "/nonexistent/config.ocio";
    EXPECT_THROW(lobe_to_rgb(lobe, missing), Error);

    testing::TemporaryDirectory directory;
    ColourSettings corrupt;
    corrupt.config_path = directory.file("corrupt.ocio");
    std::ofstream(corrupt.config_path) << "ocio_profile_version: 2\ncolorspaces: [not a colour space\n";
    EXPECT_THROW(lobe_to_rgb(lobe, corrupt), Error);

    ColourSettings unknown;
    unknown.output_space = "Rec.9000";
    try {
        lobe_to_rgb(lobe, unknown);
        FAIL() << "unknown colour space accepted";
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("Rec.9000"), std::string::npos) << message;
        EXPECT_NE(message.find("lin_rec709"), std::string::npos) << message;
    }
    ColourSettings bad_percentile;
    bad_percentile.auto_percentile = 0.0;
    EXPECT_THROW(display_exposure(lobe, bad_percentile), Error);
}

}  // namespace
}  // namespace glintscope
