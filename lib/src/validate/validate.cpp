#include "glintscope/validate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "glintscope/error.hpp"
#include "glintscope/query_keys.hpp"
#include "glintscope/text_format.hpp"

namespace glintscope {
namespace {

struct Timed {
    LobeImage image;
    double seconds = 0.0;
};

Timed timed_compute(const std::string& method, const LobeQuery& query) {
    const auto start = std::chrono::steady_clock::now();
    Timed result{compute_lobe(method, query)};
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

std::string describe_case(const Point2& centre, DiffractionModel model, int kernels) {
    return "centre " + shortest_text(centre.x) + "," + shortest_text(centre.y) + " um, " + to_string(model) +
           (kernels ? ", K = " + std::to_string(kernels) : "");
}

}  // namespace

std::vector<Point2> footprint_centres(const Heightfield& field, const Footprint& footprint, int count, bool grid,
                                      unsigned seed) {
    if (count < 1 || count > 100000) throw Error("the number of footprints must be 1 to 100000, got " + std::to_string(count));
    const Point2 reach = footprint_support_um(footprint);
    const auto span = [&](double size, double reach_um) {  // [lo, hi] of allowed centres along one axis
        return size > 2.0 * reach_um ? std::pair{reach_um, size - reach_um} : std::pair{0.0, size};
    };
    const auto [x0, x1] = span(field.width_um(), reach.x);
    const auto [y0, y1] = span(field.height_um(), reach.y);
    std::vector<Point2> centres;
    if (grid) {
        const int side = static_cast<int>(std::ceil(std::sqrt(double(count))));
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i)
                centres.push_back({x0 + (i + 0.5) / side * (x1 - x0), y0 + (j + 0.5) / side * (y1 - y0)});
        return centres;
    }
    std::mt19937_64 random(seed);  // the same seed gives the same centres on every platform
    const auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * (double(random() >> 11) * 0x1.0p-53); };
    for (int k = 0; k < count; ++k) {
        const double x = uniform(x0, x1);
        centres.push_back({x, uniform(y0, y1)});
    }
    return centres;
}

LobeImage difference_image(const LobeImage& test, const LobeImage& reference) {
    compare_lobes(test, reference);  // checks that they are comparable
    LobeImage difference = make_lobe_image(test.resolution, test.wavelengths_um, test.quantity);
    for (std::size_t i = 0; i < difference.values.size(); ++i) difference.values[i] = test.values[i] - reference.values[i];
    difference.metadata = test.metadata;
    difference.metadata["method"] = test.metadata.count("method") ? test.metadata.at("method") + " - " +
                                                                        reference.metadata.at("method")
                                                                  : "difference";
    return difference;
}

std::vector<ValidationRow> run_validation(const ValidationPlan& plan, const ProgressCallback& progress,
                                          const PairCallback& pair) {
    const std::vector<DiffractionModel> models = plan.models.empty() ? std::vector{plan.base.model} : plan.models;
    const std::vector<int> densities = plan.kernels_per_texel.empty() ? std::vector{0} : plan.kernels_per_texel;
    const std::vector<Point2> centres = plan.centres.empty() ? std::vector{plan.base.footprint.centre_um} : plan.centres;
    const std::size_t total = centres.size() * models.size() * (densities.size() + 1);
    std::size_t done = 0;
    std::vector<ValidationRow> rows;
    for (const Point2& centre : centres)
        for (DiffractionModel model : models) {
            LobeQuery query = plan.base;
            query.footprint.centre_um = centre;
            query.model = model;
            const Timed reference = timed_compute(plan.reference_method, query);
            if (progress) progress(++done, total, plan.reference_method + ", " + describe_case(centre, model, 0));
            for (int kernels : densities) {
                LobeQuery test_query = query;
                if (kernels) test_query.method_options["kernels_per_texel"] = std::to_string(kernels);
                const Timed test = timed_compute(plan.test_method, test_query);
                if (progress) progress(++done, total, plan.test_method + ", " + describe_case(centre, model, kernels));
                const std::size_t first = rows.size();
                for (const LayerComparison& layer : compare_lobes(test.image, reference.image))
                    rows.push_back({centre, model, kernels, layer, test.seconds, reference.seconds});
                if (pair) pair(rows[first], test.image, reference.image);
            }
        }
    return rows;
}

std::vector<ConvergencePoint> run_convergence(const ValidationPlan& plan, const ProgressCallback& progress) {
    LobeQuery query = plan.base;
    if (!plan.centres.empty()) query.footprint.centre_um = plan.centres.front();
    if (!plan.models.empty()) query.model = plan.models.front();
    query.wavelengths_um = {query.wavelengths_um.front()};
    query.method_options.clear();
    const std::size_t total = 1 + 4 + 1 + 4;
    std::size_t done = 0;
    const auto step = [&](const std::string& what) {
        if (progress) progress(++done, total, what);
    };
    std::vector<ConvergencePoint> points;
    const LobeImage reference = compute_lobe("fft", query);
    step("fft");
    for (int kernels = 1; kernels <= 4; ++kernels) {
        LobeQuery test = query;
        test.method_options["kernels_per_texel"] = std::to_string(kernels);
        points.push_back({"gabor_kernels_per_texel", double(kernels),
                          compare_lobes(compute_lobe("gabor", test), reference).at(0).relative_l2});
        step("gabor, K = " + std::to_string(kernels));
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
        "centre_x_um,centre_y_um,model,kernels_per_texel,wavelength_um,relative_l2,peak_relative_error,"
        "log_rms_error,energy_ratio,test_sum,reference_sum,max_abs_difference,peak_offset_pixels,test_seconds,"
        "reference_seconds\n";
    for (const ValidationRow& row : rows) {
        const LayerComparison& c = row.comparison;
        csv += join({shortest_text(row.centre_um.x), shortest_text(row.centre_um.y), to_string(row.model),
                     std::to_string(row.kernels_per_texel), shortest_text(c.wavelength_um), shortest_text(c.relative_l2),
                     shortest_text(c.peak_relative_error), shortest_text(c.log_rms_error),
                     shortest_text(c.energy_ratio()), shortest_text(c.test_sum), shortest_text(c.reference_sum),
                     shortest_text(c.max_abs_difference), shortest_text(c.peak_offset_pixels),
                     shortest_text(row.test_seconds), shortest_text(row.reference_seconds)},
                    ",") +
               "\n";
    }
    return csv;
}

std::string validation_json(const ValidationPlan& plan, const std::vector<ValidationRow>& rows) {
    nlohmann::ordered_json report;
    report["format"] = "glintscope validation";
    report["test_method"] = plan.test_method;
    report["reference_method"] = plan.reference_method;
    nlohmann::ordered_json query;
    for (const auto& [key, value] : query_text(plan.base))
        if (key != "centre") query[key] = value;
    report["query"] = query;
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const ValidationRow& row : rows) {
        const LayerComparison& c = row.comparison;
        list.push_back({{"centre_um", {row.centre_um.x, row.centre_um.y}},
                        {"model", to_string(row.model)},
                        {"kernels_per_texel", row.kernels_per_texel},
                        {"wavelength_um", c.wavelength_um},
                        {"relative_l2", c.relative_l2},
                        {"peak_relative_error", c.peak_relative_error},
                        {"log_rms_error", c.log_rms_error},
                        {"energy_ratio", c.energy_ratio()},
                        {"test_sum", c.test_sum},
                        {"reference_sum", c.reference_sum},
                        {"max_abs_difference", c.max_abs_difference},
                        {"max_pixel", {c.max_row, c.max_col}},
                        {"peak_offset_pixels", c.peak_offset_pixels},
                        {"test_seconds", row.test_seconds},
                        {"reference_seconds", row.reference_seconds}});
    }
    report["rows"] = list;
    return report.dump(2) + "\n";
}

}  // namespace glintscope
