// Render requests: every render key a manifest writes sets the scene, settings or colour the
// render command's flag sets, and a query key a render does not take is refused by name.
#include <gtest/gtest.h>

#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/render/render_request.hpp"

namespace glintscope {
namespace {

TEST(RenderRequest, EveryRenderKeySetsWhatItsFlagSets) {
    const RenderRequest request = render_request(
        "geometric", {{"heightfield", "builtin:isotropic"}, {"patch", "4cm"}, {"camera", "0,-6cm,6cm:1mm,0,0"},
                      {"fov", "12.5"}, {"size", "40x30"}, {"light", "0,6cm,7cm:2;5mm,5cm,6cm:0.5"},
                      {"light_spectrum", "e"}, {"spp", "9"}, {"exposure", "2.5"}, {"colour_space", "lin_rec2020"},
                      {"lambda", "0.6um"}, {"option.intrinsic_roughness", "0.01"}});
    EXPECT_EQ(request.heightfield, "builtin:isotropic");
    EXPECT_EQ(request.query, (QueryText{{"lambda", "0.6um"}, {"option.intrinsic_roughness", "0.01"}}));
    const Scene scene = render_view(request);
    EXPECT_EQ(scene.method, "geometric");
    EXPECT_DOUBLE_EQ(scene.patch_um, 40000.0);
    EXPECT_DOUBLE_EQ(scene.camera.position_um.y, -60000.0);
    EXPECT_DOUBLE_EQ(scene.camera.look_at_um.x, 1000.0);
    EXPECT_DOUBLE_EQ(scene.camera.vertical_fov_degrees, 12.5);
    EXPECT_EQ(scene.camera.width, 40);
    EXPECT_EQ(scene.camera.height, 30);
    ASSERT_EQ(scene.lights.size(), 2u);
    EXPECT_DOUBLE_EQ(scene.lights[1].position_um.x, 5000.0);
    EXPECT_DOUBLE_EQ(scene.lights[1].intensity_w_per_sr, 0.5);
    EXPECT_EQ(scene.light_spectrum, Illuminant::e);
    EXPECT_EQ(render_settings(request).samples_per_pixel, 9);
    const ColourSettings colour = render_colour(request);
    EXPECT_EQ(colour.exposure_ev, 2.5);
    EXPECT_EQ(colour.output_space, "lin_rec2020");
    EXPECT_EQ(colour.illuminant, Illuminant::e);
}

TEST(RenderRequest, KeysARenderDoesNotTakeAreRefusedByName) {
    for (const std::string key : {"res", "incident", "centre", "supersample"}) {
        try {
            render_request("gabor", {{key, "1"}});
            ADD_FAILURE() << key << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("'" + key + "' does not apply to a render"), std::string::npos) << e.what();
        }
    }
    // A geometric render sees the pixel's footprint: the coherence footprint's keys are refused.
    RenderRequest geometric = render_request("geometric", {{"heightfield", "builtin:isotropic"}, {"sigma_c", "5um"}});
    EXPECT_THROW(render_query_text(geometric), Error);
    geometric.method = "gabor";
    EXPECT_NO_THROW(render_query_text(geometric));
}

}  // namespace
}  // namespace glintscope
