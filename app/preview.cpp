// glintscope preview FILE -o PNG: the heights colour-mapped in map view, with a legend.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "commands.hpp"
#include "glintscope/colormap.hpp"
#include "glintscope/heightfield_io.hpp"
#include "options.hpp"

namespace glintscope::cli {
namespace {

struct PreviewSettings {
    std::string input;
    std::string output;
    std::string colormap = "viridis";
    LoadOptions load;
};

void run_preview(const PreviewSettings& settings) {
    const ColorMap map = parse_colormap(settings.colormap);
    const Heightfield field = load_heightfield_argument(settings.input, settings.load);
    ColorLegend legend{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), "height [um]",
                       map};
    for (float height : field.heights_um) {
        if (std::isnan(height)) continue;
        legend.min_value = std::min(legend.min_value, static_cast<double>(height));
        legend.max_value = std::max(legend.max_value, static_cast<double>(height));
    }
    // Heightfield rows already run from the largest y down, as the picture does.
    write_colormapped_png(settings.output, ScalarImage{field.rows, field.cols, field.heights_um}, legend);
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
    command->callback([settings] { run_preview(*settings); });
}

}  // namespace glintscope::cli
