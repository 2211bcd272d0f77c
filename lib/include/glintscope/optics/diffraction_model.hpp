#pragma once
// The five scalar diffraction models of Yan 2018 Fig. 6, through which Yan 2018 eq. 2/3/6 read
// f_r = ξ1/A_c · |∫ w ξ2 e^{−i2π ξ3 H/λ} e^{−i2π ψ̄·s/λ} ds|².
#include <string>

#include "glintscope/core/geometry.hpp"

namespace glintscope {

enum class DiffractionModel { ohs, ghs, rohs, rghs, kirchhoff };

DiffractionModel parse_diffraction_model(const std::string& name);  // "ohs", "ghs", "rohs", "rghs", "kirchhoff"
std::string to_string(DiffractionModel model);

// ξ1 without the Fresnel factor F and without 1/λ² (multiply by F/λ²): for OHS and GHS
// |ω_o·n| / |ω_i·n|, for R-OHS, R-GHS and Kirchhoff |ψ·n|² / (4 |ω_i·n| |ω_o·n|).
double xi1_geometric(DiffractionModel model, Vec3 omega_i, Vec3 omega_o);

// ξ3: 2 for OHS and R-OHS, ψ·n for GHS, R-GHS and Kirchhoff.
double xi3(DiffractionModel model, Vec3 omega_i, Vec3 omega_o);

// Whether ξ3 depends on ω_o (GHS, R-GHS, Kirchhoff), so that R* changes across a lobe image.
bool phase_depends_on_outgoing(DiffractionModel model);

// ξ2 of the Kirchhoff model at a point with slope H' = (hx, hy): 1 − ψ̄·H'/(ψ·n); 1 otherwise.
double xi2(DiffractionModel model, Vec3 omega_i, Vec3 omega_o, double hx, double hy);

}  // namespace glintscope
