// glintscope info FILE [--json]: what a heightfield file holds, as read with the loading options.
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/surface/statistics.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "options.hpp"

namespace glintscope::cli {
namespace {

struct InfoSettings {
    std::string input;
    bool json = false;
    LoadOptions load;
};

void print_json(const std::string& input, const Heightfield& field, const SurfaceStatistics& s) {
    const nlohmann::ordered_json statistics = {{"mean_um", s.mean_um},
                                               {"sq_um", s.sq_um},
                                               {"sa_um", s.sa_um},
                                               {"min_um", s.min_um},
                                               {"max_um", s.max_um},
                                               {"rms_slope_x", s.rms_slope_x},
                                               {"rms_slope_y", s.rms_slope_y},
                                               {"correlation_length_x_um", s.correlation_length_x_um},
                                               {"correlation_length_y_um", s.correlation_length_y_um},
                                               {"correlation_threshold", s.correlation_threshold}};
    nlohmann::ordered_json provenance = nlohmann::ordered_json::object();
    for (const auto& [key, value] : field.provenance) provenance[key] = value;
    const nlohmann::ordered_json json = {{"file", input},
                                         {"cols", field.cols},
                                         {"rows", field.rows},
                                         {"texel_um", field.texel_um},
                                         {"width_um", field.width_um()},
                                         {"height_um", field.height_um()},
                                         {"height_unit", "um"},
                                         {"units_assumed", field.units_assumed},
                                         {"periodic", field.periodic},
                                         {"statistics", statistics},
                                         {"missing_count", s.missing_count},
                                         {"missing_fraction", s.missing_fraction},
                                         {"provenance", provenance}};
    // Invalid UTF-8 (a file name or a header string) is replaced rather than refused.
    std::fputs((json.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n").c_str(), stdout);
}

void print_line(const char* name, const std::string& value) { std::printf("%-22s %s\n", name, value.c_str()); }

std::string number(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
    return buffer;
}

void print_text(const std::string& input, const Heightfield& field, const SurfaceStatistics& s) {
    print_line("file:", input);
    print_line("size:", std::to_string(field.cols) + " x " + std::to_string(field.rows) + " samples (x by y)");
    print_line("texel:", format_length(field.texel_um));
    print_line("extent:", format_length(field.width_um()) + " x " + format_length(field.height_um()));
    print_line("units:", field.units_assumed ? "ASSUMED: the file does not give them; texel 1 um and heights in um "
                                               "unless --texel and --height-unit say otherwise"
                                             : "from the file and options; heights in um");
    print_line("tiling:", field.periodic ? "periodic (one tile of a periodic surface)"
                                         : "non-periodic (its borders are edges; --periodic if the file tiles)");
    print_line("mean height:", format_length(s.mean_um));
    print_line("Sq (rms height):", format_length(s.sq_um));
    print_line("Sa (mean |h - mean|):", format_length(s.sa_um));
    print_line("min, max:", format_length(s.min_um) + ", " + format_length(s.max_um));
    print_line("rms slope x, y:", number(s.rms_slope_x) + ", " + number(s.rms_slope_y));
    print_line("correlation length:", "x " + format_length(s.correlation_length_x_um) + ", y " +
                                          format_length(s.correlation_length_y_um) + " (autocorrelation falls to " +
                                          number(s.correlation_threshold) + ")");
    print_line("missing points:", std::to_string(s.missing_count) + " (" + number(100.0 * s.missing_fraction) + "%)");
    if (field.provenance.empty()) {
        print_line("provenance:", "none");
        return;
    }
    std::printf("provenance:\n");
    for (const auto& [key, value] : field.provenance) std::printf("  %s: %s\n", key.c_str(), value.c_str());
}

void run_info(const InfoSettings& settings) {
    const Heightfield field = load_heightfield_argument(settings.input, settings.load);
    const SurfaceStatistics statistics = compute_statistics(field);
    if (settings.json)
        print_json(settings.input, field, statistics);
    else
        print_text(settings.input, field, statistics);
}

}  // namespace

void add_info_command(CLI::App& app) {
    auto settings = std::make_shared<InfoSettings>();
    CLI::App* command = app.add_subcommand(
        "info", "Print a heightfield's size, texel, extent, units, surface statistics and provenance");
    command
        ->add_option("file", settings->input,
                     "Heightfield file (.x3p, .exr, .tif, .png, .npy or any image) or builtin:KIND")
        ->required();
    command->add_flag("--json", settings->json, "Print one JSON object (lengths in um) instead of text");
    add_load_options(*command, settings->load);
    command->callback([settings] { run_info(*settings); });
}

}  // namespace glintscope::cli
