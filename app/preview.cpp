// glintscope preview FILE -o PNG: the heights colour-mapped in map view, with a legend.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "commands.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/output/colormap.hpp"
#include "glintscope/output/figure.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/core/units.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "options.hpp"

namespace glintscope::cli {
namespace {

struct PreviewSettings {
    std::string input;
    std::string output;
    std::string colormap = "viridis";
    LoadOptions load;
    bool bare = false;
    std::vector<std::string> centre;
    double sigma_c_um = 0.0;
    std::string box;
};

// The footprint to draw, when --centre was given (a Gaussian of --sigma-c, default 10 µm, or
// a --box).
std::optional<Footprint> footprint_of(const PreviewSettings& settings) {
    if (settings.centre.empty()) return std::nullopt;
    Footprint footprint;
    footprint.centre_um = {parse_length_um(settings.centre[0]), parse_length_um(settings.centre[1])};
    if (settings.sigma_c_um > 0.0) footprint.sigma_um = settings.sigma_c_um;
    if (!settings.box.empty()) set_box(footprint, settings.box);
    validate(footprint);
    return footprint;
}

void run_preview(const PreviewSettings& settings) {
    check_output_path(settings.output, {"png"}, "-o");
    const ColorMap map = parse_colormap(settings.colormap);
    const std::optional<Footprint> footprint = footprint_of(settings);
    const Heightfield field = load_heightfield_argument(settings.input, settings.load);
    if (!settings.bare) {
        write_height_picture(field, settings.output, map, footprint ? &*footprint : nullptr);
        return;
    }
    ColorLegend legend{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), "height [um]",
                       map};
    for (float height : field.heights_um) {
        if (std::isnan(height)) continue;
        legend.min_value = std::min(legend.min_value, static_cast<double>(height));
        legend.max_value = std::max(legend.max_value, static_cast<double>(height));
    }
    // Heightfield rows already run from the largest y down, as the picture does.
    write_colormapped_png(settings.output,
                          at_true_aspect({field.rows, field.cols, field.heights_um}, field.width_um(), field.height_um()),
                          legend);
}

}  // namespace

void add_preview_command(CLI::App& app) {
    auto settings = std::make_shared<PreviewSettings>();
    CLI::App* command =
        app.add_subcommand("preview",
                           "Draw a heightfield as a colour-mapped PNG in map view (+x right, +y up), with a legend of "
                           "the height range in um; missing points are grey");
    command
        ->add_option("file", settings->input,
                     "Heightfield file (.x3p, .exr, .tif, .png, .npy or any image) or builtin:KIND")
        ->required();
    command->add_option("-o,--output", settings->output, "Output picture (.png)")->required()->type_name("PNG");
    command->add_option("--colormap", settings->colormap, "Colour map")
        ->check(CLI::IsMember({"viridis", "inferno"}))
        ->capture_default_str();
    add_load_options(*command, settings->load);
    command->add_flag("--bare", settings->bare, "The heights and their legend only (no axes, scale bar or footprint)");
    command->add_option("--centre", settings->centre, "Draw a footprint centred at X,Y (lengths)")
        ->delimiter(',')
        ->expected(2);
    add_length_option(*command, "--sigma-c", settings->sigma_c_um, "Coherence sigma of the drawn footprint (default 10um)");
    command->add_option("--box", settings->box,
                        "Draw a box footprint of this side (or sides along x and y, e.g. 70x53um) instead");
    command->callback([settings] { run_preview(*settings); });
}

}  // namespace glintscope::cli
