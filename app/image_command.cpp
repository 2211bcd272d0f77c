#include "image_command.hpp"

#include "commands.hpp"
#include "progress.hpp"
#include "query_flags.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "glintscope/core/atomic_output.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/output/lobe_output.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/lobe/slice.hpp"
#include "glintscope/optics/spectrum.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope::cli {

struct ImageCommandSettings {
    Quantity quantity = Quantity::brdf;
    std::string method;
    QueryText given;                // query keys from flags, in command-line order
    std::string from;
    bool allow_changed_heightfield = false;
    std::string output;
    std::string png;
    std::string json;
    std::string illuminant = "d65";
    std::string exposure = "auto";
    bool log_scale = false;
    std::string colormap = "inferno";
    bool spectral_channels = false;
    bool bare = false;
    std::string exposure_from;
    std::vector<std::string> slices;
    std::string ocio_config;
    std::string colour_space = "lin_rec709";
};

namespace {

void add_output_flags(CLI::App& command, ImageCommandSettings& settings) {
    command.add_option("-o,--output", settings.output, "Output EXR (scene-linear float; the query in its header)")
        ->required();
    command.add_option("--png", settings.png, "Also write a display PNG");
    command.add_option("--slice", settings.slices,
                       "Also write OUT-slice-DIR.csv: a 1-D slice through the centre along x, y or an angle in degrees "
                       "(repeatable; Dong 2015 Fig. 9)")
        ->type_name("x|y|DEG");
    command.add_option("--json", settings.json, "Also write a JSON sidecar with the query and summary numbers");
    command.add_option("--illuminant", settings.illuminant, "d65 or e")->capture_default_str();
    command.add_option("--exposure", settings.exposure, "PNG exposure: auto or EV")->capture_default_str();
    command.add_option("--exposure-from", settings.exposure_from,
                       "PNG exposure of an earlier run's JSON sidecar, so that two pictures are exposed alike");
    command.add_flag("--log", settings.log_scale, "PNG on a log scale");
    command.add_flag("--bare", settings.bare, "PNG: the image alone (no disk guides, caption or colour bar)");
    command.add_option("--colormap", settings.colormap, "Single-wavelength PNG: inferno, viridis or grey")
        ->capture_default_str();
    command.add_flag("--spectral-channels", settings.spectral_channels, "EXR: also one channel per wavelength");
    command.add_option("--ocio-config", settings.ocio_config, "OpenColorIO config (default: $OCIO or built in)");
    command.add_option("--colour-space", settings.colour_space, "Scene-linear output colour space of the EXR")
        ->capture_default_str();
}

LobeOutputOptions output_options(const ImageCommandSettings& settings) {
    LobeOutputOptions options;
    options.colour.config_path = settings.ocio_config;
    options.colour.output_space = settings.colour_space;
    options.colour.illuminant = parse_illuminant(settings.illuminant);
    options.colour.log_scale = settings.log_scale;
    if (settings.exposure != "auto") {
        try {
            options.colour.exposure_ev = parse_number(settings.exposure);
        } catch (const Error&) {
            throw Error("--exposure must be 'auto' or a number of stops, got '" + settings.exposure + "'");
        }
    }
    if (!settings.exposure_from.empty()) {
        if (settings.exposure != "auto") throw Error("--exposure and --exposure-from exclude each other");
        options.colour.exposure_ev = recorded_exposure_ev(settings.exposure_from);
    }
    options.colormap = settings.colormap;
    options.spectral_channels = settings.spectral_channels;
    options.bare = settings.bare;
    return options;
}

std::string slice_path(const ImageCommandSettings& settings, const std::string& direction) {
    return settings.output.substr(0, settings.output.size() - 4) + "-slice-" + direction + ".csv";
}

void check_outputs(const ImageCommandSettings& settings) {
    check_output_path(settings.output, {"exr"}, "-o");
    for (const std::string& direction : settings.slices) {
        parse_slice_direction(direction);
        check_output_path(slice_path(settings, direction), {"csv"}, "--slice");
    }
    if (!settings.png.empty()) check_output_path(settings.png, {"png"}, "--png");
    if (!settings.json.empty()) check_output_path(settings.json, {"json"}, "--json");
}

// The query: --from's recorded one (its heightfield checked against the recorded MD5), overridden
// by the flags given, with the command's quantity; and the method: --method, else the one
// recorded, else the command's default.
LobeQuery query_of(const ImageCommandSettings& settings, const std::string& heightfield, std::string& method) {
    QueryText given = settings.given;
    if (!heightfield.empty()) given.emplace_back("heightfield", heightfield);
    given.emplace_back("quantity", to_string(settings.quantity));
    if (settings.from.empty()) return make_query(given);
    RecordedRun recorded = recorded_run(settings.from, given, settings.allow_changed_heightfield);
    if (method.empty()) method = recorded.method;
    return std::move(recorded.query);
}

void print_summary(const LobeImage& image, const std::string& method, DiffractionModel model) {
    const QuantityLabels& label = labels(image.quantity);
    const std::string who = method + (lobe_method(method).ignores(QueryField::model) ? "" : " " + to_string(model));
    for (const WavelengthSummary& summary : summarize_lobe(image)) {
        const std::string at = image.quantity == Quantity::brdf ? "lambda " + shortest_text(summary.wavelength_um) + " um: " : "";
        std::printf("%s, %speak %s = %.6g%s at %s = (%.4f, %.4f), %s %.6g\n", who.c_str(), at.c_str(),
                    label.symbol.c_str(), summary.peak_value, label.units == "1" ? "" : (" " + label.units).c_str(),
                    label.pixel.c_str(), summary.peak_direction.x, summary.peak_direction.y, label.sum_name.c_str(),
                    summary.disk_sum);
        if (image.quantity == Quantity::ndf) break;  // every layer of an NDF is the same
    }
}

// --verbose: what the method and the picture chose on their own.
void explain_choices(const LobeImage& image, const std::string& method, const DisplayExposure& exposure) {
    for (const auto& [key, value] : image.metadata)
        if (key.starts_with(method + ".")) std::fprintf(stderr, "glintscope: %s = %s\n", key.c_str(), value.c_str());
    std::fprintf(stderr, "glintscope: exposure %.4g EV (%s)\n", exposure.ev, exposure.rule.c_str());
}

void run(const ImageCommandSettings& settings, const std::string& heightfield, std::string method,
         const std::string& default_method) {
    check_outputs(settings);
    const LobeOutputOptions options = output_options(settings);
    check_output_options(options);
    if (!method.empty()) lobe_method(method);  // an unknown method fails before the heightfield is loaded
    const LobeQuery query = query_of(settings, heightfield, method);
    if (method.empty()) method = default_method;
    LobeRun run;
    {
        // One footprint reports each pass of the method's loops (pipeline.hpp): a count that falls
        // back is the next pass, whose ETA counts from its start.
        const bool single = query.footprints.single();
        ProgressBar progress(single ? "computing" : "footprints");
        std::size_t pass = 1, last = 0;
        run = run_lobe(method, query, [&](std::size_t done, std::size_t total) {
            if (single && done <= last) ++pass, progress.restart();
            last = done;
            progress.update(done, total, single ? "pass " + std::to_string(pass) : "");
        });
    }
    LobeImage& image = run.image;
    // Said after the computation, so that bad input fails with its one line and nothing else.
    for (const std::string& note : run.notes) std::fprintf(stderr, "glintscope: note: %s\n", note.c_str());
    for (const std::string& warning : run.warnings) std::fprintf(stderr, "glintscope: warning: %s\n", warning.c_str());
    image.metadata["command_line"] = invocation();
    write_lobe_exr(image, settings.output, options);
    DisplayExposure exposure = display_exposure(image, options.colour);
    if (!settings.png.empty()) exposure = write_lobe_png(image, settings.png, options);
    if (!settings.json.empty()) write_lobe_json(image, settings.json, options);
    for (const std::string& direction : settings.slices)
        write_text_file(slice_path(settings, direction), slice_csv(image, image_slice(image, parse_slice_direction(direction), 2 * image.resolution)));
    if (verbosity().verbose) explain_choices(image, method, exposure);
    print_summary(image, method, query.model);
}

}  // namespace

void add_image_command(CLI::App& command, Quantity quantity, const std::string& default_method) {
    auto settings = std::make_shared<ImageCommandSettings>();
    auto heightfield = std::make_shared<std::string>();
    auto method = std::make_shared<std::string>();
    settings->quantity = quantity;
    command.add_option("heightfield", *heightfield,
                       "Heightfield file, or builtin:KIND (isotropic, brushed, ...); optional with --from");
    std::vector<std::string> names;
    for (const MethodInfo& info : lobe_methods())
        if (info.answers(quantity)) names.push_back(info.name + " (" + info.reference + ")");
    command.add_option("--method", *method, "Method (default " + default_method + "): " + join(names));
    command.add_option("--from", settings->from,
                       "Re-run the query recorded in an EXR, PNG or JSON this tool wrote; flags given override it");
    command.add_flag("--allow-changed-heightfield", settings->allow_changed_heightfield,
                     "With --from: re-run even if the heightfield file's bytes differ from the recorded MD5");
    add_query_flags(command, settings->given, quantity, {"quantity"});
    add_method_option_flags(command, settings->given, quantity);
    add_output_flags(command, *settings);
    command.callback([settings, heightfield, method, default_method] {
        if (heightfield->empty() && settings->from.empty())
            throw Error("give a heightfield (or --from FILE to re-run a recorded query)");
        run(*settings, *heightfield, *method, default_method);
    });
}

}  // namespace glintscope::cli
