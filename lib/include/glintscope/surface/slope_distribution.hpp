#pragma once
// The gradient distribution of ISO 25178-2:2021 §4.6, drawn as geometric optics reads it: each
// valid sample's central-difference gradient (z_x, z_y) (the same differences as Sdq,
// areal_parameters.hpp) gives the normal m = (−z_x, −z_y, 1)/√(1 + z_x² + z_y²), counted in the
// pixel of the projected disk (conventions.md "Frames and images") its (m_x, m_y) falls in, every
// sample weighing the same projected area. The result is a density D over the disk with
// Σ D (2/N)² = 1: the whole field's projected-area density of normals, the quantity the P-NDF of a
// whole-field footprint (ndf method pndf) computes from the interpolant's continuous gradient.
#include <vector>

#include "glintscope/surface/heightfield.hpp"

namespace glintscope {

// N×N values, row-major, row 0 at m_y ≈ +1. Throws Error for an invalid field, a resolution
// outside [2, 4096], or no valid gradient (a gradient needs both neighbours along x and y; only
// periodic fields wrap around).
std::vector<float> slope_distribution(const Heightfield& field, int resolution);

}  // namespace glintscope
