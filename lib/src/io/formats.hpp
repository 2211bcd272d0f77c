#pragma once
// Internal interface between heightfield_io.cpp (dispatch, unit resolution, validation) and
// the per-format readers and writers (npy_format.cpp, x3p_format.cpp, image_format.cpp).
//
// A reader parses the file's metadata first, reports what units the file itself carries as
// StoredUnits, and converts the stored numbers to µm with the HeightConversion that
// resolve_units() builds from those and the user's LoadOptions. Converting in one step from
// the stored type (double for X3P "D") keeps float heights bit-exact through every round trip.
#include <cstddef>
#include <optional>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/surface/heightfield.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope {

// What the file says about its own units; empty when it says nothing.
struct StoredUnits {
    std::optional<double> texel_um;
    std::optional<LengthUnit> height_unit;
};

struct HeightConversion {
    double texel_um = 1.0;
    double um_per_stored_unit = 1.0;  // includes LoadOptions::height_scale
    bool units_assumed = false;

    float to_um(double stored) const { return static_cast<float>(stored * um_per_stored_unit); }
};

// Options override the file; whatever neither gives defaults to a 1 µm texel and µm heights
// (units_assumed = true). Throws Error naming `path` for a bad texel or height scale.
HeightConversion resolve_units(const StoredUnits& stored, const LoadOptions& options, const std::string& path);

// "cannot read '<path>': <problem>", the one shape of every load error.
Error read_error(const std::string& path, const std::string& problem);
Error write_error(const std::string& path, const std::string& problem);

// Largest grid any reader accepts before allocating (the limit of make_heightfield).
inline constexpr std::size_t kMaxSamples = std::size_t{1} << 31;

// Checks a grid size read from a file before anything is allocated for it.
void check_grid_size(long long cols, long long rows, const std::string& path);

// Gives a field read from `path` its spacings: dx_um (columns, as resolve_units chose it) and dy
// (rows) as the file states them, stored_dx × stored_dy (in its own length unit), scaled with dx
// when dx is not the file's own. Rectangular texels are kept, not resampled; spacings more than
// kMaxTexelAspect apart are refused naming `path`.
void set_read_spacing(Heightfield& field, double dx_um, double stored_dx, double stored_dy, const std::string& path);

// The spacing a reader gives its field, after its provenance is set: the declared one when
// LoadOptions::texel_um is given (recorded in the provenance, beside the file's own spacing where
// it states one in a known unit); else the file's, rectangular when its dy differs from its dx
// by more than square_tolerance of it (set_read_spacing).
struct FileSpacing {
    std::optional<double> dx, dy;  // as the file states them, in its own length unit
    double square_tolerance = 0.0;
    bool in_um = true;             // whether that unit is known (and dx, dy converted to µm)
};
void apply_spacing(Heightfield& field, const LoadOptions& options, double dx_um, const FileSpacing& file,
                   const std::string& path);

// Readers return heights in µm with the texel, provenance and units_assumed filled in; the
// caller validates the result.
Heightfield read_npy(const std::string& path, const LoadOptions& options);
Heightfield read_x3p(const std::string& path, const LoadOptions& options);
Heightfield read_image(const std::string& path, const LoadOptions& options);
// Through Gwyddion's library (gwyddion_format.cpp); without it in the build, throws a line
// saying how to build with it.
Heightfield read_gwyddion(const std::string& path, const LoadOptions& options);

// Writers write exactly to `file` (a temporary from write_atomically); `path` names the
// user's target in messages.
void write_npy(const std::string& file, const std::string& path, const Heightfield& field);
void write_x3p(const std::string& file, const std::string& path, const Heightfield& field);
void write_exr(const std::string& file, const std::string& path, const Heightfield& field);

}  // namespace glintscope
