// Flips and quarter turns: exact round trips and where a sample goes.
#include <gtest/gtest.h>

#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/prepare/prepare.hpp"

namespace glintscope {
namespace {

// A 3x5 field whose heights name their sample: h(r, c) = 10 r + c.
Heightfield numbered_field() {
    Heightfield field = make_heightfield(3, 5, 0.5);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) field.at(r, c) = float(10 * r + c);
    return field;
}

TEST(Orient, FlippingTwiceIsTheIdentity) {
    for (Orientation flip : {Orientation{true, false, 0}, Orientation{false, true, 0}, Orientation{true, true, 0}}) {
        Heightfield field = numbered_field();
        orient(field, flip);
        EXPECT_NE(field.heights_um, numbered_field().heights_um);
        orient(field, flip);
        EXPECT_EQ(field.heights_um, numbered_field().heights_um);
    }
}

TEST(Orient, FourQuarterTurnsAreTheIdentityAndTwoAreBothFlips) {
    Heightfield field = numbered_field();
    for (int k = 0; k < 4; ++k) orient(field, {false, false, 90});
    EXPECT_EQ(field.rows, 3);
    EXPECT_EQ(field.heights_um, numbered_field().heights_um);
    Heightfield half_turn = numbered_field();
    orient(half_turn, {false, false, 180});
    Heightfield both_flips = numbered_field();
    orient(both_flips, {true, true, 0});
    EXPECT_EQ(half_turn.heights_um, both_flips.heights_um);
    Heightfield three = numbered_field();
    orient(three, {false, false, 270});
    orient(three, {false, false, 90});
    EXPECT_EQ(three.heights_um, numbered_field().heights_um);
}

TEST(Orient, QuarterTurnMapsSampleRCToColumnR) {
    // Sample (r, c) of the turned field is sample (c, cols − 1 − r) of the original, and its
    // map-view position is the original's rotated by 90 degrees about the origin, shifted by H.
    const Heightfield original = numbered_field();
    Heightfield turned = original;
    orient(turned, {false, false, 90});
    ASSERT_EQ(turned.rows, 5);
    ASSERT_EQ(turned.cols, 3);
    EXPECT_EQ(turned.texel_um, 0.5);
    for (int r = 0; r < turned.rows; ++r)
        for (int c = 0; c < turned.cols; ++c) {
            const int r0 = c, c0 = original.cols - 1 - r;
            ASSERT_EQ(turned.at(r, c), original.at(r0, c0));
            const Point2 before = sample_position(original, r0, c0);
            const Point2 after = sample_position(turned, r, c);
            EXPECT_DOUBLE_EQ(after.x, original.height_um() - before.y);
            EXPECT_DOUBLE_EQ(after.y, before.x);
        }
    EXPECT_EQ(turned.provenance.at("prepare.1"),
              "orient: 5x3 samples, rotated 90 degrees counter-clockwise in map view");
}

// Rectangular texels turn with the field: the rows' spacing becomes the columns'.
TEST(Orient, QuarterTurnSwapsRectangularSpacings) {
    Heightfield original = numbered_field();
    set_spacing(original, 0.5, 1.5);
    Heightfield turned = original;
    orient(turned, {false, false, 90});
    EXPECT_EQ(turned.dx_um(), 1.5);
    EXPECT_EQ(turned.dy_um(), 0.5);
    for (int r = 0; r < turned.rows; ++r)
        for (int c = 0; c < turned.cols; ++c) {
            const Point2 before = sample_position(original, c, original.cols - 1 - r);
            const Point2 after = sample_position(turned, r, c);
            EXPECT_DOUBLE_EQ(after.x, original.height_um() - before.y);
            EXPECT_DOUBLE_EQ(after.y, before.x);
        }
    orient(turned, {false, false, 270});
    EXPECT_EQ(turned.dx_um(), 0.5);
    EXPECT_EQ(turned.dy_um(), 1.5);
    EXPECT_EQ(turned.heights_um, original.heights_um);
}

TEST(Orient, OtherAnglesAreRefused) {
    Heightfield field = numbered_field();
    EXPECT_THROW(orient(field, {false, false, 45}), Error);
    EXPECT_THROW(parse_rotation("-90"), Error);
    EXPECT_EQ(parse_rotation("270"), 270);
}

}  // namespace
}  // namespace glintscope
