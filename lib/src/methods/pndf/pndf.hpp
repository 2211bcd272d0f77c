#pragma once
// The patch NDF (P-NDF, Yan 2014 as summarised in Yan 2018 §2) of the query's footprint: the
// footprint-weighted density D of the shared interpolant's normals on the projected disk,
// computed exactly by geometric/normal_density.hpp (no sampling noise, sharp caustic folds).
// The image holds D, one identical layer per query wavelength; Σ D·(2/N)² = 1.
// Metadata: "pndf.refinement", "pndf.tolerance_pixels", "pndf.intrinsic_roughness_rad",
// "pndf.weight_sigma_um".
// Point field: one normal-bounds tree over the field (normal_density/normal_bounds_tree.hpp)
// answers D(h) = eval(·, h) for any Gaussian, whole-field or box footprint (a rotated box too,
// by the preimage rule), and without intrinsic roughness samples h with that density
// (sample(·, u1, u2), pdf(·, h) = D(h) h_z × the sampler's normalisation, 1 ± 1e-5); make_ndf
// answers an axis-aligned box from the images (bsdf.cpp), whose lattice follows its edges.
#include <vector>

#include "normal_density/normal_density.hpp"
#include "glintscope/lobe/query.hpp"
#include "lobe/method.hpp"

namespace glintscope {

MethodEntry pndf_method();

// The options every method built on the exact normal density shares (intrinsic_roughness,
// refinement, tolerance), their help lines and their values.
std::vector<MethodOption> normal_density_options();
NormalDensitySettings normal_density_settings(const LobeQuery& query);

// An NDF image: `density` in layer 0, copied to every wavelength layer.
LobeImage density_image(const LobeQuery& query, const std::vector<double>& density);

}  // namespace glintscope
