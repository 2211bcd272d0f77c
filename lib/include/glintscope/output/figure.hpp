#pragma once
// Pictures that describe themselves (PNG, display sRGB):
// - a lobe or NDF panel: the image with the unit-disk outline, θ rings at 30° and 60°, the
//   mirror direction of ω_i (BRDF) or the mean normal (NDF) marked, a caption (method, model,
//   Gabor's K, material; the surface and footprint centre or the number of footprints averaged;
//   λ or the spectral range where it applies, θ_i/φ_i, footprint size), a colour bar (one wavelength) or the
//   stated exposure (spectral), and a note when pixels clip;
// - a figure: a grid of such panels with a title, column and row labels and a caption line,
//   exposed alike per row or over the whole figure (stated in the caption).
// Text is ASCII (this OpenImageIO garbles multi-byte UTF-8 in render_text), in DejaVu Sans.
#include <string>
#include <vector>

#include "glintscope/output/colormap.hpp"
#include "glintscope/lobe/image.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/output/lobe_output.hpp"

namespace glintscope {

// The annotated panel of one image, written atomically.
void write_lobe_picture(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options);

enum class SharedExposure { per_panel, per_row, whole_figure };

// A row's heightfield drawn beside its panels, with the footprint of its queries.
struct HeightInset {
    const Heightfield* field = nullptr;  // nullptr: no inset for this row
    Footprint footprint;
};

struct Figure {
    std::string title;
    std::string caption;                               // a line under the grid (the exposure rule is added)
    std::vector<std::string> column_labels;
    std::vector<std::string> row_labels;
    std::vector<std::vector<const LobeImage*>> cells;  // [row][column]; nullptr leaves a cell empty
    SharedExposure exposure = SharedExposure::per_row;
    std::vector<HeightInset> insets;                   // per row; empty: no inset column
};

// A heightfield in map view (+x right, +y up), colour-mapped, with a colour bar of heights in µm,
// axes in µm, a scale bar, and, when given, a footprint drawn on it: a Gaussian as circles at σ_c
// and at its truncation 3.25σ_c (dashed), a box as its square; wrapped across the periodic edges.
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
struct FigureLayout {
    int width = 0;
    int height = 0;
    std::vector<std::vector<PixelSquare>> disks;
};

// Writes the figure atomically; throws Error for an empty or ragged grid or mixed resolutions.
FigureLayout write_figure(const Figure& figure, const std::string& path, const LobeOutputOptions& options);

// One row: test | reference | test − reference (compare.hpp: difference_image). The two inputs
// share one exposure; the difference (for a spectrum, its mean over the wavelengths, so labelled)
// is drawn on its own diverging scale, symmetric about 0, with a colour bar in the quantity's
// units. Throws Error for images compare_lobes refuses.
struct DifferenceFigure {
    std::string title;
    std::string caption;  // a line under the row
    std::string test_label;
    std::string reference_label;
    std::string difference_label;
};
FigureLayout write_difference_figure(const LobeImage& test, const LobeImage& reference, const DifferenceFigure& labels,
                                     const std::string& path, const LobeOutputOptions& options);

// The exposure a set of images shares: the auto (or given) exposure of the brightest.
DisplayExposure shared_exposure(const std::vector<const LobeImage*>& images, const ColourSettings& settings);

}  // namespace glintscope
