// glintscope lobe HEIGHTFIELD --method fft|gabor -o OUT.exr: a reflection lobe over the
// projected hemisphere for one coherence footprint and one incident direction.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "commands.hpp"
#include "glintscope/error.hpp"
#include "glintscope/lobe.hpp"
#include "glintscope/lobe_output.hpp"
#include "glintscope/spectrum.hpp"
#include "glintscope/units.hpp"
#include "options.hpp"

namespace glintscope::cli {
namespace {

struct LobeSettings {
    std::string input;
    LoadOptions load;
    std::string method = "gabor";
    std::string output;
    std::string png;
    std::string json;
    std::vector<std::string> centre;
    double sigma_c_um = 10.0;
    double box_um = 0.0;
    std::vector<double> incident_deg;
    std::vector<double> incident_xy;
    double lambda_um = 0.5;
    int spectral_bins = 0;
    std::string model = "rohs";
    std::string material;
    int resolution = 256;
    int supersample = 1;
    std::string kernels_per_texel;
    std::vector<std::string> method_options;
    std::string illuminant = "d65";
    std::string exposure = "auto";
    bool log_scale = false;
    std::string colormap = "inferno";
    bool spectral_channels = false;
    std::string ocio_config;
    std::string colour_space = "lin_rec709";
};

Vec3 incident_direction(const LobeSettings& settings) {
    if (!settings.incident_xy.empty()) {
        const double x = settings.incident_xy[0];
        const double y = settings.incident_xy[1];
        if (!(x * x + y * y < 1.0)) throw Error("--incident-xy must lie inside the unit disk, got " +
                                                std::to_string(x) + "," + std::to_string(y));
        return direction_from_disk(x, y);
    }
    if (settings.incident_deg.empty()) return {0.0, 0.0, 1.0};
    const double theta = settings.incident_deg[0];
    if (!(theta >= 0.0 && theta < 90.0))
        throw Error("--incident theta must be in [0, 90) degrees, got " + std::to_string(theta));
    return direction_from_spherical(degrees_to_radians(theta), degrees_to_radians(settings.incident_deg[1]));
}

LobeQuery build_query(const LobeSettings& settings) {
    LobeQuery query;
    set_heightfield(query, load_heightfield_argument(settings.input, settings.load));
    query.footprint.centre_um = query.field->centre_um();
    if (!settings.centre.empty())
        query.footprint.centre_um = {parse_length_um(settings.centre[0]), parse_length_um(settings.centre[1])};
    query.footprint.sigma_um = settings.sigma_c_um;
    if (settings.box_um > 0.0) {
        query.footprint.shape = FootprintShape::box;
        query.footprint.size_um = settings.box_um;
    }
    query.omega_i = incident_direction(settings);
    query.wavelengths_um = settings.spectral_bins > 0 ? spectral_bin_centres_um(settings.spectral_bins)
                                                      : std::vector<double>{settings.lambda_um};
    query.model = parse_diffraction_model(settings.model);
    query.material.name = settings.material;
    query.resolution = settings.resolution;
    query.supersample = settings.supersample;
    if (!settings.kernels_per_texel.empty()) query.method_options["kernels_per_texel"] = settings.kernels_per_texel;
    for (const std::string& option : settings.method_options) {
        const auto equals = option.find('=');
        if (equals == std::string::npos || equals == 0)
            throw Error("--option '" + option + "' is not of the form KEY=VALUE");
        query.method_options[option.substr(0, equals)] = option.substr(equals + 1);
    }
    return query;
}

// The coherence window blurs the lobe by about λ/(2πσ_c) in disk units; a pixel is 2/N wide.
void warn_if_undersampled(const LobeQuery& query) {
    if (query.supersample > 1 || query.footprint.shape != FootprintShape::gaussian) return;
    const double blur = query.wavelengths_um.front() / (2.0 * std::numbers::pi * query.footprint.sigma_um);
    const double pixel = 2.0 / query.resolution;
    if (blur < pixel)
        std::fprintf(stderr,
                     "glintscope: warning: the coherence blur lambda/(2 pi sigma_c) = %.4g is smaller than a pixel "
                     "(%.4g); the lobe is point-sampled (use --supersample or a larger --res)\n",
                     blur, pixel);
}

LobeOutputOptions output_options(const LobeSettings& settings) {
    LobeOutputOptions options;
    options.colour.config_path = settings.ocio_config;
    options.colour.output_space = settings.colour_space;
    options.colour.illuminant = parse_illuminant(settings.illuminant);
    options.colour.log_scale = settings.log_scale;
    if (settings.exposure != "auto") {
        char* end = nullptr;
        const double ev = std::strtod(settings.exposure.c_str(), &end);
        if (end == settings.exposure.c_str() || *end != '\0' || !std::isfinite(ev))
            throw Error("--exposure must be 'auto' or a number of stops, got '" + settings.exposure + "'");
        options.colour.exposure_ev = ev;
    }
    options.colormap = settings.colormap;
    options.spectral_channels = settings.spectral_channels;
    return options;
}

void run(const LobeSettings& settings) {
    lobe_method_description(settings.method);  // an unknown method fails before any work
    const LobeOutputOptions options = output_options(settings);
    const LobeQuery query = build_query(settings);
    validate(query);
    warn_if_undersampled(query);
    const LobeImage lobe = compute_lobe(settings.method, query);
    write_lobe_exr(lobe, settings.output, options);
    if (!settings.png.empty()) write_lobe_png(lobe, settings.png, options);
    if (!settings.json.empty()) write_lobe_json(lobe, settings.json, options);
    for (const WavelengthSummary& summary : summarize_lobe(lobe))
        std::printf("lambda %.4g um: peak %.6g /sr at (%.4f, %.4f), albedo %.6g\n", summary.wavelength_um,
                    summary.peak_value, summary.peak_direction.x, summary.peak_direction.y, summary.albedo);
}

}  // namespace

void add_lobe_command(CLI::App& app) {
    auto settings = std::make_shared<LobeSettings>();
    CLI::App* command = app.add_subcommand(
        "lobe", "Reflection lobe f_r(omega_i, omega_o) [1/sr] over the projected hemisphere of one footprint");
    command->add_option("heightfield", settings->input, "Heightfield file, or builtin:KIND (isotropic, brushed, ...)")
        ->required();
    add_load_options(*command, settings->load);
    command->add_option("--method", settings->method, "Method: " + [] {
        std::string names;
        for (const std::string& name : lobe_method_names()) names += (names.empty() ? "" : ", ") + name;
        return names;
    }())->capture_default_str();
    command->add_option("-o,--output", settings->output, "Output EXR (Y = f_r for one wavelength, RGB for spectral)")
        ->required();
    command->add_option("--png", settings->png, "Also write a display PNG");
    command->add_option("--json", settings->json, "Also write a JSON sidecar with the query and summary numbers");
    command->add_option("--centre", settings->centre, "Footprint centre X,Y (lengths; default: heightfield centre)")
        ->delimiter(',')
        ->expected(2);
    add_length_option(*command, "--sigma-c", settings->sigma_c_um, "Coherence sigma of the Gaussian footprint")
        ->default_str("10um");
    add_length_option(*command, "--box", settings->box_um, "Use a box footprint of this side instead of a Gaussian");
    auto* incident = command->add_option("--incident", settings->incident_deg,
                                         "Incident direction THETA,PHI in degrees (default 0,0: normal incidence)")
                         ->delimiter(',')
                         ->expected(2);
    command->add_option("--incident-xy", settings->incident_xy, "Incident direction X,Y on the projected disk")
        ->delimiter(',')
        ->expected(2)
        ->excludes(incident);
    auto* lambda = add_length_option(*command, "--lambda", settings->lambda_um, "Wavelength")->default_str("0.5um");
    command->add_option("--spectral", settings->spectral_bins, "N equal bins over 360-830 nm (instead of --lambda)")
        ->expected(0, 1)
        ->default_str("16")
        ->check(CLI::Range(1, 256))
        ->excludes(lambda);
    command->add_option("--model", settings->model, "Diffraction model: ohs, ghs, rohs, rghs, kirchhoff")
        ->capture_default_str();
    command->add_option("--material", settings->material, "Fresnel from tabulated n+ik (Ag, Al, Au, Cr, Cu, Fe); default F = 1");
    command->add_option("--res", settings->resolution, "Image resolution N (N x N)")->capture_default_str();
    command->add_option("--supersample", settings->supersample, "K x K sub-pixel average")->capture_default_str();
    command->add_option("--kernels-per-texel", settings->kernels_per_texel, "gabor: kernels per texel side");
    command->add_option("--option", settings->method_options, "Method option KEY=VALUE (repeatable; e.g. step=0.05um)");
    command->add_option("--illuminant", settings->illuminant, "d65 or e")->capture_default_str();
    command->add_option("--exposure", settings->exposure, "PNG exposure: auto or EV")->capture_default_str();
    command->add_flag("--log", settings->log_scale, "PNG on a log scale");
    command->add_option("--colormap", settings->colormap, "Single-wavelength PNG: inferno, viridis or grey")
        ->capture_default_str();
    command->add_flag("--spectral-channels", settings->spectral_channels, "EXR: also one channel per wavelength");
    command->add_option("--ocio-config", settings->ocio_config, "OpenColorIO config (default: $OCIO or built in)");
    command->add_option("--colour-space", settings->colour_space, "Scene-linear output colour space of the EXR")
        ->capture_default_str();
    command->callback([settings] { run(*settings); });
}

}  // namespace glintscope::cli
