#pragma once
// Small convex polygons of the plane clipped by axis-aligned lines (Sutherland–Hodgman, one line
// at a time) and their areas: a lobe cell's image clipped by a pixel (geometric lobe), a
// triangle clipped by a box footprint in the box's frame (the normal density's sampler).
#include <array>
#include <cmath>

#include "glintscope/core/geometry.hpp"

namespace glintscope {

// At most 8 corners: a quadrilateral clipped by 4 lines.
struct SmallPolygon {
    std::array<DiskPoint, 8> corners;
    int count = 0;
};

// Its area (shoelace; corners in order, either orientation).
inline double polygon_area(const SmallPolygon& polygon) {
    double twice = 0.0;
    for (int i = 0, j = polygon.count - 1; i < polygon.count; j = i++)
        twice += polygon.corners[j].x * polygon.corners[i].y - polygon.corners[i].x * polygon.corners[j].y;
    return 0.5 * std::abs(twice);
}

// The part of a polygon on one side of the line x = bound (along_x) or y = bound.
inline SmallPolygon clip_polygon(const SmallPolygon& polygon, bool along_x, double bound, bool keep_below) {
    SmallPolygon kept;
    const auto coordinate = [&](DiskPoint p) { return along_x ? p.x : p.y; };
    const auto inside = [&](DiskPoint p) { return keep_below ? coordinate(p) <= bound : coordinate(p) >= bound; };
    for (int i = 0, j = polygon.count - 1; i < polygon.count; j = i++) {
        const DiskPoint a = polygon.corners[j], b = polygon.corners[i];
        if (inside(a) != inside(b) && kept.count < 8) {
            const double t = (bound - coordinate(a)) / (coordinate(b) - coordinate(a));
            kept.corners[kept.count++] = {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
        }
        if (inside(b) && kept.count < 8) kept.corners[kept.count++] = b;
    }
    return kept;
}

// The part of a polygon inside the rectangle [x0, x1] × [y0, y1].
inline SmallPolygon clip_to_rectangle(const SmallPolygon& polygon, double x0, double x1, double y0, double y1) {
    return clip_polygon(clip_polygon(clip_polygon(clip_polygon(polygon, true, x0, false), true, x1, true), false, y0, false), false,
                        y1, true);
}

}  // namespace glintscope
