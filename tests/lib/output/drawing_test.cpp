// Text in pictures: lines drawn at one y share a baseline, whatever their letters.
#include "output/drawing.hpp"

#include <gtest/gtest.h>

#include <string>

namespace glintscope::drawing {
namespace {

// The lowest row holding ink (a channel below 0.5) in columns [x0, x1), or -1.
int lowest_ink_row(const OIIO::ImageBuf& picture, int x0, int x1) {
    const OIIO::ImageSpec& spec = picture.spec();
    float pixel[3];
    for (int y = spec.height - 1; y >= 0; --y)
        for (int x = x0; x < x1; ++x) {
            picture.getpixel(x, y, pixel, 3);
            if (pixel[0] < 0.5f) return y;
        }
    return -1;
}

// "0.4 um" has no ascender and "Hl" no descender: both end on the baseline. Drawn by their tops,
// the line without ascenders sat higher (the figure's column labels "spectral, 8 bins" | "0.4 um").
TEST(Drawing, LinesAtOneHeightShareABaseline) {
    for (const int size : {14, 18}) {
        OIIO::ImageBuf picture = blank(400, 60);
        text(picture, 10, 10, "0.4 um", kBlack, OIIO::ImageBufAlgo::TextAlignX::Left, size);
        text(picture, 210, 10, "Hl", kBlack, OIIO::ImageBufAlgo::TextAlignX::Left, size);
        const int digits = lowest_ink_row(picture, 0, 200), letters = lowest_ink_row(picture, 200, 400);
        ASSERT_GT(digits, 10);
        EXPECT_EQ(digits, letters) << "size " << size;
    }
}

}  // namespace
}  // namespace glintscope::drawing
