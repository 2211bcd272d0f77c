#include "glintscope/validate/validate.hpp"
#include "glintscope/pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <nlohmann/json.hpp>

#include "glintscope/core/error.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/version.hpp"

namespace glintscope {
namespace {

struct Timed {
    LobeImage image;
    double seconds = 0.0;
};

// The value a method recorded for one of its settings (e.g. gabor.order when the default was
// used), or `asked` when it was given or the method records none: rows name what ran.
int setting_used(const LobeImage& image, const std::string& key, int asked) {
    if (asked) return asked;
    const auto found = image.metadata.find(key);
    return found == image.metadata.end() ? 0 : static_cast<int>(parse_number(found->second));
}

Timed timed_compute(const std::string& method, const LobeQuery& query) {
    const auto start = std::chrono::steady_clock::now();
    Timed result{compute_lobe(method, query)};
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

std::string describe_case(const Point2& centre, DiffractionModel model, int kernels, int order) {
    return "centre " + shortest_text(centre.x) + "," + shortest_text(centre.y) + " um, " + to_string(model) +
           (kernels ? ", K = " + std::to_string(kernels) : "") + (order ? ", order " + std::to_string(order) : "");
}

std::vector<Point2> validation_centres(const ValidationPlan& plan) {
    return footprint_centres(*plan.base.field, plan.base.footprint, plan.base.footprints);
}

// The base query at one of its footprints, with the supersampling the reference method's plan
// chooses, so that test and reference sample their pixels alike.
LobeQuery single_footprint(const ValidationPlan& plan, Point2 centre) {
    LobeQuery query = plan.base;
    query.footprints = {};
    query.footprint.centre_um = centre;
    if (query.supersample == 0) query.supersample = plan_lobe(plan.reference_method, query).query.supersample;
    return query;
}

}  // namespace

std::vector<DiffractionModel> validation_models(const ValidationPlan& plan) {
    if (!plan.models.empty()) return plan.models;
    const bool test_ignores = lobe_method(plan.test_method).ignores(QueryField::model);
    const bool reference_ignores = lobe_method(plan.reference_method).ignores(QueryField::model);
    // Kirchhoff's phase (ψ·n)kH with its slope term ξ2 (Yan 2018 Fig. 6) has the geometric lobe as
    // its stationary-phase limit; OHS and R-OHS take the phase 2kH of normal incidence (ξ3 = 2),
    // which away from it overstates the slopes by 2/(ψ·n) and converges to a wider lobe.
    if (test_ignores != reference_ignores) return {DiffractionModel::kirchhoff};
    return {plan.base.model};
}

std::vector<std::string> validation_notes(const ValidationPlan& plan) {
    if (!plan.models.empty() || validation_models(plan).front() != DiffractionModel::kirchhoff ||
        plan.base.model == DiffractionModel::kirchhoff)
        return {};
    const std::string geometric = lobe_method(plan.test_method).ignores(QueryField::model) ? plan.test_method
                                                                                            : plan.reference_method;
    return {geometric + " ignores the diffraction model: the wave lobe uses kirchhoff, whose lambda -> 0 limit is "
            "geometric optics (R-OHS's phase 2kH is not; --models to choose); compare with 'smooth L2', which is speckle-free"};
}

std::vector<ValidationRow> run_validation(const ValidationPlan& plan, const ProgressCallback& progress,
                                          const PairCallback& pair) {
    const std::vector<DiffractionModel> models = validation_models(plan);
    const std::vector<int> densities = plan.kernels_per_texel.empty() ? std::vector{0} : plan.kernels_per_texel;
    const std::vector<int> orders = plan.orders.empty() ? std::vector{0} : plan.orders;
    const std::vector<Point2> centres = validation_centres(plan);
    const std::size_t total = centres.size() * models.size() * (densities.size() * orders.size() + 1);
    std::size_t done = 0;
    std::vector<ValidationRow> rows;
    for (const Point2& centre : centres)
        for (DiffractionModel model : models) {
            LobeQuery query = single_footprint(plan, centre);
            query.model = model;
            const Timed reference = timed_compute(plan.reference_method, query);
            if (progress) progress(++done, total, plan.reference_method + ", " + describe_case(centre, model, 0, 0));
            for (int kernels : densities)
                for (int order : orders) {
                    LobeQuery test_query = query;
                    if (kernels) test_query.method_options["kernels_per_texel"] = std::to_string(kernels);
                    if (order) test_query.method_options["order"] = std::to_string(order);
                    const Timed test = timed_compute(plan.test_method, test_query);
                    if (progress)
                        progress(++done, total,
                                 plan.test_method + ", " + describe_case(centre, model, kernels, order));
                    const std::size_t first = rows.size();
                    const int kernels_used = setting_used(test.image, "gabor.kernels_per_texel", kernels);
                    const int order_used = setting_used(test.image, "gabor.order", order);
                    for (const LayerComparison& layer : compare_lobes(test.image, reference.image))
                        rows.push_back({centre, model, kernels_used, order_used, layer, test.seconds, reference.seconds});
                    if (pair) pair(rows[first], test.image, reference.image);
                }
        }
    return rows;
}

std::vector<ConvergencePoint> run_convergence(const ValidationPlan& plan, const ProgressCallback& progress) {
    LobeQuery query = single_footprint(plan, validation_centres(plan).front());
    query.model = validation_models(plan).front();
    query.wavelengths_um = {query.wavelengths_um.front()};
    query.method_options.clear();
    const std::size_t total = 1 + 2 * 4 + 1 + 4;
    std::size_t done = 0;
    const auto step = [&](const std::string& what) {
        if (progress) progress(++done, total, what);
    };
    std::vector<ConvergencePoint> points;
    const LobeImage reference = compute_lobe("fft", query);
    step("fft");
    for (const int order : {1, 2})
        for (int kernels = 1; kernels <= 4; ++kernels) {
            LobeQuery test = query;
            test.method_options["kernels_per_texel"] = std::to_string(kernels);
            test.method_options["order"] = std::to_string(order);
            points.push_back({"gabor_order_" + std::to_string(order) + "_kernels_per_texel", double(kernels),
                              compare_lobes(compute_lobe("gabor", test), reference).at(0).relative_l2});
            step("gabor, order " + std::to_string(order) + ", K = " + std::to_string(kernels));
        }
    // The automatic step (the finer of the two axes'), then the FFT at fractions of it.
    const std::vector<std::string> steps = split(reference.metadata.at("fft.step_um"), ',');
    const double automatic = std::min(parse_number(steps.at(0)), parse_number(steps.at(1)));
    LobeQuery finest = query;
    finest.method_options["step"] = shortest_text(automatic / 4.0);
    const LobeImage truth = compute_lobe("fft", finest);
    step("fft at a quarter step");
    for (double factor : {2.0, 1.5, 1.0, 0.5}) {
        LobeQuery test = query;
        test.method_options["step"] = shortest_text(automatic * factor);
        points.push_back({"fft_step_um", automatic * factor, compare_lobes(compute_lobe("fft", test), truth).at(0).relative_l2});
        step("fft, step x" + shortest_text(factor));
    }
    return points;
}

std::string convergence_csv(const std::vector<ConvergencePoint>& points) {
    std::string csv = "series,parameter,relative_l2\n";
    for (const ConvergencePoint& point : points)
        csv += point.series + "," + shortest_text(point.parameter) + "," + shortest_text(point.relative_l2) + "\n";
    return csv;
}

std::string validation_csv(const std::vector<ValidationRow>& rows) {
    std::string csv =
        "centre_x_um,centre_y_um,model,kernels_per_texel,order,wavelength_um,relative_l2,peak_relative_error,"
        "log_rms_error,smoothed_relative_l2,energy_ratio,test_sum,reference_sum,max_abs_difference,peak_offset_pixels,test_seconds,"
        "reference_seconds\n";
    for (const ValidationRow& row : rows) {
        const LayerComparison& c = row.comparison;
        csv += join({shortest_text(row.centre_um.x), shortest_text(row.centre_um.y), to_string(row.model),
                     std::to_string(row.kernels_per_texel), std::to_string(row.order), shortest_text(c.wavelength_um),
                     shortest_text(c.relative_l2),
                     shortest_text(c.peak_relative_error), shortest_text(c.log_rms_error),
                     shortest_text(c.smoothed_relative_l2), shortest_text(c.energy_ratio()), shortest_text(c.test_sum), shortest_text(c.reference_sum),
                     shortest_text(c.max_abs_difference), shortest_text(c.peak_offset_pixels),
                     shortest_text(row.test_seconds), shortest_text(row.reference_seconds)},
                    ",") +
               "\n";
    }
    return csv;
}

std::vector<ValidationSummary> summarize_validation(const std::vector<ValidationRow>& rows) {
    std::vector<ValidationSummary> summary;
    for (const ValidationRow& row : rows) {
        const LayerComparison& c = row.comparison;
        auto it = std::find_if(summary.begin(), summary.end(), [&](const ValidationSummary& s) {
            return s.model == row.model && s.kernels_per_texel == row.kernels_per_texel && s.order == row.order &&
                   s.wavelength_um == c.wavelength_um;
        });
        if (it == summary.end())
            it = summary.insert(summary.end(), {row.model, row.kernels_per_texel, row.order, c.wavelength_um});
        ++it->footprints;
        it->mean_relative_l2 += c.relative_l2;
        it->worst_relative_l2 = std::max(it->worst_relative_l2, c.relative_l2);
        it->mean_peak_error += c.peak_relative_error;
        it->worst_peak_error = std::max(it->worst_peak_error, c.peak_relative_error);
        it->mean_smoothed_l2 += c.smoothed_relative_l2;
        it->worst_smoothed_l2 = std::max(it->worst_smoothed_l2, c.smoothed_relative_l2);
        it->mean_energy_ratio += c.energy_ratio();
    }
    for (ValidationSummary& s : summary) {
        s.mean_relative_l2 /= s.footprints;
        s.mean_peak_error /= s.footprints;
        s.mean_smoothed_l2 /= s.footprints;
        s.mean_energy_ratio /= s.footprints;
    }
    return summary;
}

Plot error_against_k_plot(const ValidationPlan& plan, const std::vector<ValidationSummary>& summary) {
    if (summary.empty()) throw Error("the summary figure needs at least one summary row");
    Plot plot{plan.test_method + " against " + plan.reference_method + ": error against kernels per texel K",
              "K (kernels per texel)", "mean relative L2 [%]", {}, {}, true};
    const std::size_t wavelengths = plan.base.wavelengths_um.size();
    for (const ValidationSummary& s : summary) {
        const std::string label = to_string(s.model) + (s.order ? ", order " + std::to_string(s.order) : "");
        auto series = std::find_if(plot.series.begin(), plot.series.end(), [&](const PlotSeries& p) { return p.label == label; });
        if (series == plot.series.end()) series = plot.series.insert(plot.series.end(), {label, {}, {}});
        const std::size_t k = std::find(series->x.begin(), series->x.end(), double(s.kernels_per_texel)) - series->x.begin();
        if (k == series->x.size()) {  // a new K: its mean over the wavelengths starts here
            series->x.push_back(s.kernels_per_texel);
            series->y.push_back(0.0);
        }
        series->y[k] += 100.0 * s.mean_relative_l2 / double(wavelengths);
    }
    const std::size_t footprints = summary.front().footprints;
    plot.caption.push_back("each point: the mean over " + std::to_string(footprints) + " footprint" +
                           (footprints == 1 ? "" : "s") + " and " + std::to_string(wavelengths) + " wavelength" +
                           (wavelengths == 1 ? "" : "s") + " of the relative L2 (validate's summary)");
    return plot;
}

const std::vector<std::string>& validation_column_definitions() {
    static const std::vector<std::string> columns = {
        "rel L2: sqrt(sum (t - r)^2) / sqrt(sum r^2) over the disk's pixels (t test, r reference)",
        "peak err: |t - r| / r at the reference's brightest pixel",
        "log err: root mean square of log10(t / r) where r is above 1e-3 of its peak (the tails)",
        "smooth L2: rel L2 with t and r blurred by a Gaussian of one pixel: speckle-free, for geometric against wave",
        "energy: test albedo / reference albedo, each sum f_r (2/N)^2 over the disk",
        "t test, t ref: seconds to compute the test and reference lobes (all wavelengths)",
        "mean, worst (L2, peak, smL2 = smooth L2): over the footprints of one model, K, order and wavelength (the summary)"};
    return columns;
}

std::string validation_summary_csv(const std::vector<ValidationSummary>& summary) {
    std::string csv = "model,kernels_per_texel,order,wavelength_um,footprints,mean_relative_l2,worst_relative_l2,"
                      "mean_peak_relative_error,worst_peak_relative_error,mean_smoothed_relative_l2,"
                      "worst_smoothed_relative_l2,mean_energy_ratio\n";
    for (const ValidationSummary& s : summary)
        csv += join({to_string(s.model), std::to_string(s.kernels_per_texel), std::to_string(s.order),
                     shortest_text(s.wavelength_um),
                     std::to_string(s.footprints), shortest_text(s.mean_relative_l2), shortest_text(s.worst_relative_l2),
                     shortest_text(s.mean_peak_error), shortest_text(s.worst_peak_error),
                     shortest_text(s.mean_smoothed_l2), shortest_text(s.worst_smoothed_l2),
                     shortest_text(s.mean_energy_ratio)},
                    ",") +
               "\n";
    return csv;
}

std::string validation_json(const ValidationPlan& plan, const std::vector<ValidationRow>& rows,
                            const std::string& command_line, const std::vector<std::string>& pictures) {
    nlohmann::ordered_json report;
    report["format"] = "glintscope validation";
    report["version"] = version();
    if (!command_line.empty()) report["command_line"] = command_line;
    report["test_method"] = plan.test_method;
    report["reference_method"] = plan.reference_method;
    nlohmann::ordered_json query;
    for (const auto& [key, value] : query_text(plan.base))
        if (key != "centre" && key != "model") query[key] = value;
    report["query"] = query;
    nlohmann::ordered_json models = nlohmann::ordered_json::array(), densities = nlohmann::ordered_json::array();
    for (DiffractionModel model : validation_models(plan))
        models.push_back(to_string(model));
    for (int k : plan.kernels_per_texel) densities.push_back(k);
    report["models"] = models;
    report["kernels_per_texel"] = densities;  // empty: the test method's default
    report["orders"] = plan.orders;           // empty: the test method's default
    nlohmann::ordered_json centres = nlohmann::ordered_json::array();
    for (const Point2& centre : validation_centres(plan)) centres.push_back({centre.x, centre.y});
    report["footprint_centres_um"] = centres;
    report["wavelengths_um"] = plan.base.wavelengths_um;
    report["columns"] = validation_column_definitions();
    nlohmann::ordered_json summary = nlohmann::ordered_json::array();
    for (const ValidationSummary& s : summarize_validation(rows))
        summary.push_back({{"model", to_string(s.model)},
                           {"kernels_per_texel", s.kernels_per_texel},
                           {"order", s.order},
                           {"wavelength_um", s.wavelength_um},
                           {"footprints", s.footprints},
                           {"mean_relative_l2", s.mean_relative_l2},
                           {"worst_relative_l2", s.worst_relative_l2},
                           {"mean_peak_relative_error", s.mean_peak_error},
                           {"worst_peak_relative_error", s.worst_peak_error},
                           {"mean_smoothed_relative_l2", s.mean_smoothed_l2},
                           {"worst_smoothed_relative_l2", s.worst_smoothed_l2},
                           {"mean_energy_ratio", s.mean_energy_ratio}});
    report["summary"] = summary;
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < rows.size(); ++k) {
        const ValidationRow& row = rows[k];
        const LayerComparison& c = row.comparison;
        nlohmann::ordered_json entry = {{"centre_um", {row.centre_um.x, row.centre_um.y}},
                                        {"model", to_string(row.model)},
                                        {"kernels_per_texel", row.kernels_per_texel},
                                        {"order", row.order},
                                        {"wavelength_um", c.wavelength_um},
                                        {"relative_l2", c.relative_l2},
                                        {"peak_relative_error", c.peak_relative_error},
                                        {"log_rms_error", c.log_rms_error},
                                        {"smoothed_relative_l2", c.smoothed_relative_l2},
                                        {"energy_ratio", c.energy_ratio()},
                                        {"test_sum", c.test_sum},
                                        {"reference_sum", c.reference_sum},
                                        {"max_abs_difference", c.max_abs_difference},
                                        {"max_pixel", {c.max_row, c.max_col}},
                                        {"peak_offset_pixels", c.peak_offset_pixels},
                                        {"test_seconds", row.test_seconds},
                                        {"reference_seconds", row.reference_seconds}};
        if (k < pictures.size() && !pictures[k].empty()) entry["picture"] = pictures[k];
        list.push_back(entry);
    }
    report["rows"] = list;
    return report.dump(2) + "\n";
}

}  // namespace glintscope
