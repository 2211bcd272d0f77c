#pragma once
// A heightfield: a grid of heights in µm (conventions.md "Frames and images"), one tile of a
// periodic surface when generated, a patch whose borders are edges when measured.
// Row 0 is the largest y ("map view"); sample (r, c) of an R-row grid sits at
// s = ((c + 0.5)·dx, (R − r − 0.5)·dx). Missing points (profilometer drop-outs) are NaN.
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
    double texel_um = 1.0;            // dx, the sample spacing in both x and y
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
    double width_um() const { return cols * texel_um; }
    double height_um() const { return rows * texel_um; }
    Point2 centre_um() const { return {0.5 * width_um(), 0.5 * height_um()}; }
};

// Allocates a rows×cols field filled with `value`; throws Error on non-positive sizes or texel.
Heightfield make_heightfield(int rows, int cols, double texel_um, float value = 0.0f);

// The map-view position of sample (r, c).
Point2 sample_position(const Heightfield& field, int r, int c);

std::size_t count_missing(const Heightfield& field);

// Throws Error naming `what` if the field is empty, has a bad texel size, contains
// infinities, or (unless allow_missing) contains NaN.
void validate(const Heightfield& field, const std::string& what, bool allow_missing);

}  // namespace glintscope
