// Two lobe EXRs compared layer by layer: exact numbers for known perturbations, one-line
// refusals, the report, and a difference picture that is coloured exactly where they differ.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "scoped_ocio.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/optics/spectrum.hpp"
#include "glintscope/output/lobe_comparison.hpp"

namespace glintscope {
namespace {

// A smooth lobe (a Gaussian spot off centre) in every layer, zero outside the disk.
LobeImage spot_lobe(int n, const std::vector<double>& wavelengths, double scale = 1.0, Quantity quantity = Quantity::brdf) {
    LobeImage lobe = make_lobe_image(n, wavelengths, quantity);
    for (std::size_t layer = 0; layer < lobe.layers(); ++layer)
        for (int r = 0; r < n; ++r)
            for (int c = 0; c < n; ++c)
                if (inside_unit_disk(disk_pixel_point(r, c, n)))
                    lobe.at(layer, r, c) = float(scale * (1.0 + layer) *
                                                 std::exp(-(std::pow(r - 0.4 * n, 2) + std::pow(c - 0.55 * n, 2)) / n));
    lobe.metadata["method"] = "test";
    lobe.metadata["query.res"] = std::to_string(n);
    return lobe;
}

class LobeComparison : public ::testing::Test {
protected:
    std::string write(const LobeImage& lobe, const std::string& name, bool spectral_channels = true) {
        LobeOutputOptions options;
        options.spectral_channels = spectral_channels;
        write_lobe_exr(lobe, directory.file(name), options);
        return directory.file(name);
    }
    testing::ScopedOcio no_ocio{std::nullopt};  // the built-in colour config
    testing::TemporaryDirectory directory;
};

TEST_F(LobeComparison, AnImageAgainstItselfIsExact) {
    const LobeFileComparison same = compare_lobe_exrs(write(spot_lobe(32, {0.5}), "a.exr"), write(spot_lobe(32, {0.5}), "b.exr"));
    ASSERT_EQ(same.layers.size(), 1u);
    EXPECT_EQ(same.layers[0].relative_l2, 0.0);
    EXPECT_EQ(same.layers[0].max_abs_difference, 0.0);
    EXPECT_EQ(same.layers[0].energy_ratio(), 1.0);
    EXPECT_EQ(same.test.names, std::vector<std::string>{"0.5 um"});
}

TEST_F(LobeComparison, ScalingByOnePointOneIsEnergyRatioOnePointOneAndTenPercentInEveryLayer) {
    const std::vector<double> wavelengths = spectral_bin_centres_um(4);
    const LobeFileComparison scaled =
        compare_lobe_exrs(write(spot_lobe(48, wavelengths, 1.1), "a.exr"), write(spot_lobe(48, wavelengths), "b.exr"));
    ASSERT_EQ(scaled.layers.size(), 4u);
    for (std::size_t k = 0; k < 4; ++k) {
        const LayerComparison& c = scaled.layers[k];
        EXPECT_EQ(c.wavelength_um, wavelengths[k]);
        EXPECT_NEAR(c.energy_ratio(), 1.1, 1e-6);  // float rounding of 1.1 v
        EXPECT_NEAR(c.relative_l2, 0.1, 1e-6);
        EXPECT_EQ(c.peak_offset_pixels, 0.0);
        EXPECT_NEAR(c.log_rms_error, std::log10(1.1), 1e-6);
    }
}

TEST_F(LobeComparison, ColourExrsCompareByTheirRgbChannels) {
    const std::vector<double> wavelengths = spectral_bin_centres_um(4);
    const std::string a = write(spot_lobe(32, wavelengths, 1.1), "a.exr", false);
    const std::string b = write(spot_lobe(32, wavelengths), "b.exr", false);
    EXPECT_THROW(load_lobe_exr(a), Error);  // no per-wavelength channels to make a LobeImage of
    const LobeFileComparison colour = compare_lobe_exrs(a, b);
    EXPECT_TRUE(colour.test.colour);
    EXPECT_EQ(colour.test.names, (std::vector<std::string>{"R", "G", "B"}));
    ASSERT_EQ(colour.layers.size(), 3u);
    for (const LayerComparison& c : colour.layers) {
        EXPECT_NEAR(c.energy_ratio(), 1.1, 1e-6);  // R, G, B are linear in the spectrum
        EXPECT_NEAR(c.relative_l2, 0.1, 1e-6);
    }
    // Colour channels compare across spectral samplings, not with per-wavelength layers.
    EXPECT_NO_THROW(compare_lobe_exrs(a, write(spot_lobe(32, spectral_bin_centres_um(8)), "c.exr", false)));
    EXPECT_THROW(compare_lobe_exrs(a, write(spot_lobe(32, wavelengths), "d.exr", true)), Error);
}

TEST_F(LobeComparison, RefusesDifferentQuantitiesSizesAndLayersInOneLineNamingBoth) {
    const std::string a = write(spot_lobe(32, {0.5}), "a.exr");
    const auto refusal = [&](const std::string& b) {
        try {
            compare_lobe_exrs(a, b);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string quantity = refusal(write(spot_lobe(32, {0.5}, 1.0, Quantity::ndf), "ndf.exr"));
    EXPECT_NE(quantity.find("(brdf)"), std::string::npos) << quantity;
    EXPECT_NE(quantity.find("(ndf)"), std::string::npos) << quantity;
    EXPECT_NE(quantity.find("different quantities"), std::string::npos) << quantity;
    const std::string size = refusal(write(spot_lobe(16, {0.5}), "small.exr"));
    EXPECT_NE(size.find("'" + a + "' (32x32 pixels)"), std::string::npos) << size;
    EXPECT_NE(size.find("(16x16 pixels): different sizes"), std::string::npos) << size;
    const std::string layers = refusal(write(spot_lobe(32, {0.6}), "green.exr"));
    EXPECT_NE(layers.find("(lambda 0.5 um)"), std::string::npos) << layers;
    EXPECT_NE(layers.find("(lambda 0.6 um): different layers"), std::string::npos) << layers;
    for (const std::string& message : {quantity, size, layers}) EXPECT_EQ(message.find('\n'), std::string::npos);
    const std::string missing = refusal(directory.file("missing.exr"));
    EXPECT_NE(missing.find("missing.exr"), std::string::npos) << missing;
}

TEST_F(LobeComparison, ReportHoldsBothInputsAndTheNumbersPerLayer) {
    LobeImage b = spot_lobe(32, {0.5, 0.6});
    LobeImage a = b;
    a.at(1, 10, 17) += 0.25f;  // one pixel of the second layer
    a.metadata["method"] = "gabor";
    const LobeFileComparison comparison = compare_lobe_exrs(write(a, "a.exr"), write(b, "b.exr"));
    EXPECT_EQ(worst_layer(comparison), 1u);
    const nlohmann::json report = nlohmann::json::parse(comparison_json(comparison));
    EXPECT_EQ(report["a"]["method"], "gabor");
    EXPECT_EQ(report["b"]["method"], "test");
    EXPECT_EQ(report["b"]["query"]["res"], "32");
    ASSERT_EQ(report["layers"].size(), 2u);
    EXPECT_EQ(report["layers"][0]["relative_l2"], 0.0);
    EXPECT_TRUE(report["layers"][0]["max_pixel"].is_null());  // no difference, no place
    const nlohmann::json& second = report["layers"][1];
    EXPECT_EQ(second["layer"], "0.6 um");
    EXPECT_EQ(second["wavelength_um"], 0.6);
    EXPECT_EQ(second["max_pixel"], nlohmann::json({10, 17}));
    EXPECT_NEAR(second["max_abs_difference"].get<double>(), 0.25, 1e-7);
    const DiskPoint p = disk_pixel_point(10, 17, 32);
    EXPECT_EQ(second["max_disk_point"], nlohmann::json({p.x, p.y}));
    EXPECT_NEAR(second["sum_a"].get<double>() - second["sum_b"].get<double>(), 0.25 * 4.0 / (32 * 32), 1e-7);
    EXPECT_EQ(second["energy_ratio"].get<double>(), comparison.layers[1].energy_ratio());
}

bool in_block(int r, int c) { return r >= 18 && r < 24 && c >= 6 && c < 14; }

// The third panel of the picture at `path` is coloured (not the neutral grey of 0) at exactly the
// image pixels of in_block.
void expect_difference_coloured_on_the_block(const std::string& path, const FigureLayout& layout, int n) {
    auto input = OIIO::ImageInput::open(path);
    ASSERT_TRUE(input);
    const OIIO::ImageSpec& spec = input->spec();
    EXPECT_EQ(spec.width, layout.width);
    EXPECT_EQ(spec.height, layout.height);
    ASSERT_EQ(layout.disks.size(), 1u);
    ASSERT_EQ(layout.disks[0].size(), 3u);  // A | B | A - B
    std::vector<unsigned char> pixels(std::size_t(spec.width) * spec.height * spec.nchannels);
    ASSERT_TRUE(input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data()));
    const PixelSquare disk = layout.disks[0][2];
    EXPECT_EQ(disk.size, panel_size(n));
    const int zoom = disk.size / n;
    int coloured = 0, checked = 0;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, n);
            if (p.x * p.x + p.y * p.y > 0.8) continue;  // clear of the outline
            const int x = disk.x + c * zoom + zoom / 2, y = disk.y + r * zoom + zoom / 2;
            const unsigned char* rgb = &pixels[(std::size_t(y) * spec.width + x) * spec.nchannels];
            if (rgb[0] == rgb[1] && rgb[1] == rgb[2] && rgb[0] != 221) continue;  // a guide ring or its label
            if (rgb[0] < 40 && rgb[2] == 255) continue;                           // the cyan marker
            const bool grey = rgb[0] == 221 && rgb[1] == 221 && rgb[2] == 221;     // 0 on the diverging map
            EXPECT_EQ(!grey, in_block(r, c)) << "pixel " << r << "," << c;
            coloured += !grey;
            ++checked;
        }
    EXPECT_GT(checked, 400);
    EXPECT_EQ(coloured, 6 * 8);
}

// A = B + 1 on a block of pixels.
TEST_F(LobeComparison, DifferencePanelIsColouredExactlyWhereTheImagesDiffer) {
    const int n = 32;
    const LobeImage b = spot_lobe(n, {0.5});
    LobeImage a = b;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
            if (in_block(r, c)) a.at(0, r, c) += 1.0f;
    const LobeFileComparison comparison = compare_lobe_exrs(write(a, "a.exr"), write(b, "b.exr"));
    const std::string path = directory.file("diff.png");
    expect_difference_coloured_on_the_block(path, write_comparison_figure(comparison, path), n);
}

// A spectrum gets its difference panel too: the mean over its wavelengths, here +1 at one of two.
TEST_F(LobeComparison, ASpectrumsDifferencePanelIsTheMeanOverItsWavelengths) {
    const int n = 32;
    const LobeImage b = spot_lobe(n, {0.45, 0.65});
    LobeImage a = b;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
            if (in_block(r, c)) a.at(1, r, c) += 1.0f;
    const std::string path = directory.file("spectral-diff.png");
    expect_difference_coloured_on_the_block(
        path, write_difference_figure(a, b, {"spectral", "", "a", "b", "a - b"}, path, LobeOutputOptions{}), n);
}

}  // namespace
}  // namespace glintscope
