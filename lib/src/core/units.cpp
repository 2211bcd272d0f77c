#include "glintscope/core/geometry.hpp"
#include "glintscope/core/units.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <vector>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {

LengthUnit parse_length_unit(std::string_view text) {
    text = trim(text);
    if (text == "texel") return LengthUnit::texel;
    if (text == "um" || text == "µm" || text == "micron") return LengthUnit::um;
    if (text == "nm") return LengthUnit::nm;
    if (text == "mm") return LengthUnit::mm;
    if (text == "m") return LengthUnit::m;
    throw Error("unknown length unit '" + std::string(text) + "' (expected texel, um, nm, mm or m)");
}

std::string to_string(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::texel: return "texel";
        case LengthUnit::um: return "um";
        case LengthUnit::nm: return "nm";
        case LengthUnit::mm: return "mm";
        case LengthUnit::m: return "m";
    }
    return "um";
}

double micrometres_per(LengthUnit unit) {
    switch (unit) {
        case LengthUnit::um: return 1.0;
        case LengthUnit::nm: return 1e-3;
        case LengthUnit::mm: return 1e3;
        case LengthUnit::m: return 1e6;
        case LengthUnit::texel: break;
    }
    throw Error("a texel has no fixed length; give the texel size");
}

double parse_length_um(std::string_view text) {
    const std::string_view trimmed = trim(text);
    double value = 0.0;
    const char* first = trimmed.data();
    const char* last = trimmed.data() + trimmed.size();
    if (!trimmed.empty() && *first == '+') ++first;
    const auto [end, ec] = std::from_chars(first, last, value);
    if (ec != std::errc() || end == first)
        throw Error("'" + std::string(text) + "' is not a length (examples: 0.5um, 500nm, 2mm, 10)");
    if (!std::isfinite(value)) throw Error("length '" + std::string(text) + "' is not finite");
    const std::string_view suffix = trim(std::string_view(end, static_cast<std::size_t>(last - end)));
    if (suffix.empty()) return value;
    if (suffix == "cm") return value * 1e4;  // scene sizes (a 5cm patch); no unit of stored heights
    LengthUnit unit;
    try {
        unit = parse_length_unit(suffix);
    } catch (const Error&) {
        throw Error("'" + std::string(text) + "' has an unknown unit suffix '" + std::string(suffix) +
                    "' (use um, nm, mm, cm or m)");
    }
    if (unit == LengthUnit::texel)
        throw Error("'" + std::string(text) + "': a length here must be in um, nm, mm or m");
    return value * micrometres_per(unit);
}

BoxSides parse_box_sides(std::string_view text) {
    const std::vector<std::string> parts = split(text, 'x');
    if (parts.size() == 1) {
        const double side = parse_length_um(text);
        return {side, side};
    }
    if (parts.size() != 2)
        throw Error("'" + std::string(text) + "' is not a box side LENGTH or sides WIDTHxHEIGHT (e.g. 70x53um)");
    std::string width = parts[0];
    const std::string& height = parts[1];
    const std::size_t unit = height.find_last_of("0123456789.") + 1;
    if (!width.empty() && (std::isdigit(static_cast<unsigned char>(width.back())) || width.back() == '.'))
        width += height.substr(std::min(unit, height.size()));
    return {parse_length_um(width), parse_length_um(height)};
}

std::string format_length(double micrometres) {
    char buffer[64];
    const double magnitude = std::fabs(micrometres);
    if (magnitude != 0.0 && magnitude < 1.0)
        std::snprintf(buffer, sizeof buffer, "%.6g nm", micrometres * 1e3);
    else if (magnitude >= 1e3)
        std::snprintf(buffer, sizeof buffer, "%.6g mm", micrometres * 1e-3);
    else
        std::snprintf(buffer, sizeof buffer, "%.6g um", micrometres);
    return buffer;
}

double degrees_to_radians(double degrees) { return degrees * pi / 180.0; }

}  // namespace glintscope
