// Format dispatch, unit resolution and the checks every reader shares.
#include "glintscope/io/heightfield_io.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <system_error>

#include "formats.hpp"
#include "glintscope/surface/square_texels.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope {
namespace {

// Missing, unreadable and empty files get the same message whatever their format.
void check_readable_file(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status)) throw read_error(path, "no such file");
    if (fs::is_directory(status)) throw read_error(path, "it is a directory");
    if (!fs::is_regular_file(status)) throw read_error(path, "not a regular file");
    const auto size = fs::file_size(path, ec);
    if (ec) throw read_error(path, ec.message());
    if (size == 0) throw read_error(path, "the file is empty");
}

// Extensions OpenImageIO reads: these never go to Gwyddion's library.
bool is_image_extension(const std::string& extension) {
    static const std::set<std::string> images = {"exr", "tif", "tiff", "png", "jpg", "jpeg", "hdr", "pfm", "pnm",
                                                 "pgm", "ppm", "bmp", "tga", "dpx", "webp", "jp2", "sgi", "rgb",
                                                 "psd", "iff", "gif", "heic", "avif"};
    return images.count(extension) > 0;
}

// Instrument and analysis formats only Gwyddion's library reads here (Gwyddion's own, Digital
// Surf, Sensofar, Zygo, Keyence, Nanofocus, Bruker/Veeco, Mitutoyo, ...): named so that a build
// without it says how to read them instead of an image library's puzzlement.
bool is_instrument_extension(const std::string& extension) {
    static const std::set<std::string> instruments = {"gwy", "sur", "pro", "plu", "plux", "apx", "datx", "opd",
                                                      "xyz", "zmg", "vk4", "vk6", "nms", "sdf", "spm", "mi",
                                                      "ibw", "nid", "lsm", "oir", "sxm", "mdt", "afm"};
    return instruments.count(extension) > 0;
}

Heightfield read_by_extension(const std::string& path, const LoadOptions& options) {
    const std::string extension = file_extension(path);
    if (extension == "npy") return read_npy(path, options);
    if (extension == "x3p") return read_x3p(path, options);
    if (is_image_extension(extension)) return read_image(path, options);
    if (reads_other_formats_through_gwyddion() || is_instrument_extension(extension)) return read_gwyddion(path, options);
    return read_image(path, options);
}

}  // namespace

Error read_error(const std::string& path, const std::string& problem) {
    return Error("cannot read '" + path + "': " + problem);
}

Error write_error(const std::string& path, const std::string& problem) {
    return Error("cannot write '" + path + "': " + problem);
}

void set_read_spacing(Heightfield& field, double dx_um, double stored_dx, double stored_dy, const std::string& path) {
    // The file's own dy exactly when dx is the file's; scaled with dx when the units were assumed.
    const double dy_um = dx_um == stored_dx ? stored_dy : dx_um * (stored_dy / stored_dx);
    const double aspect = std::max(dx_um, dy_um) / std::min(dx_um, dy_um);
    if (!(aspect <= kMaxTexelAspect))
        throw read_error(path, "the sample spacings " + format_length(dx_um) + " (x) and " + format_length(dy_um) +
                                   " (y) differ by more than " + shortest_text(kMaxTexelAspect) + " times");
    set_spacing(field, dx_um, dy_um);
}

void apply_spacing(Heightfield& field, const LoadOptions& options, double dx_um, const FileSpacing& file,
                   const std::string& path) {
    if (!options.texel_um) {
        if (file.dx && file.dy && std::fabs(*file.dy - *file.dx) > file.square_tolerance * *file.dx)
            set_read_spacing(field, dx_um, *file.dx, *file.dy, path);
        return;
    }
    const double declared_dx = *options.texel_um;
    const double declared_dy = options.texel_y_um.value_or(declared_dx);
    set_read_spacing(field, declared_dx, declared_dx, declared_dy, path);
    field.provenance["spacing.declared"] = texel_text(field);
    if (file.dx && file.in_um) {
        Heightfield stated;
        set_spacing(stated, *file.dx, file.dy.value_or(*file.dx));
        field.provenance["spacing.file"] = texel_text(stated);
    } else {
        field.provenance.erase("spacing.file");  // a copy's record of an earlier file
    }
}

void check_grid_size(long long cols, long long rows, const std::string& path) {
    const std::string size = std::to_string(cols) + " x " + std::to_string(rows);
    if (cols <= 0 || rows <= 0) throw read_error(path, "the grid is empty (" + size + " samples)");
    if (cols > (1LL << 31) || rows > (1LL << 31) ||
        static_cast<unsigned long long>(cols) * static_cast<unsigned long long>(rows) > kMaxSamples)
        throw read_error(path, "the grid of " + size + " samples exceeds the limit of 2^31 samples");
}

HeightConversion resolve_units(const StoredUnits& stored, const LoadOptions& options, const std::string& path) {
    if ((options.texel_um && !(*options.texel_um > 0.0 && std::isfinite(*options.texel_um))) ||
        (options.texel_y_um && !(*options.texel_y_um > 0.0 && std::isfinite(*options.texel_y_um))))
        throw read_error(path, "the texel size must be a positive length");
    if (options.texel_y_um && !options.texel_um) throw read_error(path, "a texel y spacing needs the x spacing too");
    if (!std::isfinite(options.height_scale) || options.height_scale == 0.0)
        throw read_error(path, "the height scale must be finite and non-zero");
    const std::optional<double> texel = options.texel_um ? options.texel_um : stored.texel_um;
    const std::optional<LengthUnit> unit = options.height_unit ? options.height_unit : stored.height_unit;
    if (texel && !(*texel > 0.0 && std::isfinite(*texel)))
        throw read_error(path, "the file's sample spacing is not a positive length");

    HeightConversion conversion;
    conversion.texel_um = texel.value_or(1.0);
    conversion.units_assumed = !texel || !unit;
    const LengthUnit height_unit = unit.value_or(LengthUnit::um);
    // Heights "in texels" (as in the heightfields published with Yan 2018) scale with dx.
    const double um_per_unit = height_unit == LengthUnit::texel ? conversion.texel_um : micrometres_per(height_unit);
    conversion.um_per_stored_unit = um_per_unit * options.height_scale;
    return conversion;
}

Heightfield load_heightfield(const std::string& path, const LoadOptions& options) {
    check_readable_file(path);
    Heightfield field = read_by_extension(path, options);
    validate(field, "cannot read '" + path + "'", /*allow_missing=*/true);
    // A file does not say whether it tiles; measured scans do not, so that is the default.
    field.periodic = options.periodic;
    return field;
}

void save_heightfield(const std::string& path, const Heightfield& field) {
    const std::string extension = file_extension(path);
    void (*writer)(const std::string&, const std::string&, const Heightfield&) = nullptr;
    if (extension == "exr")
        writer = write_exr;
    else if (extension == "x3p")
        writer = write_x3p;
    else if (extension == "npy")
        writer = write_npy;
    else
        throw write_error(path, (extension.empty() ? std::string("no file extension")
                                                   : "unsupported heightfield format '." + extension + "'") +
                                    " (use .exr, .x3p or .npy)");
    validate(field, "cannot write '" + path + "'", /*allow_missing=*/true);
    write_atomically(path, [&](const std::string& file) { writer(file, path, field); });
}

}  // namespace glintscope
