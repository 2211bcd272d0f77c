#pragma once
// A line plot the tool draws itself (PNG, like the figures): series of (x, y) points joined by
// lines with a mark at each point (or without, for dense curves), linear or log10 axes with round
// ticks, axis labels, a legend and caption lines. For curves a researcher reads off: the albedo
// against incidence, validate's error against K, a heightfield's spectrum and autocorrelation.
#include <string>
#include <vector>

namespace glintscope {

struct PlotSeries {
    std::string label;       // the legend's entry
    std::vector<double> x;
    std::vector<double> y;   // same length as x; non-finite points (and ≤ 0 on a log axis) are skipped
    bool dashed = false;     // e.g. a reference curve
    bool marks = true;       // a square at each point (off for curves of thousands of points)
};

struct Plot {
    std::string title;
    std::string x_label;
    std::string y_label;
    std::vector<std::string> caption;  // lines under the plot
    std::vector<PlotSeries> series;
    bool log_y = false;
    bool log_x = false;      // non-positive x are then skipped, like y on a log y axis
};

// Writes the plot atomically; throws Error for no series, mismatched x and y, or no finite point.
void write_plot(const Plot& plot, const std::string& path);

// Several plots stacked top to bottom in one picture, each with its own axes and legend.
void write_plots(const std::vector<Plot>& plots, const std::string& path);

}  // namespace glintscope
