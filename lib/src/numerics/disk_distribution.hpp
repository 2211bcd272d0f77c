#pragma once
// A projected-disk image (N×N per layer, row 0 at the top, conventions.md "Frames and images")
// read as a piecewise-constant function and as a distribution: the value at a disk point is its
// pixel's, and sampling picks a pixel with probability ∝ its mean value over the layers times its
// area inside the unit disk, then a point uniform in that area. The density per unit disk area is
// exact and piecewise constant, so a sampler over a method's own image has the weight
// value/density the same for every sample of a pixel.
#include <cstddef>
#include <optional>
#include <vector>

#include "glintscope/core/geometry.hpp"

namespace glintscope {

struct DiskDistribution {
    int resolution = 0;
    std::size_t layers = 0;
    std::vector<double> values;        // [layer][row][col]
    std::vector<double> area;          // per pixel: its area inside the unit disk; 0 if its centre is outside
    std::vector<double> cumulative;    // per pixel: Σ of the pixel probabilities up to and including it
    std::vector<double> integral;      // per layer: Σ value · area, the image's ∫ over the disk
    double total = 0.0;                // Σ mean value · area: the sampling mass (0: nothing to sample)
};

// From `layers` N×N layers of non-negative values, [layer][row][col]; pixels whose centre lies
// outside the disk hold nothing.
DiskDistribution make_disk_distribution(int resolution, std::size_t layers, std::vector<double> values);

// The pixel holding disk point (x, y), or −1 outside the unit disk.
long pixel_of(const DiskDistribution& table, double x, double y);

// The layers' values at the pixel holding (x, y): zero outside the disk.
std::vector<double> values_at(const DiskDistribution& table, double x, double y);

// The sampling density per unit disk area at (x, y).
double disk_density(const DiskDistribution& table, double x, double y);

// A point with the density above from two uniforms in [0, 1); none when the table is empty.
std::optional<DiskPoint> sample_disk(const DiskDistribution& table, double u1, double u2);

// The area of the square [x0, x1] × [y0, y1] inside the unit disk.
double area_inside_disk(double x0, double x1, double y0, double y1);

}  // namespace glintscope
