#pragma once
// Importance sampling of the discrete microfacet BRDF as Jakob 2014 §3.4 "Importance sampling"
// does it: ω'_o from the smooth model's sampler with the roughness doubled (α_sample = 2α),
// i.e. h drawn with density D(h) h_z and ω'_o = reflect(ω_i, h) (Walter 2007), then ω_o uniform in
// the cone of half-angle γ about ω'_o. Its density is the smooth density of ω'_o convolved with
// the cone, computed here by a product quadrature over the cone (the paper: 64 QMC points).
#include <optional>
#include <utility>

#include "glintscope/core/geometry.hpp"
#include "lobe/point_answers.hpp"

namespace glintscope {

// The smooth distribution the sampler draws h from, its roughness already scaled.
struct SmoothSampler {
    enum class Shape { beckmann, ggx };
    Shape shape = Shape::beckmann;
    double alpha_x = 0.4;
    double alpha_y = 0.4;
};

// Two uniforms in [0, 1) from one, by its alternate bits (26 each): Bsdf::sample gives two
// uniforms, the sampler needs four (h, then the point in the cone).
std::pair<double, double> split_uniform(double u);

class FlakeSampler {
public:
    FlakeSampler(SmoothSampler smooth, double cone);

    // ω_o, or none where h reflects ω_i below the horizon or the cone's point lies below it.
    std::optional<Vec3> draw(Vec3 omega_i, double u1, double u2) const;
    // The density per unit solid angle of draw()'s ω_o (unit vectors above the horizon).
    double pdf(Vec3 omega_i, Vec3 omega_o) const;
    DirectionSample sample(Vec3 omega_i, double u1, double u2) const;
    // The density of ω'_o before the cone: p(h)/(4 ω_i·h) (Walter 2007 eq. 14), 0 below the horizon.
    double reflected_pdf(Vec3 omega_i, Vec3 omega) const;

private:
    double h_pdf(Vec3 h) const;  // D(h) h_z of the scaled smooth distribution
    Vec3 draw_h(double u1, double u2) const;

    SmoothSampler smooth_;
    double one_minus_cos_cone_;  // 1 − cos γ = 2 sin²(γ/2), exact for small γ
};

}  // namespace glintscope
