#pragma once
// A heightfield sampled from a function of position (x, y in µm at the sample positions of
// heightfield.hpp), for tests that know the surface in closed form.
#include <functional>

#include "glintscope/surface/heightfield.hpp"

namespace glintscope::testing {

inline Heightfield sampled_field(int rows, int cols, double texel_um, const std::function<double(double, double)>& height) {
    Heightfield field = make_heightfield(rows, cols, texel_um);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            field.at(r, c) = static_cast<float>(height(s.x, s.y));
        }
    return field;
}

}  // namespace glintscope::testing
