#pragma once
// The power spectral density and the autocorrelation of a heightfield, as metrologists plot them
// first (Gwyddion's PSDF and ACF tools, MountainsMap's spectrum studies).
//
// Frequencies f are in cycles per µm (f = 1/wavelength), two-sided: the real heights give
// C(−f) = C(f), and each curve below is listed for f ≥ 0 only.
// 2-D PSD: C(f_x, f_y) = |Σ w z e^{−i2π f·s}|² dx dy / Σ w² [µm⁴], of the mean-removed heights z
//   (missing points are 0 and leave Σ w² too) under a window w: none (w = 1) on a periodic field,
//   a separable Hann window on a measured scan, whose borders would otherwise paint a cross.
//   Parseval: ∫∫ C df_x df_y = Σ w² z² / Σ w², the mean square height, exactly Sq² without a window.
// Axial 1-D PSDs [µm³]: C_x(f_x) = ∫ C df_y (the average over rows of each row's profile PSD),
//   C_y(f_y) = ∫ C df_x; ∫ C_x df_x over both signs = the same mean square.
// Radial PSD [µm⁴]: the mean of C over annuli |f| ∈ [(b − ½)Δf, (b + ½)Δf), Δf the coarser
//   frequency step of the two axes; Σ_b C_b · area_b = the mean square, area_b the part of the
//   frequency plane the annulus's grid cells cover (the annuli run out to the corners of the grid).
// Autocorrelation: the same normalised estimator as the areal parameters' Sal (areal_parameters.hpp):
//   f(0) = 1, along +x, along +y, and its radial mean over annuli of width min(dx, dy) out to the
//   shorter of the evaluated half-field lags.
#include <vector>

#include "glintscope/surface/areal_parameters.hpp"
#include "glintscope/surface/heightfield.hpp"

namespace glintscope {

struct PowerSpectralDensity {
    std::vector<double> radial_frequency_per_um;  // b·Δf, b = 0, 1, ...
    std::vector<double> radial_um4;               // NaN for an annulus without a grid cell
    std::vector<double> radial_area_per_um2;
    std::vector<double> x_frequency_per_um;       // k / (cols·dx), k = 0..cols/2
    std::vector<double> x_um3;
    std::vector<double> y_frequency_per_um;       // m / (rows·dy), m = 0..rows/2
    std::vector<double> y_um3;
    double frequency_step_x_per_um = 0.0;
    double frequency_step_y_per_um = 0.0;
    double mean_square_um2 = 0.0;  // Σ w² z² / Σ w²: what each PSD integrates to
    bool hann_window = false;
};

// Throws Error for an invalid field or fewer than 2 valid heights.
PowerSpectralDensity compute_power_spectral_density(const Heightfield& field);

struct AutocorrelationCurves {
    std::vector<double> x_lag_um, x;  // f(t, 0), t = 0..cols/2 texels
    std::vector<double> y_lag_um, y;  // f(0, t) toward +y, t = 0..rows/2 texels
    std::vector<double> radial_lag_um, radial;  // NaN where an annulus has no valid pair
    // The spatial parameters as compute_areal_parameters gives them (threshold s, Sal, the slowest
    // decay, Str, their bounds, the lags evaluated), from this same autocorrelation; the height
    // and hybrid parameters and Std are not computed here (0).
    ArealParameters parameters;
};

// Throws Error for an invalid field, fewer than 2 valid heights, flat heights or s outside (0, 1).
AutocorrelationCurves compute_autocorrelation_curves(const Heightfield& field,
                                                     double threshold = kIsoAutocorrelationThreshold);

}  // namespace glintscope
