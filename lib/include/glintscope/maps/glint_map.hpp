#pragma once
// A glint map: how one pair of directions sees the surface as the footprint moves over it, the
// picture of glitter (Jakob 2014 Fig. 1) as a map of footprint positions rather than of
// directions. The discrete method's flakes answer it with one cone query per position.
#include <cstddef>
#include <functional>

#include "glintscope/output/colormap.hpp"
#include "glintscope/lobe/query.hpp"

namespace glintscope {

// f_r(ω_i, ω_o) of the discrete method (its options in query.method_options) for footprints
// centred on a size × size grid spaced `step_um` apart around query.footprint.centre_um, in map
// view (row 0 at the largest y; position (r, c) = centre + ((c − (size − 1)/2)·step,
// ((size − 1)/2 − r)·step)). The centre position equals the discrete lobe's pixel at ω_o. F is
// the query's material at its first wavelength. Counts are exact (option error = 0) unless the
// query sets `error`: eq. 10's estimates of whole nodes would show as squares in the map. Throws
// Error for a bad size, step, option or direction.
// `progress` (may be empty) is called from the calling thread with the rows done and the total.
ScalarImage discrete_glint_map(const LobeQuery& query, Vec3 omega_o, int size, double step_um,
                               const std::function<void(std::size_t done, std::size_t total)>& progress = {});

}  // namespace glintscope
