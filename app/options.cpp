#include "options.hpp"

#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope::cli {

CLI::Option* add_length_option(CLI::App& command, const std::string& name, double& target_um,
                               const std::string& description) {
    auto* option = command.add_option_function<std::string>(
        name,
        [&target_um, name](const std::string& text) {
            try {
                target_um = parse_length_um(text);
            } catch (const Error& e) {
                throw CLI::ValidationError(name, e.what());
            }
        },
        description);
    option->type_name("LENGTH");
    return option;
}

const CLI::Validator kNonNegative(
    [](std::string& text) -> std::string {
        double value = -1.0;
        try {
            value = parse_number(text);
        } catch (const Error&) {
        }
        return value >= 0.0 && std::isfinite(value) ? "" : "must be a number 0 or more, got '" + text + "'";
    },
    "NONNEGATIVE");

void add_load_options(CLI::App& command, LoadOptions& options) {
    command
        .add_option("--channel", options.channel,
                    "Image channel holding the heights, by name or index (default: Z, Y, R or the first channel)")
        ->type_name("NAME|INDEX");
    command
        .add_option_function<std::string>(
            "--height-unit",
            [&options](const std::string& text) {
                try {
                    options.height_unit = parse_length_unit(text);
                } catch (const Error& e) {
                    throw CLI::ValidationError("--height-unit", e.what());
                }
            },
            "Unit of the stored heights: um, nm, mm, m, or texel (multiples of the texel size, as in the "
            "heightfields of Yan et al. 2018). Default: the file's own unit (X3P: m, EXR from glintscope: um), "
            "else um")
        ->type_name("UNIT");
    command
        .add_option_function<std::string>(
            "--texel",
            [&options](const std::string& text) {
                try {
                    const BoxSides spacing = parse_box_sides(text);
                    if (!(spacing.width_um > 0.0) || !(spacing.height_um > 0.0))
                        throw Error("the texel size must be positive, got '" + text + "'");
                    options.texel_um = spacing.width_um;
                    options.texel_y_um.reset();
                    if (spacing.height_um != spacing.width_um) options.texel_y_um = spacing.height_um;
                } catch (const Error& e) {
                    throw CLI::ValidationError("--texel", e.what());
                }
            },
            "Declare the sample spacing, overriding the file's: 0.5um (square), 1x2um (dx by dy, rectangular), "
            "500nm, 2mm; a bare number is um. For files that state none (NPY, plain images) or state a wrong one; "
            "info and the provenance say it was declared. Default: the file's own spacing (X3P, EXR from "
            "glintscope, Gwyddion's formats), else 1 um")
        ->type_name("LENGTH[xLENGTH]");
    command.add_flag("--periodic", options.periodic,
                     "The file holds one tile of a periodic surface (e.g. written by generate): lobe footprints and "
                     "convert's fill and resample wrap around its borders. Default: a measured patch whose borders "
                     "are edges");
    command
        .add_option("--height-scale", options.height_scale,
                    "Multiply the heights by K after the unit conversion (e.g. -1 turns a replica's heights into the "
                    "surface's)")
        ->type_name("K")
        ->capture_default_str();
}

Heightfield load_heightfield_argument(const std::string& argument, const LoadOptions& options) {
    return load_heightfield_source({argument, options, ""});
}

}  // namespace glintscope::cli
