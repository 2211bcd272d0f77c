#pragma once
// Directions and the projected-disk hemisphere map (conventions.md "Frames and images").
#include <cmath>
#include <numbers>

namespace glintscope {

// The one π of the library.
inline constexpr double pi = std::numbers::pi;

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
inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

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

// Points strictly inside the unit disk hold directions (the rim is the horizon, of zero
// projected area); pixels whose centre lies outside are 0.
inline bool inside_unit_disk(DiskPoint p) { return p.x * p.x + p.y * p.y < 1.0; }

// Supersampling, shared by every method so their images line up: sub-pixel a of K along an
// axis sits at offset (a + ½)/K − ½ pixels, and a pixel is the plain mean of its K×K sub-pixels.
inline double subpixel_offset(int a, int supersample) { return (a + 0.5) / supersample - 0.5; }
inline DiskPoint disk_subpixel_point(int row, int col, int sub_row, int sub_col, int resolution, int supersample) {
    return disk_pixel_point(row, col, resolution, subpixel_offset(sub_col, supersample),
                            subpixel_offset(sub_row, supersample));
}

// The pixel area on the disk, (2/N)²: Σ f_r·(2/N)² over an outgoing image is the albedo.
inline double disk_pixel_area(int resolution) { return 4.0 / (double(resolution) * resolution); }

}  // namespace glintscope
