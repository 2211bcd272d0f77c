#pragma once
// The geometric (microfacet) lobe of the query's footprint, Dong 2015 eq. 1:
//   f_r(ω_i, ω_o) = F(ω_i·h) D(h) G(ω_i, ω_o) / (4 cosθ_i cosθ_o),  h = (ω_i + ω_o)/|ω_i + ω_o|,
// with D the exact P-NDF (geometric/normal_density.hpp) or the filtered NDF of Dong 2015 §5.1,
// computed internally at `ndf_oversampling` × the lobe resolution and read bilinearly at each
// sub-pixel's h, so the lookup does not blur the lobe; K×K sub-pixels per pixel as the wave
// methods (query.supersample). F is the query material's Fresnel reflectance (1 without one);
// the lobe depends on λ only through F.
//
// G: none (1, the default) or smith: the separable product G1(ω_i) G1(ω_o) (Dong 2015 eq. 13)
// with Smith's G1 for the tabulated NDF, G1(ω) = cosθ / ∫ D(m) ⟨ω·m⟩⁺ dω_m (the projected-area
// condition of Smith masking, Walter 2007 and Heitz 2014), the integral summed over the NDF
// image as Σ D ⟨ω·m⟩⁺ / m_z (2/M)², G1 clamped to ≤ 1.
//
// Method options: ndf = pndf | filtered (default pndf), shadowing = none | smith,
// ndf_oversampling (1–4, default 4: near normal incidence a lobe pixel spans
// 1/N in h, an NDF pixel 2/M, and bilinear reading blurs by about one NDF pixel; at the default
// the blur is a quarter of a lobe pixel), filter_sigma (filtered only), intrinsic_roughness, refinement, tolerance.
// Metadata: "geometric.ndf", "geometric.shadowing", "geometric.ndf_resolution", "geometric.refinement".
// Point answers of one footprint (make_bsdf): its NDF table made once, read and sampled as dk's
// D_K table (normal_density/microfacet_answers.hpp); with shadowing, from the images.
// Point field: f_r with D the point query of a normal-bounds tree over the (filtered) field at
// N × ndf_oversampling (the triangles of the table of point-sampled pixels), for any Gaussian or
// whole-field footprint, sampled (without intrinsic roughness) by the point query's own sampler
// (h by the footprint's triangle weights, ω_o = reflect(ω_i, h)); shadowing and box footprints:
// from the images.
#include "glintscope/lobe/query.hpp"
#include "lobe/method.hpp"

namespace glintscope {

MethodEntry geometric_method();

}  // namespace glintscope
