// Writing lobe images: EXR round trips, the spectral channel naming, PNG and JSON contents.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "scoped_ocio.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/output/figure.hpp"
#include "glintscope/output/lobe_output.hpp"

namespace glintscope {
namespace {

// A lobe with distinct, irregular values in every layer, and metadata.
LobeImage sample_lobe(int resolution, const std::vector<double>& wavelengths) {
    LobeImage lobe = make_lobe_image(resolution, wavelengths);
    for (std::size_t i = 0; i < lobe.values.size(); ++i)
        lobe.values[i] = float(std::exp(std::sin(0.37 * double(i)) * 3.0) / 7.0);
    lobe.metadata["method"] = "test";
    lobe.metadata["query.omega_i"] = "0.1,0.2,0.97467943448089633";
    lobe.metadata["query.note"] = "quotes \" and\ttabs";
    return lobe;
}

class LobeOutput : public ::testing::Test {
protected:
    testing::ScopedOcio no_ocio{std::nullopt};  // the built-in colour config
    testing::TemporaryDirectory directory;
};

TEST_F(LobeOutput, SingleWavelengthExrRoundTripIsExact) {
    const LobeImage lobe = sample_lobe(24, {0.5});
    const std::string path = directory.file("lobe.exr");
    write_lobe_exr(lobe, path, LobeOutputOptions{});
    const LobeImage back = load_lobe_exr(path);
    EXPECT_EQ(back.resolution, lobe.resolution);
    EXPECT_EQ(back.wavelengths_um, lobe.wavelengths_um);
    ASSERT_EQ(back.values.size(), lobe.values.size());
    EXPECT_EQ(std::memcmp(back.values.data(), lobe.values.data(), lobe.values.size() * sizeof(float)), 0);
    EXPECT_EQ(back.metadata, lobe.metadata);

    auto input = OIIO::ImageInput::open(path);
    ASSERT_TRUE(input);
    EXPECT_EQ(input->spec().nchannels, 1);
    EXPECT_EQ(input->spec().channel_name(0), "Y");
    EXPECT_EQ(input->spec().get_string_attribute("glintscope:method"), "test");
    EXPECT_EQ(input->spec().get_string_attribute("glintscope:output.units"), "sr^-1");
}

TEST_F(LobeOutput, SpectralExrRoundTripIsExactAndNamesChannelsByWavelength) {
    const std::vector<double> wavelengths = spectral_bin_centres_um(8);
    const LobeImage lobe = sample_lobe(16, wavelengths);
    LobeOutputOptions options;
    options.spectral_channels = true;
    const std::string path = directory.file("spectral.exr");
    write_lobe_exr(lobe, path, options);

    const LobeImage back = load_lobe_exr(path);
    EXPECT_EQ(back.wavelengths_um, wavelengths);
    EXPECT_EQ(std::memcmp(back.values.data(), lobe.values.data(), lobe.values.size() * sizeof(float)), 0);
    EXPECT_EQ(back.metadata, lobe.metadata);

    auto input = OIIO::ImageInput::open(path);
    ASSERT_TRUE(input);
    const OIIO::ImageSpec& spec = input->spec();
    EXPECT_EQ(spec.nchannels, 3 + 8);
    for (const char* name : {"R", "G", "B", "S0.389,375000nm", "S0.800,625000nm"})
        EXPECT_GE(spec.channelindex(name), 0) << name;
    EXPECT_EQ(spec.get_string_attribute("spectralLayoutVersion"), "1.0");
    EXPECT_EQ(spec.get_string_attribute("emissiveUnits"), "W.m^-2.sr^-1");

    // R, G, B hold the colour conversion of the spectrum.
    std::vector<float> pixels(std::size_t(16) * 16 * spec.nchannels);
    ASSERT_TRUE(input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()));
    const std::vector<float> rgb = lobe_to_rgb(lobe, ColourSettings{});
    const std::size_t centre = 8 * 16 + 8;
    for (int c = 0; c < 3; ++c)
        EXPECT_EQ(pixels[centre * spec.nchannels + spec.channelindex(std::string(1, "RGB"[c]))], rgb[centre * 3 + c]);
}

TEST_F(LobeOutput, SpectralChannelNamesFollowFichet2021) {
    EXPECT_EQ(spectral_channel_name(0.56), "S0.560,000000nm");
    EXPECT_EQ(spectral_channel_name(0.389375), "S0.389,375000nm");
    // The paper's grammar: component, '.', a number with ',' as decimal mark, SI prefix, unit.
    const std::regex grammar(R"(^S([0-3])\.(\d*,?\d*([Ee][+-]?\d+)?)(Y|Z|E|P|T|G|M|k|h|da|d|c|m|u|n|p)?(m|Hz)$)");
    for (double lambda : spectral_bin_centres_um(47)) {
        const std::string name = spectral_channel_name(lambda);
        std::smatch match;
        ASSERT_TRUE(std::regex_match(name, match, grammar)) << name;
        EXPECT_EQ(match[1], "0");
        EXPECT_EQ(match[4], "n");
        EXPECT_EQ(match[5], "m");
        std::string number = match[2];
        number[number.find(',')] = '.';
        EXPECT_NEAR(std::stod(number), lambda * 1e3, 1e-6) << name;
    }
}

TEST_F(LobeOutput, RgbOnlySpectralExrCannotBeReadBack) {
    const std::string path = directory.file("rgb.exr");
    write_lobe_exr(sample_lobe(8, spectral_bin_centres_um(4)), path, LobeOutputOptions{});
    auto input = OIIO::ImageInput::open(path);
    ASSERT_TRUE(input);
    EXPECT_EQ(input->spec().nchannels, 3);
    EXPECT_THROW(load_lobe_exr(path), Error);
}

TEST_F(LobeOutput, SummaryFindsThePeakAndTheAlbedo) {
    // A Lambertian lobe f_r = ρ/π has directional albedo ρ; Σ f_r (2/N)² reaches it up to the
    // staircase edge of the disk, O(1/N).
    const int n = 256;
    const double rho = 0.6;
    LobeImage lobe = make_lobe_image(n, {0.5, 0.6});
    for (std::size_t layer = 0; layer < 2; ++layer)
        for (int row = 0; row < n; ++row)
            for (int col = 0; col < n; ++col) {
                const DiskPoint p = disk_pixel_point(row, col, n);
                if (p.x * p.x + p.y * p.y <= 1.0) lobe.at(layer, row, col) = float(rho / std::numbers::pi);
            }
    lobe.at(1, 40, 200) = 5.0f;
    const std::vector<WavelengthSummary> summary = summarize_lobe(lobe);
    ASSERT_EQ(summary.size(), 2u);
    EXPECT_NEAR(summary[0].disk_sum, rho, 2e-3);
    EXPECT_EQ(summary[1].peak_value, 5.0f);
    EXPECT_EQ(summary[1].peak_row, 40);
    EXPECT_EQ(summary[1].peak_col, 200);
    const DiskPoint p = disk_pixel_point(40, 200, n);
    EXPECT_NEAR(summary[1].peak_direction.x, p.x, 1e-12);
    EXPECT_NEAR(summary[1].peak_direction.y, p.y, 1e-12);
    EXPECT_NEAR(summary[1].peak_direction.z, std::sqrt(1.0 - p.x * p.x - p.y * p.y), 1e-12);
    EXPECT_NEAR(summary[1].disk_sum - summary[0].disk_sum, (5.0 - rho / std::numbers::pi) * 4.0 / (n * n), 1e-9);
}

TEST_F(LobeOutput, JsonSidecarCarriesMetadataWavelengthsAndSummary) {
    const LobeImage lobe = sample_lobe(16, spectral_bin_centres_um(8));
    const std::string path = directory.file("lobe.json");
    write_lobe(lobe, path, LobeOutputOptions{});
    std::ifstream stream(path);
    const nlohmann::json json = nlohmann::json::parse(stream);  // valid JSON, or this throws
    EXPECT_EQ(json["format"], "glintscope lobe");
    EXPECT_EQ(json["resolution"], 16);
    EXPECT_EQ(json["wavelengths_um"].get<std::vector<double>>(), lobe.wavelengths_um);
    EXPECT_EQ(json["metadata"]["method"], "test");
    EXPECT_EQ(json["metadata"]["query.note"], "quotes \" and\ttabs");
    EXPECT_EQ(json["metadata"]["query.omega_i"], "0.1,0.2,0.97467943448089633");  // not one number: a string
    const std::vector<WavelengthSummary> summaries = summarize_lobe(lobe);
    ASSERT_EQ(json["summary"].size(), summaries.size());
    for (std::size_t k = 0; k < summaries.size(); ++k) {
        EXPECT_EQ(json["summary"][k]["albedo"].get<double>(), summaries[k].disk_sum);
        EXPECT_EQ(json["summary"][k]["peak_value"].get<double>(), summaries[k].peak_value);
        EXPECT_EQ(json["summary"][k]["peak_pixel"], nlohmann::json({summaries[k].peak_row, summaries[k].peak_col}));
    }
    EXPECT_TRUE(json["colour"]["png_exposure_rule"].get<std::string>().starts_with("auto: 99.5th percentile"));
    EXPECT_TRUE(json["colour"].contains("luminance_albedo"));
}

TEST_F(LobeOutput, JsonMetadataNumbersAreNumbersAndInvalidUtf8IsReplaced) {
    LobeImage lobe = sample_lobe(8, {0.5});
    lobe.metadata["query.res"] = "8";
    lobe.metadata["query.sigma_c"] = "2.5";
    lobe.metadata["heightfield"] = "scan-\xe9t\xe9.x3p";  // a Latin-1 file name
    const std::string path = directory.file("lobe.json");
    write_lobe_json(lobe, path, LobeOutputOptions{});
    std::ifstream stream(path);
    const nlohmann::json json = nlohmann::json::parse(stream);
    EXPECT_EQ(json["metadata"]["query.res"], 8);
    EXPECT_TRUE(json["metadata"]["query.res"].is_number_integer());
    EXPECT_EQ(json["metadata"]["query.sigma_c"], 2.5);
    EXPECT_EQ(json["metadata"]["heightfield"], "scan-\ufffdt\ufffd.x3p");
}

TEST_F(LobeOutput, PngIsDisplayEncodedWithExposureInItsText) {
    const std::string spectral = directory.file("spectral.png");
    LobeOutputOptions bare;
    bare.bare = true;  // the image alone: one pixel per direction
    const DisplayExposure exposure = write_lobe_png(sample_lobe(16, spectral_bin_centres_um(8)), spectral, bare);
    auto input = OIIO::ImageInput::open(spectral);
    ASSERT_TRUE(input);
    EXPECT_EQ(input->spec().width, 16);
    EXPECT_EQ(input->spec().nchannels, 3);
    EXPECT_EQ(input->spec().format, OIIO::TypeDesc::UINT8);
    EXPECT_EQ(std::stod(input->spec().get_string_attribute("glintscope:output.exposure_ev")), exposure.ev);

    LobeOutputOptions grey = bare;
    grey.colormap = "grey";
    grey.colour.exposure_ev = 0.0;
    LobeImage single = make_lobe_image(16, {0.5});
    single.at(0, 8, 8) = 0.5f;
    const std::string grey_path = directory.file("grey.png");
    write_lobe_png(single, grey_path, grey);
    auto grey_input = OIIO::ImageInput::open(grey_path);
    ASSERT_TRUE(grey_input);
    std::vector<unsigned char> pixels(16 * 16 * 3);
    ASSERT_TRUE(grey_input->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
    EXPECT_EQ(pixels[(8 * 16 + 8) * 3], 188);  // sRGB encoding of 0.5

    const std::string mapped = directory.file("mapped.png");
    write_lobe_png(single, mapped, bare);  // inferno with a legend
    auto mapped_input = OIIO::ImageInput::open(mapped);
    ASSERT_TRUE(mapped_input);
    EXPECT_GT(mapped_input->spec().width, 16);  // enlarged, with the colour bar beside it

    // Annotated (the default): enlarged to a readable disk, with the exposure in its attributes.
    const std::string annotated = directory.file("annotated.png");
    const DisplayExposure shown = write_lobe_png(single, annotated, LobeOutputOptions{});
    auto annotated_input = OIIO::ImageInput::open(annotated);
    ASSERT_TRUE(annotated_input);
    EXPECT_GE(annotated_input->spec().width, panel_size(16));
    EXPECT_EQ(std::stod(annotated_input->spec().get_string_attribute("glintscope:output.exposure_ev")), shown.ev);
}

TEST_F(LobeOutput, RejectsBadRequestsWithoutLeavingFiles) {
    const LobeImage lobe = sample_lobe(8, {0.5});
    EXPECT_THROW(write_lobe(lobe, directory.file("lobe.tiff"), {}), Error);
    LobeOutputOptions jet;
    jet.colormap = "jet";
    EXPECT_THROW(write_lobe(lobe, directory.file("lobe.png"), jet), Error);
    LobeOutputOptions bad_space;
    bad_space.colour.output_space = "nope";
    EXPECT_THROW(write_lobe(sample_lobe(8, {0.45, 0.55}), directory.file("lobe.exr"), bad_space), Error);
    EXPECT_THROW(write_lobe(lobe, directory.file("missing/lobe.exr"), {}), Error);
    LobeImage broken = lobe;
    broken.values.pop_back();
    EXPECT_THROW(write_lobe(broken, directory.file("broken.exr"), {}), Error);
    EXPECT_EQ(testing::count_entries(directory.path()), 0);
}

}  // namespace
}  // namespace glintscope
