// glintscope validate HEIGHTFIELD [query flags] --footprints N|grid[:N] --models LIST
//   --kernels-per-texel LIST [--report OUT.json] [--csv OUT.csv] [--fail-above X]:
// the Gabor method against the FFT ground truth (or any two methods) on the same queries.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "commands.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/output/figure.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/validate/validate.hpp"
#include "progress.hpp"
#include "query_flags.hpp"

namespace glintscope::cli {
namespace {

struct ValidateSettings {
    std::string heightfield;
    QueryText given;
    std::string models;
    std::string kernels_per_texel;
    std::string test_method = "gabor";
    std::string reference_method = "fft";
    std::string report;
    std::string csv;
    std::string summary_csv;
    std::string images;
    std::string convergence;
    double fail_above = -1.0;
};

ValidationPlan plan_of(const ValidateSettings& settings) {
    ValidationPlan plan;
    QueryText text = settings.given;
    text.emplace_back("heightfield", settings.heightfield);
    plan.base = make_query(text);
    plan.test_method = settings.test_method;
    plan.reference_method = settings.reference_method;
    lobe_method(plan.test_method);
    lobe_method(plan.reference_method);
    if (!settings.models.empty())
        for (const std::string& name : split(settings.models, ',')) plan.models.push_back(parse_diffraction_model(name));
    if (!settings.kernels_per_texel.empty())
        for (const std::string& value : split(settings.kernels_per_texel, ','))
            plan.kernels_per_texel.push_back(static_cast<int>(parse_integer(value, 1, 16)));
    return plan;
}

void print_table(const ValidationPlan& plan, const std::vector<ValidationRow>& rows) {
    std::printf("%s against %s\n", plan.test_method.c_str(), plan.reference_method.c_str());
    std::printf("%-22s %-9s %2s %9s %9s %9s %9s %8s %9s %9s\n", "centre [um]", "model", "K", "lambda", "rel L2",
                "peak err", "log err", "energy", "t test", "t ref");
    for (const ValidationRow& row : rows) {
        const LayerComparison& c = row.comparison;
        char centre[48];
        std::snprintf(centre, sizeof centre, "%.1f,%.1f", row.centre_um.x, row.centre_um.y);
        std::printf("%-22.22s %-9s %2s %9.4g %8.3f%% %8.3f%% %9.4f %8.4f %8.3fs %8.3fs\n", centre,
                    to_string(row.model).c_str(), row.kernels_per_texel ? std::to_string(row.kernels_per_texel).c_str() : "-",
                    c.wavelength_um, 100.0 * c.relative_l2, 100.0 * c.peak_relative_error, c.log_rms_error,
                    c.energy_ratio(), row.test_seconds, row.reference_seconds);
    }
}

// The verdict: mean and worst over the footprints per model, K and wavelength.
void print_summary(const std::vector<ValidationSummary>& summary) {
    std::printf("\nsummary over footprints\n%-9s %2s %9s %4s %9s %9s %9s %9s %8s\n", "model", "K", "lambda", "n",
                "mean L2", "worst L2", "mean peak", "worst pk", "energy");
    for (const ValidationSummary& s : summary)
        std::printf("%-9s %2s %9.4g %4zu %8.3f%% %8.3f%% %8.3f%% %8.3f%% %8.4f\n", to_string(s.model).c_str(),
                    s.kernels_per_texel ? std::to_string(s.kernels_per_texel).c_str() : "-", s.wavelength_um,
                    s.footprints, 100.0 * s.mean_relative_l2, 100.0 * s.worst_relative_l2, 100.0 * s.mean_peak_error,
                    100.0 * s.worst_peak_error, s.mean_energy_ratio);
}

// test | reference | test − reference (figure.hpp: write_difference_figure).
void write_pair(const std::string& directory, std::size_t index, const ValidationPlan& plan, const ValidationRow& row,
                const LobeImage& test, const LobeImage& reference) {
    char title[160];
    std::snprintf(title, sizeof title, "%s against %s: centre %.1f,%.1f um, %s%s, relative L2 %.2f%%",
                  plan.test_method.c_str(), plan.reference_method.c_str(), row.centre_um.x, row.centre_um.y,
                  to_string(row.model).c_str(), row.kernels_per_texel ? (", K = " + std::to_string(row.kernels_per_texel)).c_str() : "",
                  100.0 * row.comparison.relative_l2);
    const LobeOutputOptions options;
    write_difference_figure(test, reference, {title, "", plan.test_method, plan.reference_method, "difference"},
                            directory + "/pair-" + std::to_string(index) + ".png", options);
}

void run(const ValidateSettings& settings) {
    if (!settings.report.empty()) check_output_path(settings.report, {"json"}, "--report");
    if (!settings.csv.empty()) check_output_path(settings.csv, {"csv"}, "--csv");
    if (!settings.summary_csv.empty()) check_output_path(settings.summary_csv, {"csv"}, "--summary-csv");
    if (!settings.images.empty()) {
        std::error_code error;
        std::filesystem::create_directories(settings.images, error);
        if (error) throw Error("--images: cannot create the folder '" + settings.images + "': " + error.message());
        check_output_path(settings.images + "/pair-1.png", {"png"}, "--images");
    }
    if (!settings.convergence.empty()) check_output_path(settings.convergence, {"csv"}, "--convergence");
    const ValidationPlan plan = plan_of(settings);
    if (!settings.convergence.empty()) {
        std::vector<ConvergencePoint> points;
        {
            ProgressBar progress("convergence");
            points = run_convergence(plan, [&](std::size_t done, std::size_t total, const std::string& what) {
                progress.update(done, total, what);
            });
        }
        for (const ConvergencePoint& point : points)
            std::printf("%-24s %10.4g  relative L2 %8.4f%%\n", point.series.c_str(), point.parameter,
                        100.0 * point.relative_l2);
        write_text_file(settings.convergence, convergence_csv(points));
        return;
    }
    std::vector<ValidationRow> rows;
    std::size_t pairs = 0;
    {
        ProgressBar progress("validate");
        rows = run_validation(
            plan, [&](std::size_t done, std::size_t total, const std::string& what) { progress.update(done, total, what); },
            [&](const ValidationRow& row, const LobeImage& test, const LobeImage& reference) {
                if (!settings.images.empty()) write_pair(settings.images, ++pairs, plan, row, test, reference);
            });
    }
    print_table(plan, rows);
    const std::vector<ValidationSummary> summary = summarize_validation(rows);
    print_summary(summary);
    // Each row names its pair's picture (a pair holds one row per wavelength).
    std::vector<std::string> pictures;
    if (!settings.images.empty())
        for (std::size_t k = 0; k < rows.size(); ++k)
            pictures.push_back("pair-" + std::to_string(k / plan.base.wavelengths_um.size() + 1) + ".png");
    if (!settings.report.empty())
        write_text_file(settings.report, validation_json(plan, rows, invocation(), pictures));
    if (!settings.csv.empty()) write_text_file(settings.csv, validation_csv(rows));
    if (!settings.summary_csv.empty()) write_text_file(settings.summary_csv, validation_summary_csv(summary));
    if (settings.fail_above >= 0.0)
        for (const ValidationSummary& s : summary)
            if (s.worst_relative_l2 > settings.fail_above)
                throw Error("worst relative L2 " + shortest_text(s.worst_relative_l2) + " exceeds --fail-above " +
                            shortest_text(settings.fail_above) + " (" + to_string(s.model) +
                            (s.kernels_per_texel ? ", K = " + std::to_string(s.kernels_per_texel) : "") + ", lambda " +
                            shortest_text(s.wavelength_um) + " um, over " + std::to_string(s.footprints) + " footprint" +
                            (s.footprints == 1 ? "" : "s") + ")");
}

}  // namespace

void add_validate_command(CLI::App& app) {
    auto settings = std::make_shared<ValidateSettings>();
    CLI::App* command = app.add_subcommand(
        "validate", "Compare a method (default gabor) with a reference (default fft) on the same queries");
    std::string columns = "Columns:";
    for (const std::string& line : validation_column_definitions()) columns += "\n  " + line;
    command->footer(columns + "\n--fail-above judges the summary's worst relative L2.");
    command->add_option("heightfield", settings->heightfield, "Heightfield file, or builtin:KIND")->required();
    add_query_flags(*command, settings->given, Quantity::brdf, {"quantity", "model", "footprints"});
    command->add_option_function<std::string>(
        "--footprints", [settings](const std::string& value) { settings->given.emplace_back("footprints", value); },
        "Footprints, a row each: N seeded random centres, grid (3 x 3) or grid:N (N x N) (default: the query's centre)")
        ->type_name("N|grid|grid:N");
    command->add_option("--models", settings->models, "Diffraction models, comma-separated (default rohs)")
        ->type_name("LIST");
    command->add_option("--kernels-per-texel", settings->kernels_per_texel,
                        "Gabor densities K, comma-separated (default the method's, 2)")
        ->type_name("LIST");
    command->add_option("--test-method", settings->test_method, "Method under test")->capture_default_str();
    command->add_option("--reference-method", settings->reference_method, "Reference method")->capture_default_str();
    command->add_option("--report", settings->report, "Full report as JSON");
    command->add_option("--csv", settings->csv, "The rows as CSV");
    command->add_option("--summary-csv", settings->summary_csv,
                        "The summary (mean and worst per model, K and wavelength) as CSV");
    command->add_option("--images", settings->images,
                        "Write DIR/pair-N.png per compared pair: test, reference and their signed difference");
    command->add_option("--convergence", settings->convergence,
                        "Instead: error against K = 1-4 (gabor vs fft) and against the FFT step, as CSV "
                        "(plot with scripts/plot-convergence.py)");
    command->add_option("--fail-above", settings->fail_above,
                        "Exit non-zero when any relative L2 exceeds X (e.g. 0.06), after writing the report");
    command->callback([settings] { run(*settings); });
}

}  // namespace glintscope::cli
