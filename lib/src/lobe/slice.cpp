#include "glintscope/lobe/slice.hpp"

#include <algorithm>
#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

// Bilinear between pixel centres at disk point (x, y); pixel (r, c) has its centre at
// ((c + ½)·2/N − 1, 1 − (r + ½)·2/N) (conventions.md).
double bilinear(const LobeImage& image, std::size_t layer, double x, double y) {
    const int n = image.resolution;
    const double u = (x + 1.0) * 0.5 * n - 0.5;  // column coordinate
    const double v = (1.0 - y) * 0.5 * n - 0.5;  // row coordinate
    const int c0 = std::clamp(int(std::floor(u)), 0, n - 2), r0 = std::clamp(int(std::floor(v)), 0, n - 2);
    const double fu = std::clamp(u - c0, 0.0, 1.0), fv = std::clamp(v - r0, 0.0, 1.0);
    return (1 - fv) * ((1 - fu) * image.at(layer, r0, c0) + fu * image.at(layer, r0, c0 + 1)) +
           fv * ((1 - fu) * image.at(layer, r0 + 1, c0) + fu * image.at(layer, r0 + 1, c0 + 1));
}

}  // namespace

std::vector<SlicePoint> image_slice(const LobeImage& image, double angle_rad, int samples) {
    if (samples < 2 || samples > 100000) throw Error("a slice needs 2 to 100000 samples");
    std::vector<SlicePoint> slice;
    for (int k = 0; k < samples; ++k) {
        SlicePoint point;
        point.position = -1.0 + (k + 0.5) * 2.0 / samples;
        point.theta_deg = std::asin(point.position) * 180.0 / pi;
        const double x = point.position * std::cos(angle_rad), y = point.position * std::sin(angle_rad);
        for (std::size_t layer = 0; layer < image.layers(); ++layer) point.values.push_back(bilinear(image, layer, x, y));
        slice.push_back(point);
    }
    return slice;
}

double parse_slice_direction(const std::string& text) {
    if (text == "x") return 0.0;
    if (text == "y") return 0.5 * pi;
    try {
        return parse_number(text) * pi / 180.0;
    } catch (const Error&) {
        throw Error("a slice direction is x, y or an angle in degrees, got '" + text + "'");
    }
}

std::string slice_csv(const LobeImage& image, const std::vector<SlicePoint>& slice) {
    std::string csv = "position,theta_deg";
    // Appended piece by piece: GCC 12 misreports "," + std::string under -Wrestrict.
    for (double lambda : image.wavelengths_um)
        csv.append(",").append(labels(image.quantity).symbol).append("_").append(shortest_text(lambda)).append("um");
    csv += "\n";
    for (const SlicePoint& point : slice) {
        csv.append(shortest_text(point.position)).append(",").append(shortest_text(point.theta_deg));
        for (double value : point.values) csv.append(",").append(shortest_text(value));
        csv.append("\n");
    }
    return csv;
}

}  // namespace glintscope
