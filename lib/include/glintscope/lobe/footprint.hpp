#pragma once
// The coherence footprint of a query (conventions.md "Coherence / footprint") and the set of
// footprints a request averages over (Dong 2015 §6: large-area NDFs and expected lobes).
#include <string>
#include <string_view>
#include <vector>

#include "glintscope/core/geometry.hpp"
#include "glintscope/surface/heightfield.hpp"

namespace glintscope {

// whole: every point of one period of the field weighs the same (Dong-style large-area NDFs;
// geometric methods only, MethodInfo::whole_field).
enum class FootprintShape { gaussian, box, whole };

// A Gaussian w(s) = exp(−|s − x_c|²/(2σ_c²)), A_c = πσ_c², or a box of sides `size_um` along x
// and `size_y_um` along y (Dong 2015's 70 × 53 µm patches; 0: a square), A_c its area. Geometric
// methods weigh the surface by |w|²/A_c: a normalised Gaussian of standard deviation σ_c/√2, or
// the box.
//
// An elliptical Gaussian (a render pixel's footprint on the patch, docs/render.md):
// w(s) = exp(−½ (s − x_c)ᵀ Σ_c⁻¹ (s − x_c)) with Σ_c = R diag(σ_c², σ_minor²) Rᵀ, R the rotation
// by `axis_radians` from +x to σ_c's axis, A_c = π σ_c σ_minor; geometric methods weigh the surface
// by |w|²/A_c, the normalised Gaussian of covariance Σ_c/2. Only point queries that say so take
// one (MethodInfo::elliptical_footprints); lobe images refuse it (validate(LobeQuery)).
//
// A box may be rotated (a render pixel's cell as a rectangle, docs/render.md): `axis_radians` is
// then the angle of its width (`size_um`) from +x. Only point queries that say so take one
// (MethodInfo::rotated_boxes); lobe images, whose boxes are axis-aligned, refuse it
// (validate(LobeQuery), BsdfField::at).
struct Footprint {
    Point2 centre_um;
    double sigma_um = 10.0;
    FootprintShape shape = FootprintShape::gaussian;
    double size_um = 0.0;         // box side along x (box only)
    double size_y_um = 0.0;       // box side along y (box only); 0: size_um
    double sigma_minor_um = 0.0;  // Gaussian: σ across the axis; 0 (or σ_c): isotropic
    double axis_radians = 0.0;    // elliptical Gaussian: σ_c's axis from +x; box: its width's axis from +x
};

// Whether the footprint is a Gaussian with two different standard deviations.
inline bool is_elliptical(const Footprint& footprint) {
    return footprint.shape == FootprintShape::gaussian && footprint.sigma_minor_um > 0.0 &&
           footprint.sigma_minor_um != footprint.sigma_um;
}

// A Gaussian footprint's σ across its axis: σ_minor of an ellipse (validate: ≤ σ_c), else σ_c.
inline double minor_sigma_um(const Footprint& footprint) {
    return footprint.sigma_minor_um > 0.0 ? footprint.sigma_minor_um : footprint.sigma_um;
}

// Whether the footprint is a box whose sides do not run along x and y.
inline bool is_rotated_box(const Footprint& footprint) {
    return footprint.shape == FootprintShape::box && footprint.axis_radians != 0.0;
}

inline double box_width_um(const Footprint& footprint) { return footprint.size_um; }
inline double box_height_um(const Footprint& footprint) {
    return footprint.size_y_um > 0.0 ? footprint.size_y_um : footprint.size_um;
}

// Makes the footprint a box of sides "70um" or "70x53um" (parse_box_sides); throws Error on a
// zero side, which validate(Footprint) would otherwise read as a square.
void set_box(Footprint& footprint, std::string_view sides);

// Checks a footprint's centre, σ_c (and an ellipse's σ_minor ≤ σ_c), axis and box sides and throws
// Error naming the bad one (part of validate(LobeQuery); also for commands that only draw a
// footprint, which draw boxes axis-aligned: they refuse a rotated one themselves).
void validate(const Footprint& footprint);

// How far a footprint reaches from its centre along x and y: 3.25σ_c for a Gaussian (the wave
// methods' truncation), half the sides of a box's bounding rectangle.
Point2 footprint_support_um(const Footprint& footprint);

// Which footprints a request averages over: the query's own (count 0, the default), `count`
// seeded uniform centres, or a grid of count × count centres. Text: "1", "N", "grid" (3 × 3),
// "grid:N" (N × N).
struct FootprintSet {
    int count = 0;
    bool grid = false;
    unsigned seed = 1;

    bool single() const { return count == 0; }
};

// Parses "N", "grid" or "grid:N"; throws Error with one line naming the accepted forms.
FootprintSet parse_footprint_set(const std::string& text);
std::string to_string(const FootprintSet& set);  // reads back as the same set ("1" for single)

// The centres of a set over a field: the footprint's own centre for a single footprint; else
// spread over the field (grid cells' centres, or seeded uniform positions), kept 3.25σ_c (or half
// a box) from the edges where the field is large enough, so that a non-periodic scan is not read
// across its seam.
std::vector<Point2> footprint_centres(const Heightfield& field, const Footprint& footprint, const FootprintSet& set);

}  // namespace glintscope
