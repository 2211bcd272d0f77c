// The projected-disk map of conventions.md, written out literally and independently of the
// library's pixel helper, so that a sign error in that helper cannot pass every lobe test.
#include <gtest/gtest.h>

#include <cmath>

#include "glintscope/lobe/compare.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/output/lobe_output.hpp"

namespace glintscope {
namespace {

TEST(ProjectedDiskMap, PixelCentresFollowTheConventionsLiterally) {
    // N = 4: columns at x = -0.75, -0.25, 0.25, 0.75; row 0 at y = +0.75 (the largest y).
    const double xs[4] = {-0.75, -0.25, 0.25, 0.75};
    const double ys[4] = {0.75, 0.25, -0.25, -0.75};
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) {
            const DiskPoint p = disk_pixel_point(row, col, 4);
            EXPECT_DOUBLE_EQ(p.x, xs[col]);
            EXPECT_DOUBLE_EQ(p.y, ys[row]);
        }
    EXPECT_DOUBLE_EQ(disk_pixel_area(4), 0.25);
}

TEST(ProjectedDiskMap, SubpixelsSitOnARegularGridInsideThePixel) {
    // K = 2 in pixel (0, 0) of N = 2 (centre (-0.5, 0.5), side 1): sub-pixels at ±0.25.
    EXPECT_DOUBLE_EQ(disk_subpixel_point(0, 0, 0, 0, 2, 2).x, -0.75);
    EXPECT_DOUBLE_EQ(disk_subpixel_point(0, 0, 0, 0, 2, 2).y, 0.75);
    EXPECT_DOUBLE_EQ(disk_subpixel_point(0, 0, 1, 1, 2, 2).x, -0.25);
    EXPECT_DOUBLE_EQ(disk_subpixel_point(0, 0, 1, 1, 2, 2).y, 0.25);
}

TEST(ProjectedDiskMap, DirectionsAndTheRim) {
    const Vec3 d = direction_from_disk(0.6, 0.0);
    EXPECT_DOUBLE_EQ(d.z, 0.8);
    const Vec3 s = direction_from_spherical(std::acos(0.8), 0.5 * pi);  // φ = 90°: toward +y
    EXPECT_NEAR(s.x, 0.0, 1e-15);
    EXPECT_NEAR(s.y, 0.6, 1e-15);
    EXPECT_TRUE(inside_unit_disk({0.6, 0.79}));
    EXPECT_FALSE(inside_unit_disk({0.6, 0.8}));  // the rim is the horizon
    // The corner pixels of any image lie outside the disk.
    EXPECT_FALSE(inside_unit_disk(disk_pixel_point(0, 0, 16)));
}

// A plane rising toward −x has its normal leaning toward +x; at normal incidence it reflects
// toward +x, i.e. into the right half of the image (columns run along +x). Leaning toward +y
// sends light into the top half (row 0 is the largest y). Checked on the FFT lobe, with the
// expected pixel computed from the literal map above, not from the library's helper.
TEST(ProjectedDiskMap, ATiltedPlaneLightsThePixelOnTheSideItLeansTo) {
    const double slope = 0.2;  // |∂H/∂x| or |∂H/∂y|; normal (−H_x, −H_y, 1)
    for (const bool along_x : {true, false}) {
        Heightfield field = make_heightfield(64, 64, 1.0);
        for (int r = 0; r < 64; ++r)
            for (int c = 0; c < 64; ++c) {
                const Point2 s = sample_position(field, r, c);
                field.at(r, c) = float(-slope * (along_x ? s.x : s.y));
            }
        LobeQuery query;
        set_heightfield(query, field);
        // Away from the periodic seam (the ramp jumps there).
        query.footprint.centre_um = {32.0, 32.0};
        query.footprint.sigma_um = 4.0;
        query.resolution = 32;
        const LobeImage lobe = compute_lobe("fft", query);
        const WavelengthSummary peak = summarize_lobe(lobe).at(0);
        // Mirror of ω_i = n about the normal m = (s, 0, 1)/√(1 + s²): ω_o = 2(n·m)m − n.
        const double norm2 = 1.0 + slope * slope;
        const double lean = 2.0 * slope / norm2;  // the x (or y) component of ω_o
        // Literal map: x = (c + ½)/N·2 − 1 and y = 1 − (r + ½)/N·2, so the pixel holding a
        // point is c = ⌊(x + 1)N/2⌋, r = ⌊(1 − y)N/2⌋ (0.385 → column 22 of 32; y = 0.385 → row 9).
        if (along_x) {
            EXPECT_EQ(peak.peak_col, int(std::floor((lean + 1.0) / 2.0 * 32)));
            EXPECT_EQ(peak.peak_col, 22);
        } else {
            EXPECT_EQ(peak.peak_row, int(std::floor((1.0 - lean) / 2.0 * 32)));
            EXPECT_EQ(peak.peak_row, 9);
        }
    }
}

}  // namespace
}  // namespace glintscope
