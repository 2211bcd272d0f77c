#pragma once
// The patch NDF (P-NDF, Yan 2014 as summarised in Yan 2018 §2) of the query's footprint: the
// footprint-weighted density D of the shared interpolant's normals on the projected disk,
// computed exactly by geometric/normal_density.hpp (no sampling noise, sharp caustic folds).
//
// Method options (LobeQuery::method_options):
//   intrinsic_roughness  radians (default 0): Gaussian blur of that angular width (Yan 2014).
//   refinement           least cells per texel along each axis (default 1).
//   tolerance            pixels (default 0.02): cells are halved until their image is that close
//                        to affine (normal_density.hpp); 0 keeps exactly `refinement`.
// The image holds D (not f_r), one identical layer per query wavelength; Σ D·(2/N)² = 1.
// The metadata records "pndf.refinement", "pndf.tolerance_pixels", "pndf.intrinsic_roughness_rad", "pndf.weight_sigma_um".
#include "glintscope/lobe.hpp"
#include "geometric/normal_density.hpp"

namespace glintscope {

LobeImage pndf(const LobeQuery& query);

// The options above as settings (shared with the methods that build on the P-NDF).
NormalDensitySettings normal_density_settings(const LobeQuery& query, const std::string& method,
                                              const std::vector<std::string>& other_keys);

// Copies one NDF layer into every wavelength layer of an image and records the query.
LobeImage density_image(const LobeQuery& query, const std::vector<double>& density);

}  // namespace glintscope
