#pragma once
// Jakob 2014 "Discrete Stochastic Microfacet Models": a surface of N mirror flakes with normals
// drawn from a smooth distribution (Beckmann or GGX, isotropic or not, or the heightfield's own
// P-NDF of the footprint), answering the query's
// footprint through a cone of directions per pixel. With quantity ndf a pixel at h counts the
// flakes whose normal lies in the cap of half-angle γ about h; with brdf a pixel at ω_o counts those
// reflecting ω_i into the cone of half-angle γ about ω_o (Jakob 2014 eq. 8) and applies eq. 5.
// As N grows the images converge to the smooth NDF and microfacet lobe (docs/discrete.md).
// Metadata: "discrete.*" (flakes in the footprint and in the tile, density, distribution, α, cone,
// seed, tile, ε, table entries, nodes visited per query).
#include "glintscope/lobe/query.hpp"
#include "lobe/method.hpp"
#include "methods/discrete/flake_hierarchy.hpp"
#include "methods/discrete/flake_sampling.hpp"

namespace glintscope {

MethodEntry discrete_method();

// The material and footprint of a query, as the method reads them from its options (exposed for
// tests and benchmarks). `integrals` must outlive the material.
struct DiscreteSetup {
    TriangleIntegrals integrals;
    FlakeMaterial material;
    FlakeFootprint footprint;
    double cone = 0.0;          // γ, radians
    double epsilon = 0.1;
    double density_per_um2 = 0.0;
    // Jakob 2014 §3.4: the smooth distribution at twice its roughness (pndf: the Beckmann
    // distribution of the P-NDF's mean square slopes).
    SmoothSampler sampler;
};

// Reads the options and builds the distribution's triangle table; throws Error naming a bad option.
void setup_discrete(const LobeQuery& query, DiscreteSetup& setup);

// What one pixel (a disk point: ω_o for brdf, h for ndf) asks of the flakes: the spherical conic
// to count in, and the factor from the weighted count to the pixel's value (Jakob 2014 eq. 5).
struct PixelQuery {
    SphericalConic conic;
    double scale = 0.0;  // value = scale × weighted count
    Vec3 h;
};
PixelQuery pixel_query(const LobeQuery& query, const DiscreteSetup& setup, DiskPoint p);
// The same for the lobe at one pair of unit directions above the horizon.
PixelQuery lobe_pixel_query(const DiscreteSetup& setup, Vec3 omega_i, Vec3 omega_o);

// F at the first wavelength, for one direction pair (1 without a material).
double fresnel_at(const LobeQuery& query, Vec3 h);

}  // namespace glintscope
