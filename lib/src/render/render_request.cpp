// Render requests (render_request.hpp): the one place where render options become a scene, its
// settings and its colour, for the render command and for batch's render cells alike.
#include "glintscope/render/render_request.hpp"

#include <algorithm>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope {

const std::vector<std::string>& render_keys() {
    static const std::vector<std::string> keys = {"patch", "camera",     "fov",      "size",        "light",
                                                  "light_spectrum", "spp", "exposure", "colour_space"};
    return keys;
}

bool is_render_key(const std::string& key) {
    return std::find(render_keys().begin(), render_keys().end(), key) != render_keys().end();
}

const std::vector<std::string>& render_excluded_query_keys() {
    static const std::vector<std::string> keys = {"quantity", "centre",      "omega_i", "incident",  "incident_xy",
                                                  "res",      "supersample", "memory",  "footprints"};
    return keys;
}

void set_render_key(RenderRequest& request, const std::string& key, const std::string& value) {
    try {
        if (key == "patch") request.patch_um = parse_length_um(value);
        else if (key == "camera") request.camera = value;
        else if (key == "fov") request.fov_degrees = parse_number(value);
        else if (key == "size") request.size = value;
        else if (key == "light") request.lights = split(value, ';');
        else if (key == "light_spectrum") request.light_spectrum = value;
        else if (key == "spp") request.samples_per_pixel = int(parse_integer(value, 1, 1 << 20));
        else if (key == "exposure") request.exposure = value;
        else if (key == "colour_space") request.colour_space = value;
        else throw Error("not a render key (" + join(render_keys()) + ")");
    } catch (const Error& e) {
        throw Error("render key " + key + ": " + e.what());
    }
}

RenderRequest render_request(const std::string& method, const QueryText& keys) {
    RenderRequest request;
    request.method = method;
    const std::vector<std::string>& excluded = render_excluded_query_keys();
    for (const auto& [key, value] : keys) {
        if (std::find(excluded.begin(), excluded.end(), key) != excluded.end())
            throw Error("query key '" + key + "' does not apply to a render (its camera, lights and pixels set it)");
        if (is_render_key(key)) set_render_key(request, key, value);
        else if (key == "heightfield") request.heightfield = value;
        else request.query.emplace_back(key, value);
    }
    return request;
}

RenderSettings render_settings(const RenderRequest& request) {
    RenderSettings settings;
    settings.samples_per_pixel = request.samples_per_pixel;
    return settings;
}

Scene render_view(const RenderRequest& request) {
    Scene scene;
    scene.method = request.method;
    scene.patch_um = request.patch_um;
    scene.camera.vertical_fov_degrees = request.fov_degrees;
    if (!request.camera.empty()) parse_camera(request.camera, scene.camera);
    parse_image_size(request.size, scene.camera);
    if (!request.lights.empty()) {
        scene.lights.clear();
        for (const std::string& light : request.lights) scene.lights.push_back(parse_light(light));
    }
    scene.light_spectrum = parse_illuminant(request.light_spectrum);
    validate_view(scene, render_settings(request));
    return scene;
}

QueryText render_query_text(const RenderRequest& request) {
    if (renders_pixel_footprint(request.method))
        for (const auto& [key, value] : request.query)
            if (key == "sigma_c" || key == "box")
                throw Error(key + " sets the coherence footprint, which a " + request.method +
                            " render does not use: it sees each pixel's footprint on the patch");
    QueryText query = request.query;
    query.emplace_back("heightfield", request.heightfield);
    query.emplace_back("quantity", "brdf");
    check_query_text(query);
    return query;
}

LobeQuery render_query(const RenderRequest& request) { return make_query(render_query_text(request)); }

Scene render_scene(const RenderRequest& request) {
    Scene scene = render_view(request);
    scene.query = render_query(request);
    validate(scene, render_settings(request));
    return scene;
}

ColourSettings render_colour(const RenderRequest& request) {
    ColourSettings colour;
    colour.config_path = request.ocio_config;
    colour.output_space = request.colour_space;
    colour.illuminant = parse_illuminant(request.light_spectrum);
    if (request.exposure != "auto") {
        try {
            colour.exposure_ev = parse_number(request.exposure);
        } catch (const Error&) {
            throw Error("exposure must be 'auto' or a number of stops, got '" + request.exposure + "'");
        }
    }
    scene_linear_chromaticities(colour, colour.output_space);  // an unknown or display space fails before the work
    return colour;
}

}  // namespace glintscope
