#pragma once
// Where the flakes' normals point: the smooth microfacet distribution D of the discrete model
// (Jakob 2014 §3.4), and its integrals over the spherical triangles of the hierarchy, memoised in a
// hash table where D is far from uniform (Jakob 2014 Algorithm 2).
#include <array>
#include <cstdint>
#include <functional>
#include <unordered_map>

#include "methods/discrete/spherical_geometry.hpp"

namespace glintscope {

// The density of flake normals per unit solid angle, D(m)(m·n): a flake's normal falls in a set Ω
// with probability ∫_Ω D(m) m_z dω, its share of projected area (conventions.md "Geometric NDFs").
using NormalDensity = std::function<double(Vec3 m)>;

// Triangle labels: the hemisphere is 1 and child j ∈ {1, 2, 3, 4} of triangle i is 4i + j − 2
// (Jakob 2014 §3.4), the order of split(); the first split gives the four quadrants.
inline constexpr std::uint64_t kHemisphereLabel = 1;
inline std::uint64_t child_label(std::uint64_t parent, int j) { return 4 * parent + static_cast<std::uint64_t>(j) - 1; }
inline constexpr int kMaxTriangleDepth = 29;  // labels stay below 2^63

// A directional cell of the hierarchy: a spherical triangle (or, with label 1, the whole
// hemisphere) with the density at its vertices and its solid angle, so that splits evaluate the
// density only at the three new midpoints.
struct DirectionCell {
    SphericalTriangle triangle;
    std::array<double, 3> density{};
    double solid_angle = 2.0 * pi;
    std::uint64_t label = kHemisphereLabel;
    int depth = 0;
};

// The four children (the quadrants for the hemisphere), in the order of split().
std::array<DirectionCell, 4> split(const DirectionCell& cell, const NormalDensity& density);

struct TriangleIntegrals {
    NormalDensity density;
    double relative_tolerance = 1e-2;  // δ_rel of Algorithm 2
    double absolute_tolerance = 1e-8;  // δ_abs: where D's integral is negligible anyway
    std::unordered_map<std::uint64_t, double> table;  // triangles where D is not uniform

    // ∫_T D m_z dω: the table's entry, or the vertex rule where D is close to uniform.
    double integral(const DirectionCell& cell) const;
    // Whether D may be treated as uniform inside the cell, the condition under which Jakob 2014's
    // adaptive criterion (eq. 10) may stop at a partial overlap: no table entry, i.e. the centroid
    // and vertex rules agree, so D has no curvature there. A linear trend across the cells on the
    // conic's boundary biases the shares of opposite sides oppositely and cancels.
    bool uniform(const DirectionCell& cell) const {
        return cell.label != kHemisphereLabel && !table.contains(cell.label);
    }
};

// Integrates D over the four quadrants, recursing and filling the table where the centroid and
// vertex rules differ by more than both tolerances, down to `max_depth` levels (Jakob 2014
// Algorithm 2). The paper takes δ_abs = δ_rel = 1e-5; an absolute tolerance near a cell's own
// integral would call a curved cell uniform in the tails, where the counts of eq. 10 then drift,
// so ours is far below any cell's share and the relative one decides.
TriangleIntegrals integrate_distribution(NormalDensity density, double relative_tolerance = 1e-2,
                                         double absolute_tolerance = 1e-8, int max_depth = 16);

// The share of a cell's flakes inside the conic, D linear across it (inside_fraction). Where the
// conic's section in the cell's plane is no ellipse (near the horizon, or the hyperbolic case of
// Jakob 2014 eq. 9), cells below 1e-4 of `reference_solid_angle` take the share of their vertices
// inside, so that refinement ends; larger ones give −1 (refine).
double cell_share(const SphericalConic& conic, const DirectionCell& cell, double reference_solid_angle);

// ∫_Ω D m_z dω over a conic: the expected share of flakes in it. Cells inside add their integral,
// partial cells where D is uniform and no larger than `cell_solid_angle` add their share (with D
// linear across them), others split.
double conic_integral(const TriangleIntegrals& integrals, const SphericalConic& conic, double cell_solid_angle);

// The vertex rule of Algorithm 2: area × mean of the density at the three vertices.
double vertex_rule(const NormalDensity& density, const SphericalTriangle& triangle);

}  // namespace glintscope
