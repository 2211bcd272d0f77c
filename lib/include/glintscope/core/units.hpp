#pragma once
// Lengths are micrometres everywhere (conventions.md "Units"); this is the one place where
// user text with unit suffixes becomes µm.
#include <string>
#include <string_view>

namespace glintscope {

enum class LengthUnit { texel, um, nm, mm, m };

// "0.5um", "500nm", "2mm", "1e-6m", "0.5µm" or a bare number (µm). Throws Error on anything else,
// including NaN, infinities and trailing garbage.
double parse_length_um(std::string_view text);

// A box's sides along x and y: "70um" (a square) or "70x53um" (a unit written once, after the
// second side, applies to both). Throws Error naming the text.
struct BoxSides {
    double width_um = 0.0;
    double height_um = 0.0;
};
BoxSides parse_box_sides(std::string_view text);

// "texel", "um" (or "µm"), "nm", "mm", "m".
LengthUnit parse_length_unit(std::string_view text);
std::string to_string(LengthUnit unit);

// Micrometres per unit; LengthUnit::texel has no fixed size and throws.
double micrometres_per(LengthUnit unit);

// Formats a length in µm with a readable suffix, e.g. "0.5 um", "2.5 mm".
std::string format_length(double micrometres);

double degrees_to_radians(double degrees);

}  // namespace glintscope
