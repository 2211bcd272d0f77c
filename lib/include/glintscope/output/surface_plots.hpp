#pragma once
// The plots `preview --psd` and `preview --acf` draw (plot.hpp): the power spectral density,
// radially averaged and along each axis, on log-log axes, and the autocorrelation along x, along y
// and radially averaged with the threshold s and Sal marked. Labels are ASCII (figure.hpp).
#include <vector>

#include "glintscope/output/plot.hpp"
#include "glintscope/surface/spectra.hpp"

namespace glintscope {

// Two plots: the radial 2-D PSD [um^4] and the axial 1-D PSDs [um^3], against f > 0 [1/um].
std::vector<Plot> power_spectral_density_plots(const PowerSpectralDensity& psd);

// One plot of f(t) against the lag t [um], with s (dashed, horizontal) and Sal (dashed, vertical).
Plot autocorrelation_plot(const AutocorrelationCurves& curves);

}  // namespace glintscope
