#pragma once
// Perceptual colour maps and colour-mapped PNG pictures with a legend, for heightfield
// previews and lobe images alike.
#include <string>
#include <string_view>
#include <vector>

namespace glintscope {

// Matplotlib's perceptually uniform maps (van der Walt & Smith 2015), dark to bright, as
// OpenImageIO provides them (ImageBufAlgo::color_map).
enum class ColorMap { viridis, inferno };

// "viridis" or "inferno"; throws Error naming the choices otherwise.
ColorMap parse_colormap(std::string_view name);
std::string to_string(ColorMap map);

// Display-referred sRGB components in [0, 1], as published with the maps.
struct SrgbColor {
    float r = 0.0f;
    float g = 0.0f;
    float b = 0.0f;
};

// The colour at t in [0, 1] (clamped), linearly interpolated between tabulated entries.
SrgbColor map_color(ColorMap map, double t);

// A scalar picture: rows × cols values, row-major, row 0 at the top (map view). NaN means "no
// data" and is drawn in neutral grey.
struct ScalarImage {
    int rows = 0;
    int cols = 0;
    std::vector<float> values;
};

struct ColorLegend {
    double min_value = 0.0;  // drawn with the map's first colour
    double max_value = 1.0;  // drawn with its last colour; values outside the range are clamped
    std::string label;       // the quantity and its unit, e.g. "height [um]"
    ColorMap map = ColorMap::viridis;
};

// The grey of missing values (sRGB), distinct from every viridis and inferno colour.
inline constexpr float kMissingGrey = 0.5f;

// An image rescaled by an integer factor so that its long side is at least `min_side` (enlarged
// by nearest neighbour, each sample a sharp square) and at most `max_side` (reduced, each pixel
// the mean of the valid values of its block). NaN stays NaN where a block has no valid value.
ScalarImage resize_for_display(const ScalarImage& image, int min_side, int max_side);

// The image with its shorter-in-µm axis repeated (nearest neighbour) so that its pixels are
// square in µm: a field of rectangular texels, `width_um` × `height_um` in all, drawn at its true
// aspect. Returns the image itself when its pixels already have that aspect.
ScalarImage at_true_aspect(const ScalarImage& image, double width_um, double height_um);

// Writes an 8-bit sRGB PNG, atomically: the image colour-mapped, a colour bar beside it with
// the min and max values written at its ends, and the label above. Images smaller than 256
// pixels on their long side are enlarged by an integer factor (nearest neighbour, so each
// sample stays a sharp square); images longer than 4096 pixels are reduced by an integer
// factor, each pixel the mean of the valid values of its block. Throws Error for a path that
// does not end in .png, an empty or mis-sized image, or a non-finite or reversed value range.
void write_colormapped_png(const std::string& path, const ScalarImage& image, const ColorLegend& legend);

}  // namespace glintscope
