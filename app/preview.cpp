// glintscope preview FILE -o PNG: the heights colour-mapped in map view, with a legend; and, on
// request, the plots metrologists read first: the power spectral density (--psd), the
// autocorrelation (--acf) and the slope distribution beside the whole-field P-NDF (--slopes).
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "commands.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/output/colormap.hpp"
#include "glintscope/output/figure.hpp"
#include "glintscope/output/surface_plots.hpp"
#include "glintscope/pipeline/slope_comparison.hpp"
#include "glintscope/surface/spectra.hpp"
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
    std::string psd;     // PNG paths; empty: not drawn
    std::string acf;
    std::string slopes;
};

// The projected-disk resolution of the --slopes panels.
constexpr int kSlopeResolution = 256;

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

void write_slope_figure(const Heightfield& field, const std::string& path) {
    const SlopeComparison comparison = compare_slopes_with_pndf(field, kSlopeResolution);
    Figure figure;
    figure.title = "Slope distribution (ISO 25178-2 4.6) and the whole-field P-NDF";
    figure.caption = "Projected-area density of normals on the projected disk (sum D (2/N)^2 = 1): left from the "
                     "samples' central differences, right from the interpolant's gradient";
    figure.column_labels = {"slope histogram", "P-NDF (pndf, whole field)"};
    figure.row_labels = {""};
    figure.cells = {{&comparison.slopes, &comparison.pndf}};
    figure.exposure = SharedExposure::whole_figure;
    const LobeOutputOptions options;
    write_figure(figure, path, options);
}

void run_preview(const PreviewSettings& settings) {
    if (settings.output.empty() && settings.psd.empty() && settings.acf.empty() && settings.slopes.empty())
        throw Error("preview needs an output: -o, --psd, --acf or --slopes");
    for (const auto& [path, flag] : {std::pair{settings.output, "-o"}, std::pair{settings.psd, "--psd"},
                                     std::pair{settings.acf, "--acf"}, std::pair{settings.slopes, "--slopes"}})
        if (!path.empty()) check_output_path(path, {"png"}, flag);
    const ColorMap map = parse_colormap(settings.colormap);
    const std::optional<Footprint> footprint = footprint_of(settings);
    const Heightfield field = load_heightfield_argument(settings.input, settings.load);
    if (!settings.psd.empty()) write_plots(power_spectral_density_plots(compute_power_spectral_density(field)), settings.psd);
    if (!settings.acf.empty()) write_plot(autocorrelation_plot(compute_autocorrelation_curves(field)), settings.acf);
    if (!settings.slopes.empty()) write_slope_figure(field, settings.slopes);
    if (settings.output.empty()) return;
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
    command->add_option("-o,--output", settings->output, "Output picture of the heights (.png)")->type_name("PNG");
    command
        ->add_option("--psd", settings->psd,
                     "Also plot the power spectral density: radially averaged (um^4) and along x and y (um^3), "
                     "log-log, normalised so that it integrates to Sq^2 (.png)")
        ->type_name("PNG");
    command
        ->add_option("--acf", settings->acf,
                     "Also plot the autocorrelation along x, along y and radially averaged, with s = 0.2 and info's "
                     "Sal marked (.png)")
        ->type_name("PNG");
    command
        ->add_option("--slopes", settings->slopes,
                     "Also draw the slope distribution (ISO 25178-2 4.6) beside the whole-field P-NDF, on one scale "
                     "(.png)")
        ->type_name("PNG");
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
