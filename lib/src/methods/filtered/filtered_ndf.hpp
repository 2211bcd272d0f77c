#pragma once
// The filtered NDF of Dong 2015 §5.1: at every point fit a plane to the heightfield by
// least squares weighted with a Gaussian window of standard deviation σ_f, take its normal,
// and accumulate those normals footprint-weighted into the NDF.
//
// For a Gaussian window g the weighted fit decouples: the window's first moments vanish and its
// second moments are σ_f² I, so the fitted slope at p is ∫ g(s − p)(s − p) H(s) ds / σ_f²
// = −∫ ∇g(s − p) H(s) ds = ∇(g ∗ H)(p): the gradient of the Gaussian-smoothed surface. The
// method therefore smooths the samples with a normalised, periodic, separable Gaussian of σ_f
// (truncated at 4σ_f: the discarded tails hold 6e-5 of the kernel, renormalised away), builds
// the shared bicubic over the smoothed samples and accumulates its normals exactly with
// geometric/normal_density.hpp. σ_f = 0 leaves the samples untouched and returns the P-NDF.
//
// Method options: filter_sigma (length, default 1 µm), and intrinsic_roughness, refinement and
// tolerance as for pndf. Metadata: "filtered.filter_sigma_um", "filtered.refinement",
// "filtered.intrinsic_roughness_rad".
#include "glintscope/lobe/query.hpp"
#include "lobe/method.hpp"

namespace glintscope {

MethodEntry filtered_method();

// The filter σ_f of a query (option filter_sigma), checked against the heightfield's size.
double filter_sigma_um(const LobeQuery& query);

// The field's samples convolved periodically with a normalised Gaussian of σ (µm) along x and y.
Heightfield gaussian_smoothed(const Heightfield& field, double sigma_um);

}  // namespace glintscope
