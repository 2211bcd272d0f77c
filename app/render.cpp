// glintscope render HEIGHTFIELD -o OUT.exr: a lit patch of the surface through a pinhole camera
// (Yan 2018 Fig. 12, "Patch"): the heightfield tiled over the patch, point lights, each pixel the
// mean radiance of --spp shading points whose f_r is the method's BSDF at a footprint there.
#include "commands.hpp"
#include "options.hpp"
#include "progress.hpp"
#include "query_flags.hpp"

#include <cstdio>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/render/render_output.hpp"

namespace glintscope::cli {
namespace {

struct RenderCommand {
    std::string heightfield;
    std::string output;
    std::string png;
    std::string method = "gabor";
    QueryText given;
    std::string camera;
    std::string size = "1280x720";
    std::vector<std::string> lights;
    std::string light_spectrum = "d65";
    std::string exposure = "auto";
    std::string ocio_config;
    std::string colour_space = "lin_rec709";
    Scene scene;
    RenderSettings settings;
};

// The scene without its query, checked before the heightfield is loaded.
Scene view_of(const RenderCommand& command) {
    Scene scene = command.scene;
    scene.method = command.method;
    if (!command.camera.empty()) parse_camera(command.camera, scene.camera);
    parse_image_size(command.size, scene.camera);
    if (!command.lights.empty()) {
        scene.lights.clear();
        for (const std::string& light : command.lights) scene.lights.push_back(parse_light(light));
    }
    scene.light_spectrum = parse_illuminant(command.light_spectrum);
    validate_view(scene, command.settings);
    return scene;
}

LobeQuery query_of(const RenderCommand& command) {
    QueryText given = command.given;
    given.emplace_back("heightfield", command.heightfield);
    given.emplace_back("quantity", "brdf");
    check_query_text(given);
    return make_query(given);
}

ColourSettings colour_of(const RenderCommand& command, Illuminant light_spectrum) {
    ColourSettings colour;
    colour.config_path = command.ocio_config;
    colour.output_space = command.colour_space;
    colour.illuminant = light_spectrum;
    if (command.exposure != "auto") {
        try {
            colour.exposure_ev = parse_number(command.exposure);
        } catch (const Error&) {
            throw Error("--exposure must be 'auto' or a number of stops, got '" + command.exposure + "'");
        }
    }
    scene_linear_chromaticities(colour, colour.output_space);  // an unknown or display space fails before the work
    return colour;
}

void run(const RenderCommand& command) {
    check_output_path(command.output, {"exr"}, "-o");
    if (!command.png.empty()) check_output_path(command.png, {"png"}, "--png");
    Scene scene = view_of(command);
    const ColourSettings colour = colour_of(command, scene.light_spectrum);
    scene.query = query_of(command);
    validate(scene, command.settings);
    RenderImage image;
    {
        ProgressBar progress("rows");
        image = render(scene, command.settings,
                       [&](std::size_t done, std::size_t total) { progress.update(done, total, scene.method); });
    }
    image.metadata["command_line"] = invocation();
    write_render_exr(image, command.output, colour);
    if (!command.png.empty()) {
        const DisplayExposure exposure = write_render_png(image, command.png, colour);
        std::printf("%s: exposure %.4g EV (%s)\n", command.png.c_str(), exposure.ev, exposure.rule.c_str());
    }
    std::printf("%s: %dx%d, %d spp, %s, %zu wavelength(s)\n", command.output.c_str(), image.width, image.height,
                command.settings.samples_per_pixel, scene.method.c_str(), image.wavelengths_um.size());
}

}  // namespace

void add_render_command(CLI::App& app) {
    CLI::App* sub = app.add_subcommand(
        "render", "Render a lit patch tiled with the heightfield through a pinhole camera (Yan 2018 Fig. 12)");
    auto command = std::make_shared<RenderCommand>();
    sub->add_option("heightfield", command->heightfield, "Heightfield file, or builtin:KIND (isotropic, brushed, ...)")
        ->required();
    sub->add_option("-o,--output", command->output,
                    "Output EXR: radiance [W m^-2 sr^-1], Y at one wavelength or linear R, G, B of a spectrum")
        ->required();
    sub->add_option("--png", command->png, "Also write a display PNG (its exposure is printed and recorded)");
    sub->add_option("--method", command->method, "Method, one with a BSDF per shading point: " + join(bsdf_field_methods()))
        ->capture_default_str();
    add_length_option(*sub, "--patch", command->scene.patch_um, "Side of the square patch (default 5cm)");
    sub->add_option("--camera", command->camera,
                    "Camera position and look-at point, lengths (default 0,-7.0711cm,7.0711cm:0,0,0: 45 deg elevation)")
        ->type_name("X,Y,Z:LX,LY,LZ");
    sub->add_option("--fov", command->scene.camera.vertical_fov_degrees, "Vertical field of view, degrees")
        ->capture_default_str();
    sub->add_option("--size", command->size, "Image size in pixels")->type_name("WxH")->capture_default_str();
    sub->add_option("--light", command->lights,
                    "Point light: position (lengths) and intensity in W/sr, repeatable (default "
                    "0,7.0711cm,7.0711cm:1: opposite the camera)")
        ->type_name("X,Y,Z:I");
    sub->add_option("--light-spectrum", command->light_spectrum, "Spectrum of the lights, for spectral renders: d65 or e")
        ->capture_default_str();
    sub->add_option("--spp", command->settings.samples_per_pixel,
                    "Shading points per pixel, a square number (n x n on a regular sub-pixel grid)")
        ->capture_default_str();
    add_query_flags(*sub, command->given, Quantity::brdf,
                    {"quantity", "centre", "omega_i", "incident", "incident_xy", "res", "supersample", "memory",
                     "footprints"});
    add_method_option_flags(*sub, command->given, Quantity::brdf, bsdf_field_methods());
    sub->add_option("--exposure", command->exposure, "PNG exposure: auto or EV")->capture_default_str();
    sub->add_option("--ocio-config", command->ocio_config, "OpenColorIO config (default: $OCIO or built in)");
    sub->add_option("--colour-space", command->colour_space, "Scene-linear output colour space of a spectral EXR")
        ->capture_default_str();
    sub->callback([command] { run(*command); });
}

}  // namespace glintscope::cli
