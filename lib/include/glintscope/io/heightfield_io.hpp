#pragma once
// Reading and writing heightfields. The format follows the file extension:
//   .exr .tif .tiff .png  images through OpenImageIO (one channel holds heights)
//   .npy                  NumPy arrays, float32/float64, C order, 2-D
//   .x3p                  ISO 25178-72 XML 3D surface profile (zip of main.xml + bindata/data.bin)
//   anything else         through Gwyddion's library when the build has it
// Files that carry no units (NPY, plain images) default to 1 µm texels and heights in µm, and
// the returned field has units_assumed = true. EXR files written here carry the texel size,
// units and provenance in their header, so they reload with units. Integer pixels are heights
// at their stored values (a 16-bit PNG holds 0..65535 in the height unit), never normalised.
// X3P's first data row is the smallest y, so it becomes the bottom row of the map view.
#include <optional>
#include <string>

#include "glintscope/surface/heightfield.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope {

struct LoadOptions {
    std::string channel;                     // image channel name or index; empty: Z, Y, R or the first
    std::optional<LengthUnit> height_unit;   // unit of the stored heights; texel = multiples of dx
    // A declared sample spacing, overriding the file's (or the 1 µm default of files that state
    // none): dx, and dy when it differs (rectangular texels). The field's provenance records that
    // the spacing was declared ("spacing.declared") and what the file states ("spacing.file").
    std::optional<double> texel_um;
    std::optional<double> texel_y_um;        // only with texel_um
    double height_scale = 1.0;               // multiplies heights after unit conversion
    bool periodic = false;                   // the file holds one tile of a periodic surface
};

// Whether this build reads the formats above and any other extension through Gwyddion's library
// (.gwy, .sur, Sensofar, Keyence, Zygo, ...; -DGLINTSCOPE_GWYDDION=ON, docs/dependencies.md).
bool reads_other_formats_through_gwyddion();

// Throws Error with a one-line message naming the file and the problem (missing, corrupt,
// truncated, empty, wrong channel, unsupported type, ...). Missing points load as NaN.
Heightfield load_heightfield(const std::string& path, const LoadOptions& options = {});

// Writes .exr (float heights, texel size, units, provenance in the header), .x3p (exact round
// trip) or .npy, atomically (see atomic_output.hpp). Throws Error for other extensions.
void save_heightfield(const std::string& path, const Heightfield& field);

}  // namespace glintscope
