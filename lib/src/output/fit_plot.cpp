#include "glintscope/output/fit_plot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>

#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

constexpr double kDecadesShown = 1e-6;  // the log axis spans six decades below the data's peak

std::string percent(double fraction) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f%%", 100.0 * fraction);
    return text;
}

// Values below `floor` left out (non-finite points are skipped): a model's Gaussian tail would
// otherwise stretch the log axis over dozens of decades and flatten what a reader compares.
std::vector<double> above(const std::vector<double>& values, double floor) {
    std::vector<double> kept = values;
    for (double& value : kept)
        if (!(value >= floor)) value = std::numeric_limits<double>::quiet_NaN();
    return kept;
}

}  // namespace

std::vector<Plot> ndf_fit_plots(const std::vector<NdfFitSlice>& slices, const std::vector<NdfFit>& fits,
                                const std::string& source) {
    std::vector<Plot> plots;
    for (std::size_t s = 0; s < slices.size(); ++s) {
        const NdfFitSlice& slice = slices[s];
        Plot plot;
        plot.title = std::string(s == 0 ? "Along" : "Across") + " the " + to_string(fits.front().model.kind) +
                     " fit's alpha_x axis (" + shortest_text(std::round(slice.angle_deg * 10.0) / 10.0) +
                     " deg from +x on the disk)";
        plot.x_label = "signed polar angle of the normal [deg]";
        plot.y_label = "D [sr^-1]";
        plot.log_y = true;
        const double floor = kDecadesShown * *std::max_element(slice.data.begin(), slice.data.end());
        plot.series.push_back({"data", slice.theta_deg, above(slice.data, floor), false, false});
        for (std::size_t f = 0; f < fits.size(); ++f)
            plot.series.push_back({to_string(fits[f].model.kind) + " (relative L2 " + percent(fits[f].relative_error) + ")",
                                   slice.theta_deg, above(slice.models[f], floor), true, false});
        plot.caption = {"NDF " + source + ", slices through n, models drawn at the data's resolution; values below 1e-6 of",
                        "the data's peak on this slice are left out"};
        plots.push_back(std::move(plot));
    }
    return plots;
}

}  // namespace glintscope
