// The coherence footprint: its box sides, its checks, its reach, and the sets of footprints a
// request averages over.
#include "glintscope/lobe/footprint.hpp"

#include <cmath>
#include <random>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope {

void set_box(Footprint& footprint, std::string_view text) {
    const BoxSides sides = parse_box_sides(text);
    if (!(sides.height_um > 0.0))
        throw Error("box footprint sides must be between 0 and 100 mm, got " + shortest_text(sides.height_um) + " um");
    footprint.shape = FootprintShape::box;
    footprint.size_um = sides.width_um;
    footprint.size_y_um = sides.height_um == sides.width_um ? 0.0 : sides.height_um;  // a square: 0
}

void validate(const Footprint& footprint) {
    // 1 m: far beyond any heightfield, while kernel and sample indices stay exact in double.
    constexpr double max_centre_um = 1e6;
    if (!(std::fabs(footprint.centre_um.x) <= max_centre_um && std::fabs(footprint.centre_um.y) <= max_centre_um))
        throw Error("footprint centre must be finite and within +-1e6 um (1 m), got (" +
                    shortest_text(footprint.centre_um.x) + ", " + shortest_text(footprint.centre_um.y) + ") um");
    if (footprint.shape == FootprintShape::gaussian && !(footprint.sigma_um > 0.0 && footprint.sigma_um <= 1e4))
        throw Error("coherence sigma must be between 0 and 10 mm, got " + shortest_text(footprint.sigma_um) + " um");
    if (!std::isfinite(footprint.axis_radians))
        throw Error("a footprint's axis must be a finite angle, got " + shortest_text(footprint.axis_radians));
    if (footprint.shape == FootprintShape::whole && footprint.axis_radians != 0.0)
        throw Error("the whole-field footprint has no axis to rotate");
    const bool elliptical_axis = footprint.shape == FootprintShape::gaussian && footprint.axis_radians != 0.0;
    if (footprint.sigma_minor_um != 0.0 || elliptical_axis) {
        if (footprint.shape != FootprintShape::gaussian) throw Error("only a Gaussian footprint can be elliptical (sigma_minor)");
        if (!(footprint.sigma_minor_um > 0.0 && footprint.sigma_minor_um <= footprint.sigma_um))
            throw Error("an elliptical footprint's minor sigma must be positive and at most sigma_c (" +
                        shortest_text(footprint.sigma_um) + " um), got " + shortest_text(footprint.sigma_minor_um) + " um");
    }
    if (footprint.shape == FootprintShape::box)
        for (const double side : {footprint.size_um, box_height_um(footprint)})
            if (!(side > 0.0 && side <= 1e5))
                throw Error("box footprint sides must be between 0 and 100 mm, got " + shortest_text(side) + " um");
}

Point2 footprint_support_um(const Footprint& footprint) {
    if (footprint.shape == FootprintShape::box) {  // the bounding rectangle of a rotated box
        const double c = std::fabs(std::cos(footprint.axis_radians)), s = std::fabs(std::sin(footprint.axis_radians));
        const double half_width = 0.5 * box_width_um(footprint), half_height = 0.5 * box_height_um(footprint);
        return {half_width * c + half_height * s, half_width * s + half_height * c};
    }
    // The Gaussian's 3.25σ_c truncation of the wave methods (weight e^{−5.3}, |w|² e^{−10.6}).
    return {3.25 * footprint.sigma_um, 3.25 * footprint.sigma_um};
}

FootprintSet parse_footprint_set(const std::string& text) {
    try {
        if (text == "grid") return {3, true};
        if (text.starts_with("grid:")) return {static_cast<int>(parse_integer(text.substr(5), 1, 316)), true};
        const int count = static_cast<int>(parse_integer(text, 1, 100000));
        return {count == 1 ? 0 : count, false};
    } catch (const Error& e) {
        throw Error("footprints must be N (1 to 100000 random centres), grid (3 x 3) or grid:N (N x N, N up to 316), got '" +
                    text + "'");
    }
}

std::string to_string(const FootprintSet& set) {
    if (set.single()) return "1";
    return set.grid ? "grid:" + std::to_string(set.count) : std::to_string(set.count);
}

std::vector<Point2> footprint_centres(const Heightfield& field, const Footprint& footprint, const FootprintSet& set) {
    if (set.single()) return {footprint.centre_um};
    const Point2 reach = footprint_support_um(footprint);
    const auto span = [](double size, double reach_um) {  // [lo, hi] of allowed centres along one axis
        return size > 2.0 * reach_um ? std::pair{reach_um, size - reach_um} : std::pair{0.0, size};
    };
    const auto [x0, x1] = span(field.width_um(), reach.x);
    const auto [y0, y1] = span(field.height_um(), reach.y);
    std::vector<Point2> centres;
    if (set.grid) {
        for (int j = 0; j < set.count; ++j)
            for (int i = 0; i < set.count; ++i)
                centres.push_back({x0 + (i + 0.5) / set.count * (x1 - x0), y0 + (j + 0.5) / set.count * (y1 - y0)});
        return centres;
    }
    std::mt19937_64 random(set.seed);  // the same seed gives the same centres on every platform
    const auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * (double(random() >> 11) * 0x1.0p-53); };
    for (int k = 0; k < set.count; ++k) {
        const double x = uniform(x0, x1);
        centres.push_back({x, uniform(y0, y1)});
    }
    return centres;
}

}  // namespace glintscope
