#pragma once
// A smooth microfacet baseline: Beckmann or GGX (fit/ndf_models.hpp) fitted to the heightfield's
// NDF over one whole period (Dong 2015 §8, Fig. 12: the fits of measured NDFs), and the lobe
//   f_r(ω_i, ω_o) = F(ω_i·h) D_fit(h) / (4 cosθ_i cosθ_o)   (Dong 2015 eq. 1, G = 1 as geometric's default)
// for every footprint alike: what a renderer without glints would show for the same surface, the
// comparison for glint renders (render.md). The NDF fitted is the exact P-NDF of the whole field
// (normal_density.hpp, footprint whole, 128², tolerance 0.1 pixel), by fit_ndf (L2 on the disk).
// Option fit = beckmann | ggx (default beckmann). Metadata: "fitted.model", "fitted.alpha_x",
// "fitted.alpha_y", "fitted.relative_error" (of the fit against the NDF).
// Point field: the same closed form for any footprint (the fit made once per heightfield).
#include "glintscope/lobe/query.hpp"
#include "lobe/method.hpp"

namespace glintscope {

MethodEntry fitted_method();

}  // namespace glintscope
