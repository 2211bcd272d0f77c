#pragma once
// What every picture of output/ draws with (figure.cpp, plot.cpp): colours, DejaVu Sans text
// through OpenImageIO, round axis steps, pasting, and writing a PNG atomically with provenance.
#include <array>
#include <string>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "glintscope/output/lobe_output.hpp"

namespace glintscope::drawing {

using Colour = std::array<float, 3>;
constexpr Colour kWhite{1.0f, 1.0f, 1.0f};
constexpr Colour kBlack{0.0f, 0.0f, 0.0f};
constexpr int kFont = 14;
constexpr int kMargin = 8;

// The font's name for OIIO's render_text; throws Error naming the package when none is found.
const std::string& font();
int text_width(const std::string& text, int size = kFont);
// A white picture.
OIIO::ImageBuf blank(int width, int height);
// One line of text whose line box starts at y (left, centred or right at x): the tallest glyphs'
// top at y, so that lines of one size drawn at one y share a baseline whatever their letters.
void text(OIIO::ImageBuf& picture, int x, int y, const std::string& line, const Colour& colour = kBlack,
          OIIO::ImageBufAlgo::TextAlignX align = OIIO::ImageBufAlgo::TextAlignX::Left, int size = kFont);
// %g with `digits` significant digits.
std::string number(double value, int digits = 3);
// A round step for axis ticks and scale bars: 1, 2 or 5 × 10^k, about span/count.
double nice_step(double span, int count);
void paste(OIIO::ImageBuf& canvas, const OIIO::ImageBuf& picture, int x, int y);
// 8-bit PNG, atomically, with the "glintscope:" attributes of every output (query_keys.hpp).
void write_png(OIIO::ImageBuf& picture, const std::string& path, const Provenance& metadata = {});

}  // namespace glintscope::drawing
