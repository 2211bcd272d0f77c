// Resampling a heightfield to a new texel size.
//
// Upsampling evaluates the shared BicubicInterpolant (conventions.md "Heightfield
// interpolation") at the new sample centres, so the surface itself is unchanged. Downsampling
// by a factor a = new texel / old texel first replaces each sample by the mean of the
// piecewise-constant surface over a box a texels wide centred on it — the height a coarser
// instrument pixel would report — and then evaluates the interpolant of those means. The box's
// transfer function sinc(a·dx·f) removes most of what lies beyond the new Nyquist frequency
// (a checkerboard of the old grid vanishes exactly at a = 2) instead of letting it alias.
//
// The new grid keeps the old extent's centre and has round(extent / texel) samples per axis.
// Borders: Tiling::periodic wraps the box and the interpolant around. Tiling::none continues the
// field beyond each border by point reflection about the border sample, h(−k) = 2 h(0) − h(k):
// a local trend runs on without a kink, where an even mirror would flatten the slope at the
// edge and wrapping would pull in the opposite edge.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/surface/interpolant.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/prepare/prepare.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "surface/line_extension.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kRowsPerChunk = 16;
// Catmull–Rom reads the samples from one before to two after a position: the added margin.
constexpr int kMargin = 2;

// Sample i of a line continued beyond its ends as `tiling` says (surface/line_extension.hpp).
double extended(const float* line, std::size_t stride, long long i, int n, Tiling tiling) {
    return extended_sample(line, stride, i, n, tiling == Tiling::periodic);
}

// Weights of a box `width` samples wide centred on sample 0 over the unit cells of samples
// −reach..reach (the overlap of each cell with the box, over the width): they sum to one.
std::vector<double> box_weights(double width) {
    const int reach = static_cast<int>(std::ceil(0.5 * width + 0.5));
    std::vector<double> weights;
    for (int k = -reach; k <= reach; ++k) {
        const double overlap = std::min(k + 0.5, 0.5 * width) - std::max(k - 0.5, -0.5 * width);
        weights.push_back(std::max(0.0, overlap) / width);
    }
    return weights;
}

// The box mean of `field` over width_x × width_y samples, separably (rectangular texels need
// different widths in samples for one box in µm).
Heightfield box_filter(const Heightfield& field, double width_x, double width_y, Tiling tiling) {
    const std::vector<double> weights_x = box_weights(width_x);
    const int reach_x = static_cast<int>(weights_x.size() / 2);
    const auto cols = static_cast<std::size_t>(field.cols);
    Heightfield along_x = field;
    parallel_for(static_cast<std::size_t>(field.rows), kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            const float* row = &field.heights_um[r * cols];
            for (int c = 0; c < field.cols; ++c) {
                const bool inside = c >= reach_x && c + reach_x < field.cols;
                double sum = 0.0;
                for (int k = -reach_x; k <= reach_x; ++k)
                    sum += weights_x[static_cast<std::size_t>(k + reach_x)] *
                           (inside ? row[c + k] : extended(row, 1, c + k, field.cols, tiling));
                along_x.heights_um[r * cols + static_cast<std::size_t>(c)] = static_cast<float>(sum);
            }
        }
    });
    Heightfield filtered = along_x;
    const std::vector<double> weights = box_weights(width_y);
    const int reach = static_cast<int>(weights.size() / 2);
    const auto rows = static_cast<std::size_t>(field.rows);
    parallel_for(rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        std::vector<double> sums(cols);
        for (std::size_t r = begin; r < end; ++r) {
            std::fill(sums.begin(), sums.end(), 0.0);
            const bool inside = r >= static_cast<std::size_t>(reach) && r + reach < rows;
            for (int k = -reach; k <= reach; ++k) {
                const double w = weights[static_cast<std::size_t>(k + reach)];
                if (inside) {
                    const float* row = &along_x.heights_um[(r + k) * cols];
                    for (std::size_t c = 0; c < cols; ++c) sums[c] += w * row[c];
                } else {
                    for (std::size_t c = 0; c < cols; ++c)
                        sums[c] += w * extended(&along_x.heights_um[c], cols, static_cast<long long>(r) + k,
                                                field.rows, tiling);
                }
            }
            for (std::size_t c = 0; c < cols; ++c) filtered.heights_um[r * cols + c] = static_cast<float>(sums[c]);
        }
    });
    return filtered;
}

// The field with kMargin samples added on every side by point reflection, so that the
// (periodic) interpolant never reaches across to the opposite border inside the original extent.
Heightfield reflected(const Heightfield& field) {
    Heightfield wide = make_heightfield(field.rows, field.cols + 2 * kMargin, field.texel_um);
    set_spacing(wide, field.dx_um(), field.dy_um());
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < wide.cols; ++c)
            wide.at(r, c) = static_cast<float>(extended(&field.heights_um[static_cast<std::size_t>(r) * field.cols], 1,
                                                        c - kMargin, field.cols, Tiling::none));
    Heightfield padded = make_heightfield(field.rows + 2 * kMargin, wide.cols, field.texel_um);
    set_spacing(padded, field.dx_um(), field.dy_um());
    for (int r = 0; r < padded.rows; ++r)
        for (int c = 0; c < padded.cols; ++c)
            padded.at(r, c) = static_cast<float>(extended(&wide.heights_um[static_cast<std::size_t>(c)],
                                                          static_cast<std::size_t>(wide.cols), r - kMargin, field.rows,
                                                          Tiling::none));
    return padded;
}

// round(extent / texel) samples, at least one.
double sample_count(double extent_um, double texel_um) { return std::max(1.0, std::round(extent_um / texel_um)); }

}  // namespace

ResampleReport resample(Heightfield& field, double texel_um, Tiling tiling) {
    validate(field, "resample", /*allow_missing=*/false);
    if (!(texel_um > 0.0) || !std::isfinite(texel_um))
        throw Error("resample: the texel size must be a positive length, got " + format_length(texel_um));
    ResampleReport report;
    report.original_texel_um = field.dx_um();
    report.original_texel_y_um = field.dy_um();
    report.texel_um = texel_um;
    report.original_rows = field.rows;
    report.original_cols = field.cols;
    const double cols = sample_count(field.width_um(), texel_um);
    const double rows = sample_count(field.height_um(), texel_um);
    if (cols * rows > 2147483648.0)
        throw Error("resample: a texel of " + format_length(texel_um) + " would make the field " +
                    std::to_string(static_cast<long long>(cols)) + "x" + std::to_string(static_cast<long long>(rows)) +
                    " samples, beyond the limit of 2^31 (its heights alone would need " +
                    shortest_text(std::ceil(4.0 * cols * rows / 1e8) / 10.0) + " GB)");
    report.cols = static_cast<int>(cols);
    report.rows = static_cast<int>(rows);
    report.tiling = tiling;
    // Per axis: rectangular texels shrink along one axis and may grow along the other.
    const double ratio_x = texel_um / field.dx_um(), ratio_y = texel_um / field.dy_um();
    report.prefiltered = ratio_x > 1.0 || ratio_y > 1.0;

    Heightfield result = make_heightfield(report.rows, report.cols, texel_um);
    {
        const Heightfield source = report.prefiltered
                                       ? box_filter(field, std::max(1.0, ratio_x), std::max(1.0, ratio_y), tiling)
                                       : field;
        const BicubicInterpolant surface(tiling == Tiling::none ? reflected(source) : source);
        const double margin_x_um = tiling == Tiling::none ? kMargin * field.dx_um() : 0.0;
        const double margin_y_um = tiling == Tiling::none ? kMargin * field.dy_um() : 0.0;
        // The new grid is centred on the old extent: its first sample centre (lowest y) is at
        // (x0, y0) in the source's frame.
        const double x0 = 0.5 * (field.width_um() - report.cols * texel_um) + margin_x_um + 0.5 * texel_um;
        const double y0 = 0.5 * (field.height_um() - report.rows * texel_um) + margin_y_um + 0.5 * texel_um;
        // Chunks of y-up grid lines j (image row rows − 1 − j).
        parallel_for(static_cast<std::size_t>(result.rows), kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
            const int lines = static_cast<int>(end - begin);
            std::vector<SurfacePoint> points(static_cast<std::size_t>(lines) * result.cols);
            surface.evaluate_grid(x0, y0 + static_cast<double>(begin) * texel_um, texel_um, result.cols, lines,
                                  points.data());
            for (int line = 0; line < lines; ++line) {
                const int r = result.rows - 1 - static_cast<int>(begin) - line;
                const SurfacePoint* line_points = &points[static_cast<std::size_t>(line) * result.cols];
                for (int c = 0; c < result.cols; ++c) result.at(r, c) = static_cast<float>(line_points[c].height);
            }
        });
    }
    field.rows = result.rows;
    field.cols = result.cols;
    set_spacing(field, texel_um, texel_um);
    field.heights_um = std::move(result.heights_um);
    record_preparation(field, describe(report));
    return report;
}

std::string describe(const ResampleReport& report) {
    const bool rectangular = report.original_texel_y_um != report.original_texel_um;
    char filter[96] = "bicubic interpolation";
    if (report.prefiltered && rectangular)
        std::snprintf(filter, sizeof filter, "box prefilter over %.4g x %.4g texels",
                      std::max(1.0, report.texel_um / report.original_texel_um),
                      std::max(1.0, report.texel_um / report.original_texel_y_um));
    else if (report.prefiltered)
        std::snprintf(filter, sizeof filter, "box prefilter over %.4g texels",
                      report.texel_um / report.original_texel_um);
    char spacing[64];
    if (rectangular)
        std::snprintf(spacing, sizeof spacing, "%.6g x %.6g um", report.original_texel_um, report.original_texel_y_um);
    else
        std::snprintf(spacing, sizeof spacing, "%.6g um", report.original_texel_um);
    char line[460];
    std::snprintf(line, sizeof line,
                  "resample: %dx%d samples of %s -> %dx%d of %.6g um (extent %.6g x %.6g um -> %.6g x %.6g um), "
                  "%s, %s borders",
                  report.original_cols, report.original_rows, spacing, report.cols, report.rows,
                  report.texel_um, report.original_cols * report.original_texel_um,
                  report.original_rows * report.original_texel_y_um, report.cols * report.texel_um,
                  report.rows * report.texel_um, filter,
                  report.tiling == Tiling::periodic ? "periodic" : "point-reflected");
    return line;
}

}  // namespace glintscope
