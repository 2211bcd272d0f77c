#include "glintscope/surface/heightfield.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "surface/valid_heights.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kRowsPerChunk = 32;

struct HeightSums {
    std::size_t valid = 0, infinite = 0;
    double sum = 0.0;  // of the finite heights
    float lowest = std::numeric_limits<float>::infinity();
    float highest = -std::numeric_limits<float>::infinity();
};

// One pass over the heights in fixed chunks of rows, summed in chunk order (the same bits on
// any thread count).
HeightSums sum_heights(const Heightfield& field) {
    const std::size_t cols = static_cast<std::size_t>(field.cols);
    const std::size_t chunks = (field.rows + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<HeightSums> partial(chunks);
    parallel_for(field.rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        HeightSums sums;  // a local, so the loop keeps it in registers
        for (std::size_t i = begin * cols; i < end * cols; ++i) {
            const float h = field.heights_um[i];
            if (std::isnan(h)) continue;
            if (std::isinf(h)) {
                ++sums.infinite;
                continue;
            }
            ++sums.valid;
            sums.sum += h;
            sums.lowest = std::min(sums.lowest, h);
            sums.highest = std::max(sums.highest, h);
        }
        partial[begin / kRowsPerChunk] = sums;
    });
    HeightSums total;
    for (const HeightSums& sums : partial) {
        total.valid += sums.valid;
        total.infinite += sums.infinite;
        total.sum += sums.sum;
        total.lowest = std::min(total.lowest, sums.lowest);
        total.highest = std::max(total.highest, sums.highest);
    }
    return total;
}

}  // namespace

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

namespace {

// Throws unless the grid and spacing are sound, the heights finite or NaN, and (unless
// allow_missing) none NaN; `valid` and `infinite` count the heights.
void check_field(const Heightfield& field, const std::string& what, bool allow_missing, std::size_t valid,
                 std::size_t infinite) {
    if (infinite > 0) throw Error(what + ": heightfield contains infinite heights");
    const std::size_t missing = field.size() - valid;
    if (missing == field.heights_um.size()) throw Error(what + ": every height is missing (NaN)");
    if (missing > 0 && !allow_missing)
        throw Error(what + ": " + std::to_string(missing) +
                    " heights are missing (NaN); fill them first (convert --fill)");
}

void check_grid(const Heightfield& field, const std::string& what) {
    if (field.rows <= 0 || field.cols <= 0 || field.heights_um.empty())
        throw Error(what + ": heightfield is empty");
    if (field.heights_um.size() != static_cast<std::size_t>(field.rows) * field.cols)
        throw Error(what + ": heightfield data size does not match its " + std::to_string(field.cols) + "x" +
                    std::to_string(field.rows) + " grid");
    if (!(field.texel_um > 0.0) || !std::isfinite(field.texel_um) || !(field.texel_y_um >= 0.0) ||
        !std::isfinite(field.texel_y_um))
        throw Error(what + ": texel size must be positive and finite");
}

}  // namespace

ValidHeights validated_heights(const Heightfield& field, const std::string& what, bool allow_missing) {
    check_grid(field, what);
    const HeightSums sums = sum_heights(field);
    check_field(field, what, allow_missing, sums.valid, sums.infinite);
    return {sums.valid, sums.sum / static_cast<double>(sums.valid), sums.lowest, sums.highest,
            sums.valid < field.size()};
}

// Without the sums: counting is a fraction of the cost of summing (no dependency chain).
void validate(const Heightfield& field, const std::string& what, bool allow_missing) {
    check_grid(field, what);
    const std::size_t cols = static_cast<std::size_t>(field.cols);
    const std::size_t chunks = (field.rows + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<std::size_t> invalid(chunks), infinite(chunks);
    parallel_for(field.rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        std::size_t nans = 0, infinities = 0;
        for (std::size_t i = begin * cols; i < end * cols; ++i) {
            const float h = field.heights_um[i];
            nans += std::isnan(h);
            infinities += std::isinf(h);
        }
        invalid[begin / kRowsPerChunk] = nans;
        infinite[begin / kRowsPerChunk] = infinities;
    });
    std::size_t nans = 0, infinities = 0;
    for (std::size_t c = 0; c < chunks; ++c) {
        nans += invalid[c];
        infinities += infinite[c];
    }
    check_field(field, what, allow_missing, field.size() - nans - infinities, infinities);
}

}  // namespace glintscope
