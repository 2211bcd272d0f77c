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
#include "glintscope/lobe.hpp"
#include "lobe/method.hpp"
#include "methods/discrete/flake_hierarchy.hpp"

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
};

// Reads the options and builds the distribution's triangle table; throws Error naming a bad option.
void setup_discrete(const LobeQuery& query, DiscreteSetup& setup);

}  // namespace glintscope
