#include "glintscope/output/surface_plots.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "output/drawing.hpp"

namespace glintscope {
namespace {

using drawing::number;

// The points of a curve from index `first` on with x ≤ last_x, drawn as a line without marks
// (thousands of points).
PlotSeries curve(const std::string& label, const std::vector<double>& x, const std::vector<double>& y,
                 std::size_t first, double last_x = std::numeric_limits<double>::infinity()) {
    PlotSeries series{label, {}, {}};
    for (std::size_t k = first; k < x.size() && x[k] <= last_x; ++k) series.x.push_back(x[k]), series.y.push_back(y[k]);
    series.marks = false;
    return series;
}

// Lags shown: up to 4 times the slowest direction's decay to s, where the shape of the decay is
// readable, or all evaluated lags when some direction does not decay.
constexpr double kShownDecayLengths = 4.0;

std::string normalisation_note(const PowerSpectralDensity& psd) {
    return "Two-sided, f = 1/wavelength; integral over the frequency plane (each 1-D PSD over both signs of f) = " +
           number(psd.mean_square_um2) + " um^2, the mean square height" +
           (psd.hann_window ? " under a Hann window (measured scan)." : " = Sq^2 (periodic field, no window).");
}

Plot log_log_plot(const std::string& title, const std::string& x_label, const std::string& y_label) {
    return Plot{title, x_label, y_label, {}, {}, /*log_y=*/true, /*log_x=*/true};
}

}  // namespace

std::vector<Plot> power_spectral_density_plots(const PowerSpectralDensity& psd) {
    Plot radial = log_log_plot("Radially averaged power spectral density", "spatial frequency |f| [1/um]",
                               "C(|f|) [um^4]");
    radial.series.push_back(curve("radial mean", psd.radial_frequency_per_um, psd.radial_um4, 1));
    radial.caption = {"Mean of the 2-D PSD C(fx, fy) over annuli of width " +
                          number(psd.radial_frequency_per_um[1]) + " /um (out to the grid's corners).",
                      normalisation_note(psd)};
    Plot axial = log_log_plot("Axial power spectral density (profiles along x and along y, averaged)",
                              "spatial frequency f [1/um]", "Cx(fx), Cy(fy) [um^3]");
    axial.series.push_back(curve("along x: Cx(fx)", psd.x_frequency_per_um, psd.x_um3, 1));
    axial.series.push_back(curve("along y: Cy(fy)", psd.y_frequency_per_um, psd.y_um3, 1));
    axial.caption = {"Cx = integral of C over fy (the mean of the rows' profile PSDs); Cy likewise over fx.",
                     normalisation_note(psd)};
    return {radial, axial};
}

Plot autocorrelation_plot(const AutocorrelationCurves& curves) {
    const ArealParameters& p = curves.parameters;
    Plot plot;
    plot.title = "Autocorrelation of the mean-removed heights";
    plot.x_label = "lag t [um]";
    plot.y_label = "autocorrelation f(t)";
    const double evaluated = std::max(curves.x_lag_um.back(), curves.y_lag_um.back());
    const double longest =
        p.longest_is_lower_bound ? evaluated : std::min(evaluated, kShownDecayLengths * p.longest_decay_um);
    plot.series.push_back(curve("along +x", curves.x_lag_um, curves.x, 0, longest));
    plot.series.push_back(curve("along +y", curves.y_lag_um, curves.y, 0, longest));
    plot.series.push_back(curve("radial mean", curves.radial_lag_um, curves.radial, 0, longest));
    PlotSeries threshold{"s = " + number(p.threshold), {0.0, longest}, {p.threshold, p.threshold}, true};
    threshold.marks = false;
    plot.series.push_back(threshold);
    const std::string sal = number(p.sal_um) + " um";
    double lowest = 0.0;
    for (std::size_t k = 0; k < 3; ++k)
        for (double value : plot.series[k].y)
            if (std::isfinite(value)) lowest = std::min(lowest, value);
    PlotSeries sal_line{(p.sal_is_lower_bound ? "Sal > " : "Sal = ") + sal, {p.sal_um, p.sal_um}, {lowest, 1.0}, true};
    sal_line.marks = false;
    plot.series.push_back(sal_line);
    plot.caption = {
        "f(t) = sum z(s) z(s+t) / sum z^2 over the pairs inside the field (the estimator of info's Sal), lags up to " +
            number(longest) + " um" +
            (longest < evaluated ? " (" + number(kShownDecayLengths) + " times the slowest decay; evaluated to " + number(evaluated) + " um)." : "."),
        p.sal_is_lower_bound
            ? "Sal: no direction decays to s within the lags evaluated; Sal exceeds " + sal + "."
            : "Sal = " + sal + ": the shortest lag, over all directions, where f falls to s (here at " +
                  number(p.sal_direction_deg) + " deg from +x); the axial and radial curves cross s at or beyond it."};
    return plot;
}

}  // namespace glintscope
