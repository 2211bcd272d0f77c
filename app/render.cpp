// glintscope render HEIGHTFIELD -o OUT.exr: a lit patch of the surface through a pinhole camera
// (Yan 2018 Fig. 12, "Patch"): the heightfield tiled over the patch, point lights, each pixel the
// mean radiance of --spp shading points whose f_r is the method's BSDF at a footprint there.
#include "commands.hpp"
#include "options.hpp"
#include "progress.hpp"
#include "query_flags.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/render/render_output.hpp"
#include "glintscope/render/render_request.hpp"

namespace glintscope::cli {
namespace {

struct RenderCommand {
    RenderRequest request;  // the scene, query and colour options (render_request.hpp)
    std::string output;
    std::string png;
    int sweep_frames = 0;  // 0: one image
    double sweep_span_um = 0.0;  // 0: the patch side
};

// PATH without its extension, then -NN and the extension: frame k of a sweep of `frames`.
std::string frame_path(const std::string& path, int k, int frames) {
    const std::filesystem::path p(path);
    const int digits = static_cast<int>(std::to_string(frames - 1).size());
    std::string number = std::to_string(k);
    number.insert(0, std::size_t(std::max(0, digits - int(number.size()))), '0');
    return (p.parent_path() / (p.stem().string() + "-" + number + p.extension().string())).string();
}

std::string with_suffix(const std::string& path, const std::string& suffix) {
    const std::filesystem::path p(path);
    return (p.parent_path() / (p.stem().string() + suffix)).string();
}

// Runs a program found on the PATH with these arguments, without a shell, so that file names
// pass as they are (quotes, spaces, a leading '-' or '$' are not syntax); its exit status, or
// nothing when it cannot be started (not installed).
std::optional<int> run_program(const std::vector<std::string>& arguments) {
    std::vector<char*> argv;
    for (const std::string& argument : arguments) argv.push_back(const_cast<char*>(argument.c_str()));
    argv.push_back(nullptr);
    pid_t child = 0;
    if (posix_spawnp(&child, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return std::nullopt;
    int status = 0;
    while (waitpid(child, &status, 0) < 0)
        if (errno != EINTR) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// A file name that ffmpeg cannot take for an option (a relative name starting with '-').
std::string not_an_option(const std::filesystem::path& path) {
    return path.is_absolute() ? path.string() : "./" + path.string();
}

// A file name in ffmpeg's image sequence pattern, which takes %% for a literal %.
std::string pattern_text(const std::string& name) {
    std::string escaped;
    for (const char c : name) escaped += c == '%' ? std::string("%%") : std::string(1, c);
    return escaped;
}

// The frames as an MP4 through ffmpeg when it is installed (a note otherwise), written beside
// the PNGs under a temporary name and renamed, as every output is. Odd frame sizes are padded
// to even ones (H.264 in yuv420p needs them); -nostdin keeps ffmpeg off the terminal.
void write_sweep_video(const std::string& png, int frames) {
    const std::string video = with_suffix(png, ".mp4"), partial = with_suffix(png, ".partial.mp4");
    const std::filesystem::path p(png);
    const std::string digits = std::to_string(std::to_string(frames - 1).size());
    const std::string pattern = pattern_text(not_an_option(p.parent_path() / p.stem())) + "-%0" + digits + "d.png";
    const std::optional<int> status =
        run_program({"ffmpeg", "-nostdin", "-y", "-loglevel", "error", "-framerate", "8", "-i", pattern, "-vf",
                     "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p", "-f", "mp4", not_an_option(partial)});
    if (!status) {
        std::printf("no MP4: ffmpeg is not installed (apt-get install ffmpeg); the frames and the contact sheet are written\n");
        return;
    }
    if (*status != 0) {
        std::filesystem::remove(partial);
        throw Error("ffmpeg could not write '" + video + "' from the frames");
    }
    std::filesystem::rename(partial, video);
    std::printf("%s: %d frames at 8 per second\n", video.c_str(), frames);
}

// --light-sweep N: N renders with the lights moved left to right, one EXR and PNG per frame, one
// exposure for all, a contact sheet and (with ffmpeg) an MP4.
void run_sweep(const RenderCommand& command, const Scene& scene, const RenderSettings& settings,
               const ColourSettings& colour) {
    const double span = command.sweep_span_um > 0.0 ? command.sweep_span_um : scene.patch_um;
    std::vector<RenderImage> frames;
    {
        ProgressBar progress("rows of all frames");
        frames = render_light_sweep(scene, command.sweep_frames, span, settings,
                                    [&](std::size_t done, std::size_t total) { progress.update(done, total, scene.method); });
    }
    for (const std::string& warning : frames.front().warnings) std::fprintf(stderr, "glintscope: warning: %s\n", warning.c_str());
    for (RenderImage& frame : frames) frame.metadata["command_line"] = invocation();
    const int n = static_cast<int>(frames.size());
    std::vector<std::string> pngs;
    for (int k = 0; k < n; ++k) {
        write_render_exr(frames[k], frame_path(command.output, k, n), colour);
        pngs.push_back(frame_path(command.png, k, n));
    }
    const std::string sheet = with_suffix(command.png, "-sheet.png");
    const DisplayExposure exposure = write_sweep_pngs(frames, pngs, sheet, colour);
    std::printf("%s .. %s: %d frames, lights swept over %s, exposure %.4g EV (%s) for all\n", pngs.front().c_str(),
                pngs.back().c_str(), n, format_length(span).c_str(), exposure.ev, exposure.rule.c_str());
    std::printf("%s: contact sheet\n", sheet.c_str());
    write_sweep_video(command.png, n);
}

void run(const RenderCommand& command) {
    check_output_path(command.output, {"exr"}, "-o");
    if (!command.png.empty()) check_output_path(command.png, {"png"}, "--png");
    Scene scene = render_view(command.request);
    const RenderSettings settings = render_settings(command.request);
    if (command.sweep_frames > 0) {  // its frames and outputs checked before the heightfield is read
        if (command.png.empty()) throw Error("--light-sweep needs --png: the frames and their contact sheet are PNGs");
        light_sweep(scene, command.sweep_frames, command.sweep_span_um > 0.0 ? command.sweep_span_um : scene.patch_um);
    }
    const ColourSettings colour = render_colour(command.request);
    scene.query = render_query(command.request);
    validate(scene, settings);
    if (command.sweep_frames > 0) return run_sweep(command, scene, settings, colour);
    RenderImage image;
    {
        ProgressBar progress("rows");
        image = render(scene, settings, [&](std::size_t done, std::size_t total) { progress.update(done, total, scene.method); });
    }
    for (const std::string& warning : image.warnings) std::fprintf(stderr, "glintscope: warning: %s\n", warning.c_str());
    image.metadata["command_line"] = invocation();
    write_render_exr(image, command.output, colour);
    if (!command.png.empty()) {
        const DisplayExposure exposure = write_render_png(image, command.png, colour);
        std::printf("%s: exposure %.4g EV (%s)\n", command.png.c_str(), exposure.ev, exposure.rule.c_str());
    }
    std::printf("%s: %dx%d, %d spp, %s, %zu wavelength(s)\n", command.output.c_str(), image.width, image.height,
                settings.samples_per_pixel, scene.method.c_str(), image.wavelengths_um.size());
}

}  // namespace

void add_render_command(CLI::App& app) {
    CLI::App* sub = app.add_subcommand(
        "render", "Render a lit patch tiled with the heightfield through a pinhole camera (Yan 2018 Fig. 12)");
    auto command = std::make_shared<RenderCommand>();
    sub->add_option("heightfield", command->request.heightfield, "Heightfield file, or builtin:KIND (isotropic, brushed, ...)")
        ->required();
    sub->add_option("-o,--output", command->output,
                    "Output EXR: radiance [W m^-2 sr^-1], Y at one wavelength or linear R, G, B of a spectrum")
        ->required();
    sub->add_option("--png", command->png, "Also write a display PNG (its exposure is printed and recorded)");
    sub->add_option("--method", command->request.method, "Method, one with a BSDF per shading point: " + join(bsdf_field_methods()))
        ->capture_default_str();
    add_length_option(*sub, "--patch", command->request.patch_um, "Side of the square patch (default 5cm)");
    sub->add_option("--camera", command->request.camera,
                    "Camera position and look-at point, lengths (default 0,-7.0711cm,7.0711cm:0,0,0: 45 deg elevation)")
        ->type_name("X,Y,Z:LX,LY,LZ");
    sub->add_option("--fov", command->request.fov_degrees, "Vertical field of view, degrees")
        ->capture_default_str();
    sub->add_option("--size", command->request.size, "Image size in pixels")->type_name("WxH")->capture_default_str();
    sub->add_option("--light", command->request.lights,
                    "Point light: position (lengths) and intensity in W/sr, repeatable (default "
                    "0,7.0711cm,7.0711cm:1: opposite the camera)")
        ->type_name("X,Y,Z:I");
    sub->add_option("--light-spectrum", command->request.light_spectrum, "Spectrum of the lights, for spectral renders: d65 or e")
        ->capture_default_str();
    sub->add_option("--spp", command->request.samples_per_pixel,
                    "Shading points per pixel, a square number (n x n on a regular sub-pixel grid)")
        ->capture_default_str();
    sub->add_option("--light-sweep", command->sweep_frames,
                    "Render N frames (2-256) with the lights moving left to right (Yan 2018's video): OUT-K.exr and "
                    "PNG-K.png per frame, one exposure for all, PNG-sheet.png, and PNG.mp4 when ffmpeg is installed")
        ->type_name("N")
        ->check(CLI::Range(2, 256));
    add_length_option(*sub, "--sweep-span", command->sweep_span_um,
                      "How far the lights move during --light-sweep, along the camera's right (default: the patch side)");
    add_query_flags(*sub, command->request.query, Quantity::brdf, render_excluded_query_keys());
    add_method_option_flags(*sub, command->request.query, Quantity::brdf, bsdf_field_methods());
    sub->add_option("--exposure", command->request.exposure, "PNG exposure: auto or EV")->capture_default_str();
    sub->add_option("--ocio-config", command->request.ocio_config, "OpenColorIO config (default: $OCIO or built in)");
    sub->add_option("--colour-space", command->request.colour_space, "Scene-linear output colour space of a spectral EXR")
        ->capture_default_str();
    sub->callback([command] { run(*command); });
}

}  // namespace glintscope::cli
