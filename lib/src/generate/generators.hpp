#pragma once
// The generators behind glintscope::generate (generate.hpp), one file each. They assume a
// validated recipe (validate_recipe) and fill heights only; generate() records the provenance.
#include <cstdint>
#include <vector>

#include "glintscope/generate/generate.hpp"

namespace glintscope {

// generate_gaussian_random_field.cpp: a zero-mean field with Sq exactly parameters.sigma_h_um.
std::vector<float> gaussian_random_field(const GridSpec& grid, const GaussianFieldParameters& parameters,
                                         std::uint64_t seed);

// generate_scratches.cpp: carves the scratches into the field (the deepest groove wins).
void carve_scratches(Heightfield& field, const std::vector<Scratch>& scratches);

// generate_grating.cpp
std::vector<float> sinusoidal_grating(const GridSpec& grid, const GratingParameters& parameters);

// generate_cd_tracks.cpp
std::vector<float> cd_tracks(const GridSpec& grid, const CdParameters& parameters, std::uint64_t seed);

}  // namespace glintscope
