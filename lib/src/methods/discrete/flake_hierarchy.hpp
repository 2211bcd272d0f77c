#pragma once
// Jakob 2014's pseudorandom position-normal hierarchy (§3.3–3.4): a tile of surface × the
// hemisphere of normals holding N flakes, whose node counts are drawn top-down from multinomial
// distributions seeded by each node's label, so that every node has one count whatever the query
// and children always sum to their parent. Counting the flakes of a footprint × spherical conic
// query is Algorithm 1 with the adaptive error criterion (eq. 10).
#include <array>
#include <cstdint>
#include <unordered_map>

#include "methods/discrete/flake_distribution.hpp"
#include "methods/discrete/spherical_geometry.hpp"

namespace glintscope {

// The flakes of a material: uniform in position over a periodic square tile, normals drawn from
// the distribution. Nodes split in space or in direction by Jakob 2014 eq. 11, with the expected
// query sizes fixed here (the footprint's area and the query's solid angle in normal space), so the
// flake set is the same for every query of that size.
struct FlakeMaterial {
    const TriangleIntegrals* normals = nullptr;
    double tile_um = 1000.0;
    double flakes = 0.0;             // in the whole tile (an integer)
    std::uint64_t seed = 1;
    double query_area_um2 = 100.0;   // eq. 11's E[A(query)]
    double query_solid_angle = 1e-4;  // eq. 11's E[σ(query)]
};

// The footprint as a weight on flakes: a box of sides `size_um` (along x) and `size_y_um` counts
// each flake inside once; a
// Gaussian counts exp(−|x − c|²/σ²) (σ = σ_c: the normalised weight |w|²/A_c of conventions.md
// times A_c), cut where it falls below e^−25. `area_um2` is ∫ weight: the box area, or πσ_c² = A_c.
struct FlakeFootprint {
    double centre_x = 0.0, centre_y = 0.0;
    bool gaussian = true;
    double sigma_um = 10.0;
    double size_um = 0.0;
    double size_y_um = 0.0;
    double area_um2() const;
};

// A node: a square of the tile × a directional cell (label 1: the whole hemisphere).
struct FlakeNode {
    double x0 = 0.0, y0 = 0.0, size = 0.0;
    DirectionCell direction;
    std::uint64_t label = 1;  // seeds the node's multinomial draw
    double count = 0.0;
    int space_depth = 0;
};

FlakeNode root_node(const FlakeMaterial& material);

// Nodes holding at most this many flakes are leaves: their flakes are drawn one by one (a
// position uniform in the square, a normal from D in the triangle), each from its own stream.
// Resolving a Gaussian footprint's weight flake by flake would otherwise need a spatial subdivision
// down to a fraction of σ_c around every flake.
inline constexpr double kLeafFlakes = 8.0;

// The four children, their counts a multinomial draw of the parent's count with probabilities
// 1/4 (a spatial split) or ∫D over the child triangles (a directional split) (Jakob 2014 §3.4).
std::array<FlakeNode, 4> split(const FlakeMaterial& material, const FlakeNode& node);

// Binomial(n, q) drawn from the counter-based generator under (seed, label), draw `index`: exact by
// inversion while the variance nq(1−q) is below 50, otherwise the rounded normal approximation
// (Jakob 2014 §3.4 uses the normal approximation above n = 8).
double binomial_draw(double n, double q, std::uint64_t seed, std::uint64_t label, int index);

struct FlakeCount {
    double weighted = 0.0;  // Σ weight(x_k) over flakes in footprint × conic, in flakes
    long nodes = 0;         // nodes visited
};

// Children already drawn, by node label: neighbouring pixels' queries walk the same upper levels
// of the tree. A cache changes no result, only the time.
struct SplitCache {
    std::unordered_map<std::uint64_t, std::array<FlakeNode, 4>> children;
};

// Algorithm 1 of Jakob 2014: breadth-first from the root, adding nodes inside the query, splitting
// partial ones, and stopping early where D is uniform in the node and the node's expected share is
// known to within ε of the running count (eq. 10), or each of its flakes' weight to within ε.
FlakeCount count_flakes(const FlakeMaterial& material, const FlakeFootprint& footprint, const SphericalConic& conic,
                        double epsilon = 0.1, SplitCache* cache = nullptr);

}  // namespace glintscope
