// Figures: the zoom box of a lobe against its closed-form extent, the log and diverging colour
// scales, the pixels a zoomed difference figure draws, and the paper style's one colour bar per row.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <OpenImageIO/imageio.h>

#include "cli_runner.hpp"
#include "scoped_ocio.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/output/figure.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace glintscope {
namespace {

// exp(−(Δr²/2s_r² + Δc²/2s_c²)) about pixel (r0, c0), in every disk pixel of an n × n BRDF image.
LobeImage gaussian_lobe(int n, int r0, int c0, double s_r, double s_c, double peak = 1.0) {
    LobeImage lobe = make_lobe_image(n, {0.5});
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c)
            if (inside_unit_disk(disk_pixel_point(r, c, n)))
                lobe.at(0, r, c) = float(peak * std::exp(-0.5 * (std::pow((r - r0) / s_r, 2) + std::pow((c - c0) / s_c, 2))));
    lobe.metadata["method"] = "test";
    lobe.metadata["query.omega_i"] = "0,0,1";
    return lobe;
}

// Along one axis the Gaussian reaches fraction f of its peak out to s·sqrt(−2 ln f) pixels.
int reach(double s, double fraction) { return int(std::floor(s * std::sqrt(-2.0 * std::log(fraction)))); }

TEST(FigureZoom, TheBoundingBoxOfAGaussianLobeIsItsClosedFormExtent) {
    const double fraction = 0.01;
    const LobeImage lobe = gaussian_lobe(128, 50, 70, 4.0, 9.0);
    const PixelBox box = lobe_bounding_box({&lobe}, fraction);
    EXPECT_EQ(box.row0, 50 - reach(4.0, fraction));  // 12 pixels
    EXPECT_EQ(box.row1, 50 + reach(4.0, fraction) + 1);
    EXPECT_EQ(box.col0, 70 - reach(9.0, fraction));  // 27 pixels
    EXPECT_EQ(box.col1, 70 + reach(9.0, fraction) + 1);

    // Two lobes: the union of their boxes, each judged against its own peak.
    const LobeImage dim = gaussian_lobe(128, 90, 60, 3.0, 3.0, 1e-3);
    const PixelBox both = lobe_bounding_box({&lobe, &dim}, fraction);
    EXPECT_EQ(both.row0, box.row0);
    EXPECT_EQ(both.row1, 90 + reach(3.0, fraction) + 1);
    EXPECT_EQ(both.col0, box.col0);
    EXPECT_EQ(both.col1, box.col1);

    EXPECT_TRUE(lobe_bounding_box({}, fraction).empty());
}

TEST(FigureZoom, TheZoomSquareHoldsTheBoxWithItsMarginInsideTheImage) {
    const PixelBox box{38, 43, 63, 98};  // 25 × 55 pixels
    const PixelBox square = zoom_square(box, 128, 0.25);
    const int side = 55 + 2 * 14;  // the larger side and ⌈0.25 · 55⌉ on either side
    EXPECT_EQ(square.row1 - square.row0, side);
    EXPECT_EQ(square.col1 - square.col0, side);
    EXPECT_EQ(square.col0, 43 - 14);
    EXPECT_EQ(square.row0, (38 + 63 - side) / 2);  // centred on the box
    // Near an edge it shifts inside; too large, it is the whole image.
    EXPECT_EQ(zoom_square({0, 0, 10, 10}, 128, 0.25).row0, 0);
    EXPECT_EQ(zoom_square({118, 118, 128, 128}, 128, 0.25).row1, 128);
    const PixelBox whole = zoom_square({0, 0, 100, 100}, 128, 0.25);
    EXPECT_EQ(whole.row0, 0);
    EXPECT_EQ(whole.row1, 128);
}

TEST(FigureScales, TheLogScaleMapsThePeakToTheTopAndDecadesBelowToTheBottom) {
    const double peak = 37.5, decades = 4.0;
    EXPECT_DOUBLE_EQ(log_display_value(peak, peak, decades), 1.0);
    EXPECT_NEAR(log_display_value(peak * 1e-4, peak, decades), 0.0, 1e-12);
    EXPECT_NEAR(log_display_value(peak * 1e-2, peak, decades), 0.5, 1e-12);
    EXPECT_EQ(log_display_value(peak * 1e-6, peak, decades), 0.0);  // below the floor
    EXPECT_EQ(log_display_value(0.0, peak, decades), 0.0);
    EXPECT_EQ(log_display_value(10.0 * peak, peak, decades), 1.0);  // above white
}

TEST(FigureScales, APositiveDifferenceIsRedANegativeOneBlueAndZeroGrey) {
    const SrgbColor positive = difference_colour(0.3, 1.0), negative = difference_colour(-0.3, 1.0);
    const SrgbColor zero = difference_colour(0.0, 1.0);
    EXPECT_GT(positive.r, positive.b);
    EXPECT_GT(negative.b, negative.r);
    EXPECT_EQ(zero.r, zero.b);
    EXPECT_EQ(zero.r, zero.g);
    EXPECT_GT(difference_colour(1.0, 1.0).r - difference_colour(1.0, 1.0).b, positive.r - positive.b);  // saturates at the end
}

bool mentions(const std::vector<std::string>& lines, const std::string& text) {
    return std::any_of(lines.begin(), lines.end(), [&](const std::string& line) { return line.find(text) != std::string::npos; });
}

// Captions name what the panel shows and nothing that does not apply: the surface and footprint
// centre always, Gabor's model and K, and no wavelength for geometric optics without a material.
TEST(FigureCaption, APanelNamesItsSurfaceCentreAndModelAndOmitsWhatDoesNotApply) {
    testing::TemporaryDirectory directory;
    Heightfield field = make_heightfield(48, 48, 0.5);
    for (int r = 0; r < 48; ++r)
        for (int c = 0; c < 48; ++c) field.at(r, c) = float(0.05 * std::sin(0.5 * c + 0.3 * r));
    save_heightfield(directory.file("ripples.exr"), field);
    const QueryText text = {{"heightfield", directory.file("ripples.exr")}, {"res", "16"}, {"centre", "12,10"},
                            {"sigma_c", "3um"}, {"lambda", "0.5um"}, {"model", "kirchhoff"}, {"periodic", "yes"}};
    const std::vector<std::string> geometric = panel_caption(compute_lobe("geometric", make_query(text)));
    EXPECT_EQ(geometric.front(), "geometric");  // no model: geometric optics has none
    EXPECT_TRUE(mentions(geometric, "surface ripples.exr, centre 12, 10 um")) << join(geometric, " | ");
    EXPECT_FALSE(mentions(geometric, "lambda")) << join(geometric, " | ");
    EXPECT_TRUE(mentions(geometric, "sigma_c 3 um"));

    QueryText gabor_text = text;
    gabor_text.emplace_back("option.kernels_per_texel", "1");
    const std::vector<std::string> gabor = panel_caption(compute_lobe("gabor", make_query(gabor_text)));
    EXPECT_EQ(gabor.front(), "gabor, kirchhoff, K = 1, order 2");  // the default order, named
    EXPECT_TRUE(mentions(gabor, "surface ripples.exr, centre 12, 10 um")) << join(gabor, " | ");
    EXPECT_TRUE(mentions(gabor, "lambda 500 nm")) << join(gabor, " | ");

    // A material makes the wavelength matter to geometric optics too (through F).
    QueryText gold = text;
    gold.emplace_back("material", "Au");
    const std::vector<std::string> metal = panel_caption(compute_lobe("geometric", make_query(gold)));
    EXPECT_TRUE(mentions(metal, "lambda 500 nm")) << join(metal, " | ");
    EXPECT_TRUE(mentions(metal, "Au")) << join(metal, " | ");
}

class FigurePicture : public ::testing::Test {
protected:
    std::vector<unsigned char> read(const std::string& path, int& width) {
        auto input = OIIO::ImageInput::open(path);
        EXPECT_TRUE(input);
        const OIIO::ImageSpec& spec = input->spec();
        width = spec.width;
        std::vector<unsigned char> pixels(std::size_t(spec.width) * spec.height * 3);
        EXPECT_TRUE(input->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
        return pixels;
    }
    testing::ScopedOcio no_ocio{std::nullopt};
    testing::TemporaryDirectory directory;
};

// The picture colour at the centre of image pixel (r, c) of panel `panel` of a one-row figure.
const unsigned char* at(const std::vector<unsigned char>& pixels, int width, const FigureLayout& layout, int panel, int r,
                        int c) {
    const PixelSquare& disk = layout.disks[0][std::size_t(panel)];
    const double zoom = double(disk.size) / (layout.view.col1 - layout.view.col0);
    const int x = disk.x + int((c - layout.view.col0 + 0.5) * zoom), y = disk.y + int((r - layout.view.row0 + 0.5) * zoom);
    return &pixels[(std::size_t(y) * width + x) * 3];
}

TEST_F(FigurePicture, AZoomedLogDifferenceFigureShowsTheLobeBoxAndASignedDifference) {
    const int n = 128;
    const LobeImage test = gaussian_lobe(n, 50, 70, 3.0, 5.0, 2.0);
    const LobeImage reference = gaussian_lobe(n, 50, 72, 3.0, 5.0, 2.0);
    LobeOutputOptions options;
    options.colour.log_scale = true;
    options.colour.log_decades = 4.0;
    const std::string path = directory.file("pair.png");
    const FigureLayout layout =
        write_difference_figure(test, reference, {"t", "", "test", "reference", "difference", 1e-3}, path, options);
    // One square for all three panels: the box where either lobe exceeds 1e-3 of its peak, with its margin.
    const PixelBox expected = zoom_square(lobe_bounding_box({&test, &reference}, 1e-3), n, 0.25);
    EXPECT_EQ(layout.view.row0, expected.row0);
    EXPECT_EQ(layout.view.col0, expected.col0);
    EXPECT_EQ(layout.view.col1 - layout.view.col0, expected.col1 - expected.col0);
    EXPECT_LT(layout.view.col1 - layout.view.col0, n / 2);  // zoomed in
    ASSERT_EQ(layout.caption.size(), 2u);
    EXPECT_NE(layout.caption[1].find("zoomed to where either lobe exceeds 0.001 of its peak"), std::string::npos);

    int width = 0;
    const std::vector<unsigned char> pixels = read(path, width);
    // Log scale: the peak (2.0, the shared white) is inferno's top, 2·10^-2 its middle.
    const SrgbColor top = map_color(ColorMap::inferno, 1.0);
    const unsigned char* peak = at(pixels, width, layout, 0, 50, 70);
    EXPECT_NEAR(peak[0], 255 * top.r, 2);
    EXPECT_NEAR(peak[1], 255 * top.g, 2);
    // Where exp(−Δc²/50) = 10^-2 (Δc = 5·sqrt(2 ln 100) ≈ 15.2): the pixel 15 columns out, ≈ 0.49.
    const double t = log_display_value(std::exp(-0.5 * std::pow(15.0 / 5.0, 2)), 1.0, 4.0);
    const SrgbColor middle = map_color(ColorMap::inferno, t);
    const unsigned char* tail = at(pixels, width, layout, 0, 50, 85);
    EXPECT_NEAR(tail[0], 255 * middle.r, 3);
    EXPECT_NEAR(tail[2], 255 * middle.b, 3);
    // The difference: test > reference on the left of the peaks (red), below it on the right (blue).
    const unsigned char* left = at(pixels, width, layout, 2, 50, 66);
    const unsigned char* right = at(pixels, width, layout, 2, 50, 77);
    EXPECT_GT(left[0], left[2] + 60);
    EXPECT_GT(right[2], right[0] + 60);
    EXPECT_EQ(layout.colour_bars.size(), 3u);  // test and reference (alike), and the difference's own
}

TEST_F(FigurePicture, APaperFigureHasOneColourBarPerRowAndTheSharedLegendInItsCaption) {
    const LobeImage a = gaussian_lobe(32, 10, 12, 2.0, 2.0), b = gaussian_lobe(32, 16, 16, 3.0, 2.0, 0.5);
    Figure figure;
    figure.cells = {{&a, &b, &a}, {&b, &a, &b}};
    figure.row_labels = {"one", "two"};
    figure.column_labels = {"x", "y", "z"};
    figure.caption = "two rows";
    const FigureLayout standard = write_figure(figure, directory.file("standard.png"), {});
    EXPECT_EQ(standard.colour_bars.size(), 6u);  // one per panel
    figure.style = FigureStyle::paper;
    const FigureLayout paper = write_figure(figure, directory.file("paper.png"), {});
    ASSERT_EQ(paper.colour_bars.size(), 2u);
    // Each row's bar is right of its last panel, as tall as the disks, at the row's height.
    for (std::size_t r = 0; r < 2; ++r) {
        EXPECT_GT(paper.colour_bars[r].x, paper.disks[r][2].x + paper.disks[r][2].size);
        EXPECT_EQ(paper.colour_bars[r].y, paper.disks[r][0].y);
        EXPECT_EQ(paper.colour_bars[r].height, paper.disks[r][0].size);
    }
    const auto has = [](const std::vector<std::string>& lines, const std::string& text) {
        return std::find(lines.begin(), lines.end(), text) != lines.end();
    };
    EXPECT_TRUE(has(paper.caption, "rings: theta_o 30, 60 deg; cyan: mirror direction"));
    EXPECT_FALSE(has(standard.caption, "rings: theta_o 30, 60 deg; cyan: mirror direction"));
    EXPECT_EQ(paper.caption.front(), "two rows; one exposure per row");
    // A paper figure needs a shared exposure for its row bars.
    figure.exposure = SharedExposure::per_panel;
    EXPECT_THROW(write_figure(figure, directory.file("refused.png"), {}), Error);
}

}  // namespace
}  // namespace glintscope

namespace glintscope {
namespace {

// A render cell (a 16:9 picture) beside a square lobe: the picture fills a rectangle of its own
// aspect, zoomed by a whole factor, every pixel of it the picture's pixel, with the figure's white
// background right outside it; the lobe keeps its square disk.
// The footprint drawn on a height map has its own shape: an elliptical Gaussian's outline is
// σ_c / σ_minor times wider than tall (a circle would be as tall as wide), and a box turned by
// 90° is as wide as its height (W × H drawn axis-aligned would be W wide).
TEST_F(FigurePicture, AHeightMapDrawsAnEllipseAndATurnedBoxWithTheirOwnShapes) {
    Heightfield field = make_heightfield(400, 400, 1.0);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) field.heights_um[std::size_t(r) * field.cols + c] = 0.001f * float(c);
    // The bounding box of the footprint colour's pixels: its width over its height.
    const auto aspect = [&](const Footprint& footprint, const std::string& name) {
        const std::string path = directory.file(name);
        write_height_picture(field, path, ColorMap::viridis, &footprint);
        int width = 0;
        const std::vector<unsigned char> pixels = read(path, width);
        const int height = int(pixels.size() / 3 / std::size_t(width));
        int x0 = width, x1 = -1, y0 = height, y1 = -1;
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const unsigned char* p = &pixels[(std::size_t(y) * width + x) * 3];
                if (p[0] == 255 && std::abs(p[1] - 26) <= 1 && std::abs(p[2] - 140) <= 1)
                    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
            }
        EXPECT_GE(x1, x0) << name << ": no footprint drawn";
        return double(x1 - x0 + 1) / (y1 - y0 + 1);
    };
    Footprint ellipse;
    ellipse.centre_um = {200.0, 200.0};
    ellipse.sigma_um = 40.0;
    ellipse.sigma_minor_um = 10.0;  // the dashed outline at 3.25σ: 260 × 65 µm
    EXPECT_NEAR(aspect(ellipse, "ellipse.png"), 4.0, 0.25);
    ellipse.axis_radians = 0.5 * pi;  // the long axis along y
    EXPECT_NEAR(aspect(ellipse, "upright.png"), 0.25, 0.02);
    Footprint box;
    box.centre_um = {200.0, 200.0};
    box.shape = FootprintShape::box;
    box.size_um = 200.0;
    box.size_y_um = 60.0;
    box.axis_radians = 0.5 * pi;
    EXPECT_NEAR(aspect(box, "box.png"), 0.3, 0.03);
}

TEST(FigureCells, APictureIsDrawnAtItsAspectBesideASquareLobe) {
    testing::TemporaryDirectory directory;
    const LobeImage lobe = gaussian_lobe(16, 8, 8, 3.0, 3.0);
    DisplayPicture picture;
    picture.width = 32;
    picture.height = 18;
    picture.caption = {"render, 32x18"};
    for (int y = 0; y < picture.height; ++y)
        for (int x = 0; x < picture.width; ++x)
            for (int channel = 0; channel < 3; ++channel)
                picture.rgb.push_back(std::uint8_t((x * 7 + y * 13 + channel * 50) % 200));  // never white
    Figure figure;
    figure.column_labels = {"lobe", "render"};
    figure.row_labels = {"row"};
    figure.cells = {{&lobe, nullptr}};
    figure.pictures = {{nullptr, &picture}};
    const std::string path = directory.file("cells.png");
    const FigureLayout layout = write_figure(figure, path, {});
    const PixelRect rect = layout.pictures[0][1];
    EXPECT_EQ(picture_zoom(32, 18), 10);
    EXPECT_EQ(rect.width, 320);
    EXPECT_EQ(rect.height, 180);  // 16:9, as the picture
    EXPECT_EQ(layout.pictures[0][0].width, 0);
    EXPECT_EQ(layout.disks[0][0].size, 320);  // the lobe's square disk
    EXPECT_GT(rect.x, layout.disks[0][0].x + layout.disks[0][0].size);

    auto input = OIIO::ImageInput::open(path);
    ASSERT_TRUE(input);
    const int width = input->spec().width, height = input->spec().height;
    std::vector<std::uint8_t> pixels(std::size_t(width) * height * 3);
    ASSERT_TRUE(input->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, pixels.data()));
    const auto at = [&](int x, int y) { return &pixels[(std::size_t(y) * width + x) * 3]; };
    int mismatches = 0;
    for (int y = 0; y < rect.height; ++y)
        for (int x = 0; x < rect.width; ++x)
            for (int channel = 0; channel < 3; ++channel)
                mismatches += at(rect.x + x, rect.y + y)[channel] !=
                              picture.rgb[(std::size_t(y / 10) * picture.width + x / 10) * 3 + channel];
    EXPECT_EQ(mismatches, 0);
    for (int x = rect.x; x < rect.x + rect.width; ++x) {
        EXPECT_EQ(at(x, rect.y - 1)[0], 255) << x;                // white above
        EXPECT_EQ(at(x, rect.y + rect.height)[0], 255) << x;      // and below: exactly 180 rows
    }
    for (int y = rect.y; y < rect.y + rect.height; ++y) {
        EXPECT_EQ(at(rect.x - 1, y)[1], 255) << y;                // white left
        EXPECT_EQ(at(rect.x + rect.width, y)[1], 255) << y;       // and right: exactly 320 columns
    }
}

}  // namespace
}  // namespace glintscope
