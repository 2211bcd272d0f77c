#pragma once
// One query describes a lobe or an NDF; every method (fft, gabor, and the geometric and other
// methods that follow) answers it with the same image type (image.hpp). Methods are listed once
// in the method table (lib/src/lobe/method_table.cpp); compute_lobe is the single place that
// finds, checks, runs and labels them. Queries are written and read as text by query_keys.hpp.
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "glintscope/diffraction_model.hpp"
#include "glintscope/geometry.hpp"
#include "glintscope/heightfield.hpp"
#include "glintscope/heightfield_io.hpp"
#include "glintscope/image.hpp"
#include "glintscope/interpolant.hpp"

namespace glintscope {

// whole: every point of one period of the field weighs the same (Dong-style large-area NDFs;
// geometric methods only, MethodInfo::whole_field).
enum class FootprintShape { gaussian, box, whole };

// The coherence footprint (conventions.md "Coherence / footprint"): a Gaussian
// w(s) = exp(−|s − x_c|²/(2σ_c²)), A_c = πσ_c², or a box of sides `size_um` along x and
// `size_y_um` along y (Dong 2015's 70 × 53 µm patches; 0: a square), A_c its area. Geometric
// methods weigh the surface by |w|²/A_c: a normalised Gaussian of standard deviation σ_c/√2, or
// the box.
struct Footprint {
    Point2 centre_um;
    double sigma_um = 10.0;
    FootprintShape shape = FootprintShape::gaussian;
    double size_um = 0.0;    // box side along x (box only)
    double size_y_um = 0.0;  // box side along y (box only); 0: size_um
};

inline double box_width_um(const Footprint& footprint) { return footprint.size_um; }
inline double box_height_um(const Footprint& footprint) {
    return footprint.size_y_um > 0.0 ? footprint.size_y_um : footprint.size_um;
}

// Makes the footprint a box of sides "70um" or "70x53um" (parse_box_sides); throws Error on a
// zero side, which validate(Footprint) would otherwise read as a square.
void set_box(Footprint& footprint, std::string_view sides);

// Checks a footprint's centre, σ_c and box sides and throws Error naming the bad one (part of
// validate(LobeQuery); also for commands that only draw a footprint).
void validate(const Footprint& footprint);

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

struct LobeQuery {
    std::shared_ptr<const Heightfield> field;
    std::shared_ptr<const BicubicInterpolant> surface;  // of `field`; built by set_heightfield
    HeightfieldSource source;
    Quantity quantity = Quantity::brdf;   // brdf: pixel = ω_o; ndf: pixel = h
    Footprint footprint;
    Vec3 omega_i{0.0, 0.0, 1.0};          // toward the light, unit length, z > 0
    std::vector<double> wavelengths_um{0.5};
    DiffractionModel model = DiffractionModel::rohs;
    MaterialChoice material;
    int resolution = 256;                 // N of the N×N projected-disk image
    int supersample = 1;                  // K×K sub-pixel average (geometry.hpp)
    // Method-specific settings by name (e.g. "kernels_per_texel" for gabor, "step" for fft);
    // compute_lobe rejects keys the method does not declare.
    std::map<std::string, std::string> method_options;
};

// Builds the shared interpolant for a field and fills query.field / query.surface.
void set_heightfield(LobeQuery& query, Heightfield field);

// Checks a query (directions, wavelengths, footprint, resolution, material, ...) and throws
// Error with a one-line message naming the bad parameter.
void validate(const LobeQuery& query);

// How far a footprint reaches from its centre along x and y: 3.25σ_c for a Gaussian (the wave
// methods' truncation), half the sides for a box.
Point2 footprint_support_um(const Footprint& footprint);

// On a non-periodic field (Heightfield::periodic false) a footprint whose support crosses the
// border is refused with one line giving the valid range of centres; periodic fields and the
// whole-field footprint always pass, and so does a query with method option edge=truncate (the
// fft method then cuts its window at the border; other methods refuse the option). compute_lobe
// calls it for every method that reads the footprint.
void check_footprint_inside(const LobeQuery& query);

// Physics warnings about a query for a method, one line each; empty when there is nothing to
// say: a coherence blur below a pixel that point-samples a wave lobe (its albedo and peak are
// then off), incidence beyond the models' validity (shadowing is ignored).
std::vector<std::string> query_warnings(const std::string& method, const LobeQuery& query);

// The supersampling at which a wave lobe's coherence blur λ/(2πσ_c) spans at least 1.5
// sub-pixels (at most 8): 1 when the blur already spans a pixel or the method is not wave optics.
int recommended_supersample(const std::string& method, const LobeQuery& query);

// Warnings about a computed image: a BRDF albedo above 1 beyond 2% (energy the model creates,
// e.g. R-OHS's 1/cosθ_o near grazing), an NDF whose disk sum is off 1 by more than 2%.
std::vector<std::string> image_warnings(const LobeImage& image);

// ---- Methods ------------------------------------------------------------------------------

// Query fields a method may ignore; compute_lobe records them as not applicable.
enum class QueryField { footprint, incident, wavelengths, model, material, supersample };
std::string to_string(QueryField field);

struct MethodOption {
    std::string key;   // e.g. "kernels_per_texel"
    std::string help;  // one line, with the default
};

struct MethodInfo {
    std::string name;                 // e.g. "fft"
    std::string description;          // one line
    std::string reference;            // e.g. "Yan 2018 eq. 6"
    std::vector<Quantity> quantities;  // what it can answer
    std::vector<QueryField> ignored;   // query fields that do not affect its result
    std::vector<MethodOption> options;
    bool wave_optics = false;          // its lobes carry the coherence blur λ/(2πσ_c)
    bool whole_field = false;          // it answers FootprintShape::whole

    bool answers(Quantity quantity) const;
};

// Every method, in table order.
std::vector<MethodInfo> lobe_methods();

// The named method; throws Error listing the available ones for an unknown name.
MethodInfo lobe_method(const std::string& name);

// Validates the query, checks that the method answers its quantity and knows its options,
// runs it, and writes the metadata: the query (query_keys.hpp), fields the method ignores as
// "not applicable", "method", "method.reference" and "quantity". Errors from the method come
// prefixed with its name.
LobeImage compute_lobe(const std::string& method, const LobeQuery& query);

// The mean of compute_lobe over footprint centres (for large-area NDFs and expected lobes, Dong
// 2015 §6): the images of `centres` averaged pixel by pixel in order (deterministic). The
// metadata is the first image's, with "footprints.count" and the centres' bounding box.
LobeImage compute_mean_lobe(const std::string& method, const LobeQuery& query, const std::vector<Point2>& centres);

}  // namespace glintscope
