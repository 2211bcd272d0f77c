#include "glintscope/lobe/compare.hpp"

#include <algorithm>
#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"

namespace glintscope {
namespace {

void check_comparable(const LobeImage& test, const LobeImage& reference) {
    if (test.resolution != reference.resolution)
        throw Error("cannot compare images of " + std::to_string(test.resolution) + "² and " +
                    std::to_string(reference.resolution) + "² pixels");
    if (test.quantity != reference.quantity)
        throw Error("cannot compare " + to_string(test.quantity) + " with " + to_string(reference.quantity));
    if (test.wavelengths_um != reference.wavelengths_um)
        throw Error("cannot compare images of different wavelengths");
}

double log_rms_error(const LobeImage& test, const LobeImage& reference, std::size_t layer, double reference_peak) {
    const int n = test.resolution;
    const double floor = 1e-3 * reference_peak;
    double sum = 0.0;
    std::size_t count = 0;
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            const double r = reference.at(layer, row, col);
            if (!(r > floor) || !inside_unit_disk(disk_pixel_point(row, col, n))) continue;
            const double t = std::max<double>(test.at(layer, row, col), floor);
            sum += std::pow(std::log10(t / r), 2);
            ++count;
        }
    return count ? std::sqrt(sum / count) : 0.0;
}

}  // namespace

std::vector<LayerComparison> compare_lobes(const LobeImage& test, const LobeImage& reference) {
    check_comparable(test, reference);
    const int n = test.resolution;
    std::vector<LayerComparison> layers;
    for (std::size_t layer = 0; layer < test.layers(); ++layer) {
        LayerComparison result;
        result.wavelength_um = test.wavelengths_um[layer];
        double difference2 = 0.0, reference2 = 0.0;
        float test_peak = -INFINITY, reference_peak = -INFINITY;
        int test_peak_index = 0, reference_peak_index = 0;
        for (int row = 0; row < n; ++row)
            for (int col = 0; col < n; ++col) {
                if (!inside_unit_disk(disk_pixel_point(row, col, n))) continue;
                const double t = test.at(layer, row, col);
                const double r = reference.at(layer, row, col);
                difference2 += (t - r) * (t - r);
                reference2 += r * r;
                result.test_sum += t;
                result.reference_sum += r;
                if (std::fabs(t - r) > result.max_abs_difference) {
                    result.max_abs_difference = std::fabs(t - r);
                    result.max_row = row;
                    result.max_col = col;
                }
                if (t > test_peak) test_peak = float(t), test_peak_index = row * n + col;
                if (r > reference_peak) reference_peak = float(r), reference_peak_index = row * n + col;
            }
        result.relative_l2 = reference2 > 0.0 ? std::sqrt(difference2 / reference2) : std::sqrt(difference2);
        result.test_sum *= disk_pixel_area(n);
        result.reference_sum *= disk_pixel_area(n);
        result.peak_offset_pixels = std::hypot(test_peak_index / n - reference_peak_index / n,
                                               test_peak_index % n - reference_peak_index % n);
        const float test_at_peak = test.values[layer * n * n + reference_peak_index];
        result.peak_relative_error = reference_peak > 0.0f ? std::fabs(test_at_peak - reference_peak) / reference_peak : 0.0;
        result.log_rms_error = log_rms_error(test, reference, layer, reference_peak);
        layers.push_back(result);
    }
    return layers;
}

}  // namespace glintscope
