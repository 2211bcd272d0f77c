// Dong 2015 §9: ellipsoid parameters fitted per patch, as maps.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include "cli_runner.hpp"
#include "ellipsoid_expect.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/maps/ellipsoid_maps.hpp"

namespace glintscope {
namespace {

TEST(EllipsoidMaps, PerPatchFitsRecoverEachPatchAndRoundTripThroughExr) {
    const auto truth = [](int row, int col) {
        return EllipsoidNdf{0.2 + 0.1 * col, 0.08 + 0.02 * row, 0.05 * (row + 1), -0.04 * (col + 1), 0.3 * (col - row)};
    };
    const EllipsoidMaps maps = fit_ellipsoid_maps(2, 3, [&](int row, int col) {
        return model_ndf_image({NdfModelKind::ellipsoid, truth(row, col)}, 64);
    });
    ASSERT_EQ(maps.parameters.size(), 6u);
    for (int row = 0; row < 2; ++row)
        for (int col = 0; col < 3; ++col) testing::expect_within_percent(maps.parameters[row * 3 + col], truth(row, col));

    testing::TemporaryDirectory directory;
    const std::string path = directory.file("maps.exr");
    write_ellipsoid_maps_exr(maps, path);
    auto input = OIIO::ImageInput::open(path);
    ASSERT_TRUE(input);
    ASSERT_EQ(input->spec().nchannels, 6);
    std::vector<float> pixels(6 * 6);
    ASSERT_TRUE(input->read_image(0, 0, 0, 6, OIIO::TypeDesc::FLOAT, pixels.data()));
    const auto channel = [&](const std::string& name) { return input->spec().channelindex(name); };
    ASSERT_GE(channel("theta_z"), 0);
    EXPECT_EQ(pixels[6 * 5 + channel("alpha_x")], float(maps.parameters[5].alpha_x));  // row 1, col 2
    EXPECT_EQ(pixels[6 * 5 + channel("theta_z")], float(maps.parameters[5].theta_z));
    EXPECT_EQ(pixels[6 * 5 + channel("relative_error")], float(maps.relative_error[5]));
}

TEST(EllipsoidMaps, EveryPatchOfABrushedFieldIsAnisotropic) {
    Recipe recipe = default_recipe("brushed");
    recipe.grid.rows = recipe.grid.cols = 256;
    recipe.gaussian.correlation_length_x_um = 64.0;
    LobeQuery query;
    set_heightfield(query, generate(recipe));
    query.resolution = 64;
    const EllipsoidMaps maps = fit_ellipsoid_maps(query, "pndf", 128.0);
    ASSERT_EQ(maps.rows, 2);
    ASSERT_EQ(maps.cols, 2);
    // Brushing is local: each 128 µm patch shows the field's strong anisotropy.
    // Roughness across the grooves, along y, in the canonical frame (|theta_z| <= pi/4).
    for (const EllipsoidNdf& p : maps.parameters) EXPECT_GT(p.alpha_y / p.alpha_x, 2.0);
}

}  // namespace
}  // namespace glintscope
