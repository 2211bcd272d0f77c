#include "output/drawing.hpp"

#include <cmath>
#include <cstdio>

#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope::drawing {

const std::string& font() {
    static const std::string name = [] {
        for (const char* candidate : {"DejaVuSans", "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"})
            if (OIIO::ImageBufAlgo::text_size("0", kFont, candidate).defined()) return std::string(candidate);
        return std::string();
    }();
    if (name.empty()) throw Error("no font for picture text (install the fonts-dejavu-core package)");
    return name;
}

int text_width(const std::string& text, int size) {
    if (text.empty()) return 0;
    // A text without glyphs measures as an inverted box whose width() overflows an int: take the
    // extent in 64 bits and count only a real one.
    const OIIO::ROI box = OIIO::ImageBufAlgo::text_size(text, size, font());
    const long long width = static_cast<long long>(box.xend) - box.xbegin;
    return box.defined() && width > 0 && width < (1 << 24) ? static_cast<int>(width) : 0;
}

OIIO::ImageBuf blank(int width, int height) {
    OIIO::ImageBuf picture(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT));
    OIIO::ImageBufAlgo::fill(picture, kWhite);
    return picture;
}

void text(OIIO::ImageBuf& picture, int x, int y, const std::string& line, const Colour& colour,
          OIIO::ImageBufAlgo::TextAlignX align, int size) {
    if (line.empty()) return;
    // Every line of one size shares a baseline: its top at y would raise a line without
    // ascenders ("0.4 um") above its neighbours ("spectral, 8 bins").
    const OIIO::ROI tallest = OIIO::ImageBufAlgo::text_size("Hdl", size, font());
    const int baseline = tallest.defined() ? y - tallest.ybegin : y + size;
    if (!OIIO::ImageBufAlgo::render_text(picture, x, baseline, line, size, font(), colour, align,
                                         OIIO::ImageBufAlgo::TextAlignY::Baseline))
        throw Error("drawing text failed: " + picture.geterror());
}

std::string number(double value, int digits) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
    return buffer;
}

double nice_step(double span, int count) {
    const double raw = span / count;
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * power >= raw) return m * power;
    return 10.0 * power;
}

void paste(OIIO::ImageBuf& canvas, const OIIO::ImageBuf& picture, int x, int y) {
    if (!OIIO::ImageBufAlgo::paste(canvas, x, y, 0, 0, picture)) throw Error("composing the figure failed: " + canvas.geterror());
}

void write_png(OIIO::ImageBuf& picture, const std::string& path, const Provenance& metadata) {
    for (const auto& [key, value] : metadata) picture.specmod().attribute("glintscope:" + key, value);
    write_atomically(path, [&](const std::string& file) {
        if (!picture.write(file, OIIO::TypeDesc::UINT8, "png"))
            throw Error("cannot write '" + path + "': " + picture.geterror());
    });
}

}  // namespace glintscope::drawing
