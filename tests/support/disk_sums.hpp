#pragma once
// Sums over a projected-disk image that several method tests assert on (Σ value (2/N)² itself
// is the library's disk_sum, image.hpp).
#include <cstddef>

#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/image.hpp"

namespace glintscope::testing {

// Σ D |h_xy|² (2/N)²: an NDF's second moment on the disk (its squared rms width).
inline double second_moment(const LobeImage& image) {
    double sum = 0.0;
    for (int r = 0; r < image.resolution; ++r)
        for (int c = 0; c < image.resolution; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, image.resolution);
            sum += image.at(0, r, c) * (p.x * p.x + p.y * p.y);
        }
    return sum * disk_pixel_area(image.resolution);
}

}  // namespace glintscope::testing
