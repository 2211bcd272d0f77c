#pragma once
// Spherical triangles and the spherical conic of Jakob 2014 §3.2: the directional half of the
// discrete microfacet hierarchy. A triangle's vertices are unit vectors in counter-clockwise order
// seen from outside the sphere; the hemisphere's root splits into the four octant quadrants.
#include <array>

#include "glintscope/core/geometry.hpp"

namespace glintscope {

struct SphericalTriangle {
    std::array<Vec3, 3> v;
};

// The four octant quadrants of the upper hemisphere (Jakob 2014 §3.3: its first directional split).
std::array<SphericalTriangle, 4> hemisphere_quadrants();

// The four children made by the normalised edge midpoints (Jakob 2014 §3.3), in a fixed order:
// the three corner triangles, then the middle one.
std::array<SphericalTriangle, 4> split(const SphericalTriangle& triangle);

// Solid angle (Van Oosterom & Strackee 1983).
double solid_angle(const SphericalTriangle& triangle);

// The normalised centroid direction.
Vec3 centre(const SphericalTriangle& triangle);

// Whether a unit vector lies inside the triangle (three great-circle sidedness tests).
bool contains(const SphericalTriangle& triangle, Vec3 m);

// The normals that reflect ω_i into the cone of half-angle γ about ω_o: mᵀ C m ≤ 0 with
// C = I (cos γ + ω_i·ω_o)/2 − sym(ω_i ω_oᵀ) (Jakob 2014 eq. 8), on the nappe around the half
// vector h = (ω_i + ω_o)/|ω_i + ω_o| (the cone also holds −Ω_h). ω_i = ω_o = m gives the cap of
// radius γ/2 about m.
struct SphericalConic {
    std::array<std::array<double, 3>, 3> c{};
    Vec3 axis;    // h, inside the set
    Vec3 facing;  // ω_i: −m reflects like m, and only normals facing the light count
    bool elliptic = true;  // λ1 > 0 of Jakob 2014 eq. 9: the set is a disc-like region about h
};

SphericalConic spherical_conic(Vec3 omega_i, Vec3 omega_o, double gamma);

double quadratic_form(const SphericalConic& conic, Vec3 m);
double bilinear_form(const SphericalConic& conic, Vec3 a, Vec3 b);
bool contains(const SphericalConic& conic, Vec3 m);

enum class Overlap { disjoint, partial, inside };

// How a triangle lies with respect to the conic (Jakob 2014 §3.3): inside when the boundaries do
// not cross and a vertex is inside; disjoint when they do not cross, no vertex is inside and the
// triangle does not hold the conic's axis; partial otherwise.
Overlap overlap(const SphericalConic& conic, const SphericalTriangle& triangle);

// The share of a weight w inside the conic, ∫_{T∩Ω} w / ∫_T w, with w linear across the
// triangle through its vertex values (all 1: the area fraction). Computed in the plane of the
// vertices with the planar conic section there (Jakob 2014 §3.3: small triangles are flat enough)
// exactly, as a triangle inside an ellipse. Negative when the section there is not an ellipse (the
// caller then refines instead of estimating).
double inside_fraction(const SphericalConic& conic, const SphericalTriangle& triangle,
                       const std::array<double, 3>& weights = {1.0, 1.0, 1.0});

}  // namespace glintscope
