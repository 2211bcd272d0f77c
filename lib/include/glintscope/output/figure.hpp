#pragma once
// Pictures that describe themselves (PNG, display sRGB):
// - a lobe or NDF panel: the image with the unit-disk outline, θ rings at 30° and 60°, the
//   mirror direction of ω_i (BRDF) or the mean normal (NDF) marked, a caption (method, model,
//   Gabor's K, material; the surface and footprint centre or the number of footprints averaged;
//   λ or the spectral range where it applies, θ_i/φ_i, footprint size), a colour bar (one wavelength) or the
//   stated exposure (spectral), and a note when pixels clip;
// - a figure: a grid of such panels with a title, column and row labels and a caption line,
//   exposed alike per row or over the whole figure (stated in the caption); a cell may instead
//   hold a display picture (a render) drawn as it is, at its own aspect.
// Text is ASCII (this OpenImageIO garbles multi-byte UTF-8 in render_text), in DejaVu Sans.
#include <cstdint>
#include <string>
#include <vector>

#include "glintscope/output/colormap.hpp"
#include "glintscope/lobe/image.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/output/lobe_output.hpp"

namespace glintscope {

// A panel's caption lines, from the image's metadata (the pipeline writes it): the method, model
// (BRDF), Gabor's K and material; the surface and footprint centre (or the footprints averaged);
// λ where it applies (not for a geometric method without a material), θ_i/φ_i, the footprint's
// size; the legend of the guides.
std::vector<std::string> panel_caption(const LobeImage& lobe);

// The annotated panel of one image, written atomically.
void write_lobe_picture(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options);

enum class SharedExposure { per_panel, per_row, whole_figure };

// standard: each panel with its own colour bar and full caption, in 14 px type. paper: larger
// type, one colour bar per row (the row's shared exposure), and the caption lines every panel
// repeats (the guides' legend, a common method or wavelength) stated once in the figure caption.
enum class FigureStyle { standard, paper };

// A square of image pixels: rows [row0, row1), columns [col0, col1); {} is the whole image.
struct PixelBox {
    int row0 = 0;
    int col0 = 0;
    int row1 = 0;
    int col1 = 0;
    bool empty() const { return row1 <= row0 || col1 <= col0; }
};

// The smallest box holding every disk pixel where any of the images (any wavelength) reaches
// `fraction` of that image's (that wavelength's) peak; empty when every image is black.
PixelBox lobe_bounding_box(const std::vector<const LobeImage*>& images, double fraction);

// The box grown by `margin` times its larger side on every side (at least 2 pixels), made square
// about its centre and shifted to lie inside the N×N image (the whole image when it does not fit).
PixelBox zoom_square(const PixelBox& box, int resolution, double margin);

// Log display: value ↦ 1 + log10(value / white_level) / decades, clamped to [0, 1] (0 for value ≤ 0):
// white_level shows at the top of the colour bar, white_level·10^-decades at its bottom.
double log_display_value(double value, double white_level, double decades);

// The diverging colour (Moreland 2009's cool-warm map: blue, grey at 0, red) of a signed value
// on a scale symmetric about 0 whose ends are ±scale: positive values are red, negative blue.
SrgbColor difference_colour(double value, double scale);

// A row's heightfield drawn beside its panels, with the footprint of its queries.
struct HeightInset {
    const Heightfield* field = nullptr;  // nullptr: no inset for this row
    Footprint footprint;
};

// A picture shown as it is, at its own aspect (a render's display PNG, already exposed): 8-bit
// display RGB, row 0 at the top, with the caption lines to write under it.
struct DisplayPicture {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;  // [row][col][r, g, b]
    std::vector<std::string> caption;
    Provenance metadata;            // its "glintscope:" attributes
};

// A display PNG read back with its metadata (caption empty); throws Error naming the file.
DisplayPicture load_display_picture(const std::string& path);

// How many figure pixels (per side) a picture pixel takes: the largest whole factor that keeps the
// picture's longer side within the 320 pixels of the smallest lobe panel, at least 1.
int picture_zoom(int width, int height);

struct Figure {
    std::string title;
    std::string caption;                               // a line under the grid (the exposure rule is added)
    std::vector<std::string> column_labels;
    std::vector<std::string> row_labels;
    std::vector<std::vector<const LobeImage*>> cells;  // [row][column]; nullptr leaves a cell empty
    // [row][column] like cells, or empty: a picture where a cell holds no lobe, drawn at
    // picture_zoom with its caption and no colour bar (its exposure is its own, in its caption).
    std::vector<std::vector<const DisplayPicture*>> pictures;
    SharedExposure exposure = SharedExposure::per_row;
    std::vector<HeightInset> insets;                   // per row; empty: no inset column
    FigureStyle style = FigureStyle::standard;         // paper: needs a shared exposure (per row or whole)
    PixelBox view;                                     // the image pixels every panel shows (square); {}: all
    std::string view_note;                             // said in the caption when `view` zooms
};

// A heightfield in map view (+x right, +y up), colour-mapped, with a colour bar of heights in µm,
// axes in µm, a scale bar, and, when given, a footprint drawn on it: a Gaussian as its ellipse (a
// circle when isotropic) at σ_c and at 3.25σ_c (dashed, gabor's default truncation), a box as its
// rectangle, turned by its axis; wrapped across the periodic edges.
void write_height_picture(const Heightfield& field, const std::string& path, ColorMap map,
                          const Footprint* footprint = nullptr);

// The pixel size of a panel for an image of `resolution` (the same for every panel of a figure).
int panel_size(int resolution);

// A square of picture pixels: top-left corner (x right, y down) and side.
struct PixelSquare {
    int x = 0;
    int y = 0;
    int size = 0;
};

// Where a written figure put things: its size and, per cell [row][column], the square its image's
// disk fills (panel_size(resolution) pixels, image pixel (r, c) zoomed by size/resolution).
// A rectangle of picture pixels: top-left corner and size.
struct PixelRect {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
};

struct FigureLayout {
    int width = 0;
    int height = 0;
    std::vector<std::vector<PixelSquare>> disks;  // the square the view fills (image pixel (r, c) of
                                                  // the view at zoom size/(view side))
    std::vector<std::vector<PixelRect>> pictures; // per cell, the rectangle its picture fills ({} without one)
    PixelBox view;                                // the image pixels shown ({0, 0, N, N}: all)
    std::vector<PixelRect> colour_bars;           // every colour bar drawn
    std::vector<std::string> caption;             // the caption's lines, as written under the grid
};

// Writes the figure atomically; throws Error for an empty or ragged grid, mixed resolutions, or a
// cell given both a lobe and a picture.
FigureLayout write_figure(const Figure& figure, const std::string& path, const LobeOutputOptions& options);

// One row: test | reference | test − reference (compare.hpp: difference_image). The two inputs
// share one exposure; the difference (for a spectrum, its mean over the wavelengths, so labelled)
// is drawn on its own diverging scale, symmetric about 0, with a colour bar in the quantity's
// units. Throws Error for images compare_lobes refuses.
// With zoom_fraction > 0, all three panels show the same square: lobe_bounding_box of test and
// reference at that fraction of their peaks, grown by zoom_square's margin 0.25 (stated in the caption).
struct DifferenceFigure {
    std::string title;
    std::string caption;  // a line under the row
    std::string test_label;
    std::string reference_label;
    std::string difference_label;
    double zoom_fraction = 0.0;
};
FigureLayout write_difference_figure(const LobeImage& test, const LobeImage& reference, const DifferenceFigure& labels,
                                     const std::string& path, const LobeOutputOptions& options);

// The exposure a set of images shares: the auto (or given) exposure of the brightest.
DisplayExposure shared_exposure(const std::vector<const LobeImage*>& images, const ColourSettings& settings);

}  // namespace glintscope
