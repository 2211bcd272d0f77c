// glintscope convert IN OUT [--flip-x] [--flip-y] [--rotate DEG] [--crop X0,Y0,W,H] [--fill]
// [--remove-form FORM] [--resample TEXEL]: prepares a measured heightfield and writes it in
// another format. The steps always run in the order orient, crop, fill, form removal, resample
// (see prepare.hpp for why; orienting first puts --crop in the frame the output shows); each
// prints one line and is recorded in the output's provenance.
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/prepare/prepare.hpp"
#include "glintscope/core/units.hpp"
#include "options.hpp"

namespace glintscope::cli {
namespace {

struct ConvertSettings {
    std::string input;
    std::string output;
    std::string crop;
    bool fill = false;
    std::string fill_method = "biharmonic";
    std::string form;
    double resample_texel_um = 0.0;
    Orientation orientation;
    std::string rotate = "0";
    LoadOptions load;
};

// "X0,Y0,W,H", four lengths with optional units.
CropRegion parse_crop(const std::string& text) {
    std::vector<std::string> parts;
    std::stringstream stream(text);
    for (std::string part; std::getline(stream, part, ',');) parts.push_back(part);
    if (parts.size() != 4 || text.back() == ',')
        throw Error("--crop: expected X0,Y0,W,H (four lengths, e.g. 10um,5um,100um,50um), got '" + text + "'");
    try {
        return {parse_length_um(parts[0]), parse_length_um(parts[1]), parse_length_um(parts[2]),
                parse_length_um(parts[3])};
    } catch (const Error& e) {
        throw Error(std::string("--crop: ") + e.what());
    }
}

int parse_form_option(const std::string& text) {
    try {
        return parse_form_order(text);
    } catch (const Error& e) {
        throw Error(std::string("--remove-form: ") + e.what());
    }
}

std::string summary(const std::string& verb, const std::string& path, const Heightfield& field) {
    char line[512];
    std::snprintf(line, sizeof line, "%s %s: %dx%d samples of %s (%s x %s), %zu missing", verb.c_str(), path.c_str(),
                  field.cols, field.rows, texel_text(field).c_str(),
                  format_length(field.width_um()).c_str(), format_length(field.height_um()).c_str(),
                  count_missing(field));
    return line;
}

void run_convert(const ConvertSettings& settings, bool resample_given) {
    // Every option is checked before the (possibly large) input is read.
    check_output_path(settings.output, {"exr", "x3p", "npy"}, "-o");
    const bool crop_given = !settings.crop.empty();
    const CropRegion region = crop_given ? parse_crop(settings.crop) : CropRegion{};
    const bool form_given = !settings.form.empty();
    const int form_order = form_given ? parse_form_option(settings.form) : 0;
    const FillMethod fill_method = parse_fill_method(settings.fill_method);
    Orientation orientation = settings.orientation;
    orientation.rotate_degrees = parse_rotation(settings.rotate);
    const bool orient_given = orientation.flip_x || orientation.flip_y || orientation.rotate_degrees != 0;
    const Tiling tiling = settings.load.periodic ? Tiling::periodic : Tiling::none;

    Heightfield field = load_heightfield_argument(settings.input, settings.load);
    // Printed only once everything succeeded, so that a failure is one line.
    std::vector<std::string> lines{summary("read", settings.input, field)};
    if (orient_given) lines.push_back("  " + describe(orient(field, orientation)));
    if (crop_given) lines.push_back("  " + describe(crop(field, region)));
    if (settings.fill) lines.push_back("  " + describe(fill_missing(field, fill_method, tiling)));
    if (form_given) lines.push_back("  " + describe(remove_form(field, form_order)));
    if (resample_given) lines.push_back("  " + describe(resample(field, settings.resample_texel_um, tiling)));
    save_heightfield(settings.output, field);
    lines.push_back(summary("wrote", settings.output, field));
    // NPY has no place for it (and a sidecar would be lost as soon as the file is copied alone).
    if (settings.output.ends_with(".npy"))
        lines.push_back(field.square_texels()
                            ? "  note: NPY stores no texel size or units: read it back with --texel " +
                                  shortest_text(field.texel_um) + "um (heights are in um)"
                            : "  note: NPY stores no texel size or units, and --texel gives square texels only: these "
                              "are " + texel_text(field) + "; write .x3p or .exr to keep them");
    for (const std::string& line : lines) std::printf("%s\n", line.c_str());
}

}  // namespace

void add_convert_command(CLI::App& app) {
    auto settings = std::make_shared<ConvertSettings>();
    CLI::App* command = app.add_subcommand(
        "convert",
        "Prepare a measured heightfield and write it (format from OUT's extension: .exr, .x3p, .npy). Steps run in "
        "this order, each only when asked: orient (flips, rotation), crop, fill, form removal, resample; each is printed and recorded in the "
        "output's provenance");
    command->add_option("input", settings->input, "Heightfield file (.x3p, .exr, .tif, .png, .npy) or builtin:KIND")
        ->required();
    command->add_option("output", settings->output, "Output file: .exr, .x3p or .npy")->required();
    command->add_flag("--flip-x", settings->orientation.flip_x,
                      "Mirror in x (columns reversed, x -> W - x); applied before --flip-y and --rotate");
    command->add_flag("--flip-y", settings->orientation.flip_y,
                      "Mirror in y (rows reversed, y -> H - y): shows an X3P the way Gwyddion does (see "
                      "docs/heightfields.md)");
    command
        ->add_option("--rotate", settings->rotate,
                     "Rotate counter-clockwise in map view by 90, 180 or 270 degrees, after the flips")
        ->check(CLI::IsMember({"0", "90", "180", "270"}))
        ->type_name("DEGREES")
        ->capture_default_str();
    command
        ->add_option("--crop", settings->crop,
                     "Keep the region X0,Y0,W,H: lower-left corner (X0, Y0) and size W x H in map view, measured "
                     "from the field's lower-left corner (x right, y up); lengths take units (10um,5um,100um,50um; "
                     "bare numbers are um); edges snap to the nearest texel boundary. Default: no crop")
        ->type_name("X0,Y0,W,H");
    auto* fill = command->add_flag("--fill", settings->fill,
                                   "Fill missing (NaN) points by smooth inpainting; valid points are kept exactly");
    command
        ->add_option("--fill-method", settings->fill_method,
                     "biharmonic: heights and slopes continue across each hole's rim; harmonic: a membrane that "
                     "never leaves the range of the rim heights")
        ->check(CLI::IsMember({"harmonic", "biharmonic"}))
        ->needs(fill)
        ->capture_default_str();
    command
        ->add_option("--remove-form", settings->form,
                     "Subtract the least-squares form of the valid points: mean, plane, or poly:N (N = 0..6, all "
                     "x^i y^j with i + j <= N). Default: none")
        ->type_name("FORM");
    auto* resample_option =
        add_length_option(*command, "--resample", settings->resample_texel_um,
                          "Resample to this texel size (0.5um, 500nm; bare numbers are um): bicubic when finer, box "
                          "average then bicubic when coarser; the extent changes by less than half a texel. "
                          "Default: keep the texel");
    add_load_options(*command, settings->load);
    command->callback([settings, resample_option] { run_convert(*settings, resample_option->count() > 0); });
}

}  // namespace glintscope::cli
