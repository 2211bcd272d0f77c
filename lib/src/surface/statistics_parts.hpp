#pragma once
// Internal to surface/: compute_statistics (statistics.cpp) in its parts, so that
// compute_surface_report (areal_parameters.cpp) validates once and reads the 1/e correlation
// lengths off the autocorrelation it computes for Sal instead of transforming every line again.
#include "glintscope/surface/statistics.hpp"
#include "surface/field_transforms.hpp"
#include "surface/valid_heights.hpp"

namespace glintscope {

// Everything but the correlation lengths, from the validation's result.
SurfaceStatistics statistics_without_correlation(const Heightfield& field, const ValidHeights& heights);

// The correlation lengths from the lines' spectra (rows for x, columns for y).
void line_correlation_lengths(const Heightfield& field, SurfaceStatistics& stats);

// The same lengths read along the axes of the areal autocorrelation: the same estimator (pairs
// inside a non-periodic field, circular on a periodic one, masked where points are missing), so
// the same values to float rounding.
void read_correlation_lengths(const field_transforms::Autocorrelation& acf, double dx, double dy,
                              SurfaceStatistics& stats);

}  // namespace glintscope
