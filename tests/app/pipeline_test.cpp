// One query, one image, whoever asks: `lobe`, `ndf` and `batch` run the library's one pipeline,
// so a figure panel and the same query run by `lobe` are the same image, and an averaged NDF
// re-runs exactly from its record.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "cli_runner.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

struct ExrImage {
    std::vector<std::string> channels;
    std::vector<float> pixels;
    std::string supersample;
};

ExrImage read_exr(const std::string& path) {
    auto input = OIIO::ImageInput::open(path);
    EXPECT_TRUE(input) << path;
    if (!input) return {};
    const OIIO::ImageSpec& spec = input->spec();
    ExrImage image{spec.channelnames, std::vector<float>(spec.image_pixels() * spec.nchannels), ""};
    input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, image.pixels.data());
    image.supersample = spec.get_string_attribute("glintscope:query.supersample");
    return image;
}

// The values of one channel, by name.
std::vector<float> channel(const ExrImage& image, const std::string& name) {
    const auto it = std::find(image.channels.begin(), image.channels.end(), name);
    EXPECT_NE(it, image.channels.end()) << name;
    if (it == image.channels.end()) return {};
    const std::size_t c = it - image.channels.begin(), n = image.channels.size();
    std::vector<float> values;
    for (std::size_t i = c; i < image.pixels.size(); i += n) values.push_back(image.pixels[i]);
    return values;
}

// Fig. 10's spectral cell (builtin:isotropic, fft, 16 bins, 20 degrees, sigma_c 10 um, res 256),
// where the coherence blur is below a pixel and the pipeline supersamples.
TEST(Pipeline, ABatchPanelIsTheLobeOfTheSameQueryInEveryChannel) {
    TemporaryDirectory directory;
    std::ofstream(directory.file("cell.toml")) << R"(title = "One cell"
output = "cell.png"
[[row]]
label = "isotropic"
heightfield = "builtin:isotropic"
[[column]]
label = "spectral"
method = "fft"
spectral = 16
incident = [20, 0]
sigma_c = "10um"
res = 256
)";
    const auto batch = testing::run_cli({"batch", directory.file("cell.toml")});
    ASSERT_EQ(batch.exit_code, 0) << batch.output;
    const auto lobe = testing::run_cli({"lobe", "builtin:isotropic", "--method", "fft", "--spectral", "16", "--incident",
                                        "20,0", "--sigma-c", "10um", "--res", "256", "--spectral-channels", "-o",
                                        directory.file("lobe.exr")});
    ASSERT_EQ(lobe.exit_code, 0) << lobe.output;
    const ExrImage panel = read_exr(directory.file("cell.panels/r1-c1.exr"));
    const ExrImage single = read_exr(directory.file("lobe.exr"));
    EXPECT_EQ(panel.supersample, "2");
    EXPECT_EQ(single.supersample, panel.supersample);
    ASSERT_EQ(single.channels, panel.channels);
    for (const std::string& name : single.channels) EXPECT_EQ(channel(single, name), channel(panel, name)) << name;
}

TEST(Pipeline, AnAveragedNdfRerunsExactlyFromItsRecord) {
    TemporaryDirectory directory;
    const auto first = testing::run_cli({"ndf", "builtin:brushed", "--method", "pndf", "--res", "64", "--footprints",
                                         "grid:2", "-o", directory.file("n.exr")});
    ASSERT_EQ(first.exit_code, 0) << first.output;
    const auto single = testing::run_cli({"ndf", "builtin:brushed", "--method", "pndf", "--res", "64", "-o",
                                          directory.file("one.exr")});
    ASSERT_EQ(single.exit_code, 0) << single.output;
    const auto again = testing::run_cli({"ndf", "--from", directory.file("n.exr"), "-o", directory.file("again.exr")});
    ASSERT_EQ(again.exit_code, 0) << again.output;
    const ExrImage averaged = read_exr(directory.file("n.exr"));
    EXPECT_EQ(channel(read_exr(directory.file("again.exr")), "D"), channel(averaged, "D"));
    EXPECT_NE(channel(read_exr(directory.file("one.exr")), "D"), channel(averaged, "D"));
}

// --from re-runs on the data it recorded: a heightfield whose bytes changed is refused in one line
// (unless told), and a relative path is read relative to the record, from any folder.
TEST(Pipeline, FromChecksTheRecordedHeightfieldAndFindsItBesideTheRecord) {
    TemporaryDirectory directory;
    const auto generated = testing::run_cli({"generate", "gaussian", "--size", "64", "--seed", "3", "-o",
                                             directory.file("rough.exr")});
    ASSERT_EQ(generated.exit_code, 0) << generated.output;
    const std::string in_directory = "cd '" + directory.path().string() + "' && " + testing::executable();
    const auto first = testing::run_shell(in_directory + " lobe rough.exr --periodic yes --res 32 -o first.exr");
    ASSERT_EQ(first.exit_code, 0) << first.output;
    const auto elsewhere = testing::run_shell("cd / && " + testing::executable() + " lobe --from '" +
                                              directory.file("first.exr") + "' -o '" + directory.file("again.exr") + "'");
    ASSERT_EQ(elsewhere.exit_code, 0) << elsewhere.output;
    EXPECT_EQ(channel(read_exr(directory.file("again.exr")), "Y"), channel(read_exr(directory.file("first.exr")), "Y"));

    const auto changed = testing::run_cli({"generate", "gaussian", "--size", "64", "--seed", "4", "-o",
                                           directory.file("rough.exr")});
    ASSERT_EQ(changed.exit_code, 0) << changed.output;
    const auto refused = testing::run_cli({"lobe", "--from", directory.file("first.exr"), "-o", directory.file("x.exr")});
    EXPECT_NE(refused.exit_code, 0);
    EXPECT_NE(refused.output.find("has changed since"), std::string::npos) << refused.output;
    EXPECT_EQ(std::count(refused.output.begin(), refused.output.end(), '\n'), 1) << refused.output;
    EXPECT_FALSE(std::filesystem::exists(directory.file("x.exr")));
    const auto allowed = testing::run_cli({"lobe", "--from", directory.file("first.exr"), "--allow-changed-heightfield",
                                           "-o", directory.file("x.exr")});
    EXPECT_EQ(allowed.exit_code, 0) << allowed.output;
    EXPECT_NE(channel(read_exr(directory.file("x.exr")), "Y"), channel(read_exr(directory.file("first.exr")), "Y"));
}

}  // namespace
}  // namespace glintscope
