#include "glintscope/surface/heightfield.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope {

Heightfield make_heightfield(int rows, int cols, double texel_um, float value) {
    if (rows <= 0 || cols <= 0)
        throw Error("heightfield size " + std::to_string(cols) + "x" + std::to_string(rows) +
                    " is empty or negative");
    if (!(texel_um > 0.0) || !std::isfinite(texel_um))
        throw Error("texel size must be a positive length, got " + shortest_text(texel_um));
    constexpr std::size_t max_samples = std::size_t{1} << 31;
    if (static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols) > max_samples)
        throw Error("heightfield size " + std::to_string(cols) + "x" + std::to_string(rows) +
                    " exceeds the limit of 2^31 samples");
    Heightfield field;
    field.rows = rows;
    field.cols = cols;
    field.texel_um = texel_um;
    field.heights_um.assign(static_cast<std::size_t>(rows) * cols, value);
    return field;
}

void set_spacing(Heightfield& field, double dx_um, double dy_um) {
    if (!(dx_um > 0.0) || !std::isfinite(dx_um) || !(dy_um > 0.0) || !std::isfinite(dy_um))
        throw Error("texel size must be a positive length, got " + shortest_text(dx_um) + " x " + shortest_text(dy_um));
    field.texel_um = dx_um;
    field.texel_y_um = dy_um == dx_um ? 0.0 : dy_um;
}

std::string texel_text(const Heightfield& field) {
    if (field.square_texels()) return format_length(field.dx_um());
    return format_length(field.dx_um()) + " x " + format_length(field.dy_um()) + " (x by y)";
}

Point2 sample_position(const Heightfield& field, int r, int c) {
    return {(c + 0.5) * field.texel_um, (field.rows - r - 0.5) * field.dy_um()};
}

std::size_t count_missing(const Heightfield& field) {
    return static_cast<std::size_t>(
        std::count_if(field.heights_um.begin(), field.heights_um.end(), [](float h) { return std::isnan(h); }));
}

void validate(const Heightfield& field, const std::string& what, bool allow_missing) {
    if (field.rows <= 0 || field.cols <= 0 || field.heights_um.empty())
        throw Error(what + ": heightfield is empty");
    if (field.heights_um.size() != static_cast<std::size_t>(field.rows) * field.cols)
        throw Error(what + ": heightfield data size does not match its " + std::to_string(field.cols) + "x" +
                    std::to_string(field.rows) + " grid");
    if (!(field.texel_um > 0.0) || !std::isfinite(field.texel_um) || !(field.texel_y_um >= 0.0) ||
        !std::isfinite(field.texel_y_um))
        throw Error(what + ": texel size must be positive and finite");
    std::size_t missing = 0;
    for (float h : field.heights_um) {
        if (std::isinf(h)) throw Error(what + ": heightfield contains infinite heights");
        if (std::isnan(h)) ++missing;
    }
    if (missing == field.heights_um.size()) throw Error(what + ": every height is missing (NaN)");
    if (missing > 0 && !allow_missing)
        throw Error(what + ": " + std::to_string(missing) +
                    " heights are missing (NaN); fill them first (convert --fill)");
}

}  // namespace glintscope
