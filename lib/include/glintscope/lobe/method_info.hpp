#pragma once
// What the library says about a method: its name, reference, the quantities it answers, the
// query fields it ignores and its option keys (the method table, pipeline.hpp, lists them).
#include <string>
#include <vector>

#include "glintscope/lobe/image.hpp"

namespace glintscope {

// Query fields a method may ignore; the pipeline records them as not applicable.
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
    bool exact_pixels = false;         // it can integrate pixels exactly (supersample exact, its automatic choice)
    // Its point query for any footprint (BsdfField) answers elliptical Gaussians (Footprint::sigma_minor_um).
    bool elliptical_footprints = false;
    // Its point query for any footprint (BsdfField) answers boxes, rotated ones too
    // (Footprint::axis_radians), on the texels' lattice; make_bsdf answers an axis-aligned box from
    // its images, whose lattice follows the box's edges.
    bool rotated_boxes = false;
    // It reads square texels only: the pipeline resamples a field with dx ≠ dy to square texels
    // first (surface/square_texels.hpp) and records it (metadata heightfield.square_texels).
    bool needs_square_texels = false;

    bool answers(Quantity quantity) const;
    bool ignores(QueryField field) const;
};

}  // namespace glintscope
