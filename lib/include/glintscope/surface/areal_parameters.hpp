#pragma once
// ISO 25178-2 areal field parameters of a heightfield, over its valid points, on the surface as
// given: levelling and S-/L-filtering (ISO 16610-61) are done first, by the caller
// (prepare.hpp), and stated beside the numbers.
//
// Height (ISO 25178-2 §4.1.1-4.1.7), about the mean height z̄ of the valid points:
//   Sq = √mean((z−z̄)²), Ssk = mean((z−z̄)³)/Sq³, Sku = mean((z−z̄)⁴)/Sq⁴, Sp = max(z−z̄),
//   Sv = −min(z−z̄), Sz = Sp + Sv, Sa = mean|z−z̄|.
// Hybrid (§4.3): Sdq = √mean(z_x² + z_y²), Sdr = mean(√(1 + z_x² + z_y²) − 1), with central
//   differences where both neighbours are valid (wrapping around only on periodic fields).
// Spatial (§4.2): the normalised autocorrelation f(t) = Σ z(s) z(s+t) / Σ z² (each sum over the
//   pairs inside the field, divided by their number, so that missing points and the border do
//   not bias it; circular on periodic fields). Along each direction θ its decay length is the
//   first lag where f falls to s (default 0.2). Sal is the shortest decay length over all
//   directions, Str the ratio of the shortest to the longest, evaluated over lags up to half the
//   field in x and in y. Std is the lay (texture) direction: perpendicular to the direction of
//   the maximum of the angular power spectrum (the field's mean-removed heights under a Hann
//   window, over the frequencies inside the Nyquist ellipse), in (−90°, 90°] counter-clockwise
//   from +x, so a sinusoid in x, whose ridges run along y, has Std = 90°.
#include <optional>
#include <string>

#include "glintscope/surface/heightfield.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {

inline constexpr double kIsoAutocorrelationThreshold = 0.2;

struct ArealParameters {
    // height, µm
    double sq_um = 0.0;
    double ssk = 0.0;
    double sku = 0.0;
    double sp_um = 0.0;
    double sv_um = 0.0;
    double sz_um = 0.0;
    double sa_um = 0.0;
    // hybrid
    double sdq = 0.0;
    double sdr = 0.0;  // a fraction of the projected area (× 100 for %)
    // spatial
    double threshold = kIsoAutocorrelationThreshold;  // s
    // Sal: when no direction decays to s within the evaluated lags, a lower bound (the shortest
    // ray evaluated), with the autocorrelation that ray reached at its end.
    double sal_um = 0.0;
    bool sal_is_lower_bound = false;
    double sal_direction_deg = 0.0;    // the direction of the fastest decay, from +x
    double longest_decay_um = 0.0;     // the slowest direction's decay length (a lower bound if it never decays)
    double longest_direction_deg = 0.0;
    bool longest_is_lower_bound = false;
    // Str = Sal / longest decay; an upper bound when the longest decay is only a lower bound.
    double str = 0.0;
    bool str_is_upper_bound = false;
    // When a direction does not decay: the autocorrelation reached at the edge of the evaluated
    // lags in that direction (the fastest direction's for Sal, the slowest's for Str).
    double sal_autocorrelation_at_edge = 0.0;
    double longest_autocorrelation_at_edge = 0.0;
    double max_lag_x_um = 0.0;  // the evaluated lags: |t_x| ≤ max_lag_x_um, |t_y| ≤ max_lag_y_um
    double max_lag_y_um = 0.0;
    double std_deg = 0.0;
};

// Throws Error for an invalid field, fewer than 2 valid points, or flat heights (every parameter
// above needs Sq > 0); `threshold` must lie in (0, 1).
ArealParameters compute_areal_parameters(const Heightfield& field,
                                         double threshold = kIsoAutocorrelationThreshold);

// The statistics and, where they are defined, the ISO 25178-2 parameters (what `info` reports),
// computed together: one validation and one autocorrelation, the statistics' 1/e correlation
// lengths read along its axes (the estimator compute_statistics uses, so the same values to
// float rounding) instead of from their own line spectra.
struct SurfaceReport {
    SurfaceStatistics statistics;
    std::optional<ArealParameters> iso;
    std::string iso_undefined;  // why iso is empty: "the heights do not vary", "fewer than 3 x 3 samples"
};

// Throws as compute_statistics does, and as compute_areal_parameters does for a threshold outside
// (0, 1) or a field without valid slopes.
SurfaceReport compute_surface_report(const Heightfield& field, double threshold = kIsoAutocorrelationThreshold);

}  // namespace glintscope
