// Colour maps and colour-mapped PNG pictures with a legend.
#include "glintscope/output/colormap.hpp"

#include "drawing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

using Rgb = std::array<float, 3>;

// The sRGB encoding of a linear component (IEC 61966-2-1).
float srgb_encode(float linear) {
    return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

// OpenImageIO's "viridis" and "inferno" (matplotlib's maps, whose knots it stores linearised),
// sampled once at 256 points and encoded back to sRGB; lookups interpolate between them.
std::vector<Rgb> sample_map(const char* name) {
    constexpr int kSamples = 256;
    OIIO::ImageBuf ramp(OIIO::ImageSpec(kSamples, 1, 1, OIIO::TypeDesc::FLOAT));
    for (int i = 0; i < kSamples; ++i) ramp.setpixel(i, 0, std::array<float, 1>{float(i) / (kSamples - 1)}.data());
    const OIIO::ImageBuf mapped = OIIO::ImageBufAlgo::color_map(ramp, 0, name);
    if (mapped.has_error()) throw Error(std::string("OpenImageIO has no colour map '") + name + "'");
    std::vector<Rgb> entries(kSamples);
    for (int i = 0; i < kSamples; ++i) {
        mapped.getpixel(i, 0, entries[i].data(), 3);
        for (float& component : entries[i]) component = srgb_encode(component);
    }
    return entries;
}

const std::vector<Rgb>& table(ColorMap map) {
    static const std::vector<Rgb> viridis = sample_map("viridis");
    static const std::vector<Rgb> inferno = sample_map("inferno");
    return map == ColorMap::inferno ? inferno : viridis;
}

constexpr Rgb kWhite = {1.0f, 1.0f, 1.0f};
constexpr Rgb kBlack = {0.0f, 0.0f, 0.0f};
constexpr Rgb kGrey = {kMissingGrey, kMissingGrey, kMissingGrey};

constexpr int kMinDisplaySide = 256;
constexpr int kMaxDisplaySide = 4096;
constexpr int kFontSize = 14;
constexpr int kMargin = 10;
constexpr int kBarWidth = 20;
constexpr int kMinBarHeight = 128;

ScalarImage display_image(const ScalarImage& image) { return resize_for_display(image, kMinDisplaySide, kMaxDisplaySide); }

}  // namespace

ScalarImage resize_for_display(const ScalarImage& image, int min_side, int max_side) {
    const int side = std::max(image.rows, image.cols);
    if (side < min_side) {
        const int factor = min_side / side;
        ScalarImage large{image.rows * factor, image.cols * factor, {}};
        large.values.resize(static_cast<std::size_t>(large.rows) * large.cols);
        for (int r = 0; r < large.rows; ++r)
            for (int c = 0; c < large.cols; ++c)
                large.values[static_cast<std::size_t>(r) * large.cols + c] =
                    image.values[static_cast<std::size_t>(r / factor) * image.cols + c / factor];
        return large;
    }
    if (side <= max_side) return image;
    const int factor = (side + max_side - 1) / max_side;
    ScalarImage small{(image.rows + factor - 1) / factor, (image.cols + factor - 1) / factor, {}};
    small.values.resize(static_cast<std::size_t>(small.rows) * small.cols);
    parallel_for(static_cast<std::size_t>(small.rows), 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            for (int c = 0; c < small.cols; ++c) {
                double sum = 0.0;
                int count = 0;
                for (int rr = static_cast<int>(r) * factor; rr < std::min(image.rows, static_cast<int>(r + 1) * factor);
                     ++rr)
                    for (int cc = c * factor; cc < std::min(image.cols, (c + 1) * factor); ++cc) {
                        const float value = image.values[static_cast<std::size_t>(rr) * image.cols + cc];
                        if (!std::isnan(value)) {
                            sum += value;
                            ++count;
                        }
                    }
                small.values[r * small.cols + c] =
                    count > 0 ? static_cast<float>(sum / count) : std::numeric_limits<float>::quiet_NaN();
            }
        }
    });
    return small;
}

ScalarImage at_true_aspect(const ScalarImage& image, double width_um, double height_um) {
    const double pixel_aspect = (width_um / image.cols) / (height_um / image.rows);  // dx / dy of a pixel
    const bool wider = pixel_aspect > 1.0;  // columns too narrow on screen: repeat them
    const int cols = wider ? static_cast<int>(std::lround(image.cols * pixel_aspect)) : image.cols;
    const int rows = wider ? image.rows : static_cast<int>(std::lround(image.rows / pixel_aspect));
    if (cols == image.cols && rows == image.rows) return image;
    ScalarImage stretched{rows, cols, {}};
    stretched.values.resize(static_cast<std::size_t>(rows) * cols);
    for (int r = 0; r < rows; ++r) {
        const int source_row = static_cast<int>(static_cast<long long>(r) * image.rows / rows);
        for (int c = 0; c < cols; ++c)
            stretched.values[static_cast<std::size_t>(r) * cols + c] =
                image.values[static_cast<std::size_t>(source_row) * image.cols +
                             static_cast<std::size_t>(static_cast<long long>(c) * image.cols / cols)];
    }
    return stretched;
}

namespace {

// The legend's text: the pictures' shared font and measure (drawing.hpp).
int text_width(const std::string& text) { return drawing::text_width(text, kFontSize); }

std::string format_value(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.4g", value);
    return buffer;
}

class Canvas {
public:
    Canvas(int width, int height) : width_(width), height_(height), rgb_(static_cast<std::size_t>(width) * height * 3) {
        fill(0, 0, width, height, kWhite);
    }
    void set(int x, int y, const Rgb& color) {
        std::copy(color.begin(), color.end(), rgb_.begin() + (static_cast<std::ptrdiff_t>(y) * width_ + x) * 3);
    }
    void fill(int x0, int y0, int width, int height, const Rgb& color) {
        for (int y = y0; y < y0 + height; ++y)
            for (int x = x0; x < x0 + width; ++x) set(x, y, color);
    }
    int width() const { return width_; }
    int height() const { return height_; }
    float* data() { return rgb_.data(); }

private:
    int width_;
    int height_;
    std::vector<float> rgb_;
};

Rgb to_rgb(const SrgbColor& color) { return {color.r, color.g, color.b}; }

double normalised(double value, const ColorLegend& legend) {
    const double range = legend.max_value - legend.min_value;
    return range > 0.0 ? (value - legend.min_value) / range : 0.5;
}

void check_plot_input(const std::string& path, const ScalarImage& image, const ColorLegend& legend) {
    if (file_extension(path) != "png")
        throw Error("cannot write '" + path + "': colour-mapped pictures are PNG files (.png)");
    if (image.rows <= 0 || image.cols <= 0) throw Error("cannot write '" + path + "': the image is empty");
    if (image.values.size() != static_cast<std::size_t>(image.rows) * image.cols)
        throw Error("cannot write '" + path + "': the image data does not match its size");
    if (!std::isfinite(legend.min_value) || !std::isfinite(legend.max_value) || legend.max_value < legend.min_value)
        throw Error("cannot write '" + path + "': the value range [" + format_value(legend.min_value) + ", " +
                    format_value(legend.max_value) + "] is not a finite, ordered range");
}

}  // namespace

ColorMap parse_colormap(std::string_view name) {
    if (name == "viridis") return ColorMap::viridis;
    if (name == "inferno") return ColorMap::inferno;
    throw Error("unknown colour map '" + std::string(name) + "' (expected viridis or inferno)");
}

std::string to_string(ColorMap map) { return map == ColorMap::inferno ? "inferno" : "viridis"; }

SrgbColor map_color(ColorMap map, double t) {
    const auto& entries = table(map);
    const double clamped = t > 0.0 ? std::min(t, 1.0) : 0.0;
    const double position = clamped * static_cast<double>(entries.size() - 1);
    const std::size_t below = std::min(static_cast<std::size_t>(position), entries.size() - 2);
    const auto fraction = static_cast<float>(position - static_cast<double>(below));
    const Rgb& a = entries[below];
    const Rgb& b = entries[below + 1];
    return {a[0] + fraction * (b[0] - a[0]), a[1] + fraction * (b[1] - a[1]), a[2] + fraction * (b[2] - a[2])};
}

void write_colormapped_png(const std::string& path, const ScalarImage& image, const ColorLegend& legend) {
    check_plot_input(path, image, legend);
    const ScalarImage shown = display_image(image);
    const std::string max_text = format_value(legend.max_value);
    const std::string min_text = format_value(legend.min_value);

    // Layout: label on top; the picture below it; the colour bar to its right, max at the top.
    const int top = kMargin + kFontSize + kMargin;
    const int bar_height = std::max(shown.rows, kMinBarHeight);
    const int bar_x = kMargin + shown.cols + 2 * kMargin;
    const int text_x = bar_x + kBarWidth + kMargin / 2;
    const int width = std::max(text_x + std::max(text_width(max_text), text_width(min_text)) + kMargin,
                               2 * kMargin + text_width(legend.label));
    const int height = top + bar_height + kMargin;
    Canvas canvas(width, height);

    parallel_for(static_cast<std::size_t>(shown.rows), 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < shown.cols; ++c) {
                const float value = shown.values[r * shown.cols + c];
                canvas.set(kMargin + c, top + static_cast<int>(r),
                           std::isnan(value) ? kGrey : to_rgb(map_color(legend.map, normalised(value, legend))));
            }
    });
    canvas.fill(bar_x - 1, top - 1, kBarWidth + 2, bar_height + 2, kBlack);
    for (int y = 0; y < bar_height; ++y) {
        const double t = 1.0 - (y + 0.5) / bar_height;
        canvas.fill(bar_x, top + y, kBarWidth, 1, to_rgb(map_color(legend.map, t)));
    }

    OIIO::ImageSpec spec(canvas.width(), canvas.height(), 3, OIIO::TypeDesc::FLOAT);
    spec.attribute("oiio:ColorSpace", "sRGB");
    OIIO::ImageBuf picture(spec, canvas.data());
    const std::string& font = drawing::font();
    const float black[3] = {0.0f, 0.0f, 0.0f};
    using OIIO::ImageBufAlgo::TextAlignX;
    using OIIO::ImageBufAlgo::TextAlignY;
    const bool drawn = OIIO::ImageBufAlgo::render_text(picture, kMargin, kMargin, legend.label, kFontSize, font, black,
                                                       TextAlignX::Left, TextAlignY::Top) &&
                       OIIO::ImageBufAlgo::render_text(picture, text_x, top, max_text, kFontSize, font, black,
                                                       TextAlignX::Left, TextAlignY::Top) &&
                       OIIO::ImageBufAlgo::render_text(picture, text_x, top + bar_height, min_text, kFontSize, font,
                                                       black, TextAlignX::Left, TextAlignY::Bottom);
    if (!drawn) throw Error("cannot write '" + path + "': drawing the legend failed (" + picture.geterror() + ")");
    write_atomically(path, [&](const std::string& file) {
        if (!picture.write(file, OIIO::TypeDesc::UINT8, "png"))
            throw Error("cannot write '" + path + "': " + picture.geterror());
    });
}

}  // namespace glintscope
