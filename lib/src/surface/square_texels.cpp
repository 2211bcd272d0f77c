#include "glintscope/surface/square_texels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "surface/catmull_rom.hpp"
#include "surface/line_extension.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kLinesPerChunk = 16;

// A line of n samples `step` apart resampled onto m samples: new sample k sits at source index
// offset + k·step (in source samples), read with the Catmull–Rom kernel.
struct AxisMap {
    int n = 0, m = 0;
    double offset = 0.0, step = 1.0;
};

// Sample positions centred on the same extent: new sample k, spaced `step` source samples
// apart, lies at source index (k + ½ − m/2)·step + n/2 − ½. step = t/d keeps the spacing t; a
// periodic line keeps its period instead (step = n/m, which differs from t/d by the rounding of m).
AxisMap centred_map(int n, double d, int m, double t, bool periodic) {
    const double step = periodic ? static_cast<double>(n) / m : t / d;
    return {n, m, (0.5 - 0.5 * m) * step + 0.5 * n - 0.5, step};
}

// The line (n samples, `stride` apart) at source index u; NaN when a sample with non-zero
// weight is missing.
double interpolate(const float* line, std::size_t stride, const AxisMap& map, double u, bool periodic) {
    const double floor_u = std::floor(u);
    const CubicWeights weights = catmull_rom(u - floor_u);
    const auto base = static_cast<long long>(floor_u);
    double sum = 0.0;
    for (int j = 0; j < 4; ++j) {
        if (weights.w[j] == 0.0) continue;
        sum += weights.w[j] * extended_sample(line, stride, base - 1 + j, map.n, periodic);
    }
    return sum;
}

// Resamples every line along one axis (rows along y when !along_x) into `out`.
Heightfield resample_axis(const Heightfield& field, bool along_x, const AxisMap& map) {
    Heightfield out = make_heightfield(along_x ? field.rows : map.m, along_x ? map.m : field.cols, field.texel_um);
    const int lines = along_x ? field.rows : field.cols;
    const std::size_t source_stride = along_x ? 1 : static_cast<std::size_t>(field.cols);
    const std::size_t out_stride = along_x ? 1 : static_cast<std::size_t>(out.cols);
    parallel_for(static_cast<std::size_t>(lines), kLinesPerChunk, [&](std::size_t begin, std::size_t end) {
        for (std::size_t line = begin; line < end; ++line) {
            const float* source = field.heights_um.data() + (along_x ? line * field.cols : line);
            float* target = out.heights_um.data() + (along_x ? line * out.cols : line);
            for (int k = 0; k < map.m; ++k)
                target[k * out_stride] = static_cast<float>(
                    interpolate(source, source_stride, map, map.offset + k * map.step, field.periodic));
        }
    });
    return out;
}

// max |h − back-interpolated h| over the original valid samples, reading the new lines at the
// original positions (the inverse map).
double round_trip_change(const Heightfield& before, const Heightfield& after, bool along_x, const AxisMap& map) {
    const AxisMap back{map.m, map.n, -map.offset / map.step, 1.0 / map.step};
    const int lines = along_x ? before.rows : before.cols;
    const std::size_t chunks = (static_cast<std::size_t>(lines) + kLinesPerChunk - 1) / kLinesPerChunk;
    std::vector<double> largest(chunks, 0.0);
    parallel_for(static_cast<std::size_t>(lines), kLinesPerChunk, [&](std::size_t begin, std::size_t end) {
        double chunk_largest = 0.0;
        for (std::size_t line = begin; line < end; ++line) {
            const float* source = before.heights_um.data() + (along_x ? line * before.cols : line);
            const float* resampled = after.heights_um.data() + (along_x ? line * after.cols : line);
            const std::size_t source_stride = along_x ? 1 : static_cast<std::size_t>(before.cols);
            const std::size_t stride = along_x ? 1 : static_cast<std::size_t>(after.cols);
            for (int k = 0; k < map.n; ++k) {
                const double value = interpolate(resampled, stride, back, back.offset + k * back.step, before.periodic);
                const double original = source[k * source_stride];
                if (!std::isnan(value) && !std::isnan(original))
                    chunk_largest = std::max(chunk_largest, std::fabs(value - original));
            }
        }
        largest[begin / kLinesPerChunk] = chunk_largest;
    });
    return *std::max_element(largest.begin(), largest.end());
}

}  // namespace

SquareTexelReport make_texels_square(Heightfield& field, std::size_t max_samples, const std::string& what) {
    validate(field, what, /*allow_missing=*/true);
    const double dx_um = field.dx_um(), dy_um = field.dy_um();
    if (!(dx_um > 0.0 && dy_um > 0.0) || !std::isfinite(dx_um) || !std::isfinite(dy_um))
        throw Error(what + ": the sample spacing must be positive and finite, got " + format_length(dx_um) + " x " +
                    format_length(dy_um));
    const double aspect = std::max(dx_um, dy_um) / std::min(dx_um, dy_um);
    if (aspect > kMaxTexelAspect)
        throw Error(what + ": the sample spacings " + format_length(dx_um) + " (x) and " + format_length(dy_um) +
                    " (y) differ by more than " + shortest_text(kMaxTexelAspect) +
                    " times; resampling to square texels would multiply the samples by as much");
    SquareTexelReport report;
    report.dx_um = dx_um;
    report.dy_um = dy_um;
    report.texel_um = std::min(dx_um, dy_um);
    report.rows_before = field.rows;
    report.cols_before = field.cols;
    const bool along_x = dx_um > dy_um;  // the coarser axis is resampled
    const int n = along_x ? field.cols : field.rows;
    const double d = along_x ? dx_um : dy_um;
    const double count = std::max(1.0, std::round(n * d / report.texel_um));
    const double other = along_x ? field.rows : field.cols;
    if (count * other > static_cast<double>(max_samples))
        throw Error(what + ": square texels of " + format_length(report.texel_um) + " would need " +
                    shortest_text(count) + " x " + shortest_text(other) + " samples, more than glintscope reads");
    const AxisMap map = centred_map(n, d, static_cast<int>(count), report.texel_um, field.periodic);
    if (field.periodic) report.period_change = count * report.texel_um / (n * d) - 1.0;
    Heightfield square = resample_axis(field, along_x, map);
    square.texel_um = report.texel_um;
    report.round_trip_max_um = round_trip_change(field, square, along_x, map);
    square.provenance = std::move(field.provenance);
    square.units_assumed = field.units_assumed;
    square.periodic = field.periodic;
    field = std::move(square);
    return report;
}

std::string describe(const SquareTexelReport& report, const Heightfield& field) {
    const bool along_x = report.dx_um > report.dy_um;
    std::string text = "spacing " + format_length(report.dx_um) + " (x) by " + format_length(report.dy_um) +
                       " (y): " + (along_x ? "columns " : "rows ") + shortest_text(along_x ? report.cols_before : report.rows_before) +
                       " -> " + shortest_text(along_x ? field.cols : field.rows) +
                       " resampled (Catmull-Rom) to square texels of " + format_length(report.texel_um) +
                       "; largest round-trip change " + format_length(report.round_trip_max_um);
    if (report.period_change != 0.0)
        text += "; period along " + std::string(along_x ? "x" : "y") + " changed by " +
                shortest_text(report.period_change * 100.0) + "%";
    return text;
}

}  // namespace glintscope
