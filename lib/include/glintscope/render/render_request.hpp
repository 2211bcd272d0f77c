#pragma once
// A render as the command line and batch manifests ask for it: the scene's options as text or
// numbers, the per-shading-point query keys and the colour options, turned into a Scene,
// RenderSettings and ColourSettings by one set of functions, so that `glintscope render` and a
// manifest's render cell (docs/batch.md) compute the same image from the same options.
#include <string>
#include <vector>

#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/output/colour.hpp"
#include "glintscope/render/render.hpp"

namespace glintscope {

struct RenderRequest {
    std::string heightfield;             // a file, or builtin:KIND
    std::string method = "gabor";
    QueryText query;                     // query keys and method options ("option.KEY") per shading point
    double patch_um = 50000.0;           // the Patch scene's 5 cm
    std::string camera;                  // "X,Y,Z:LX,LY,LZ"; empty: the Patch scene's camera
    double fov_degrees = 30.0;
    std::string size = "1280x720";       // "WIDTHxHEIGHT"
    std::vector<std::string> lights;     // "X,Y,Z:I" each; empty: the Patch scene's light
    std::string light_spectrum = "d65";  // d65 or e
    int samples_per_pixel = 4;
    std::string exposure = "auto";       // the PNG's exposure: auto or EV
    std::string ocio_config;             // empty: $OCIO or the built-in config
    std::string colour_space = "lin_rec709";
};

// The render options a manifest writes by name (patch, camera, fov, size, light, light_spectrum,
// spp, exposure, colour_space), each with its command-line flag's meaning; `light` takes one or
// more lights separated by ';'.
const std::vector<std::string>& render_keys();
bool is_render_key(const std::string& key);

// The query keys a render does not take (the camera and lights set the directions, the shading
// points the footprint's centre, the image its sampling): quantity, centre, omega_i, incident,
// incident_xy, res, supersample, memory, footprints.
const std::vector<std::string>& render_excluded_query_keys();

// Sets one render key from text; throws Error naming the key for a value that does not parse.
void set_render_key(RenderRequest& request, const std::string& key, const std::string& value);

// A request from a manifest cell's keys: render keys set as above, `heightfield` taken out, the
// other keys (query keys and option.KEY) kept as its query. Throws Error for a key a render does
// not take.
RenderRequest render_request(const std::string& method, const QueryText& keys);

// The scene without its query (camera, lights, patch, method) and the settings, checked as
// validate_view checks them: what can be refused before the heightfield is loaded.
Scene render_view(const RenderRequest& request);
RenderSettings render_settings(const RenderRequest& request);

// The query per shading point as text (with the heightfield and quantity brdf), checked without
// loading the heightfield (check_query_text); a geometric method refuses sigma_c and box, which
// set the coherence footprint it does not use.
QueryText render_query_text(const RenderRequest& request);
// The same query built, its heightfield loaded.
LobeQuery render_query(const RenderRequest& request);

// The whole scene, validated (render.hpp validate): render_view with render_query.
Scene render_scene(const RenderRequest& request);

// The colour pipeline's settings (output space, config, exposure, the lights' spectrum as the
// illuminant); an unknown or display-referred output space is refused here.
ColourSettings render_colour(const RenderRequest& request);

}  // namespace glintscope
