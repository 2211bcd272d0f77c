#pragma once
// Metals as measured complex refractive indices n + ik (data/materials/*.csv, compiled into the
// library) and their Fresnel reflectance F(λ, cos θ) for the lobe methods.
#include <string>
#include <vector>

namespace glintscope {

// The known materials by chemical symbol: Ag, Al, Au, Cr, Cu, Fe.
std::vector<std::string> material_names();

// Throws Error for a name that is not a known material (any case), listing the known ones.
void check_material_name(const std::string& material);

// The measurement a material's table comes from (one line, for metadata).
std::string material_source(const std::string& material);

struct ComplexIndex {
    double n = 1.0;  // real part of the refractive index
    double k = 0.0;  // extinction coefficient
};

// n + ik at a vacuum wavelength, interpolated linearly between table rows. Names match in any
// case; throws Error for an unknown material (listing the known ones) or a wavelength outside
// the table.
ComplexIndex complex_refractive_index(const std::string& material, double lambda_um);

// Unpolarised reflectance (|r_s|² + |r_p|²)/2 of light arriving from vacuum at cos θ on a
// medium of index n + ik: the exact Fresnel equations in complex form. cos θ is clamped to
// [0, 1]; NaN throws Error.
double fresnel_conductor(ComplexIndex eta, double cos_theta);

// Fresnel reflectance of a named material; the empty name means no material, F = 1.
double fresnel_reflectance(const std::string& material, double lambda_um, double cos_theta);

}  // namespace glintscope
