// glintscope fit ellipsoid NDF.exr -o FIT.json [--image FITTED.exr] [--residual RESIDUAL.exr]
// [--plot FIT.png] [--models ellipsoid,beckmann,ggx]: parametric NDFs fitted to an NDF image
// (Dong 2015 §8).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/output/lobe_output.hpp"
#include "glintscope/fit/ndf_fit.hpp"
#include "glintscope/fit/ndf_fit_slices.hpp"
#include "glintscope/output/fit_plot.hpp"

namespace glintscope::cli {
namespace {

struct FitSettings {
    std::string family;
    std::string input;
    std::string output;
    std::string image;
    std::string residual;
    std::string plot;
    std::vector<std::string> models{"ellipsoid"};
};

// data − model, pixel by pixel (0 outside the disk, where both are 0).
LobeImage residual_image(const LobeImage& data, const LobeImage& model) {
    LobeImage residual = model;
    for (std::size_t i = 0; i < residual.values.size(); ++i) residual.values[i] = data.values[i] - model.values[i];
    residual.metadata["ndf.residual"] = "data - model";
    return residual;
}

void run_fit(const FitSettings& settings) {
    std::vector<NdfModelKind> kinds;
    for (const std::string& name : settings.models) kinds.push_back(parse_ndf_model_kind(name));
    check_output_path(settings.output, {"json"}, "-o");
    if (!settings.image.empty()) check_output_path(settings.image, {"exr"}, "--image");
    if (!settings.residual.empty()) check_output_path(settings.residual, {"exr"}, "--residual");
    if (!settings.plot.empty()) check_output_path(settings.plot, {"png"}, "--plot");
    const LobeImage data = load_lobe_exr(settings.input);
    std::vector<NdfFit> fits;
    for (NdfModelKind kind : kinds) {
        fits.push_back(fit_ndf(data, kind));
        std::printf("%s: relative error %.4g\n", to_string(kind).c_str(), fits.back().relative_error);
    }
    write_text_file(settings.output, ndf_fits_json(fits, settings.input));
    LobeImage fitted = model_ndf_image(fits.front().model, data.resolution);
    fitted.metadata["command_line"] = invocation();
    if (!settings.image.empty()) write_lobe_exr(fitted, settings.image, {});
    if (!settings.residual.empty()) write_lobe_exr(residual_image(data, fitted), settings.residual, {});
    if (!settings.plot.empty()) write_plots(ndf_fit_plots(ndf_fit_slices(data, fits, 401), fits, settings.input), settings.plot);
}

}  // namespace

void add_fit_command(CLI::App& app) {
    // One positional names the family ("ellipsoid" fits it and its special cases), so that the
    // whole command, options included, is one --help page.
    CLI::App* command = app.add_subcommand(
        "fit", "Fit the ellipsoid NDF (Dong 2015 eq. 10), Beckmann and GGX to an NDF image by least squares over the projected disk");
    auto settings = std::make_shared<FitSettings>();
    command->add_option("family", settings->family, "What to fit: ellipsoid (the only family so far)")
        ->required()
        ->check(CLI::IsMember({"ellipsoid"}));
    command->add_option("ndf", settings->input, "NDF image (EXR written by 'glintscope ndf')")->required();
    command->add_option("-o,--output", settings->output, "JSON report: parameters (angles in degrees) and relative errors")
        ->required();
    command->add_option("--image", settings->image, "EXR of the first model's fitted NDF");
    command->add_option("--residual", settings->residual, "EXR of the NDF minus the first model's fit");
    command->add_option("--plot", settings->plot,
                        "PNG: the NDF against every fitted model along and across the first fit's principal axes (log D against the polar angle)");
    command->add_option("--models", settings->models, "Models to fit, comma separated: ellipsoid, beckmann, ggx (default ellipsoid)")
        ->delimiter(',');
    command->callback([settings] { run_fit(*settings); });
}

}  // namespace glintscope::cli
