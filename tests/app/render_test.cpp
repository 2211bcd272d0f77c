// The render command as a user drives it: its EXR is the library's render of the scene its flags
// describe, a spectral render goes through the colour pipeline with the lights' spectrum and a
// recorded exposure, and bad scenes fail in one line before any work, writing nothing.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <string>

#include "cli_runner.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/render/render.hpp"
#include "glintscope/render/render_output.hpp"

namespace glintscope {
namespace {

using testing::run_cli;
using testing::TemporaryDirectory;

const std::vector<std::string> kScene = {"builtin:isotropic", "--size", "20x12", "--fov", "4", "--spp", "4",
                                         "--camera", "0,-6cm,6cm:1mm,0,0", "--light", "0,6cm,7cm:2",
                                         "--light", "5mm,5cm,6cm:0.5", "--patch", "4cm", "--sigma-c", "8um"};

std::vector<std::string> with(std::vector<std::string> arguments, const std::vector<std::string>& more) {
    arguments.insert(arguments.end(), more.begin(), more.end());
    return arguments;
}

TEST(RenderCommand, TheExrIsTheLibrarysRenderOfTheSceneTheFlagsDescribe) {
    TemporaryDirectory directory;
    const std::string exr = directory.file("patch.exr");
    const auto result = run_cli(with({"render"}, with(kScene, {"--lambda", "0.4um", "-o", exr})));
    ASSERT_EQ(result.exit_code, 0) << result.output;
    Scene scene;
    set_heightfield(scene.query, generate_builtin("isotropic"));
    scene.query.wavelengths_um = {0.4};
    scene.query.footprint.sigma_um = 8.0;
    scene.patch_um = 40000.0;
    scene.camera = {{0.0, -60000.0, 60000.0}, {1000.0, 0.0, 0.0}, 4.0, 20, 12};
    scene.lights = {PointLight{{0.0, 60000.0, 70000.0}, 2.0}, PointLight{{5000.0, 50000.0, 60000.0}, 0.5}};
    const RenderImage expected = render(scene, RenderSettings{4, 0});
    const RenderExr written = load_render_exr(exr);
    ASSERT_EQ(written.channels, std::vector<std::string>{"Y"});
    EXPECT_EQ(written.values, expected.values);
    EXPECT_GT(*std::max_element(expected.values.begin(), expected.values.end()), 0.0f);
}

// The lights' spectrum weighs the spectral radiance into colour: E (flat) and D65 differ.
TEST(RenderCommand, SpectralRendersAreColourWithTheLightsSpectrumAndARecordedExposure) {
    TemporaryDirectory directory;
    std::vector<std::vector<float>> rgb;
    for (const std::string spectrum : {"d65", "e"}) {
        const std::string exr = directory.file(spectrum + ".exr"), png = directory.file(spectrum + ".png");
        const auto result = run_cli(with({"render"}, with(kScene, {"--spectral", "3", "--light-spectrum", spectrum,
                                                                   "--exposure", "2.5", "-o", exr, "--png", png})));
        ASSERT_EQ(result.exit_code, 0) << result.output;
        const RenderExr written = load_render_exr(exr);
        ASSERT_EQ(written.channels, (std::vector<std::string>{"R", "G", "B"}));
        rgb.push_back(written.values);
        auto input = OIIO::ImageInput::open(png);
        ASSERT_TRUE(input);
        EXPECT_EQ(input->spec().get_string_attribute("glintscope:output.exposure_ev"), "2.5");
        EXPECT_EQ(input->spec().width, 20);
    }
    EXPECT_NE(rgb[0], rgb[1]);
}

TEST(RenderCommand, BadScenesFailInOneLineAndWriteNothing) {
    TemporaryDirectory directory;
    const std::string exr = directory.file("bad.exr");
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{"--camera", "0,-6cm,-1cm:0,0,0"}, {"--light", "0,6cm,-7cm:2"}, {"--fov", "0"},
          {"--size", "1000000x1000000"}, {"--spp", "0"}, {"--light", "0,nan,7cm:2"}, {"--method", "stam"},
          {"--method", "geometric", "--sigma-c", "5um"}, {"--sigma-c", "0.3um"}}) {
        const auto result = run_cli(with({"render", "builtin:isotropic", "-o", exr}, bad));
        EXPECT_EQ(result.exit_code, 1) << bad[0] << " " << bad[1] << ": " << result.output;
        EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
        EXPECT_EQ(testing::count_entries(directory.path()), 0) << result.output;
    }
}

}  // namespace
}  // namespace glintscope

namespace glintscope {
namespace {

// --light-sweep: one EXR and PNG per frame, one exposure for all, and a contact sheet whose
// tiles are the frames' PNGs pixel for pixel (2 × 2 for 3 frames, the fourth black), 2 grey
// pixels apart, each under a 20-pixel grey strip with white label text (none over the empty tile).
TEST(RenderCommand, ALightSweepWritesItsFramesWithOneExposureAndAContactSheetOfThem) {
    TemporaryDirectory directory;
    const auto result = run_cli(with({"render"}, with(kScene, {"--lambda", "0.4um", "--light-sweep", "3", "-o",
                                                               directory.file("s.exr"), "--png", directory.file("s.png")})));
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const auto read = [](const std::string& path, OIIO::ImageSpec& spec) {
        auto input = OIIO::ImageInput::open(path);
        EXPECT_TRUE(input) << path;
        spec = input->spec();
        std::vector<unsigned char> pixels(std::size_t(spec.width) * spec.height * spec.nchannels);
        input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data());
        return pixels;
    };
    OIIO::ImageSpec sheet_spec;
    const std::vector<unsigned char> sheet = read(directory.file("s-sheet.png"), sheet_spec);
    constexpr std::size_t kStrip = 20, kTile = kStrip + 12;
    ASSERT_EQ(sheet_spec.width, 42);
    ASSERT_EQ(sheet_spec.height, int(2 * kTile + 2));
    for (const std::size_t i : {std::size_t(kStrip * 42 + 20), std::size_t(kStrip * 42 + 21), kTile * 42 + 5,
                                (kTile + 1) * 42 + 30})
        EXPECT_EQ(sheet[i * 3], 96) << "gap pixel " << i;
    // The strips: grey with white text over the frames, all grey over the empty fourth tile.
    const auto brightest_in_strip = [&](std::size_t left, std::size_t top) {
        unsigned char brightest = 0;
        for (std::size_t row = top; row < top + kStrip; ++row)
            for (std::size_t col = left; col < left + 20; ++col) {
                EXPECT_GE(sheet[(row * 42 + col) * 3], 96) << "strip pixel " << row << "," << col;
                brightest = std::max(brightest, sheet[(row * 42 + col) * 3]);
            }
        return brightest;
    };
    EXPECT_GT(brightest_in_strip(0, 0), 200);
    EXPECT_GT(brightest_in_strip(22, 0), 200);
    EXPECT_GT(brightest_in_strip(0, kTile + 2), 200);
    EXPECT_EQ(brightest_in_strip(22, kTile + 2), 96);
    std::string exposure;
    for (int k = 0; k < 4; ++k) {
        const std::size_t left = (k % 2) * 22, top = (k / 2) * (kTile + 2) + kStrip;
        std::vector<unsigned char> frame(20 * 12 * 3, 0);
        if (k < 3) {
            EXPECT_TRUE(std::filesystem::exists(directory.file("s-" + std::to_string(k) + ".exr")));
            OIIO::ImageSpec spec;
            frame = read(directory.file("s-" + std::to_string(k) + ".png"), spec);
            const std::string ev = spec.get_string_attribute("glintscope:output.exposure_ev");
            if (k == 0) exposure = ev;
            EXPECT_EQ(ev, exposure);  // one exposure for every frame
        }
        for (std::size_t row = 0; row < 12; ++row)
            for (std::size_t i = 0; i < 20 * 3; ++i)
                ASSERT_EQ(sheet[((top + row) * 42) * 3 + left * 3 + i], frame[row * 20 * 3 + i]) << k;
    }
    const auto refused = run_cli(with({"render"}, with(kScene, {"--light-sweep", "3", "-o", directory.file("t.exr")})));
    EXPECT_NE(refused.exit_code, 0);
    EXPECT_NE(refused.output.find("--light-sweep needs --png"), std::string::npos) << refused.output;
}

// With ffmpeg installed, the sweep's MP4 holds every frame at the frames' size padded to even
// sides, whatever the file name holds: ffmpeg is run without a shell, so a quote, a space, a '%'
// (ffmpeg's own pattern syntax) or a command substitution in the name is just a name.
TEST(RenderCommand, ALightSweepsVideoHoldsEveryFrameWhateverItsFileName) {
    if (testing::run_shell("command -v ffmpeg && command -v ffprobe").exit_code != 0)
        GTEST_SKIP() << "ffmpeg is not installed (scripts/setup.sh installs it)";
    TemporaryDirectory directory;
    std::filesystem::remove("injected");
    const std::string name = "it's 100% $(touch injected)";
    const auto result = run_cli({"render", "builtin:isotropic", "--size", "21x13", "--fov", "4", "--spp", "1",
                                 "--camera", "0,-6cm,6cm:1mm,0,0", "--light", "0,6cm,7cm:2", "--patch", "4cm",
                                 "--sigma-c", "8um", "--lambda", "0.4um", "--order", "1", "--light-sweep", "3", "-o",
                                 directory.file("v.exr"), "--png", directory.file(name + ".png")});
    ASSERT_EQ(result.exit_code, 0) << result.output;
    EXPECT_NE(result.output.find(name + ".mp4: 3 frames at 8 per second"), std::string::npos) << result.output;
    const auto probe = testing::run_shell("ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                                          "stream=nb_read_frames,width,height -of csv=p=0 " +
                                          testing::shell_quote(directory.file(name + ".mp4")));
    ASSERT_EQ(probe.exit_code, 0) << probe.output;
    EXPECT_EQ(probe.output, "22,14,3\n");
    // 3 EXRs, 3 PNGs, the sheet and the video (no partial file), and the substitution never ran
    // (a shell would run it in the working directory).
    EXPECT_EQ(testing::count_entries(directory.path()), 8);
    EXPECT_FALSE(std::filesystem::exists("injected"));
}

}  // namespace
}  // namespace glintscope
