// Footprints on non-periodic heightfields: every method samples its interpolant periodically,
// so on a measured patch a footprint that crosses the border would mix in heights from the
// opposite edge. Such queries are refused with the range of centres that fit.
#include <algorithm>
#include <cmath>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

std::string um(double length) { return shortest_text(std::round(length * 1e4) / 1e4) + " um"; }

// The centres c with [c − reach, c + reach] inside [0, extent], as text.
std::string centre_range(double reach, double extent) { return um(reach) + " to " + um(extent - reach); }

}  // namespace

void check_footprint_inside(const LobeQuery& query) {
    const Heightfield& field = *query.field;
    const Footprint& footprint = query.footprint;
    if (field.periodic || footprint.shape == FootprintShape::whole) return;
    // The fft method can instead cut its window at the border (its option edge=truncate);
    // methods without that option refuse the option itself.
    const auto edge = query.method_options.find("edge");
    if (edge != query.method_options.end() && edge->second == "truncate") return;
    const Point2 reach = footprint_support_um(footprint);
    const double width = field.width_um(), height = field.height_um();
    const double slack = 1e-9 * std::max(width, height);  // rounding in a centre computed as W/2
    const std::string support =
        footprint.shape != FootprintShape::box ? "+-3.25 sigma_c = " + um(reach.x)
        : reach.x == reach.y                   ? "box half-side " + um(reach.x)
                                               : "box half-sides " + um(reach.x) + " x " + um(reach.y);
    const std::string field_text = "the non-periodic heightfield (" + um(width) + " x " + um(height) + ")";
    if (2.0 * reach.x > width + 2.0 * slack || 2.0 * reach.y > height + 2.0 * slack)
        throw Error("the footprint's support (" + support + ") is wider than " + field_text +
                    ": no centre fits; use a smaller footprint, or --periodic if the file tiles");
    const Point2 c = footprint.centre_um;
    if (c.x - reach.x < -slack || c.x + reach.x > width + slack || c.y - reach.y < -slack ||
        c.y + reach.y > height + slack)
        throw Error("footprint centre (" + um(c.x) + ", " + um(c.y) + ") with support " + support +
                    " crosses the edge of " + field_text + ": centres must lie in x " + centre_range(reach.x, width) +
                    ", y " + centre_range(reach.y, height) +
                    " (or --periodic if the file tiles, or fft's --edge truncate)");
}

}  // namespace glintscope
