#pragma once
// A heightfield sampled from a function of position (x, y in µm at the sample positions of
// heightfield.hpp), for tests that know the surface in closed form.
#include <functional>

#include "glintscope/generate/generate.hpp"
#include "glintscope/surface/heightfield.hpp"

namespace glintscope::testing {

// The same with columns dx_um and rows dy_um apart (rectangular texels).
inline Heightfield sampled_field(int rows, int cols, double dx_um, double dy_um,
                                 const std::function<double(double, double)>& height) {
    Heightfield field = make_heightfield(rows, cols, dx_um);
    set_spacing(field, dx_um, dy_um);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            field.at(r, c) = static_cast<float>(height(s.x, s.y));
        }
    return field;
}

inline Heightfield sampled_field(int rows, int cols, double texel_um, const std::function<double(double, double)>& height) {
    return sampled_field(rows, cols, texel_um, texel_um, height);
}

// The isotropic builtin's recipe on a smaller square grid (1 µm texel, T = 10 µm, rms slope 0.17).
inline Heightfield isotropic_field(int size) {
    Recipe recipe = default_recipe("isotropic");
    recipe.grid.rows = recipe.grid.cols = size;
    return generate(recipe);
}

}  // namespace glintscope::testing
