// Colour maps and colour-mapped PNG pictures with a legend.
#include "glintscope/colormap.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "glintscope/atomic_output.hpp"
#include "glintscope/error.hpp"
#include "glintscope/parallel.hpp"

namespace glintscope {
namespace {

using Rgb = std::array<float, 3>;

// Every 5th entry (0, 5, ..., 255) of matplotlib's 256-entry listed maps (_cm_listed.py, CC0),
// in sRGB. Linear interpolation between them stays within 0.003 of the full tables, under one
// 8-bit step.
constexpr std::array<Rgb, 52> kViridis = {{
    {0.267004, 0.004874, 0.329415}, {0.273809, 0.031497, 0.358853}, {0.278791, 0.062145, 0.386592},
    {0.281924, 0.089666, 0.412415}, {0.283197, 0.115680, 0.436115}, {0.282623, 0.140926, 0.457517},
    {0.280255, 0.165693, 0.476498}, {0.276194, 0.190074, 0.493001}, {0.270595, 0.214069, 0.507052},
    {0.263663, 0.237631, 0.518762}, {0.255645, 0.260703, 0.528312}, {0.246811, 0.283237, 0.535941},
    {0.237441, 0.305202, 0.541921}, {0.227802, 0.326594, 0.546532}, {0.218130, 0.347432, 0.550038},
    {0.208623, 0.367752, 0.552675}, {0.199430, 0.387607, 0.554642}, {0.190631, 0.407061, 0.556089},
    {0.182256, 0.426184, 0.557120}, {0.174274, 0.445044, 0.557792}, {0.166617, 0.463708, 0.558119},
    {0.159194, 0.482237, 0.558073}, {0.151918, 0.500685, 0.557587}, {0.144759, 0.519093, 0.556572},
    {0.137770, 0.537492, 0.554906}, {0.131172, 0.555899, 0.552459}, {0.125394, 0.574318, 0.549086},
    {0.121148, 0.592739, 0.544641}, {0.119423, 0.611141, 0.538982}, {0.121380, 0.629492, 0.531973},
    {0.128087, 0.647749, 0.523491}, {0.140210, 0.665859, 0.513427}, {0.157851, 0.683765, 0.501686},
    {0.180653, 0.701402, 0.488189}, {0.208030, 0.718701, 0.472873}, {0.239374, 0.735588, 0.455688},
    {0.274149, 0.751988, 0.436601}, {0.311925, 0.767822, 0.415586}, {0.352360, 0.783011, 0.392636},
    {0.395174, 0.797475, 0.367757}, {0.440137, 0.811138, 0.340967}, {0.487026, 0.823929, 0.312321},
    {0.535621, 0.835785, 0.281908}, {0.585678, 0.846661, 0.249897}, {0.636902, 0.856542, 0.216620},
    {0.688944, 0.865448, 0.182725}, {0.741388, 0.873449, 0.149561}, {0.793760, 0.880678, 0.120005},
    {0.845561, 0.887322, 0.099702}, {0.896320, 0.893616, 0.096335}, {0.945636, 0.899815, 0.112838},
    {0.993248, 0.906157, 0.143936},
}};

constexpr std::array<Rgb, 52> kInferno = {{
    {0.001462, 0.000466, 0.013866}, {0.007676, 0.006136, 0.046836}, {0.019373, 0.015133, 0.088767},
    {0.037668, 0.025921, 0.132232}, {0.061340, 0.036590, 0.177642}, {0.087411, 0.044556, 0.224813},
    {0.116656, 0.047574, 0.272321}, {0.149073, 0.045468, 0.317085}, {0.183429, 0.040329, 0.354971},
    {0.217949, 0.036615, 0.383522}, {0.251620, 0.037705, 0.403378}, {0.284321, 0.043933, 0.416608},
    {0.316282, 0.053490, 0.425116}, {0.347771, 0.064616, 0.430217}, {0.379001, 0.076253, 0.432719},
    {0.410113, 0.087896, 0.433098}, {0.441207, 0.099338, 0.431594}, {0.472328, 0.110547, 0.428334},
    {0.503493, 0.121575, 0.423356}, {0.534683, 0.132534, 0.416667}, {0.565854, 0.143567, 0.408258},
    {0.596940, 0.154848, 0.398125}, {0.627847, 0.166575, 0.386276}, {0.658463, 0.178962, 0.372748},
    {0.688653, 0.192239, 0.357603}, {0.718264, 0.206636, 0.340931}, {0.747127, 0.222378, 0.322856},
    {0.775059, 0.239667, 0.303526}, {0.801871, 0.258674, 0.283099}, {0.827372, 0.279517, 0.261750},
    {0.851384, 0.302260, 0.239636}, {0.873741, 0.326906, 0.216886}, {0.894305, 0.353399, 0.193584},
    {0.912966, 0.381636, 0.169755}, {0.929644, 0.411479, 0.145367}, {0.944285, 0.442772, 0.120354},
    {0.956852, 0.475356, 0.094695}, {0.967322, 0.509078, 0.068659}, {0.975677, 0.543798, 0.043618},
    {0.981895, 0.579392, 0.026250}, {0.985952, 0.615750, 0.025592}, {0.987819, 0.652773, 0.045581},
    {0.987464, 0.690366, 0.079990}, {0.984865, 0.728427, 0.120785}, {0.980032, 0.766837, 0.166353},
    {0.973088, 0.805409, 0.216877}, {0.964394, 0.843848, 0.273391}, {0.954997, 0.881569, 0.337475},
    {0.947594, 0.917399, 0.410665}, {0.947937, 0.949318, 0.491426}, {0.961812, 0.975924, 0.571925},
    {0.988362, 0.998364, 0.644924},
}};

const std::array<Rgb, 52>& table(ColorMap map) { return map == ColorMap::inferno ? kInferno : kViridis; }

constexpr Rgb kWhite = {1.0f, 1.0f, 1.0f};
constexpr Rgb kBlack = {0.0f, 0.0f, 0.0f};
constexpr Rgb kGrey = {kMissingGrey, kMissingGrey, kMissingGrey};

constexpr int kMinDisplaySide = 256;
constexpr int kMaxDisplaySide = 4096;
constexpr int kFontSize = 14;
constexpr int kMargin = 10;
constexpr int kBarWidth = 20;
constexpr int kMinBarHeight = 128;

// Integer rescaling so that small images are legible and huge ones stay a reasonable file.
ScalarImage display_image(const ScalarImage& image) {
    const int side = std::max(image.rows, image.cols);
    if (side < kMinDisplaySide) {
        const int factor = kMinDisplaySide / side;
        ScalarImage large{image.rows * factor, image.cols * factor, {}};
        large.values.resize(static_cast<std::size_t>(large.rows) * large.cols);
        for (int r = 0; r < large.rows; ++r)
            for (int c = 0; c < large.cols; ++c)
                large.values[static_cast<std::size_t>(r) * large.cols + c] =
                    image.values[static_cast<std::size_t>(r / factor) * image.cols + c / factor];
        return large;
    }
    if (side <= kMaxDisplaySide) return image;
    const int factor = (side + kMaxDisplaySide - 1) / kMaxDisplaySide;
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

// The first font OpenImageIO can load; fonts-dejavu-core provides DejaVuSans.
const std::string& legend_font() {
    static const std::string font = [] {
        for (const char* candidate :
             {"DejaVuSans", "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", "LiberationSans-Regular", "FreeSans"})
            if (OIIO::ImageBufAlgo::text_size("0", kFontSize, candidate).defined()) return std::string(candidate);
        return std::string();
    }();
    if (font.empty()) throw Error("no font found for legend text (install the fonts-dejavu-core package)");
    return font;
}

int text_width(const std::string& text) {
    const OIIO::ROI size = OIIO::ImageBufAlgo::text_size(text, kFontSize, legend_font());
    return size.defined() ? size.width() : 0;
}

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
    const std::string& font = legend_font();
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
