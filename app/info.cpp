// glintscope info FILE [--json]: what a heightfield file holds, as read with the loading options,
// with its surface statistics and ISO 25178-2 areal parameters on the surface as read or after
// the ISO 16610-61 S-filter, levelling and L-filter the flags ask for (in that order).
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/prepare/prepare.hpp"
#include "glintscope/surface/areal_parameters.hpp"
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
    double s_filter_um = 0.0;  // 0: none
    double l_filter_um = 0.0;
    bool level = false;
    double threshold = kIsoAutocorrelationThreshold;
};

struct Report {
    SurfaceStatistics statistics;
    std::optional<ArealParameters> iso;
    std::string iso_undefined;  // why iso is empty
    std::string surface;  // the operations applied before the numbers, or "as read"
};

std::string number(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
    return buffer;
}

// A 1/e correlation length, or the bound when the autocorrelation stays above 1/e to half the field.
std::string correlation_text(double length_um, double at_half, double half_um) {
    if (std::isfinite(length_um)) return format_length(length_um);
    if (!std::isfinite(at_half)) return "not measurable (the heights do not vary, or no valid pairs)";
    return "longer than " + format_length(half_um) + " (half the field; autocorrelation still " + number(at_half) +
           " there)";
}

std::string sal_text(const ArealParameters& p) {
    if (p.sal_is_lower_bound)
        return "longer than " + format_length(p.sal_um) + " (the autocorrelation stays above s = " + number(p.threshold) +
               " to the edge of the lags evaluated in every direction, " + number(p.sal_autocorrelation_at_edge) +
               " at the edge)";
    return format_length(p.sal_um) + " (fastest decay to s = " + number(p.threshold) + ", at " +
           number(p.sal_direction_deg) + " deg from +x)";
}

std::string str_text(const ArealParameters& p) {
    if (p.sal_is_lower_bound) return "not determined (no direction decays to s within the field)";
    if (p.str_is_upper_bound)
        return "less than " + number(p.str) + " (at " + number(p.longest_direction_deg) +
               " deg the autocorrelation is still " + number(p.longest_autocorrelation_at_edge) + " at " +
               format_length(p.longest_decay_um) + ", the edge of the lags evaluated)";
    return number(p.str) + " (Sal / slowest decay " + format_length(p.longest_decay_um) + " at " +
           number(p.longest_direction_deg) + " deg)";
}

nlohmann::ordered_json iso_json(const Report& report) {
    nlohmann::ordered_json iso = {{"surface", report.surface}};
    if (!report.iso) {
        iso["undefined"] = report.iso_undefined;
        return iso;
    }
    const ArealParameters& p = *report.iso;
    iso.update(nlohmann::ordered_json{{"Sq_um", p.sq_um},
                                      {"Ssk", p.ssk},
                                      {"Sku", p.sku},
                                      {"Sp_um", p.sp_um},
                                      {"Sv_um", p.sv_um},
                                      {"Sz_um", p.sz_um},
                                      {"Sa_um", p.sa_um},
                                      {"Sdq", p.sdq},
                                      {"Sdr_percent", 100.0 * p.sdr},
                                      {"autocorrelation_threshold_s", p.threshold},
                                      {"Sal_um", p.sal_um},
                                      {"Sal_is_lower_bound", p.sal_is_lower_bound},
                                      {"Sal_direction_deg", p.sal_direction_deg}});
    if (!p.sal_is_lower_bound) {
        iso["Str"] = p.str;
        iso["Str_is_upper_bound"] = p.str_is_upper_bound;
        iso["slowest_decay_um"] = p.longest_decay_um;
        iso["slowest_decay_direction_deg"] = p.longest_direction_deg;
    }
    if (p.sal_is_lower_bound) iso["autocorrelation_at_edge"] = p.sal_autocorrelation_at_edge;
    if (p.str_is_upper_bound) iso["autocorrelation_at_edge"] = p.longest_autocorrelation_at_edge;
    iso["Std_deg"] = p.std_deg;
    return iso;
}

void print_json(const std::string& input, const Heightfield& field, const Report& report, bool declared_spacing) {
    const SurfaceStatistics& s = report.statistics;
    nlohmann::ordered_json statistics = {{"mean_um", s.mean_um}, {"sq_um", s.sq_um},   {"sa_um", s.sa_um},
                                         {"min_um", s.min_um},   {"max_um", s.max_um}, {"rms_slope_x", s.rms_slope_x},
                                         {"rms_slope_y", s.rms_slope_y}};
    const auto correlation = [&](const std::string& axis, double length, double at_half, double half) {
        const bool bound = !std::isfinite(length) && std::isfinite(at_half);
        if (!std::isfinite(length) && !bound) {  // flat heights, or no valid pairs
            statistics["correlation_length_" + axis + "_measurable"] = false;
            return;
        }
        statistics["correlation_length_" + axis + "_um"] = bound ? half : length;
        statistics["correlation_length_" + axis + "_is_lower_bound"] = bound;
        if (bound) statistics["autocorrelation_at_half_" + axis] = at_half;
    };
    correlation("x", s.correlation_length_x_um, s.autocorrelation_at_half_x, 0.5 * field.width_um());
    correlation("y", s.correlation_length_y_um, s.autocorrelation_at_half_y, 0.5 * field.height_um());
    statistics["correlation_threshold"] = s.correlation_threshold;
    nlohmann::ordered_json provenance = nlohmann::ordered_json::object();
    for (const auto& [key, value] : field.provenance) provenance[key] = value;
    const nlohmann::ordered_json json = {{"file", input},
                                         {"cols", field.cols},
                                         {"rows", field.rows},
                                         {"texel_um", field.dx_um()},
                                         {"texel_y_um", field.dy_um()},
                                         {"spacing_declared", declared_spacing},
                                         {"width_um", field.width_um()},
                                         {"height_um", field.height_um()},
                                         {"height_unit", "um"},
                                         {"units_assumed", field.units_assumed},
                                         {"periodic", field.periodic},
                                         {"statistics", statistics},
                                         {"iso_25178_2", iso_json(report)},
                                         {"missing_count", s.missing_count},
                                         {"missing_fraction", s.missing_fraction},
                                         {"provenance", provenance}};
    // Invalid UTF-8 (a file name or a header string) is replaced rather than refused.
    std::fputs((json.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n").c_str(), stdout);
}

void print_line(const char* name, const std::string& value) { std::printf("%-22s %s\n", name, value.c_str()); }

void print_iso(const Report& report) {
    if (!report.iso) {
        print_line("ISO 25178-2:", report.iso_undefined);
        return;
    }
    const ArealParameters& p = *report.iso;
    std::printf("ISO 25178-2 areal parameters, on the surface %s; heights about their mean:\n", report.surface.c_str());
    const auto line = [](const char* name, const std::string& value) { std::printf("  %-38s %s\n", name, value.c_str()); };
    line("Sq  root mean square height:", format_length(p.sq_um));
    line("Ssk skewness:", number(p.ssk));
    line("Sku kurtosis:", number(p.sku));
    line("Sp  maximum peak height:", format_length(p.sp_um));
    line("Sv  maximum pit height:", format_length(p.sv_um));
    line("Sz  maximum height (Sp + Sv):", format_length(p.sz_um));
    line("Sa  arithmetic mean height:", format_length(p.sa_um));
    line("Sdq root mean square gradient:", number(p.sdq));
    line("Sdr developed interfacial area ratio:", number(100.0 * p.sdr) + "%");
    line("Sal autocorrelation length:", sal_text(p));
    line("Str texture aspect ratio:", str_text(p));
    line("Std texture direction (lay):", number(p.std_deg) + " deg from +x, counter-clockwise");
    line("gradient distribution (2021 §4.6):",
         "the whole-field P-NDF: glintscope ndf FILE --method pndf --footprint whole");
}

// The mean height, 0 when it is rounding noise (below 1e-6 of the height range: float heights
// carry about 7 digits), so that a zero-mean surface reads 0 and not 3e-9 nm.
double displayed_mean(const SurfaceStatistics& s) {
    return std::fabs(s.mean_um) <= 1e-6 * (s.max_um - s.min_um) ? 0.0 : s.mean_um;
}

void print_text(const std::string& input, const Heightfield& field, const Report& report, bool declared_spacing) {
    const SurfaceStatistics& s = report.statistics;
    const bool builtin = input.starts_with("builtin:");
    print_line(builtin ? "surface:" : "file:", builtin ? input + ", generated: " + kind_description(input.substr(8)) : input);
    print_line("size:", std::to_string(field.cols) + " x " + std::to_string(field.rows) + " samples (x by y)");
    print_line("texel:", texel_text(field));
    if (declared_spacing) {
        const auto file = field.provenance.find("spacing.file");
        print_line("spacing:", "DECLARED with --texel, not read from the file; " +
                                   (file == field.provenance.end() ? std::string("the file states none")
                                    : file->second == texel_text(field)
                                        ? "the file states the same"
                                        : "the file states " + file->second + ", overridden"));
    }
    print_line("extent:", format_length(field.width_um()) + " x " + format_length(field.height_um()));
    print_line("units:", builtin                ? "exact: generated in um"
                         : field.units_assumed ? "ASSUMED: the file does not give them; texel 1 um and heights in um "
                                                 "unless --texel and --height-unit say otherwise"
                                               : "from the file and options; heights in um");
    print_line("tiling:", field.periodic ? "periodic (one tile of a periodic surface)"
                                         : "non-periodic (its borders are edges; --periodic if the file tiles)");
    print_line("mean height:", format_length(displayed_mean(s)));
    print_line("min, max:", format_length(s.min_um) + ", " + format_length(s.max_um));
    print_line("rms slope x, y:", number(s.rms_slope_x) + ", " + number(s.rms_slope_y));
    print_line("correlation length:",
               "x " + correlation_text(s.correlation_length_x_um, s.autocorrelation_at_half_x, 0.5 * field.width_um()) +
                   ", y " +
                   correlation_text(s.correlation_length_y_um, s.autocorrelation_at_half_y, 0.5 * field.height_um()) +
                   " (1/e decay along each axis, not Sal)");
    print_line("missing points:", std::to_string(s.missing_count) + " (" + number(100.0 * s.missing_fraction) + "%)");
    print_iso(report);
    if (field.provenance.empty()) {
        print_line("provenance:", "none");
        return;
    }
    std::printf("provenance:\n");
    for (const auto& [key, value] : field.provenance) std::printf("  %s: %s\n", key.c_str(), value.c_str());
}

void run_info(const InfoSettings& settings) {
    Heightfield field = load_heightfield_argument(settings.input, settings.load);
    // ISO 25178-2's order: S-filter, then the F-operator (levelling), then the L-filter.
    std::vector<std::string> steps;
    if (settings.s_filter_um > 0.0) {
        apply_s_filter(field, settings.s_filter_um);
        steps.push_back("S-filtered (ISO 16610-61 Gaussian, nesting index " + format_length(settings.s_filter_um) + ")");
    }
    if (settings.level) {
        remove_form(field, 1);
        steps.push_back("levelled (least-squares plane removed)");
    }
    if (settings.l_filter_um > 0.0) {
        apply_l_filter(field, settings.l_filter_um);
        steps.push_back("L-filtered (ISO 16610-61 Gaussian, nesting index " + format_length(settings.l_filter_um) + ")");
    }
    Report report;
    report.surface = steps.empty() ? "as read (not levelled, no S- or L-filter)" : join(steps, ", then ");
    const SurfaceReport numbers = compute_surface_report(field, settings.threshold);
    report.statistics = numbers.statistics;
    report.iso = numbers.iso;
    if (!numbers.iso) report.iso_undefined = "not defined: " + numbers.iso_undefined;
    if (settings.json)
        print_json(settings.input, field, report, settings.load.texel_um.has_value());
    else
        print_text(settings.input, field, report, settings.load.texel_um.has_value());
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
    add_length_option(*command, "--s-filter", settings->s_filter_um,
                      "Before the statistics, keep the ISO 16610-61 Gaussian mean surface of this nesting index "
                      "(removes shorter wavelengths; a sinusoid of this wavelength keeps 50%)");
    command->add_flag("--level", settings->level,
                      "Before the statistics (after --s-filter), remove the least-squares plane");
    add_length_option(*command, "--l-filter", settings->l_filter_um,
                      "Before the statistics (last), subtract the ISO 16610-61 Gaussian mean surface of this nesting "
                      "index (removes longer wavelengths)");
    command->add_option("--acf-threshold", settings->threshold,
                        "The autocorrelation value s that Sal and Str measure the decay to (ISO 25178-2 default 0.2)")
        ->check(CLI::Range(0.0, 1.0).description("in (0, 1)"));
    add_load_options(*command, settings->load);
    command->callback([settings] { run_info(*settings); });
}

}  // namespace glintscope::cli
