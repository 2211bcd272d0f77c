// Cropping to a region of interest, in samples or in map-view micrometres.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/prepare/prepare.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope {
namespace {

std::string range_text(std::int64_t first, std::int64_t count) {
    return std::to_string(first) + ".." + std::to_string(first + count - 1);
}

}  // namespace

CropReport crop_samples(Heightfield& field, int first_row, int first_col, int rows, int cols) {
    validate(field, "crop", /*allow_missing=*/true);
    if (rows < 1 || cols < 1)
        throw Error("crop: the region must be at least one sample wide and high, got " + std::to_string(cols) + "x" +
                    std::to_string(rows));
    // 64-bit sums: first + count may exceed int for absurd requests.
    if (first_row < 0 || first_col < 0 || std::int64_t{first_row} + rows > field.rows ||
        std::int64_t{first_col} + cols > field.cols)
        throw Error("crop: rows " + range_text(first_row, rows) + ", columns " + range_text(first_col, cols) +
                    " lie outside the " + std::to_string(field.cols) + "x" + std::to_string(field.rows) +
                    " field (rows 0.." + std::to_string(field.rows - 1) + ", columns 0.." +
                    std::to_string(field.cols - 1) + ")");
    CropReport report;
    report.first_row = first_row;
    report.first_col = first_col;
    report.rows = rows;
    report.cols = cols;
    report.original_rows = field.rows;
    report.original_cols = field.cols;
    report.texel_um = field.dx_um();
    report.texel_y_um = field.dy_um();
    // Lower-left corner of the kept cells: sample (R − 1, 0) of the original has its cell at (0, 0).
    report.origin_um = {first_col * field.dx_um(), (field.rows - first_row - rows) * field.dy_um()};

    std::vector<float> kept(static_cast<std::size_t>(rows) * cols);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
            kept[static_cast<std::size_t>(r) * cols + c] = field.at(first_row + r, first_col + c);
    field.heights_um = std::move(kept);
    field.rows = rows;
    field.cols = cols;
    // A part of a tile does not tile.
    report.ended_periodicity = field.periodic && (rows != report.original_rows || cols != report.original_cols);
    if (report.ended_periodicity) field.periodic = false;
    record_preparation(field, describe(report));
    return report;
}

CropReport crop(Heightfield& field, const CropRegion& region) {
    validate(field, "crop", /*allow_missing=*/true);
    if (!std::isfinite(region.x0_um) || !std::isfinite(region.y0_um) || !std::isfinite(region.width_um) ||
        !std::isfinite(region.height_um))
        throw Error("crop: the region's corner and size must be finite lengths");
    if (!(region.width_um > 0.0) || !(region.height_um > 0.0))
        throw Error("crop: the region's width and height must be positive, got " + format_length(region.width_um) +
                    " x " + format_length(region.height_um));
    const double dx = field.dx_um(), dy = field.dy_um();
    // Edges within a millionth of a texel of the field's border count as on it (rounding in
    // the user's arithmetic), anything further out is an error rather than silently clipped.
    const double slack_x = 1e-6 * dx, slack_y = 1e-6 * dy;
    if (region.x0_um < -slack_x || region.y0_um < -slack_y ||
        region.x0_um + region.width_um > field.width_um() + slack_x ||
        region.y0_um + region.height_um > field.height_um() + slack_y)
        throw Error("crop: the region x " + format_length(region.x0_um) + " to " +
                    format_length(region.x0_um + region.width_um) + ", y " + format_length(region.y0_um) + " to " +
                    format_length(region.y0_um + region.height_um) + " lies outside the field (x 0 to " +
                    format_length(field.width_um()) + ", y 0 to " + format_length(field.height_um()) +
                    ", measured from its lower-left corner)");
    // Edges snap to the nearest texel boundary: column c's cell spans [c·dx, (c + 1)·dx), rows' dy.
    const auto snap = [](double length, double d) { return static_cast<std::int64_t>(std::llround(length / d)); };
    const std::int64_t first_col = snap(region.x0_um, dx);
    const std::int64_t end_col = std::min<std::int64_t>(snap(region.x0_um + region.width_um, dx), field.cols);
    const std::int64_t first_y = snap(region.y0_um, dy);  // in cells, counted upward from the bottom
    const std::int64_t end_y = std::min<std::int64_t>(snap(region.y0_um + region.height_um, dy), field.rows);
    if (end_col - first_col < 1 || end_y - first_y < 1)
        throw Error("crop: the region " + format_length(region.width_um) + " x " + format_length(region.height_um) +
                    " is smaller than one texel (" + format_length(dx) +
                    (dy == dx ? std::string() : " x " + format_length(dy)) + ") after snapping to the grid");
    return crop_samples(field, static_cast<int>(field.rows - end_y), static_cast<int>(first_col),
                        static_cast<int>(end_y - first_y), static_cast<int>(end_col - first_col));
}

std::string describe(const CropReport& report) {
    char line[320];
    std::snprintf(line, sizeof line,
                  "crop: %dx%d of %dx%d samples (rows %d..%d, columns %d..%d); region x %.6g..%.6g um, y %.6g..%.6g um "
                  "from the original's lower-left corner",
                  report.cols, report.rows, report.original_cols, report.original_rows, report.first_row,
                  report.first_row + report.rows - 1, report.first_col, report.first_col + report.cols - 1,
                  report.origin_um.x, report.origin_um.x + report.cols * report.texel_um, report.origin_um.y,
                  report.origin_um.y + report.rows * report.texel_y_um);
    return line + std::string(report.ended_periodicity ? "; the field is no longer periodic" : "");
}

}  // namespace glintscope
