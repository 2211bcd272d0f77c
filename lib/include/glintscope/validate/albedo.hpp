#pragma once
// Directional albedo against incidence, per method and diffraction model: ∫ f_r cosθ_o dω_o
// (the lobe image's disk sum) as θ_i sweeps at the query's φ_i, beside the material's Fresnel
// reflectance F(θ_i), which is a flat mirror's albedo. A model that creates energy shows as a
// curve above F: R-OHS toward grazing incidence (Yan 2018 Fig. 6), an unshadowed geometric
// lobe (G = 1) on a rough surface.
#include <string>
#include <vector>

#include "glintscope/lobe/query.hpp"
#include "glintscope/validate/validate.hpp"

namespace glintscope {

struct AlbedoCurve {
    std::string method;
    DiffractionModel model = DiffractionModel::rohs;
    bool model_applies = true;                 // false: the method ignores the model (one curve)
    std::vector<std::vector<double>> albedo;   // [θ_i][wavelength]
};

struct AlbedoStudy {
    std::vector<double> theta_i_deg;
    std::vector<double> wavelengths_um;
    std::vector<std::vector<double>> fresnel;  // [θ_i][wavelength]: F(λ, cosθ_i), 1 without a material
    std::vector<AlbedoCurve> curves;
};

// Every method × model (once for a method that ignores the model) × θ_i, with the query's
// heightfield, footprint, wavelengths, material, resolution and supersampling (0: automatic).
// Throws Error (before computing) for an unknown method or a θ_i outside [0, 90).
AlbedoStudy albedo_versus_incidence(const LobeQuery& query, const std::vector<std::string>& methods,
                                    const std::vector<DiffractionModel>& models,
                                    const std::vector<double>& theta_i_deg, const ProgressCallback& progress = {});

// The default sweep: θ_i = 0, 10, ..., 80 degrees.
std::vector<double> default_albedo_angles();

// One line per θ_i: theta_i_deg, fresnel, then each curve's albedo (named method/model), each the
// mean over wavelengths.
std::string albedo_csv(const AlbedoStudy& study);

// A curve's name in tables and legends: "fft, rohs" or "geometric".
std::string curve_name(const AlbedoCurve& curve);

// The mean over wavelengths of a [θ_i][wavelength] table, per θ_i.
std::vector<double> band_mean(const std::vector<std::vector<double>>& table);

}  // namespace glintscope
