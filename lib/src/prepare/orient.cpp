// Mirroring and quarter-turn rotation of a heightfield in map view (conventions.md "Frames"):
// x to the right, y up, row 0 at the top. Tools disagree on which way is up (docs/heightfields.md),
// so `convert` can bring a scan into the orientation another tool shows.
#include <cstdio>
#include <string>
#include <utility>

#include "glintscope/core/error.hpp"
#include "glintscope/prepare/prepare.hpp"

namespace glintscope {
namespace {

// x → width − x: columns reversed.
void mirror_x(Heightfield& field) {
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols / 2; ++c) std::swap(field.at(r, c), field.at(r, field.cols - 1 - c));
}

// y → height − y: rows reversed.
void mirror_y(Heightfield& field) {
    for (int r = 0; r < field.rows / 2; ++r)
        for (int c = 0; c < field.cols; ++c) std::swap(field.at(r, c), field.at(field.rows - 1 - r, c));
}

// A quarter turn counter-clockwise in map view, (x, y) → (H − y, x) for a field of height H:
// sample (r, c) of the result is sample (c, cols − 1 − r) of the original, whose top row becomes
// the left column, read bottom to top.
void quarter_turn(Heightfield& field) {
    Heightfield turned = field;
    turned.rows = field.cols;
    turned.cols = field.rows;
    for (int r = 0; r < turned.rows; ++r)
        for (int c = 0; c < turned.cols; ++c) turned.at(r, c) = field.at(c, field.cols - 1 - r);
    field.rows = turned.rows;
    field.cols = turned.cols;
    field.heights_um = std::move(turned.heights_um);
    set_spacing(field, field.dy_um(), field.dx_um());  // rows become columns
}

}  // namespace

OrientReport orient(Heightfield& field, const Orientation& orientation) {
    validate(field, "orient", /*allow_missing=*/true);
    const int degrees = orientation.rotate_degrees;
    if (degrees != 0 && degrees != 90 && degrees != 180 && degrees != 270)
        throw Error("orient: rotation must be 0, 90, 180 or 270 degrees, got " + std::to_string(degrees));
    OrientReport report{orientation, field.rows, field.cols};
    if (orientation.flip_x) mirror_x(field);
    if (orientation.flip_y) mirror_y(field);
    for (int turn = 0; turn < degrees / 90; ++turn) quarter_turn(field);
    record_preparation(field, describe(report));
    return report;
}

int parse_rotation(const std::string& text) {
    if (text == "0" || text == "90" || text == "180" || text == "270") return std::stoi(text);
    throw Error("'" + text + "' is not a rotation (expected 0, 90, 180 or 270 degrees)");
}

std::string describe(const OrientReport& report) {
    const Orientation& o = report.orientation;
    std::string steps;
    if (o.flip_x) steps += ", mirrored in x (columns reversed)";
    if (o.flip_y) steps += ", mirrored in y (rows reversed)";
    if (o.rotate_degrees != 0)
        steps += ", rotated " + std::to_string(o.rotate_degrees) + " degrees counter-clockwise in map view";
    char line[96];
    std::snprintf(line, sizeof line, "orient: %dx%d samples", report.original_cols, report.original_rows);
    return line + (steps.empty() ? std::string(", unchanged") : steps);
}

}  // namespace glintscope
