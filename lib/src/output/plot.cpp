#include "glintscope/output/plot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "glintscope/core/error.hpp"
#include "output/drawing.hpp"

namespace glintscope {
namespace {

using namespace drawing;

// Distinct hues for the series (Okabe-Ito, readable by the colour-blind), then repeating.
constexpr Colour kPalette[] = {{0.0f, 0.45f, 0.70f}, {0.84f, 0.37f, 0.0f},  {0.0f, 0.62f, 0.45f},
                               {0.80f, 0.47f, 0.65f}, {0.34f, 0.71f, 0.91f}, {0.90f, 0.62f, 0.0f},
                               {0.35f, 0.35f, 0.35f}};
constexpr Colour kGrid{0.88f, 0.88f, 0.88f};
constexpr int kAreaWidth = 560;
constexpr int kAreaHeight = 360;
constexpr int kLeft = 90;
constexpr int kTop = 58;

Colour series_colour(std::size_t k) { return kPalette[k % std::size(kPalette)]; }

struct Range {
    double low = std::numeric_limits<double>::infinity();
    double high = -std::numeric_limits<double>::infinity();
    void include(double value) { low = std::min(low, value), high = std::max(high, value); }
};

bool shown(double value, bool log_axis) { return std::isfinite(value) && (!log_axis || value > 0.0); }

// The axis range in plotted units (log10 of the value on a log axis), widened to round ticks.
Range axis_range(Range data, bool log_axis) {
    if (log_axis) return {std::floor(data.low), std::max(std::ceil(data.high), std::floor(data.low) + 1.0)};
    if (data.high - data.low < 1e-12 * std::max(1.0, std::fabs(data.high))) data.low -= 0.5, data.high += 0.5;
    const double step = nice_step(data.high - data.low, 6);
    return {std::floor(data.low / step) * step, std::ceil(data.high / step) * step};
}

// The plotting area of one plot, its top-left corner `top` pixels down the picture.
struct Axes {
    Range x, y;
    bool log_x = false, log_y = false;
    int top = kTop;
    int px(double value) const {
        const double v = log_x ? std::log10(value) : value;
        return kLeft + int(std::lround((v - x.low) / (x.high - x.low) * kAreaWidth));
    }
    int py(double value) const {
        const double v = log_y ? std::log10(value) : value;
        return top + kAreaHeight - int(std::lround((v - y.low) / (y.high - y.low) * kAreaHeight));
    }
};

Axes axes_of(const Plot& plot, int top) {
    Range x, y;
    for (const PlotSeries& series : plot.series) {
        if (series.x.size() != series.y.size())
            throw Error("plot series '" + series.label + "' has " + std::to_string(series.x.size()) + " x and " +
                        std::to_string(series.y.size()) + " y values");
        for (std::size_t k = 0; k < series.x.size(); ++k)
            if (shown(series.x[k], plot.log_x) && shown(series.y[k], plot.log_y))
                x.include(plot.log_x ? std::log10(series.x[k]) : series.x[k]),
                    y.include(plot.log_y ? std::log10(series.y[k]) : series.y[k]);
    }
    if (!(x.low <= x.high)) throw Error("plot '" + plot.title + "' has no point to draw");
    return {axis_range(x, plot.log_x), axis_range(y, plot.log_y), plot.log_x, plot.log_y, top};
}

// The tick values of an axis: round steps, or on a log axis its decades (and 2 and 5 within them
// when there are few).
std::vector<double> ticks(const Range& range, bool log_axis, int count) {
    std::vector<double> values;
    if (log_axis) {
        for (double v = range.low; v <= range.high + 1e-9; v += 1.0)
            for (double m : range.high - range.low <= 2.0 ? std::vector{1.0, 2.0, 5.0} : std::vector{1.0})
                if (v + std::log10(m) <= range.high + 1e-9) values.push_back(m * std::pow(10.0, v));
        return values;
    }
    const double step = nice_step(range.high - range.low, count);
    for (double v = range.low; v <= range.high + 1e-9 * step; v += step) values.push_back(v);
    return values;
}

void draw_ticks(OIIO::ImageBuf& picture, const Axes& axes, const Plot& plot) {
    const auto centre = OIIO::ImageBufAlgo::TextAlignX::Center, right = OIIO::ImageBufAlgo::TextAlignX::Right;
    const int bottom = axes.top + kAreaHeight;
    for (double x : ticks(axes.x, axes.log_x, 8)) {
        OIIO::ImageBufAlgo::render_line(picture, axes.px(x), axes.top, axes.px(x), bottom, kGrid);
        text(picture, axes.px(x), bottom + 6, number(x, 4), kBlack, centre, 12);
    }
    for (double y : ticks(axes.y, axes.log_y, 6)) {
        OIIO::ImageBufAlgo::render_line(picture, kLeft, axes.py(y), kLeft + kAreaWidth, axes.py(y), kGrid);
        text(picture, kLeft - 6, axes.py(y) - 7, number(y, 4), kBlack, right, 12);
    }
    OIIO::ImageBufAlgo::render_box(picture, kLeft, axes.top, kLeft + kAreaWidth, bottom, kBlack);
    text(picture, kLeft + kAreaWidth / 2, bottom + 24, plot.x_label + (plot.log_x ? " (log scale)" : ""), kBlack,
         centre);
    text(picture, kMargin, axes.top - 26, plot.y_label + (plot.log_y ? " (log scale)" : ""));
}

// Lines two pixels thick between consecutive drawable points, and a square mark at each point.
void draw_series(OIIO::ImageBuf& picture, const Axes& axes, const PlotSeries& series, const Colour& colour) {
    int last_x = 0, last_y = 0;
    bool have_last = false;
    for (std::size_t k = 0; k < series.x.size(); ++k) {
        if (!shown(series.x[k], axes.log_x) || !shown(series.y[k], axes.log_y)) {
            have_last = false;
            continue;
        }
        const int x = axes.px(series.x[k]), y = axes.py(series.y[k]);
        if (have_last)
            for (int d = 0; d < 2; ++d) {
                if (!series.dashed) OIIO::ImageBufAlgo::render_line(picture, last_x, last_y + d, x, y + d, colour);
                else
                    for (int s = 0; s < 12; s += 2)  // six dashes per segment
                        OIIO::ImageBufAlgo::render_line(picture, last_x + (x - last_x) * s / 12,
                                                        last_y + d + (y - last_y) * s / 12,
                                                        last_x + (x - last_x) * (s + 1) / 12,
                                                        last_y + d + (y - last_y) * (s + 1) / 12, colour);
            }
        if (series.marks) OIIO::ImageBufAlgo::render_box(picture, x - 3, y - 3, x + 3, y + 3, colour, true);
        last_x = x, last_y = y, have_last = true;
    }
}

// The picture's width for a plot, and the height it takes from its title to its last caption line.
int plot_width(const Plot& plot) {
    int legend_width = 0;
    for (const PlotSeries& series : plot.series) legend_width = std::max(legend_width, text_width(series.label) + 44);
    int caption_width = 0;
    for (const std::string& line : plot.caption) caption_width = std::max(caption_width, text_width(line));
    return std::max({kLeft + kAreaWidth + 2 * kMargin + legend_width, caption_width + 2 * kMargin,
                     text_width(plot.title, 16) + 2 * kMargin});
}

int plot_height(const Plot& plot) { return kTop + kAreaHeight + 50 + 20 * int(plot.caption.size()); }

// Draws the plot with its title `offset` pixels down the picture.
void draw_plot(OIIO::ImageBuf& picture, const Plot& plot, int offset) {
    if (plot.series.empty()) throw Error("plot '" + plot.title + "' has no series");
    const Axes axes = axes_of(plot, offset + kTop);
    text(picture, kMargin, offset + kMargin, plot.title, kBlack, OIIO::ImageBufAlgo::TextAlignX::Left, 16);
    draw_ticks(picture, axes, plot);
    for (std::size_t k = 0; k < plot.series.size(); ++k) {
        draw_series(picture, axes, plot.series[k], series_colour(k));
        const int x = kLeft + kAreaWidth + 2 * kMargin, y = axes.top + 8 + 22 * int(k);
        for (int d = 0; d < 2; ++d)
            for (int s = 0; s < 28; s += plot.series[k].dashed ? 6 : 28)
                OIIO::ImageBufAlgo::render_line(picture, x + s, y + 7 + d, x + std::min(s + (plot.series[k].dashed ? 3 : 28), 28),
                                                y + 7 + d, series_colour(k));
        text(picture, x + 36, y, plot.series[k].label);
    }
    const int caption_top = axes.top + kAreaHeight + 50;
    for (std::size_t k = 0; k < plot.caption.size(); ++k) text(picture, kMargin, caption_top + 20 * int(k), plot.caption[k]);
}

}  // namespace

void write_plot(const Plot& plot, const std::string& path) { write_plots({plot}, path); }

void write_plots(const std::vector<Plot>& plots, const std::string& path) {
    if (plots.empty()) throw Error("no plot to draw into " + path);
    int width = 0, height = kMargin;
    for (const Plot& plot : plots) width = std::max(width, plot_width(plot)), height += plot_height(plot);
    OIIO::ImageBuf picture = blank(width, height);
    int offset = 0;
    for (const Plot& plot : plots) {
        draw_plot(picture, plot, offset);
        offset += plot_height(plot);
    }
    write_png(picture, path);
}

}  // namespace glintscope
