#pragma once
// Areal surface statistics in the spirit of ISO 25178-2, over the valid (non-missing) points.
#include <cstddef>

#include "glintscope/surface/heightfield.hpp"

namespace glintscope {

struct SurfaceStatistics {
    double mean_um = 0.0;
    double sq_um = 0.0;          // root-mean-square height about the mean (Sq)
    double sa_um = 0.0;          // arithmetic mean absolute height about the mean (Sa)
    double min_um = 0.0;
    double max_um = 0.0;
    double rms_slope_x = 0.0;    // rms of ∂H/∂x (central differences, periodic; NaN if no valid pair)
    double rms_slope_y = 0.0;
    // Distance along x (y) at which the normalised autocorrelation first falls to
    // `correlation_threshold`; for Stam's C1, C2, C3 at 1/e this is T_x (T_y). From row (column)
    // spectra, with the areal parameters' estimator: circular on a periodic field, over the pairs
    // inside the field (zero-padded lines) on a non-periodic one, where wrapping would pair
    // opposite edges of a scan; with missing points the masked estimator keeps it unbiased. NaN
    // when it stays above the threshold up to half the field (or the field is flat).
    double correlation_length_x_um = 0.0;
    double correlation_length_y_um = 0.0;
    double correlation_threshold = 0.0;
    // The normalised autocorrelation at the largest lag evaluated (half the field) along x (y):
    // what a correlation length reported as NaN still reached there.
    double autocorrelation_at_half_x = 0.0;
    double autocorrelation_at_half_y = 0.0;
    std::size_t missing_count = 0;
    double missing_fraction = 0.0;
};

// 1/e, so that the reported length is the T of an exponential or Gaussian correlation.
inline constexpr double kCorrelationThreshold = 0.36787944117144233;

SurfaceStatistics compute_statistics(const Heightfield& field);

}  // namespace glintscope
