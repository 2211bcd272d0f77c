#include "glintscope/core/geometry.hpp"

#include <algorithm>

namespace glintscope {

Vec3 direction_from_spherical(double theta, double phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

Vec3 direction_from_disk(double x, double y) {
    return {x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))};
}

DiskPoint disk_pixel_point(int row, int col, int resolution, double du, double dv) {
    const double scale = 2.0 / resolution;
    return {(col + 0.5 + du) * scale - 1.0, 1.0 - (row + 0.5 + dv) * scale};
}

}  // namespace glintscope
