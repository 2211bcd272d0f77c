#pragma once
// Directions and the projected-disk hemisphere map (conventions.md "Frames and images").
#include <cmath>

namespace glintscope {

struct Vec3 {
    double x = 0.0;
    double y = 0.0;
    double z = 0.0;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) { return (1.0 / length(a)) * a; }

// ω = (sinθ cosφ, sinθ sinφ, cosθ), φ from +x toward +y; angles in radians.
Vec3 direction_from_spherical(double theta, double phi);

// The upper-hemisphere direction whose xy part is (x, y); requires x² + y² ≤ 1.
Vec3 direction_from_disk(double x, double y);

// Centre of pixel (row, col) of an N×N projected-disk image, plus a sub-pixel offset in
// [−0.5, 0.5) pixels: (x, y) = ((c + 0.5 + du)/N·2 − 1, 1 − (r + 0.5 + dv)/N·2).
struct DiskPoint {
    double x = 0.0;
    double y = 0.0;
};
DiskPoint disk_pixel_point(int row, int col, int resolution, double du = 0.0, double dv = 0.0);

// The pixel area on the disk, (2/N)²: Σ f_r·(2/N)² over an outgoing image is the albedo.
inline double disk_pixel_area(int resolution) { return 4.0 / (double(resolution) * resolution); }

}  // namespace glintscope
