// glintscope validate HEIGHTFIELD [query flags] --footprints N|grid[:N] --models LIST
//   --kernels-per-texel LIST [--report OUT.json] [--csv OUT.csv] [--fail-above X]:
// the Gabor method against the FFT ground truth (or any two methods) on the same queries.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "commands.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/output/figure.hpp"
#include "glintscope/output/plot.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/methods/gabor/gabor_surface.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/validate/albedo.hpp"
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
    std::string orders;
    std::string test_method = "gabor";
    std::string reference_method = "fft";
    std::string report;
    std::string csv;
    std::string summary_csv;
    std::string images;
    std::string convergence;
    std::string albedo;
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
    if (!settings.orders.empty())
        for (const std::string& value : split(settings.orders, ',')) {
            if (trim(value) != "1" && trim(value) != "2")
                throw Error("--order takes orders 1 and 2, comma-separated, got '" + value + "'");
            plan.orders.push_back(trim(value) == "1" ? 1 : 2);
        }
    return plan;
}

void print_table(const ValidationPlan& plan, const std::vector<ValidationRow>& rows) {
    std::printf("%s against %s\n", plan.test_method.c_str(), plan.reference_method.c_str());
    std::printf("%-22s %-9s %2s %5s %9s %9s %9s %9s %9s %8s %9s %9s\n", "centre [um]", "model", "K", "order",
                "lambda", "rel L2", "peak err", "log err", "smooth L2", "energy", "t test", "t ref");
    for (const ValidationRow& row : rows) {
        const LayerComparison& c = row.comparison;
        char centre[48];
        std::snprintf(centre, sizeof centre, "%.1f,%.1f", row.centre_um.x, row.centre_um.y);
        std::printf("%-22.22s %-9s %2s %5s %9.4g %8.3f%% %8.3f%% %9.4f %8.3f%% %8.4f %8.3fs %8.3fs\n", centre,
                    to_string(row.model).c_str(), row.kernels_per_texel ? std::to_string(row.kernels_per_texel).c_str() : "-",
                    row.order ? std::to_string(row.order).c_str() : "-", c.wavelength_um, 100.0 * c.relative_l2,
                    100.0 * c.peak_relative_error, c.log_rms_error, 100.0 * c.smoothed_relative_l2, c.energy_ratio(),
                    row.test_seconds, row.reference_seconds);
    }
}

// The verdict: mean and worst over the footprints per model, K, order and wavelength.
void print_summary(const std::vector<ValidationSummary>& summary) {
    std::printf("\nsummary over footprints\n%-9s %2s %5s %9s %4s %9s %9s %9s %9s %10s %10s %8s\n", "model", "K",
                "order", "lambda", "n", "mean L2", "worst L2", "mean peak", "worst pk", "mean smL2", "worst smL2", "energy");
    for (const ValidationSummary& s : summary)
        std::printf("%-9s %2s %5s %9.4g %4zu %8.3f%% %8.3f%% %8.3f%% %8.3f%% %9.3f%% %9.3f%% %8.4f\n",
                    to_string(s.model).c_str(), s.kernels_per_texel ? std::to_string(s.kernels_per_texel).c_str() : "-",
                    s.order ? std::to_string(s.order).c_str() : "-", s.wavelength_um, s.footprints,
                    100.0 * s.mean_relative_l2, 100.0 * s.worst_relative_l2, 100.0 * s.mean_peak_error,
                    100.0 * s.worst_peak_error, 100.0 * s.mean_smoothed_l2, 100.0 * s.worst_smoothed_l2,
                    s.mean_energy_ratio);
}

// A pair's picture zooms to where either lobe exceeds this fraction of its peak.
constexpr double kPairZoomFraction = 1e-3;

// Test and reference on a log scale of kPairDecades below the brighter one's peak: a narrow
// lobe's peak and its tails both show.
constexpr double kPairDecades = 4.0;
LobeOutputOptions pair_picture_options() {
    LobeOutputOptions options;
    options.colour.log_scale = true;
    options.colour.log_decades = kPairDecades;
    return options;
}

// test | reference | test − reference (figure.hpp: write_difference_figure), titled with the
// pair's relative L2 (its mean and worst over the wavelengths of a spectrum).
void write_pair(const std::string& directory, std::size_t index, const ValidationPlan& plan, const ValidationRow& row,
                const LobeImage& test, const LobeImage& reference) {
    const std::vector<LayerComparison> layers = compare_lobes(test, reference);
    double mean = 0.0, worst = 0.0;
    for (const LayerComparison& layer : layers) mean += layer.relative_l2 / double(layers.size()), worst = std::max(worst, layer.relative_l2);
    char l2[96];
    if (layers.size() == 1) std::snprintf(l2, sizeof l2, "relative L2 %.2f%%", 100.0 * mean);
    else std::snprintf(l2, sizeof l2, "relative L2 mean %.2f%%, worst %.2f%% over %zu wavelengths", 100.0 * mean, 100.0 * worst, layers.size());
    char title[240];
    const std::string density = row.kernels_per_texel ? ", K = " + std::to_string(row.kernels_per_texel) : "";
    const std::string order = row.order ? ", order " + std::to_string(row.order) : "";
    std::snprintf(title, sizeof title, "%s against %s: centre %.1f,%.1f um, %s%s%s, %s", plan.test_method.c_str(),
                  plan.reference_method.c_str(), row.centre_um.x, row.centre_um.y, to_string(row.model).c_str(),
                  density.c_str(), order.c_str(), l2);
    write_difference_figure(test, reference,
                            {title, "", plan.test_method, plan.reference_method, "difference", kPairZoomFraction},
                            directory + "/pair-" + std::to_string(index) + ".png", pair_picture_options());
}

// The albedo of the test and reference methods against incidence, for --models (default rohs and
// kirchhoff: the default model and the one that keeps energy), beside the material's F.
void run_albedo(const ValidateSettings& settings, const ValidationPlan& plan) {
    if (!settings.report.empty() || !settings.summary_csv.empty() || !settings.images.empty() ||
        !settings.convergence.empty() || settings.fail_above >= 0.0)
        throw Error("--albedo draws its plot (and --csv its numbers) only: drop --report, --summary-csv, --images, "
                    "--convergence and --fail-above");
    std::vector<std::string> methods = {plan.test_method};
    if (plan.reference_method != plan.test_method) methods.push_back(plan.reference_method);
    const std::vector<DiffractionModel> models =
        plan.models.empty() ? std::vector{DiffractionModel::rohs, DiffractionModel::kirchhoff} : plan.models;
    AlbedoStudy study;
    {
        ProgressBar progress("albedo");
        study = albedo_versus_incidence(plan.base, methods, models, default_albedo_angles(),
                                        [&](std::size_t done, std::size_t total, const std::string& what) {
                                            progress.update(done, total, what);
                                        });
    }
    const std::string csv = albedo_csv(study);
    std::fputs(csv.c_str(), stdout);
    if (!settings.csv.empty()) write_text_file(settings.csv, csv);
    Plot plot{"Directional albedo against incidence: " + settings.heightfield, "theta_i [deg]", "albedo", {}, {}};
    const std::vector<double>& wavelengths = study.wavelengths_um;
    const std::string material = plan.base.material.name.empty() ? "no material (F = 1)" : plan.base.material.name;
    plot.caption.push_back(material + ", lambda " + shortest_text(wavelengths.front() * 1e3) +
                           (wavelengths.size() > 1 ? "-" + shortest_text(wavelengths.back() * 1e3) + " nm (mean over " +
                                                         std::to_string(wavelengths.size()) + " wavelengths)"
                                                   : " nm") +
                           ", phi_i " + shortest_text(std::round(std::atan2(plan.base.omega_i.y, plan.base.omega_i.x) * 180.0 / pi * 10) / 10) +
                           " deg");
    plot.caption.push_back("dashed: the material's Fresnel F(theta_i), a flat mirror's albedo; a curve above it creates energy");
    for (const AlbedoCurve& curve : study.curves) plot.series.push_back({curve_name(curve), study.theta_i_deg, band_mean(curve.albedo)});
    plot.series.push_back({"Fresnel F", study.theta_i_deg, band_mean(study.fresnel), true});
    write_plot(plot, settings.albedo);
}

// --images DIR is created only when the run starts: here, DIR is a folder or can be made in its
// nearest existing ancestor (a writable folder).
void check_images_folder(const std::string& folder) {
    namespace fs = std::filesystem;
    std::error_code error;
    fs::path existing = fs::absolute(folder, error);
    while (!existing.empty() && !fs::exists(existing, error) && existing != existing.parent_path()) existing = existing.parent_path();
    if (!fs::is_directory(existing, error))
        throw Error("--images '" + folder + "': '" + existing.string() + "' is not a folder");
    check_output_path((existing / "pair-1.png").string(), {"png"}, "--images");
}

void run(const ValidateSettings& settings) {
    if (!settings.report.empty()) check_output_path(settings.report, {"json"}, "--report");
    if (!settings.csv.empty()) check_output_path(settings.csv, {"csv"}, "--csv");
    if (!settings.summary_csv.empty()) check_output_path(settings.summary_csv, {"csv"}, "--summary-csv");
    if (!settings.images.empty()) check_images_folder(settings.images);
    if (!settings.convergence.empty()) check_output_path(settings.convergence, {"csv"}, "--convergence");
    if (!settings.albedo.empty()) check_output_path(settings.albedo, {"png"}, "--albedo");
    const ValidationPlan plan = plan_of(settings);
    if (!settings.albedo.empty()) return run_albedo(settings, plan);
    if (!settings.images.empty()) {  // created once everything else is known to be right
        std::error_code error;
        std::filesystem::create_directories(settings.images, error);
        if (error) throw Error("--images: cannot create the folder '" + settings.images + "': " + error.message());
    }
    for (const std::string& note : validation_notes(plan)) std::fprintf(stderr, "glintscope: note: %s\n", note.c_str());
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
    if (!settings.images.empty() && plan.kernels_per_texel.size() > 1) {
        write_plot(error_against_k_plot(plan, summary), settings.images + "/summary.png");
        std::printf("\nerror against K: %s/summary.png\n", settings.images.c_str());
    }
    if (!settings.report.empty())
        write_text_file(settings.report, validation_json(plan, rows, invocation(), pictures));
    if (!settings.csv.empty()) write_text_file(settings.csv, validation_csv(rows));
    if (!settings.summary_csv.empty()) write_text_file(settings.summary_csv, validation_summary_csv(summary));
    if (settings.fail_above >= 0.0)
        for (const ValidationSummary& s : summary)
            if (s.worst_relative_l2 > settings.fail_above)
                throw Error("worst relative L2 " + shortest_text(s.worst_relative_l2) + " exceeds --fail-above " +
                            shortest_text(settings.fail_above) + " (" + to_string(s.model) +
                            (s.kernels_per_texel ? ", K = " + std::to_string(s.kernels_per_texel) : "") +
                            (s.order ? ", order " + std::to_string(s.order) : "") + ", lambda " +
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
    command->add_option("--models", settings->models,
                        "Diffraction models, comma-separated (default rohs; kirchhoff when one method is geometric)")
        ->type_name("LIST");
    const GaborSettings gabor_defaults;  // the help states the method's own defaults
    command->add_option("--kernels-per-texel", settings->kernels_per_texel,
                        "Gabor densities K, comma-separated (default the method's, " +
                            std::to_string(gabor_defaults.kernels_per_texel) + ")")
        ->type_name("LIST");
    command->add_option("--order", settings->orders,
                        "Gabor expansion orders, comma-separated: 1 (Yan 2018), 2 (chirped kernels) (default the "
                        "method's, " + std::to_string(gabor_defaults.order) + ")")
        ->type_name("LIST");
    command->add_option("--test-method", settings->test_method, "Method under test")->capture_default_str();
    command->add_option("--reference-method", settings->reference_method, "Reference method")->capture_default_str();
    command->add_option("--report", settings->report, "Full report as JSON");
    command->add_option("--csv", settings->csv, "The rows as CSV");
    command->add_option("--summary-csv", settings->summary_csv,
                        "The summary (mean and worst per model, K, order and wavelength) as CSV");
    command->add_option("--images", settings->images,
                        "Write DIR/pair-N.png per compared pair: test and reference on one log scale (4 decades), "
                        "and their signed difference (a spectrum's: the mean over its wavelengths), all zoomed to where "
                        "either lobe exceeds 1e-3 of its peak; and DIR/summary.png, error against K, when several K");
    command->add_option("--convergence", settings->convergence,
                        "Instead: error against K = 1-4 (gabor vs fft) and against the FFT step, as CSV "
                        "(plot with scripts/plot-convergence.py)");
    command->add_option("--albedo", settings->albedo,
                        "Instead: plot the directional albedo against theta_i = 0-80 deg of the test and reference "
                        "methods per --models (default rohs,kirchhoff) beside the material's F; --csv gets the numbers")
        ->type_name("PLOT.png");
    command->add_option("--fail-above", settings->fail_above,
                        "Exit non-zero when any relative L2 exceeds X (e.g. 0.06), after writing the report");
    command->callback([settings] { run(*settings); });
}

}  // namespace glintscope::cli
