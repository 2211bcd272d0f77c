#include "glintscope/output/figure.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "glintscope/core/atomic_output.hpp"
#include "glintscope/output/colormap.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/lobe/compare.hpp"
#include "output/drawing.hpp"
#include "output/image_files.hpp"

namespace glintscope {
namespace {

using namespace drawing;

constexpr Colour kGuide{0.62f, 0.62f, 0.62f};    // disk outline and θ rings
constexpr Colour kMarker{0.1f, 0.85f, 1.0f};     // mirror direction
constexpr Colour kFootprint{1.0f, 0.1f, 0.55f};  // footprints on height maps (off the viridis/inferno hues)
constexpr int kBarWidth = 14;
constexpr int kMinPanel = 320;

// Where a panel draws its image: the square (x0, y0, size) of picture pixels showing the image
// pixels `box` of an N×N image.
struct DiskView {
    int x0 = 0;
    int y0 = 0;
    int size = 0;
    int n = 0;
    PixelBox box;

    double zoom() const { return double(size) / (box.col1 - box.col0); }
    // The picture position of disk point (x, y): columns along +x, row 0 at y = +1 (map view).
    std::pair<int, int> to_picture(double x, double y) const {
        return {x0 + int(std::lround(((x + 1.0) * 0.5 * n - box.col0) * zoom())),
                y0 + int(std::lround(((1.0 - y) * 0.5 * n - box.row0) * zoom()))};
    }
    bool contains(int x, int y) const { return x >= x0 && x < x0 + size && y >= y0 && y < y0 + size; }
    OIIO::ROI roi() const { return OIIO::ROI(x0, x0 + size, y0, y0 + size); }
};

// A circle of radius r (disk units) about the disk's centre, as a polyline clipped to the view.
void circle(OIIO::ImageBuf& picture, const DiskView& view, double r, const Colour& colour, bool dashed) {
    const int segments = 180;
    for (int k = 0; k < segments; ++k) {
        if (dashed && k % 2) continue;
        const double a0 = 2.0 * pi * k / segments, a1 = 2.0 * pi * (k + 1) / segments;
        const auto [xa, ya] = view.to_picture(r * std::cos(a0), r * std::sin(a0));
        const auto [xb, yb] = view.to_picture(r * std::cos(a1), r * std::sin(a1));
        OIIO::ImageBufAlgo::render_line(picture, xa, ya, xb, yb, colour, false, view.roi());
    }
}

// A ring with four ticks, two pixels thick, visible on dark and bright lobes alike.
void marker(OIIO::ImageBuf& picture, const DiskView& view, int x, int y, const Colour& colour) {
    if (!view.contains(x, y)) return;
    for (int d = 0; d < 2; ++d) {
        OIIO::ImageBufAlgo::render_line(picture, x - 12, y + d, x - 5, y + d, colour, false, view.roi());
        OIIO::ImageBufAlgo::render_line(picture, x + 5, y + d, x + 12, y + d, colour, false, view.roi());
        OIIO::ImageBufAlgo::render_line(picture, x + d, y - 12, x + d, y - 5, colour, false, view.roi());
        OIIO::ImageBufAlgo::render_line(picture, x + d, y + 5, x + d, y + 12, colour, false, view.roi());
    }
}

bool spectral(const LobeImage& lobe) { return lobe.layers() > 1; }

std::string metadata(const LobeImage& lobe, const std::string& key) {
    const auto it = lobe.metadata.find(key);
    return it == lobe.metadata.end() ? "" : it->second;
}

bool applies(const LobeImage& lobe, const std::string& key) {
    const std::string ignored = metadata(lobe, "not_applicable");
    for (const std::string& name : split(ignored, ','))
        if (name == key) return false;
    return true;
}

std::string wavelength_text(const LobeImage& lobe) {
    if (!spectral(lobe)) return "lambda " + number(lobe.wavelengths_um[0] * 1e3, 4) + " nm";
    return "lambda " + number(lobe.wavelengths_um.front() * 1e3, 4) + "-" + number(lobe.wavelengths_um.back() * 1e3, 4) +
           " nm, " + std::to_string(lobe.layers()) + " bins";
}

}  // namespace

// Caption lines from the image's metadata (lobe::compute_lobe writes them).
std::vector<std::string> panel_caption(const LobeImage& lobe) {
    std::vector<std::string> first = {metadata(lobe, "method").empty() ? "?" : metadata(lobe, "method")};
    if (applies(lobe, "model") && lobe.quantity == Quantity::brdf && !metadata(lobe, "query.model").empty())
        first.push_back(metadata(lobe, "query.model"));
    if (!metadata(lobe, "gabor.kernels_per_texel").empty()) first.push_back("K = " + metadata(lobe, "gabor.kernels_per_texel"));
    if (!metadata(lobe, "gabor.order").empty()) first.push_back("order " + metadata(lobe, "gabor.order"));
    if (applies(lobe, "material") && metadata(lobe, "query.material") != "none" && !metadata(lobe, "query.material").empty())
        first.push_back(metadata(lobe, "query.material"));
    std::vector<std::string> second;
    if (applies(lobe, "lambda")) second.push_back(wavelength_text(lobe));
    const std::string lambda_q = metadata(lobe, "dk.lambda_q_um");
    if (lambda_q == "per-pixel") second.push_back("lambda_q per pixel");
    else if (!lambda_q.empty()) second.push_back(std::string("lambda_q ").append(number(std::stod(lambda_q) * 1e3, 4)).append(" nm"));
    if (applies(lobe, "omega_i") && !metadata(lobe, "info.theta_i_deg").empty())
        second.push_back("theta_i " + number(std::stod(metadata(lobe, "info.theta_i_deg"))) + " deg, phi_i " +
                         number(std::stod(metadata(lobe, "info.phi_i_deg"))) + " deg");
    if (!metadata(lobe, "query.sigma_c").empty())
        second.push_back("sigma_c " + number(std::stod(metadata(lobe, "query.sigma_c"))) + " um");
    else if (!metadata(lobe, "query.box").empty()) {
        std::vector<std::string> sides;  // "70" or "70x53" (query_keys.cpp)
        for (const std::string& side : split(metadata(lobe, "query.box"), 'x')) sides.push_back(number(std::stod(side)));
        second.push_back("box " + join(sides, " x ") + " um");
    }
    else if (metadata(lobe, "query.footprint") == "whole")
        second.push_back("whole field");
    std::vector<std::string> surface;
    if (!metadata(lobe, "query.heightfield").empty())
        surface.push_back("surface " + std::filesystem::path(metadata(lobe, "query.heightfield")).filename().string());
    if (!metadata(lobe, "query.centre").empty() && metadata(lobe, "query.footprint") != "whole" &&
        metadata(lobe, "footprints.count").empty())
        surface.push_back("centre " + join(split(metadata(lobe, "query.centre"), ','), ", ") + " um");
    else if (!metadata(lobe, "footprints.count").empty())
        surface.push_back("mean of " + metadata(lobe, "footprints.count") + " footprints");
    const std::string guides = lobe.quantity == Quantity::brdf ? "rings: theta_o 30, 60 deg; cyan: mirror direction"
                                                               : "rings: theta_h 30, 60 deg; cyan: mean normal n";
    if (surface.empty()) return {join(first, ", "), join(second, ", "), guides};
    return {join(first, ", "), join(surface, ", "), join(second, ", "), guides};
}

namespace {

// Display value in [0, 1] of a scalar (one-wavelength or NDF) pixel under the exposure.
double shown(double value, const DisplayExposure& exposure) {
    if (!exposure.log_scale) return value / exposure.white_level;
    return log_display_value(value, exposure.white_level, exposure.log_decades);
}

// A signed image (a difference of two lobes, compare.hpp, even where it is ≥ 0, or any image
// with a negative value) is drawn on a diverging scale symmetric about 0.
bool is_signed(const LobeImage& lobe) {
    if (spectral(lobe)) return false;
    return lobe.metadata.contains("difference") ||
           std::any_of(lobe.values.begin(), lobe.values.end(), [](float v) { return v < 0.0f; });
}

DisplayExposure signed_exposure(const LobeImage& lobe) {
    DisplayExposure exposure;
    exposure.white_level = 0.0;  // the largest |value|, however small (the default white is 1)
    for (float v : lobe.values)
        if (std::isfinite(v)) exposure.white_level = std::max(exposure.white_level, double(std::fabs(v)));
    if (!(exposure.white_level > 0.0)) exposure.white_level = 1.0;  // all zero: any scale shows it grey
    exposure.ev = -std::log2(exposure.white_level);
    exposure.rule = "symmetric: +-max |value| maps to the ends";
    return exposure;
}

Colour diverging(double value, double scale) {
    const SrgbColor c = difference_colour(value, scale);
    return {c.r, c.g, c.b};
}

// The N×N display colours of the disk (and the number of disk pixels above white).
struct DiskColours {
    std::vector<Colour> pixels;
    std::size_t clipped = 0;
};

DiskColours disk_colours(const LobeImage& lobe, const LobeOutputOptions& options, const DisplayExposure& exposure) {
    const int n = lobe.resolution;
    DiskColours result;
    result.pixels.assign(std::size_t(n) * n, kWhite);
    std::vector<std::uint8_t> display;
    std::vector<float> xyz;
    if (spectral(lobe)) {
        ColourSettings settings = options.colour;
        settings.exposure_ev = exposure.ev;
        display = lobe_to_display(lobe, settings).pixels;
        xyz = lobe_to_xyz(lobe, settings.illuminant);
    }
    const ColorMap map = options.colormap == "viridis" ? ColorMap::viridis : ColorMap::inferno;
    const bool signed_values = is_signed(lobe);  // once: it reads every pixel
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            if (!inside_unit_disk(disk_pixel_point(row, col, n))) continue;
            const std::size_t i = std::size_t(row) * n + col;
            if (spectral(lobe)) {
                result.pixels[i] = {display[3 * i] / 255.0f, display[3 * i + 1] / 255.0f, display[3 * i + 2] / 255.0f};
                if (!exposure.log_scale && xyz[3 * i + 1] > exposure.white_level) ++result.clipped;
                continue;
            }
            const double value = lobe.at(0, row, col);
            if (signed_values) {
                result.pixels[i] = diverging(value, exposure.white_level);
                continue;
            }
            const double t = shown(value, exposure);
            if (!exposure.log_scale && t > 1.0) ++result.clipped;
            if (options.colormap == "grey") {
                const float grey = float(std::clamp(t, 0.0, 1.0));
                result.pixels[i] = {grey, grey, grey};
            } else {
                const SrgbColor c = map_color(map, t);
                result.pixels[i] = {c.r, c.g, c.b};
            }
        }
    return result;
}

// Draws the view's image pixels, zoomed to fill its square, with the guides that fall inside.
void draw_disk(OIIO::ImageBuf& picture, const DiskView& view, const LobeImage& lobe, const DiskColours& colours, int font) {
    const int n = lobe.resolution, side = view.box.col1 - view.box.col0;
    for (int y = 0; y < view.size; ++y)
        for (int x = 0; x < view.size; ++x) {
            const std::size_t i =
                std::size_t(view.box.row0 + y * side / view.size) * n + std::size_t(view.box.col0 + x * side / view.size);
            picture.setpixel(view.x0 + x, view.y0 + y, colours.pixels[i].data(), 3);
        }
    circle(picture, view, 1.0, kGuide, false);
    for (const double theta_deg : {30.0, 60.0}) {
        circle(picture, view, std::sin(theta_deg * pi / 180.0), kGuide, true);
        const auto [x, y] = view.to_picture(0.0, std::sin(theta_deg * pi / 180.0));
        if (view.contains(x, y) && view.contains(x + 4 * font, y + font))
            text(picture, x + 3, y + 2, number(theta_deg) + " deg", kGuide, OIIO::ImageBufAlgo::TextAlignX::Left,
                 font * 11 / kFont);
    }
    if (lobe.quantity == Quantity::brdf) {
        // Mirror direction of ω_i: −ω̄_i (conventions.md), if the query recorded ω_i.
        const std::vector<std::string> parts = split(metadata(lobe, "query.omega_i"), ',');
        if (parts.size() == 3) {
            const auto [x, y] = view.to_picture(-parse_number(parts[0]), -parse_number(parts[1]));
            marker(picture, view, x, y, kMarker);
        }
    } else {
        const auto [x, y] = view.to_picture(0.0, 0.0);
        marker(picture, view, x, y, kMarker);
    }
}

// The colour bar's label: the quantity and units, "difference" for a signed image, and on a
// log scale the decades it shows.
std::string bar_unit(const LobeImage& lobe, const DisplayExposure& exposure) {
    const QuantityLabels& label = labels(lobe.quantity);
    return (is_signed(lobe) ? "difference " : "") + label.symbol + (label.units == "1" ? "" : " [" + label.units + "]") +
           (exposure.log_scale && !is_signed(lobe) ? ", log, " + number(exposure.log_decades) + " decades" : "");
}

double bar_bottom(const LobeImage& lobe, const DisplayExposure& exposure) {
    return is_signed(lobe)        ? -exposure.white_level
           : exposure.log_scale ? exposure.white_level * std::pow(10.0, -exposure.log_decades)
                                : 0.0;
}

// A vertical colour bar from 0 (or the log floor, or −max for a difference) to white, labelled,
// at (x0, y0); returns its rectangle.
PixelRect draw_colour_bar(OIIO::ImageBuf& picture, int x0, int y0, int height, const LobeImage& lobe,
                          const LobeOutputOptions& options, const DisplayExposure& exposure, int font) {
    const ColorMap map = options.colormap == "viridis" ? ColorMap::viridis : ColorMap::inferno;
    const bool signed_values = is_signed(lobe);
    for (int y = 0; y < height; ++y) {
        const double t = 1.0 - (y + 0.5) / height;
        Colour c{float(t), float(t), float(t)};
        if (signed_values) {
            c = diverging(2.0 * t - 1.0, 1.0);
        } else if (options.colormap != "grey") {
            const SrgbColor m = map_color(map, t);
            c = {m.r, m.g, m.b};
        }
        for (int x = 0; x < kBarWidth; ++x) picture.setpixel(x0 + x, y0 + y, c.data(), 3);
    }
    OIIO::ImageBufAlgo::render_box(picture, x0 - 1, y0 - 1, x0 + kBarWidth, y0 + height, kBlack);
    text(picture, x0 + kBarWidth + 4, y0 - 2, number(exposure.white_level), kBlack, OIIO::ImageBufAlgo::TextAlignX::Left, font);
    text(picture, x0 + kBarWidth + 4, y0 + height - font - 2, number(bar_bottom(lobe, exposure)), kBlack,
         OIIO::ImageBufAlgo::TextAlignX::Left, font);
    text(picture, x0 + kBarWidth + 4, y0 + height / 2 - font / 2, bar_unit(lobe, exposure), kBlack,
         OIIO::ImageBufAlgo::TextAlignX::Left, font);
    return {x0, y0, kBarWidth, height};
}

// The width a colour bar and its labels take beside a disk.
int bar_space(const LobeImage& lobe, const DisplayExposure& exposure, int font) {
    if (spectral(lobe)) return 0;
    return kMargin + kBarWidth + 8 +
           std::max({text_width(number(exposure.white_level), font), text_width(number(bar_bottom(lobe, exposure)), font),
                     text_width(bar_unit(lobe, exposure), font)});
}

std::string exposure_line(const LobeImage& lobe, const DisplayExposure& exposure) {
    if (!spectral(lobe)) return "";
    return "exposure " + number(exposure.ev) + " EV: white = " + number(exposure.white_level) + " " +
           labels(lobe.quantity).units + (exposure.log_scale ? ", log scale, " + number(exposure.log_decades) + " decades" : "");
}

std::string clip_line(std::size_t clipped) {
    return clipped ? std::to_string(clipped) + " pixel" + (clipped == 1 ? "" : "s") + " above white (clipped)" : "";
}

// How a panel is drawn: its type size, whether it carries its own colour bar, the image pixels shown.
struct PanelStyle {
    int font = kFont;
    bool colour_bar = true;
    PixelBox view;  // {}: the whole image
};

// The caption lines every non-empty cell has, removed from the cells (in the first cell's order).
std::vector<std::string> shared_lines(const std::vector<std::vector<bool>>& present,
                                      std::vector<std::vector<std::vector<std::string>>>& lines) {
    std::vector<std::string> common;
    bool first = true;
    for (std::size_t r = 0; r < present.size(); ++r)
        for (std::size_t c = 0; c < present[r].size(); ++c) {
            if (!present[r][c]) continue;
            if (first) common = lines[r][c];
            std::erase_if(common, [&](const std::string& line) {
                return std::find(lines[r][c].begin(), lines[r][c].end(), line) == lines[r][c].end();
            });
            first = false;
        }
    for (auto& row : lines)
        for (auto& cell : row)
            std::erase_if(cell, [&](const std::string& line) { return std::find(common.begin(), common.end(), line) != common.end(); });
    return common;
}

PixelBox whole_or(const PixelBox& view, int resolution) { return view.empty() ? PixelBox{0, 0, resolution, resolution} : view; }

// One annotated panel: the disk with guides, its colour bar, and `lines` of caption below.
OIIO::ImageBuf panel(const LobeImage& lobe, const LobeOutputOptions& options, const DisplayExposure& exposure,
                     std::vector<std::string> lines, const PanelStyle& style = {}) {
    const int size = panel_size(lobe.resolution);
    const DiskColours colours = disk_colours(lobe, options, exposure);
    lines.push_back(exposure_line(lobe, exposure));
    lines.push_back(clip_line(colours.clipped));
    lines.erase(std::remove(lines.begin(), lines.end(), std::string()), lines.end());
    int width = kMargin + size + (style.colour_bar ? bar_space(lobe, exposure, style.font) : 0) + kMargin;
    for (const std::string& line : lines) width = std::max(width, 2 * kMargin + text_width(line, style.font));
    const int line_height = style.font + 5;
    OIIO::ImageBuf picture = blank(width, kMargin + size + kMargin + int(lines.size()) * line_height + kMargin);
    draw_disk(picture, {kMargin, kMargin, size, lobe.resolution, whole_or(style.view, lobe.resolution)}, lobe, colours,
              style.font);
    if (!spectral(lobe) && style.colour_bar)
        draw_colour_bar(picture, kMargin + size + kMargin, kMargin, size, lobe, options, exposure, style.font);
    for (std::size_t k = 0; k < lines.size(); ++k)
        text(picture, kMargin, kMargin + size + kMargin + int(k) * line_height, lines[k], kBlack,
             OIIO::ImageBufAlgo::TextAlignX::Left, style.font);
    return picture;
}

// A picture at picture_zoom, as it is (each display pixel copied, zoomed by repetition), and
// `lines` of caption below.
OIIO::ImageBuf picture_panel(const DisplayPicture& picture, const std::vector<std::string>& lines, int font) {
    const int zoom = picture_zoom(picture.width, picture.height);
    const int shown_width = picture.width * zoom, shown_height = picture.height * zoom;
    int width = kMargin + shown_width + kMargin;
    for (const std::string& line : lines) width = std::max(width, 2 * kMargin + text_width(line, font));
    const int line_height = font + 5;
    OIIO::ImageBuf panel = blank(width, kMargin + shown_height + kMargin + int(lines.size()) * line_height + kMargin);
    for (int y = 0; y < shown_height; ++y)
        for (int x = 0; x < shown_width; ++x) {
            const std::uint8_t* rgb = &picture.rgb[(std::size_t(y / zoom) * picture.width + x / zoom) * 3];
            const Colour colour{rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f};
            panel.setpixel(kMargin + x, kMargin + y, colour.data(), 3);
        }
    for (std::size_t k = 0; k < lines.size(); ++k)
        text(panel, kMargin, kMargin + shown_height + kMargin + int(k) * line_height, lines[k], kBlack,
             OIIO::ImageBufAlgo::TextAlignX::Left, font);
    return panel;
}

DisplayExposure exposure_of(const LobeImage& lobe, const ColourSettings& settings) {
    return is_signed(lobe) ? signed_exposure(lobe) : display_exposure(lobe, settings);
}

// Axes of a map-view picture of width_um × height_um drawn at (x0, y0) with size (w, h) pixels.
void draw_axes(OIIO::ImageBuf& picture, int x0, int y0, int w, int h, double width_um, double height_um) {
    OIIO::ImageBufAlgo::render_box(picture, x0 - 1, y0 - 1, x0 + w, y0 + h, kBlack);
    const double step = nice_step(std::max(width_um, height_um), 8);
    for (double x = 0.0; x <= width_um + 1e-9; x += step) {
        const int px = x0 + int(std::lround(x / width_um * w));
        OIIO::ImageBufAlgo::render_line(picture, px, y0 + h, px, y0 + h + 5, kBlack);
        text(picture, px, y0 + h + 7, number(x, 4), kBlack, OIIO::ImageBufAlgo::TextAlignX::Center, 12);
    }
    for (double y = 0.0; y <= height_um + 1e-9; y += step) {
        const int py = y0 + h - int(std::lround(y / height_um * h));
        OIIO::ImageBufAlgo::render_line(picture, x0 - 6, py, x0 - 1, py, kBlack);
        text(picture, x0 - 8, py - 7, number(y, 4), kBlack, OIIO::ImageBufAlgo::TextAlignX::Right, 12);
    }
    text(picture, x0 + w / 2, y0 + h + 24, "x [um]", kBlack, OIIO::ImageBufAlgo::TextAlignX::Center, 12);
    text(picture, x0 - 8, y0 - 22, "y [um]", kBlack, OIIO::ImageBufAlgo::TextAlignX::Right, 12);
}

// A scale bar of a round length in the lower right corner, white on a dark outline.
void draw_scale_bar(OIIO::ImageBuf& picture, int x0, int y0, int w, int h, double width_um) {
    const double length = nice_step(width_um, 4);
    const int pixels = int(std::lround(length / width_um * w));
    const int right = x0 + w - 12, bottom = y0 + h - 12;
    OIIO::ImageBufAlgo::render_box(picture, right - pixels - 1, bottom - 5, right + 1, bottom + 1, kBlack, true);
    OIIO::ImageBufAlgo::render_box(picture, right - pixels, bottom - 4, right, bottom, kWhite, true);
    const std::string label = number(length, 4) + " um";
    text(picture, right - pixels / 2 + 1, bottom - 23, label, kBlack, OIIO::ImageBufAlgo::TextAlignX::Center, 13);
    text(picture, right - pixels / 2, bottom - 24, label, kWhite, OIIO::ImageBufAlgo::TextAlignX::Center, 13);
}

// The same along y, in the lower left corner.
void draw_vertical_scale_bar(OIIO::ImageBuf& picture, int x0, int y0, int h, double height_um) {
    const double length = nice_step(height_um, 4);
    const int pixels = int(std::lround(length / height_um * h));
    const int left = x0 + 12, bottom = y0 + h - 12;
    OIIO::ImageBufAlgo::render_box(picture, left - 1, bottom - pixels - 1, left + 5, bottom + 1, kBlack, true);
    OIIO::ImageBufAlgo::render_box(picture, left, bottom - pixels, left + 4, bottom, kWhite, true);
    const std::string label = number(length, 4) + " um";
    text(picture, left + 9, bottom - pixels / 2 - 7, label, kBlack, OIIO::ImageBufAlgo::TextAlignX::Left, 13);
    text(picture, left + 8, bottom - pixels / 2 - 8, label, kWhite, OIIO::ImageBufAlgo::TextAlignX::Left, 13);
}

// A footprint's outline about its centre in µm, as a closed polyline: a box's four corners, or
// the ellipse r·(σ_c cos a, σ_minor sin a) turned by its axis (a circle when isotropic).
std::vector<Point2> footprint_outline(const Footprint& footprint, double r) {
    const double c = std::cos(footprint.axis_radians), s = std::sin(footprint.axis_radians);
    const auto turned = [&](double u, double v) { return Point2{c * u - s * v, s * u + c * v}; };
    std::vector<Point2> points;
    if (footprint.shape == FootprintShape::box) {
        const double hw = 0.5 * box_width_um(footprint), hh = 0.5 * box_height_um(footprint);
        for (const auto& [u, v] : {std::pair{-hw, -hh}, std::pair{hw, -hh}, std::pair{hw, hh}, std::pair{-hw, hh}})
            points.push_back(turned(u, v));
        return points;
    }
    const double minor = is_elliptical(footprint) ? footprint.sigma_minor_um : footprint.sigma_um;
    const int segments = 120;
    for (int k = 0; k < segments; ++k) {
        const double a = 2.0 * pi * k / segments;
        points.push_back(turned(r * footprint.sigma_um * std::cos(a), r * minor * std::sin(a)));
    }
    return points;
}

// The closed polyline `points` (µm about the pixel (px, py), y up) two pixels wide; dashed: every other segment.
void draw_outline(OIIO::ImageBuf& picture, int px, int py, const std::vector<Point2>& points, double sx, double sy,
                  bool dashed, OIIO::ROI clip) {
    for (std::size_t k = 0; k < points.size(); ++k) {
        if (dashed && k % 2) continue;
        const Point2 a = points[k], b = points[(k + 1) % points.size()];
        for (int d = 0; d < 2; ++d)
            OIIO::ImageBufAlgo::render_line(picture, px + d + int(std::lround(a.x * sx)), py - int(std::lround(a.y * sy)),
                                            px + d + int(std::lround(b.x * sx)), py - int(std::lround(b.y * sy)),
                                            kFootprint, false, clip);
    }
}

// The footprint in map view (a box, or a Gaussian's σ_c ellipse and, dashed, gabor's default
// truncation at 3.25 σ_c), and its copies across the periodic edges.
void draw_footprint(OIIO::ImageBuf& picture, int x0, int y0, int w, int h, const Heightfield& field,
                    const Footprint& footprint) {
    const double sx = w / field.width_um(), sy = h / field.height_um();
    const OIIO::ROI clip(x0, x0 + w, y0, y0 + h);
    for (int ty = -1; ty <= 1; ++ty)
        for (int tx = -1; tx <= 1; ++tx) {
            const double cx = footprint.centre_um.x + tx * field.width_um();
            const double cy = footprint.centre_um.y + ty * field.height_um();
            const int px = x0 + int(std::lround(cx * sx)), py = y0 + h - int(std::lround(cy * sy));
            if (footprint.shape == FootprintShape::box) {
                draw_outline(picture, px, py, footprint_outline(footprint, 1.0), sx, sy, false, clip);
                continue;
            }
            for (const auto& [radius, dashed] : {std::pair{1.0, false}, std::pair{3.25, true}})
                draw_outline(picture, px, py, footprint_outline(footprint, radius), sx, sy, dashed, clip);
        }
}

// The caption's words for a footprint: its size, and its shape when not an axis-aligned square or circle.
std::string footprint_caption(const Footprint& footprint) {
    const std::string turned =
        footprint.axis_radians != 0.0 ? " turned " + number(footprint.axis_radians * 180.0 / pi, 3) + " deg" : "";
    if (footprint.shape == FootprintShape::box)
        return ", box footprint " + number(box_width_um(footprint), 4) +
               (box_height_um(footprint) != box_width_um(footprint) ? " x " + number(box_height_um(footprint), 4) : "") +
               " um" + turned;
    if (is_elliptical(footprint))
        return ", footprint sigma_c " + number(footprint.sigma_um, 4) + " x " + number(footprint.sigma_minor_um, 4) +
               " um" + turned + " (dashed: 3.25 sigma)";
    return ", footprint sigma_c " + number(footprint.sigma_um, 4) + " um (dashed: 3.25 sigma_c)";
}

// The annotated height map: colour-mapped heights (longer side between min_side and max_side
// pixels), axes, scale bar, colour bar, the footprint if given, and a caption line.
OIIO::ImageBuf height_panel(const Heightfield& field, ColorMap map, const Footprint* footprint, int min_side, int max_side) {
    const ScalarImage shown = resize_for_display(
        at_true_aspect({field.rows, field.cols, field.heights_um}, field.width_um(), field.height_um()), min_side, max_side);
    double low = INFINITY, high = -INFINITY;
    for (float h : field.heights_um)
        if (!std::isnan(h)) low = std::min(low, double(h)), high = std::max(high, double(h));
    if (!(low <= high)) throw Error("the heightfield has no valid height");
    const int w = shown.cols, h = shown.rows;
    const int left = 70, top = 40;
    std::string caption = std::to_string(field.cols) + " x " + std::to_string(field.rows) + " samples, texel " +
                          number(field.dx_um(), 4) +
                          (field.square_texels() ? "" : " x " + number(field.dy_um(), 4) + " (x by y)") + " um";
    if (footprint) caption += footprint_caption(*footprint);
    OIIO::ImageBuf picture =
        blank(std::max(left + w + 2 * kMargin + kBarWidth + 80, left + text_width(caption) + kMargin), top + h + 70);
    const Colour grey{kMissingGrey, kMissingGrey, kMissingGrey};
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            const float v = shown.values[std::size_t(r) * w + c];
            Colour colour = grey;
            if (!std::isnan(v)) {
                const SrgbColor m = map_color(map, high > low ? (v - low) / (high - low) : 0.5);
                colour = {m.r, m.g, m.b};
            }
            picture.setpixel(left + c, top + r, colour.data(), 3);
        }
    draw_axes(picture, left, top, w, h, field.width_um(), field.height_um());
    draw_scale_bar(picture, left, top, w, h, field.width_um());
    // Rectangular texels: a bar along y too, so that each axis carries its own length.
    if (!field.square_texels()) draw_vertical_scale_bar(picture, left, top, h, field.height_um());
    if (footprint) draw_footprint(picture, left, top, w, h, field, *footprint);
    const int bar_x = left + w + 2 * kMargin;
    for (int y = 0; y < h; ++y) {
        const SrgbColor m = map_color(map, 1.0 - (y + 0.5) / h);
        const Colour c{m.r, m.g, m.b};
        for (int x = 0; x < kBarWidth; ++x) picture.setpixel(bar_x + x, top + y, c.data(), 3);
    }
    OIIO::ImageBufAlgo::render_box(picture, bar_x - 1, top - 1, bar_x + kBarWidth, top + h, kBlack);
    text(picture, bar_x + kBarWidth + 4, top - 2, number(high, 4));
    text(picture, bar_x + kBarWidth + 4, top + h - kFont - 2, number(low, 4));
    text(picture, bar_x - 4, top - 24, "height [um]");
    text(picture, left, top + h + 44, caption);
    return picture;
}

}  // namespace

void write_height_picture(const Heightfield& field, const std::string& path, ColorMap map, const Footprint* footprint) {
    if (file_extension(path) != "png") throw Error("cannot write '" + path + "': a PNG file name must end in .png");
    try {
        OIIO::ImageBuf picture = height_panel(field, map, footprint, 384, 768);
        write_png(picture, path, field.provenance);
    } catch (const Error& e) {
        throw Error("cannot write '" + path + "': " + e.what());
    }
}

int panel_size(int resolution) {
    const int zoom = std::max(1, (kMinPanel + resolution - 1) / resolution);
    return resolution * zoom;
}

PixelBox lobe_bounding_box(const std::vector<const LobeImage*>& images, double fraction) {
    PixelBox box{INT_MAX, INT_MAX, 0, 0};
    for (const LobeImage* image : images) {
        if (!image) continue;
        const int n = image->resolution;
        for (std::size_t layer = 0; layer < image->layers(); ++layer) {
            float peak = 0.0f;
            for (int row = 0; row < n; ++row)
                for (int col = 0; col < n; ++col)
                    if (inside_unit_disk(disk_pixel_point(row, col, n)) && std::isfinite(image->at(layer, row, col)))
                        peak = std::max(peak, image->at(layer, row, col));
            if (!(peak > 0.0f)) continue;
            for (int row = 0; row < n; ++row)
                for (int col = 0; col < n; ++col)
                    if (inside_unit_disk(disk_pixel_point(row, col, n)) && image->at(layer, row, col) >= fraction * peak) {
                        box.row0 = std::min(box.row0, row), box.row1 = std::max(box.row1, row + 1);
                        box.col0 = std::min(box.col0, col), box.col1 = std::max(box.col1, col + 1);
                    }
        }
    }
    return box.empty() ? PixelBox{} : box;
}

PixelBox zoom_square(const PixelBox& box, int resolution, double margin) {
    if (box.empty()) return {0, 0, resolution, resolution};
    const int extent = std::max(box.row1 - box.row0, box.col1 - box.col0);
    const int pad = std::max(2, int(std::ceil(margin * extent)));
    const int side = extent + 2 * pad;
    if (side >= resolution) return {0, 0, resolution, resolution};
    // The square about the box's centre, shifted back inside [0, N).
    const auto start = [&](int low, int high) { return std::clamp((low + high - side) / 2, 0, resolution - side); };
    const int row0 = start(box.row0, box.row1), col0 = start(box.col0, box.col1);
    return {row0, col0, row0 + side, col0 + side};
}

double log_display_value(double value, double white_level, double decades) {
    if (!(value > 0.0)) return 0.0;
    return std::clamp(1.0 + std::log10(value / white_level) / decades, 0.0, 1.0);
}

SrgbColor difference_colour(double value, double scale) {
    // Moreland 2009's cool-warm end points and its grey middle, in sRGB.
    constexpr Colour blue{0.230f, 0.299f, 0.754f}, middle{0.865f, 0.865f, 0.865f}, red{0.706f, 0.016f, 0.150f};
    const double t = value / scale;
    const float a = float(std::min(1.0, std::fabs(t)));
    const Colour& end = t < 0.0 ? blue : red;
    return {middle[0] + a * (end[0] - middle[0]), middle[1] + a * (end[1] - middle[1]), middle[2] + a * (end[2] - middle[2])};
}

DisplayExposure shared_exposure(const std::vector<const LobeImage*>& images, const ColourSettings& settings) {
    DisplayExposure brightest;
    bool first = true;
    for (const LobeImage* image : images) {
        if (!image) continue;
        const DisplayExposure exposure = exposure_of(*image, settings);
        if (first || exposure.white_level > brightest.white_level) brightest = exposure;
        first = false;
    }
    if (!settings.exposure_ev) brightest.rule = "shared: the brightest panel's " + brightest.rule.substr(brightest.rule.find(' ') + 1);
    return brightest;
}

DisplayPicture load_display_picture(const std::string& path) {
    DisplayPicture picture;
    const OIIO::ImageSpec spec = read_image_file(path, "picture", 3, picture.rgb);
    picture.width = spec.width;
    picture.height = spec.height;
    // Every "glintscope:" attribute, the output's own (exposure, wavelengths) included.
    for (const OIIO::ParamValue& attribute : spec.extra_attribs) {
        const std::string name = attribute.name().string();
        if (name.starts_with(attribute_prefix) && attribute.type() == OIIO::TypeDesc::STRING)
            picture.metadata[name.substr(attribute_prefix.size())] = attribute.get_string();
    }
    return picture;
}

int picture_zoom(int width, int height) {
    const int side = std::max(1, std::max(width, height));
    return std::max(1, kMinPanel / side);
}

void write_lobe_picture(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options) {
    if (file_extension(path) != "png") throw Error("cannot write '" + path + "': a PNG file name must end in .png");
    const DisplayExposure exposure = exposure_of(lobe, options.colour);
    OIIO::ImageBuf picture = panel(lobe, options, exposure, panel_caption(lobe));
    Provenance metadata = lobe.metadata;
    metadata["output.exposure_ev"] = shortest_text(exposure.ev);
    metadata["output.exposure_rule"] = exposure.rule;
    write_png(picture, path, metadata);
}

FigureLayout write_figure(const Figure& figure, const std::string& path, const LobeOutputOptions& options) {
    if (figure.cells.empty() || figure.cells.front().empty()) throw Error("cannot write '" + path + "': the figure has no panels");
    const std::size_t columns = figure.cells.front().size();
    if (!figure.pictures.empty() && figure.pictures.size() != figure.cells.size())
        throw Error("cannot write '" + path + "': the figure's pictures and lobes differ in rows");
    const auto picture_at = [&](std::size_t r, std::size_t c) -> const DisplayPicture* {
        return figure.pictures.empty() ? nullptr : figure.pictures[r][c];
    };
    int resolution = 0;
    bool any_picture = false;
    for (std::size_t r = 0; r < figure.cells.size(); ++r) {
        const auto& row = figure.cells[r];
        if (row.size() != columns || (!figure.pictures.empty() && figure.pictures[r].size() != columns))
            throw Error("cannot write '" + path + "': the figure's rows differ in length");
        for (std::size_t c = 0; c < columns; ++c) {
            const LobeImage* image = row[c];
            if (image && picture_at(r, c)) throw Error("cannot write '" + path + "': a cell holds both a lobe and a picture");
            any_picture = any_picture || picture_at(r, c);
            if (image) {
                if (resolution && image->resolution != resolution)
                    throw Error("cannot write '" + path + "': the panels differ in resolution");
                resolution = image->resolution;
            }
        }
    }
    if (!resolution && !any_picture) throw Error("cannot write '" + path + "': every cell of the figure is empty");
    if (figure.style == FigureStyle::paper && figure.exposure == SharedExposure::per_panel)
        throw Error("cannot write '" + path + "': a paper figure has one colour bar per row, which needs a shared exposure "
                    "(per row or for the whole figure), not one per panel");
    const PixelBox& view = figure.view;
    if (!view.empty() && (view.row1 - view.row0 != view.col1 - view.col0 || view.row0 < 0 || view.col0 < 0 ||
                          view.row1 > resolution || view.col1 > resolution))
        throw Error("cannot write '" + path + "': the zoomed view is not a square inside the image");

    // Exposures: per panel, per row, or one for the figure (each shared among panels of one quantity).
    std::vector<std::vector<DisplayExposure>> exposures(figure.cells.size(), std::vector<DisplayExposure>(columns));
    const auto share = [&](const std::vector<std::pair<std::size_t, std::size_t>>& members) {
        for (Quantity quantity : {Quantity::brdf, Quantity::ndf}) {
            std::vector<const LobeImage*> group;
            // Signed panels (differences) keep their own symmetric scale.
            const auto member = [&](std::size_t r, std::size_t c) {
                const LobeImage* image = figure.cells[r][c];
                return image && image->quantity == quantity && !is_signed(*image);
            };
            for (const auto& [r, c] : members)
                if (member(r, c)) group.push_back(figure.cells[r][c]);
            for (const auto& [r, c] : members)
                if (figure.cells[r][c] && is_signed(*figure.cells[r][c])) exposures[r][c] = signed_exposure(*figure.cells[r][c]);
            if (group.empty()) continue;
            const DisplayExposure exposure = shared_exposure(group, options.colour);
            for (const auto& [r, c] : members)
                if (member(r, c)) exposures[r][c] = exposure;
        }
    };
    std::vector<std::pair<std::size_t, std::size_t>> all;
    for (std::size_t r = 0; r < figure.cells.size(); ++r) {
        std::vector<std::pair<std::size_t, std::size_t>> row;
        for (std::size_t c = 0; c < columns; ++c) row.emplace_back(r, c);
        if (figure.exposure == SharedExposure::per_row) share(row);
        if (figure.exposure == SharedExposure::per_panel)
            for (const auto& cell : row) share({cell});
        all.insert(all.end(), row.begin(), row.end());
    }
    if (figure.exposure == SharedExposure::whole_figure) share(all);

    // Caption lines per cell; a paper figure states the lines every panel repeats once, in its caption.
    const bool paper = figure.style == FigureStyle::paper;
    const int font = paper ? 20 : kFont;
    std::vector<std::vector<std::vector<std::string>>> cell_lines(figure.cells.size(), std::vector<std::vector<std::string>>(columns));
    std::vector<std::vector<bool>> present(figure.cells.size(), std::vector<bool>(columns));
    for (std::size_t r = 0; r < figure.cells.size(); ++r)
        for (std::size_t c = 0; c < columns; ++c) {
            if (figure.cells[r][c]) cell_lines[r][c] = panel_caption(*figure.cells[r][c]);
            if (picture_at(r, c)) cell_lines[r][c] = picture_at(r, c)->caption;
            present[r][c] = figure.cells[r][c] || picture_at(r, c);
        }
    std::vector<std::string> common;
    if (paper) common = shared_lines(present, cell_lines);

    // Panels: each cell drawn with the caption lines its own (λ, angles, footprint).
    std::vector<std::vector<OIIO::ImageBuf>> panels(figure.cells.size());
    int cell_width = 0, cell_height = 0;
    for (std::size_t r = 0; r < figure.cells.size(); ++r)
        for (std::size_t c = 0; c < columns; ++c) {
            const LobeImage* image = figure.cells[r][c];
            // In a paper figure a difference keeps its own bar (its scale is its own); the others share the row's.
            const PanelStyle style{font, !paper || (image && is_signed(*image)), figure.view};
            panels[r].push_back(image              ? panel(*image, options, exposures[r][c], cell_lines[r][c], style)
                                : picture_at(r, c) ? picture_panel(*picture_at(r, c), cell_lines[r][c], font)
                                                   : blank(1, 1));
            cell_width = std::max(cell_width, panels[r].back().spec().width);
            cell_height = std::max(cell_height, panels[r].back().spec().height);
        }
    // A paper figure's row bar: the row's shared exposure, right of its panels.
    std::vector<const LobeImage*> row_bar(figure.cells.size(), nullptr);
    int row_bar_width = 0;
    if (paper)
        for (std::size_t r = 0; r < figure.cells.size(); ++r) {
            for (std::size_t c = 0; c < columns && !row_bar[r]; ++c) {
                const LobeImage* image = figure.cells[r][c];
                if (image && !is_signed(*image) && !spectral(*image)) row_bar[r] = image, row_bar_width = std::max(row_bar_width, bar_space(*image, exposures[r][c], font));
            }
        }
    // Heightfield insets: one more column on the left, each row's surface with its footprint.
    const bool insets = std::any_of(figure.insets.begin(), figure.insets.end(),
                                    [](const HeightInset& inset) { return inset.field != nullptr; });
    std::vector<OIIO::ImageBuf> inset_panels;
    int inset_width = 0;
    if (insets)
        for (const HeightInset& inset : figure.insets) {
            inset_panels.push_back(inset.field ? height_panel(*inset.field, ColorMap::viridis, &inset.footprint,
                                                              cell_height / 2, cell_height - 120)
                                               : blank(1, 1));
            inset_width = std::max(inset_width, inset_panels.back().spec().width);
        }
    int label_width = 0;
    for (const std::string& label : figure.row_labels) label_width = std::max(label_width, text_width(label, font) + 2 * kMargin);
    const int title_height = figure.title.empty() ? kMargin : font + 4 + 2 * kMargin;
    const int header_height = figure.column_labels.empty() ? 0 : font + 2 * kMargin;
    const std::string rule = figure.exposure == SharedExposure::per_panel ? "each panel exposed on its own"
                           : figure.exposure == SharedExposure::per_row   ? "one exposure per row"
                                                                          : "one exposure for the whole figure";
    bool differences = false;
    for (const auto& row : figure.cells)
        for (const LobeImage* image : row) differences = differences || (image && is_signed(*image));
    std::string rules = differences ? rule + ", differences each on their own scale symmetric about 0" : rule;
    const std::string picture_rule = "renders each at their own aspect and exposure (under each)";
    if (any_picture) rules = resolution ? rules + "; " + picture_rule : picture_rule;
    std::vector<std::string> caption = {figure.caption.empty() ? rules : figure.caption + "; " + rules};
    if (!figure.view_note.empty()) caption.push_back(figure.view_note);
    caption.insert(caption.end(), common.begin(), common.end());
    int caption_width = 0;
    for (const std::string& line : caption) caption_width = std::max(caption_width, 2 * kMargin + text_width(line, font));
    const int line_height = font + 5;
    const int width = std::max(label_width + inset_width + int(columns) * cell_width + row_bar_width, caption_width);
    const int height = title_height + header_height + int(figure.cells.size()) * cell_height +
                       int(caption.size()) * line_height + 2 * kMargin;
    OIIO::ImageBuf canvas = blank(width, height);
    text(canvas, width / 2, kMargin, figure.title, kBlack, OIIO::ImageBufAlgo::TextAlignX::Center, font + 4);
    if (insets)
        text(canvas, label_width + inset_width / 2, title_height + kMargin / 2, "heightfield and footprint", kBlack,
             OIIO::ImageBufAlgo::TextAlignX::Center, font);
    for (std::size_t c = 0; c < figure.column_labels.size() && c < columns; ++c)
        text(canvas, label_width + inset_width + int(c) * cell_width + cell_width / 2, title_height + kMargin / 2,
             figure.column_labels[c], kBlack, OIIO::ImageBufAlgo::TextAlignX::Center, font);
    FigureLayout layout{width, height, std::vector<std::vector<PixelSquare>>(figure.cells.size()),
                        std::vector<std::vector<PixelRect>>(figure.cells.size(), std::vector<PixelRect>(columns)),
                        whole_or(figure.view, resolution), {}, caption};
    const int size = resolution ? panel_size(resolution) : 0;
    for (std::size_t r = 0; r < figure.cells.size(); ++r) {
        const int y = title_height + header_height + int(r) * cell_height;
        if (r < figure.row_labels.size())
            text(canvas, kMargin, y + cell_height / 2 - font, figure.row_labels[r], kBlack, OIIO::ImageBufAlgo::TextAlignX::Left, font);
        if (r < inset_panels.size()) paste(canvas, inset_panels[r], label_width, y);
        for (std::size_t c = 0; c < columns; ++c) {
            const int x = label_width + inset_width + int(c) * cell_width;
            const LobeImage* image = figure.cells[r][c];
            if (image || picture_at(r, c)) paste(canvas, panels[r][c], x, y);
            layout.disks[r].push_back({x + kMargin, y + kMargin, size});  // panel(): the disk's place
            if (const DisplayPicture* picture = picture_at(r, c)) {  // picture_panel(): the picture's place
                const int zoom = picture_zoom(picture->width, picture->height);
                layout.pictures[r][c] = {x + kMargin, y + kMargin, picture->width * zoom, picture->height * zoom};
            }
            if (image && !spectral(*image) && (!paper || is_signed(*image)))
                layout.colour_bars.push_back({x + kMargin + size + kMargin, y + kMargin, kBarWidth, size});
        }
        if (row_bar[r]) {
            const std::size_t c = std::find(figure.cells[r].begin(), figure.cells[r].end(), row_bar[r]) - figure.cells[r].begin();
            layout.colour_bars.push_back(draw_colour_bar(canvas, label_width + inset_width + int(columns) * cell_width + kMargin,
                                                         y + kMargin, size, *row_bar[r], options, exposures[r][c], font));
        }
    }
    for (std::size_t k = 0; k < caption.size(); ++k)
        text(canvas, kMargin, height - kMargin - int(caption.size() - k) * line_height, caption[k], kBlack,
             OIIO::ImageBufAlgo::TextAlignX::Left, font);
    write_png(canvas, path);
    return layout;
}

namespace {

// The band's signed difference: the mean over wavelengths of test − reference, one layer, its
// caption without a λ (the not-applicable list) since it stands for the whole spectrum.
LobeImage band_mean_difference(const LobeImage& difference) {
    if (difference.layers() == 1) return difference;
    const double mean_lambda = std::accumulate(difference.wavelengths_um.begin(), difference.wavelengths_um.end(), 0.0) /
                               double(difference.layers());
    LobeImage mean = make_lobe_image(difference.resolution, {mean_lambda}, difference.quantity);
    const std::size_t pixels = std::size_t(difference.resolution) * difference.resolution;
    for (std::size_t layer = 0; layer < difference.layers(); ++layer)
        for (std::size_t i = 0; i < pixels; ++i)
            mean.values[i] += difference.values[layer * pixels + i] / float(difference.layers());
    mean.metadata = difference.metadata;
    const std::string ignored = metadata(difference, "not_applicable");
    mean.metadata["not_applicable"] = ignored.empty() ? "lambda" : ignored + ",lambda";
    return mean;
}

}  // namespace

FigureLayout write_difference_figure(const LobeImage& test, const LobeImage& reference, const DifferenceFigure& labels,
                                     const std::string& path, const LobeOutputOptions& options) {
    const LobeImage difference = band_mean_difference(difference_image(test, reference));
    Figure figure;
    figure.title = labels.title;
    figure.caption = labels.caption;
    figure.column_labels = {labels.test_label, labels.reference_label,
                            test.layers() == 1 ? labels.difference_label
                                               : labels.difference_label + " (mean over " +
                                                     std::to_string(test.layers()) + " wavelengths)"};
    figure.cells = {{&test, &reference, &difference}};
    figure.exposure = SharedExposure::per_row;  // test and reference alike; the difference on its own scale
    if (labels.zoom_fraction > 0.0) {
        figure.view = zoom_square(lobe_bounding_box({&test, &reference}, labels.zoom_fraction), test.resolution, 0.25);
        const PixelBox& v = figure.view;
        const DiskPoint top_left = disk_pixel_point(v.row0, v.col0, test.resolution);
        const DiskPoint bottom_right = disk_pixel_point(v.row1 - 1, v.col1 - 1, test.resolution);
        const double half_pixel = 1.0 / test.resolution;
        figure.view_note = v.row1 - v.row0 == test.resolution
                               ? "whole disk shown: the lobes reach " + number(labels.zoom_fraction) + " of their peaks near its edge"
                               : "zoomed to where either lobe exceeds " + number(labels.zoom_fraction) +
                                     " of its peak, with a margin: disk x " + number(top_left.x - half_pixel) + " to " +
                                     number(bottom_right.x + half_pixel) + ", y " + number(bottom_right.y - half_pixel) +
                                     " to " + number(top_left.y + half_pixel);
    }
    return write_figure(figure, path, options);
}

}  // namespace glintscope
