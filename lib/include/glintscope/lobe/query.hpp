#pragma once
// One query describes a lobe or an NDF; every method answers it with the same image type
// (image.hpp). The pipeline (glintscope/pipeline/pipeline.hpp) plans and runs a query with a
// method; query_keys.hpp writes and reads queries as text.
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "glintscope/optics/diffraction_model.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/surface/heightfield.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/lobe/image.hpp"
#include "glintscope/surface/interpolant.hpp"
#include "glintscope/lobe/footprint.hpp"
#include "glintscope/lobe/method_info.hpp"

namespace glintscope {

// A material's Fresnel reflectance F(λ, cos θ); empty name means F = 1.
struct MaterialChoice {
    std::string name;
};

// Where the heightfield came from (a file with its load options, or builtin:KIND), so that any
// output can be re-run from its metadata.
struct HeightfieldSource {
    std::string argument;
    LoadOptions load;
    std::string content_md5;  // of the file's bytes, filled by make_query (empty for builtins)
};

// LobeQuery::supersample for a method that integrates each pixel exactly (the geometric lobe over
// its tabulated NDF) instead of averaging K×K point samples.
constexpr int kExactPixels = -1;

struct LobeQuery {
    std::shared_ptr<const Heightfield> field;
    std::shared_ptr<const BicubicInterpolant> surface;  // of `field`; built by set_heightfield
    HeightfieldSource source;
    Quantity quantity = Quantity::brdf;   // brdf: pixel = ω_o; ndf: pixel = h
    Footprint footprint;
    FootprintSet footprints;              // averaged over by the pipeline; default the footprint alone
    Vec3 omega_i{0.0, 0.0, 1.0};          // toward the light, unit length, z > 0
    std::vector<double> wavelengths_um{0.5};
    DiffractionModel model = DiffractionModel::rohs;
    MaterialChoice material;
    int resolution = 256;                 // N of the N×N projected-disk image
    int supersample = 0;                  // K×K sub-pixel average (geometry.hpp); 0: the pipeline chooses;
                                          // kExactPixels: pixels integrated exactly (MethodInfo::exact_pixels)
    double memory_budget_gb = 4.0;        // for a method's working grids (the FFT's footprint grid)
    // Method-specific settings by name (e.g. "kernels_per_texel" for gabor, "step" for fft);
    // compute_lobe rejects keys the method does not declare.
    std::map<std::string, std::string> method_options;
};

// Builds the shared interpolant for a field and fills query.field / query.surface.
void set_heightfield(LobeQuery& query, Heightfield field);

// Checks a query (directions, wavelengths, footprint, resolution, material, ...) and throws
// Error with a one-line message naming the bad parameter.
void validate(const LobeQuery& query);

// On a non-periodic field (Heightfield::periodic false) a footprint whose support crosses the
// border is refused with one line giving the valid range of centres; periodic fields and the
// whole-field footprint always pass, and so does a query with method option edge=truncate (the
// fft method then cuts its window at the border; other methods refuse the option). compute_lobe
// calls it for every method that reads the footprint.
void check_footprint_inside(const LobeQuery& query);

}  // namespace glintscope
