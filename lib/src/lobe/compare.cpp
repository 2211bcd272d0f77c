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

double log_rms_error(std::span<const float> test, std::span<const float> reference, int n, double reference_peak) {
    const double floor = 1e-3 * reference_peak;
    double sum = 0.0;
    std::size_t count = 0;
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            const std::size_t i = std::size_t(row) * n + col;
            const double r = reference[i];
            if (!(r > floor) || !inside_unit_disk(disk_pixel_point(row, col, n))) continue;
            const double t = std::max<double>(test[i], floor);
            sum += std::pow(std::log10(t / r), 2);
            ++count;
        }
    return count ? std::sqrt(sum / count) : 0.0;
}

// √(Σ (t − r)²)/√(Σ r²) over the disk's pixels.
template <typename Values>
double relative_l2(const Values& test, const Values& reference, int n) {
    double difference2 = 0.0, reference2 = 0.0;
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            if (!inside_unit_disk(disk_pixel_point(row, col, n))) continue;
            const std::size_t i = std::size_t(row) * n + col;
            difference2 += (double(test[i]) - reference[i]) * (double(test[i]) - reference[i]);
            reference2 += double(reference[i]) * reference[i];
        }
    return reference2 > 0.0 ? std::sqrt(difference2 / reference2) : std::sqrt(difference2);
}

}  // namespace

std::vector<double> smooth_layer(std::span<const float> layer, int n) {
    constexpr int reach = 4;
    double taps[2 * reach + 1];
    double total = 0.0;
    for (int k = -reach; k <= reach; ++k) total += taps[k + reach] = std::exp(-0.5 * k * k);
    for (double& tap : taps) tap /= total;  // a unit-sum kernel: a blurred constant keeps its value
    std::vector<double> along_rows(layer.size(), 0.0), smoothed(layer.size(), 0.0);
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col)
            for (int k = std::max(-reach, -col); k <= std::min(reach, n - 1 - col); ++k)
                along_rows[std::size_t(row) * n + col] += taps[k + reach] * layer[std::size_t(row) * n + col + k];
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col)
            for (int k = std::max(-reach, -row); k <= std::min(reach, n - 1 - row); ++k)
                smoothed[std::size_t(row) * n + col] += taps[k + reach] * along_rows[std::size_t(row + k) * n + col];
    return smoothed;
}

LayerComparison compare_layer(std::span<const float> test, std::span<const float> reference, int n) {
    const std::size_t pixels = std::size_t(n) * n;
    if (n < 1 || test.size() != pixels || reference.size() != pixels)
        throw Error("cannot compare layers of " + std::to_string(test.size()) + " and " +
                    std::to_string(reference.size()) + " values as " + std::to_string(n) + "² images");
    LayerComparison result;
    float test_peak = -INFINITY, reference_peak = -INFINITY;
    std::size_t test_peak_index = 0, reference_peak_index = 0;
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            if (!inside_unit_disk(disk_pixel_point(row, col, n))) continue;
            const std::size_t i = std::size_t(row) * n + col;
            const double t = test[i];
            const double r = reference[i];
            if (std::fabs(t - r) > result.max_abs_difference) {
                result.max_abs_difference = std::fabs(t - r);
                result.max_row = row;
                result.max_col = col;
            }
            if (t > test_peak) test_peak = float(t), test_peak_index = i;
            if (r > reference_peak) reference_peak = float(r), reference_peak_index = i;
        }
    result.relative_l2 = relative_l2(test, reference, n);
    result.smoothed_relative_l2 = relative_l2(smooth_layer(test, n), smooth_layer(reference, n), n);
    result.test_sum = disk_sum(test, n);
    result.reference_sum = disk_sum(reference, n);
    result.peak_offset_pixels = std::hypot(double(test_peak_index / n) - double(reference_peak_index / n),
                                           double(test_peak_index % n) - double(reference_peak_index % n));
    const float test_at_peak = test[reference_peak_index];
    result.peak_relative_error = reference_peak > 0.0f ? std::fabs(test_at_peak - reference_peak) / reference_peak : 0.0;
    result.log_rms_error = log_rms_error(test, reference, n, reference_peak);
    return result;
}

std::vector<LayerComparison> compare_lobes(const LobeImage& test, const LobeImage& reference) {
    check_comparable(test, reference);
    std::vector<LayerComparison> layers;
    for (std::size_t layer = 0; layer < test.layers(); ++layer) {
        layers.push_back(compare_layer(layer_values(test, layer), layer_values(reference, layer), test.resolution));
        layers.back().wavelength_um = test.wavelengths_um[layer];
    }
    return layers;
}

LobeImage difference_image(const LobeImage& test, const LobeImage& reference) {
    check_comparable(test, reference);
    LobeImage difference = make_lobe_image(test.resolution, test.wavelengths_um, test.quantity);
    for (std::size_t i = 0; i < difference.values.size(); ++i) difference.values[i] = test.values[i] - reference.values[i];
    difference.metadata = test.metadata;
    const auto method = [](const LobeImage& image) {
        const auto it = image.metadata.find("method");
        return it == image.metadata.end() ? std::string("?") : it->second;
    };
    difference.metadata["method"] = method(test) + " - " + method(reference);
    difference.metadata["difference"] = "test - reference";  // drawn signed even where it is ≥ 0 (figure.hpp)
    return difference;
}

}  // namespace glintscope
