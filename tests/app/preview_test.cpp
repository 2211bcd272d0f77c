// glintscope preview: a colour-mapped map-view PNG (+y up), missing points grey, and no output
// file at all when anything fails.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "cli_runner.hpp"
#include "glintscope/output/colormap.hpp"
#include "glintscope/io/heightfield_io.hpp"

namespace glintscope {
namespace {

using testing::run_cli;
using testing::TemporaryDirectory;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Mean row of the pixels within one 8-bit step of `color`, and how many there are.
std::pair<double, long> rows_of_color(const std::string& png, const SrgbColor& color) {
    auto input = OIIO::ImageInput::open(png);
    if (!input) return {0.0, 0};
    const int width = input->spec().width;
    const int height = input->spec().height;
    std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width) * height * 3);
    input->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, rgb.data());
    const long target[3] = {std::lround(color.r * 255), std::lround(color.g * 255), std::lround(color.b * 255)};
    double row_sum = 0.0;
    long count = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::uint8_t* p = &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
            if (std::labs(p[0] - target[0]) <= 1 && std::labs(p[1] - target[1]) <= 1 &&
                std::labs(p[2] - target[2]) <= 1) {
                row_sum += y;
                ++count;
            }
        }
    return {count > 0 ? row_sum / count : 0.0, count};
}

// Heights equal to y: the highest row of samples is the top of the field.
Heightfield ramp_in_y() {
    Heightfield field = make_heightfield(64, 48, 1.0);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) field.at(r, c) = static_cast<float>(sample_position(field, r, c).y);
    field.at(40, 10) = std::numeric_limits<float>::quiet_NaN();
    return field;
}

TEST(PreviewCommand, RampInPlusYIsBrightAtTheTopAndMissingPointsAreGrey) {
    TemporaryDirectory directory;
    const std::string input = directory.file("ramp.x3p");
    save_heightfield(input, ramp_in_y());
    const std::string png = directory.file("ramp.png");
    const auto result = run_cli({"preview", input, "-o", png, "--colormap", "viridis"});
    ASSERT_EQ(result.exit_code, 0) << result.output;

    // Heights run 0.5 .. 63.5 µm; the 64-row field is enlarged 4 times (256 rows).
    const auto [bright_row, bright_count] = rows_of_color(png, map_color(ColorMap::viridis, 1.0));
    const auto [dark_row, dark_count] = rows_of_color(png, map_color(ColorMap::viridis, 0.0));
    EXPECT_GE(bright_count, 4 * 4 * 48);
    EXPECT_GE(dark_count, 4 * 4 * 48);
    EXPECT_LT(bright_row + 200, dark_row);  // the top sample row sits 252 pixel rows above the bottom one
    const auto [grey_row, grey_count] = rows_of_color(png, {kMissingGrey, kMissingGrey, kMissingGrey});
    EXPECT_GE(grey_count, 16);
}

// A float32 NPY of one row whose heights are all NaN.
void write_nan_npy(const std::string& path) {
    std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 2), }";
    header.append((64 - (10 + header.size() + 1) % 64) % 64, ' ');
    header += '\n';
    const float nan[2] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::quiet_NaN()};
    std::ofstream out(path, std::ios::binary);
    const auto length = static_cast<std::uint16_t>(header.size());
    out.write("\x93NUMPY\x01\x00", 8).write(reinterpret_cast<const char*>(&length), 2);
    out << header;
    out.write(reinterpret_cast<const char*>(nan), sizeof nan);
}

TEST(PreviewCommand, FailuresLeaveNoFile) {
    TemporaryDirectory directory;
    const std::string input = directory.file("ramp.exr");
    save_heightfield(input, ramp_in_y());
    const std::string nan_input = directory.file("nan.npy");
    write_nan_npy(nan_input);
    const std::pair<std::vector<std::string>, std::string> cases[] = {
        {{"preview", directory.file("absent.exr"), "-o", directory.file("out.png")}, "no such file"},
        {{"preview", nan_input, "-o", directory.file("out.png")}, "every height is missing (NaN)"},
        {{"preview", input, "-o", directory.file("out.jpg")}, "the file name must end in .png"},
        {{"preview", input, "-o", directory.file("no/such/dir/out.png")}, "does not exist"},
        {{"preview", input, "-o", directory.file("out.png"), "--channel", "Q"}, "no channel 'Q'"},
        {{"preview", input, "-o", directory.file("out.png"), "--centre", "8,8", "--box", "7x0um"},
         "box footprint sides must be between 0 and 100 mm, got 0 um"},
        {{"preview", input, "-o", directory.file("out.png"), "--centre", "8,8", "--box", "7x5x3"}, "WIDTHxHEIGHT"},
        {{"preview", input, "-o", directory.file("out.png"), "--centre", "1e9,8"}, "footprint centre must be finite"},
        {{"preview", input}, "preview needs an output: -o, --psd, --acf or --slopes"},
        {{"preview", input, "--psd", directory.file("psd.jpg")}, "psd.jpg': the file name must end in .png"},
    };
    for (const auto& [arguments, message] : cases) {
        const auto result = run_cli(arguments);
        EXPECT_EQ(result.exit_code, 1) << result.output;
        EXPECT_TRUE(contains(result.output, message)) << message << "\n" << result.output;
        EXPECT_EQ(result.output.find('\n'), result.output.size() - 1) << result.output;
        EXPECT_EQ(testing::count_entries(directory.path()), 2) << result.output;  // the two inputs
    }
}

// The picture's height in pixels (0 when it cannot be read).
int picture_height(const std::string& png) {
    auto input = OIIO::ImageInput::open(png);
    return input ? input->spec().height : 0;
}

TEST(PreviewCommand, SpectrumAutocorrelationAndSlopePlotsAreWrittenWhereAsked) {
    TemporaryDirectory directory;
    const std::string input = directory.file("ramp.npy");
    Heightfield ramp = ramp_in_y();
    ramp.at(40, 10) = ramp.at(41, 10) + 1.0f;  // filled: the P-NDF's interpolant refuses missing points
    save_heightfield(input, ramp);
    const std::string psd = directory.file("psd.png"), acf = directory.file("acf.png");
    const auto result = run_cli({"preview", input, "--psd", psd, "--acf", acf});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 3);  // no height picture without -o
    // The PSD stacks two plots (radial, axial), the autocorrelation is one.
    EXPECT_GT(picture_height(acf), 300);
    EXPECT_GT(picture_height(psd), 2 * picture_height(acf) - 100);
    const std::string slopes = directory.file("slopes.png");
    const auto slope_result = run_cli({"preview", input, "--slopes", slopes});
    ASSERT_EQ(slope_result.exit_code, 0) << slope_result.output;
    EXPECT_GT(picture_height(slopes), 300);
    EXPECT_EQ(testing::count_entries(directory.path()), 4);
}

TEST(PreviewCommand, UnknownColormapIsRejected) {
    TemporaryDirectory directory;
    const std::string input = directory.file("ramp.npy");
    save_heightfield(input, ramp_in_y());
    const auto result = run_cli({"preview", input, "-o", directory.file("out.png"), "--colormap", "jet"});
    EXPECT_NE(result.exit_code, 0);
    EXPECT_TRUE(contains(result.output, "jet")) << result.output;
    EXPECT_EQ(testing::count_entries(directory.path()), 1);
}

}  // namespace
}  // namespace glintscope
