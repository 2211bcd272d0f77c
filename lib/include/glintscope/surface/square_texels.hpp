#pragma once
// Rectangular texels made square, for the methods that want square texels (MethodInfo::
// needs_square_texels: Gabor's kernel grid). Instruments' sample spacings differ in x and y, by
// their calibration (0.01–0.1% on focus-variation scans) or by design (line scanners, stitched
// maps); fields keep them as read, and most code works with dx ≠ dy. For the others a field
// sampled at dx × dy is resampled along its coarser axis onto the finer spacing with the shared
// interpolant's Catmull–Rom kernel (conventions.md "Heightfield interpolation"), keeping the
// extent's centre: no sample is dropped and nothing is smoothed (upsampling only). The caller
// records what was done and its size (describe()), so the change is never silent.
#include <cstddef>
#include <string>

#include "glintscope/surface/heightfield.hpp"

namespace glintscope {

// Spacings further apart than this ratio are refused: the finer axis would multiply the
// samples of the coarser one by more.
constexpr double kMaxTexelAspect = 16.0;

struct SquareTexelReport {
    double dx_um = 0.0, dy_um = 0.0;  // the spacings as read
    double texel_um = 0.0;            // the square texel now: the finer of the two
    int rows_before = 0, cols_before = 0;
    // The largest change of a valid sample when the square grid is interpolated back at the
    // original positions: an estimate of what resampling changed (0 when nothing moved).
    double round_trip_max_um = 0.0;
    // Periodic fields: the relative change of the resampled axis's period (the count is rounded).
    double period_change = 0.0;
};

// `field` holds columns dx apart and rows dy apart (Heightfield::dy_um()); on return its texels
// are square. Missing points stay missing: a new sample is missing when a sample its kernel reads is.
// Throws Error (naming `what`) for a spacing ratio beyond kMaxTexelAspect or a result of more
// than `max_samples` samples.
SquareTexelReport make_texels_square(Heightfield& field, std::size_t max_samples, const std::string& what);

// One line for the provenance ("square_texels") and `info`: the spacings, the axis resampled,
// the sample counts and the round-trip change.
std::string describe(const SquareTexelReport& report, const Heightfield& field);

}  // namespace glintscope
