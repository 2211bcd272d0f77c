#pragma once
// A heightfield: a grid of heights in µm (conventions.md "Frames and images"), one tile of a
// periodic surface when generated, a patch whose borders are edges when measured.
// Row 0 is the largest y ("map view"); sample (r, c) of an R-row grid sits at
// s = ((c + 0.5)·dx, (R − r − 0.5)·dy). Missing points (profilometer drop-outs) are NaN.
// Texels may be rectangular (dx ≠ dy): instruments' spacings differ by their calibration or by
// design, and the field keeps them as measured (docs/heightfields.md "Rectangular texels").
#include <cstddef>
#include <string>
#include <vector>

#include "glintscope/surface/metadata.hpp"

namespace glintscope {

struct Point2 {
    double x = 0.0;
    double y = 0.0;
};

struct Heightfield {
    int rows = 0;
    int cols = 0;
    double texel_um = 1.0;            // dx, the sample spacing along x (columns)
    // dy, the spacing along y (rows); 0 means square texels (dy = dx), so that code which sets
    // only texel_um keeps square texels instead of silently disagreeing. Read it through dy_um().
    double texel_y_um = 0.0;
    std::vector<float> heights_um;    // rows·cols, row-major, row 0 at the top (largest y)
    Provenance provenance;
    bool units_assumed = false;       // true when the file carried no units and defaults were used
    // Whether the field tiles the plane (generated fields) or simply ends at its borders
    // (measured scans, and any field loaded from a file unless LoadOptions::periodic). Lobes
    // refuse footprints that cross the border of a non-periodic field (lobe.hpp).
    bool periodic = true;

    float at(int r, int c) const { return heights_um[static_cast<std::size_t>(r) * cols + c]; }
    float& at(int r, int c) { return heights_um[static_cast<std::size_t>(r) * cols + c]; }
    std::size_t size() const { return heights_um.size(); }
    double dx_um() const { return texel_um; }
    double dy_um() const { return texel_y_um > 0.0 ? texel_y_um : texel_um; }
    bool square_texels() const { return dy_um() == texel_um; }
    double width_um() const { return cols * texel_um; }
    double height_um() const { return rows * dy_um(); }
    Point2 centre_um() const { return {0.5 * width_um(), 0.5 * height_um()}; }
};

// Allocates a rows×cols field filled with `value`; throws Error on non-positive sizes or texel.
Heightfield make_heightfield(int rows, int cols, double texel_um, float value = 0.0f);

// Sets the spacings dx (columns) and dy (rows); dy equal to dx is stored as square (texel_y_um 0).
// Throws Error on a non-positive or non-finite spacing.
void set_spacing(Heightfield& field, double dx_um, double dy_um);

// The spacing as text: "0.5 um" for square texels, "0.5 x 1 um (x by y)" otherwise.
std::string texel_text(const Heightfield& field);

// The map-view position of sample (r, c).
Point2 sample_position(const Heightfield& field, int r, int c);

std::size_t count_missing(const Heightfield& field);

// Throws Error naming `what` if the field is empty, has a bad texel size, contains
// infinities, or (unless allow_missing) contains NaN.
void validate(const Heightfield& field, const std::string& what, bool allow_missing);

}  // namespace glintscope
