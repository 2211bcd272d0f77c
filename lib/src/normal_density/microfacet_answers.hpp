#pragma once
// The single-direction answers (lobe/point_answers.hpp) of a microfacet lobe over a tabulated
// NDF, f_r = F(ω_i·h) D(h) G(ω_i, ω_o) / (4 cosθ_i cosθ_o) (Dong 2015 eq. 1 and eq. 8), for the
// methods that tabulate D once per footprint (geometric, dk): eval reads the table bilinearly
// as their images do, and sample draws h from the table (piecewise constant over its pixels,
// exact pdf) and reflects ω_i about it.
#include <functional>
#include <memory>
#include <vector>

#include "glintscope/lobe/query.hpp"
#include "glintscope/optics/material.hpp"
#include "lobe/point_answers.hpp"
#include "numerics/disk_table.hpp"

namespace glintscope {

struct MicrofacetTable {
    DiskTable density;                  // D(h) on the projected disk of normals
    std::vector<ComplexIndex> indices;  // per query wavelength; empty: F = 1
    // G(ω_i, ω_o, h); empty: 1.
    std::function<double(Vec3 omega_i, Vec3 omega_o, Vec3 h)> shadowing;
};

PointAnswers microfacet_answers(MicrofacetTable table, std::size_t wavelengths);

// The pdf per solid angle of ω_o = reflect(ω_i, h) for h drawn with `disk_density_of_h` per
// unit disk area (Walter 2007 eq. 14); 0 where ω_o·h ≤ 0.
double reflection_pdf(double disk_density_of_h, Vec3 h, Vec3 omega_o);

// ω_o = reflect(ω_i, h) for the drawn disk point h and its pdf; none where ω_o falls below the
// horizon or h faces away from ω_i.
DirectionSample reflected_sample(Vec3 omega_i, DiskPoint h_disk, double disk_density_of_h);

// F(ω_i·h) D G / (4 cosθ_i cosθ_o) per wavelength (Dong 2015 eq. 1) for the density D and
// shadowing G at h: one Fresnel factor per index, F = 1 for all `wavelengths` without indices.
std::vector<double> microfacet_value(double density, double shadowing, Vec3 omega_i, Vec3 omega_o, Vec3 h,
                                     const std::vector<ComplexIndex>& indices, std::size_t wavelengths);

// The query material's complex index at each query wavelength; empty without a material.
std::vector<ComplexIndex> refractive_indices(const LobeQuery& query);

}  // namespace glintscope
