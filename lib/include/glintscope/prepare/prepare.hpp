#pragma once
// Preparing measured (profilometer) heightfields before any lobe is computed: fill the
// drop-outs, remove the form (tilt, curvature), crop to a region, resample to a texel size.
// `convert` applies them in that fixed order: crop, fill, form removal, resample — crop first
// so the later steps see only the region of interest; fill next, so that the form is fitted to
// and removed from a complete field (a plane does not change the thin-plate fill, as it costs
// no energy); resample last, as it needs every point and sets the final texel.
//
// Every step changes the field in place, returns a report, and appends its one-line
// description to field.provenance as "prepare.N" (N = 1, 2, ... in the order applied), so
// `info` and every output's metadata show what was done.
//
// Heightfield::periodic: orient, fill and resample keep it (fill and resample take the matching
// Tiling from the caller); crop to a part of the field and form removal of order >= 1 clear it,
// since a part of a tile, or a tile minus a tilt, does not tile (their reports and provenance lines say so).
#include <cstddef>
#include <string>
#include <vector>

#include "glintscope/surface/heightfield.hpp"

namespace glintscope {

// How the field continues beyond its borders. Profilometer scans simply end (Tiling::none);
// generated fields are one tile of a periodic surface (conventions.md "Heightfields tile").
//   fill_missing: none   → only differences between in-field points count (the energies'
//                          natural boundary condition at the border);
//                 periodic → neighbours wrap around.
//   resample:     none   → the field is continued by point reflection about its border samples,
//                          h(−k) = 2 h(0) − h(k), so a trend runs on and the opposite edge never
//                          leaks in;
//                 periodic → the interpolant and the prefilter wrap around.
enum class Tiling { none, periodic };

// ---- Filling missing points (lib/src/fill_missing.cpp) ----------------------------------

// Each hole is filled with the minimum of a smoothness energy, the valid heights held fixed:
// harmonic:   the membrane energy Σ |∇H|², so ΔH = 0 in the hole: continuous across the rim and
//             never outside the range of the rim heights (maximum principle), but with a kink
//             in slope at the rim.
// biharmonic: the thin-plate energy Σ H_xx² + 2 H_xy² + H_yy², so Δ²H = 0 in the hole, with the
//             two rings of valid points around it as boundary data: heights and slopes continue
//             smoothly across the rim (no spurious normals), cubics are carried through
//             interior holes exactly and planes into holes at the border. The default.
enum class FillMethod { harmonic, biharmonic };

struct FillReport {
    std::size_t filled_points = 0;
    double filled_fraction = 0.0;          // of all points
    FillMethod method = FillMethod::biharmonic;
    Tiling tiling = Tiling::none;
    std::size_t holes = 0;                 // independent groups of missing points, solved separately
    std::size_t largest_hole = 0;          // points in the largest group
    int iterations = 0;                    // most conjugate-gradient iterations any hole needed
    double relative_residual = 0.0;        // largest final |b − A x| / |b| over the holes
};

// Replaces every NaN by the solution of `method` over the missing region; valid points are
// left unchanged bit for bit. Throws Error if the field is invalid or every point is missing.
// Degenerate data: a single valid point fills the field with its height (either method); valid
// points all on one grid line are refused for the biharmonic fill with Tiling::none, whose
// thin plate could tilt across the line at no energy (the harmonic fill is unique there).
FillReport fill_missing(Heightfield& field, FillMethod method = FillMethod::biharmonic, Tiling tiling = Tiling::none);

// ---- Form removal (lib/src/form_removal.cpp) -------------------------------------------

// The form is the least-squares polynomial Σ a_ij P_i(u) P_j(v), i + j ≤ order, over the valid
// points, where P_n are Legendre polynomials and u, v ∈ [−1, 1] are the map-view x, y of the
// sample centres scaled about the field centre (well conditioned at every order).
inline constexpr int kMaxFormOrder = 6;

struct FormTerm {
    int i = 0;                    // degree in u (x)
    int j = 0;                    // degree in v (y)
    double coefficient_um = 0.0;  // a_ij
};

struct FormReport {
    int order = 0;
    std::vector<FormTerm> terms;
    double u_scale_um = 1.0;         // x = centre.x + u·u_scale_um
    double v_scale_um = 1.0;         // y = centre.y + v·v_scale_um
    Point2 centre_um;
    double mean_um = 0.0;            // the form's mean over the valid points
    double slope_x = 0.0;            // the fitted ∂H/∂x at the centre (dimensionless)
    double slope_y = 0.0;
    double rms_removed_um = 0.0;     // rms of the subtracted form about its mean, over the valid points
    double rms_residual_um = 0.0;    // rms of what remains (about zero)
    std::size_t fitted_points = 0;
    bool ended_periodicity = false;  // the field was periodic and no longer is (order >= 1)
};

// Subtracts the fitted form from the valid points (NaN stay NaN). order 0 removes the mean,
// 1 a plane. Throws Error for orders outside 0..kMaxFormOrder or when the valid points cannot
// determine the polynomial (too few rows or columns of valid points).
FormReport remove_form(Heightfield& field, int order);

// Parses "plane" (order 1), "mean" (order 0) or "poly:N" (N in 0..kMaxFormOrder); throws Error
// (a message without option name, for the caller to prefix) on anything else.
int parse_form_order(const std::string& text);

// ---- Crop (lib/src/crop.cpp) --------------------------------------------------------------

// A rectangle in map-view µm (conventions.md "Frames"): (x0_um, y0_um) is its lower-left
// corner measured from the lower-left corner of the field, the same frame as sample_position.
struct CropRegion {
    double x0_um = 0.0;
    double y0_um = 0.0;
    double width_um = 0.0;
    double height_um = 0.0;
};

struct CropReport {
    int first_row = 0;       // image row of the crop's top row in the original field
    int first_col = 0;
    int rows = 0;
    int cols = 0;
    Point2 origin_um;        // the crop's lower-left corner in the original field's frame
    int original_rows = 0;
    int original_cols = 0;
    double texel_um = 1.0;    // dx
    double texel_y_um = 1.0;  // dy
    bool ended_periodicity = false;  // a periodic field was cut to a part of itself
};

// Keeps rows [first_row, first_row + rows) and columns [first_col, first_col + cols) (image
// indices, row 0 at the top). Sample (r, c) of the result is sample (first_row + r, first_col + c)
// of the original, and sits at the original's position minus report.origin_um.
CropReport crop_samples(Heightfield& field, int first_row, int first_col, int rows, int cols);

// Keeps the texels whose cells lie in the region, its edges snapped to the nearest texel
// boundary. Throws Error if the region is not finite, extends outside the field (beyond a
// rounding tolerance), or is narrower than one texel.
CropReport crop(Heightfield& field, const CropRegion& region);

// ---- Resample (lib/src/resample.cpp) ------------------------------------------------------

struct ResampleReport {
    double original_texel_um = 0.0;    // dx
    double original_texel_y_um = 0.0;  // dy (the result's texels are square)
    double texel_um = 0.0;
    int original_rows = 0;
    int original_cols = 0;
    int rows = 0;
    int cols = 0;
    bool prefiltered = false;        // true when downsampling (area average before sampling)
    Tiling tiling = Tiling::none;
};

// Resamples to square texels of `texel_um` (from square or rectangular ones). The new grid has
// round(extent / texel) samples per axis (at least one), centred on the old extent, so the
// physical size changes by at most half a new texel per axis. Upsampling samples the shared
// BicubicInterpolant (the surface is unchanged); downsampling first averages the samples over the
// new texel's area (a box prefilter, each axis by its own ratio, that removes most detail the
// coarser grid cannot hold) and then samples the interpolant of that average. The field must have no missing points. Throws Error for missing points, for
// non-positive or non-finite texels, and for results beyond 2^31 samples.
ResampleReport resample(Heightfield& field, double texel_um, Tiling tiling = Tiling::none);

// ---- Orientation (lib/src/prepare/orient.cpp) ---------------------------------------------

// Mirrors and quarter turns in map view (x right, y up; docs/heightfields.md compares the
// orientations of other tools). Applied in this order: flip_x (x → W − x, columns reversed),
// flip_y (y → H − y, rows reversed), then rotate_degrees counter-clockwise: one quarter turn maps
// (x, y) to (H − y, x), so sample (r, c) of the result is sample (c, cols − 1 − r) of the input.
// Exact: the heights are moved, never interpolated, and the texel is unchanged.
struct Orientation {
    bool flip_x = false;
    bool flip_y = false;
    int rotate_degrees = 0;  // 0, 90, 180 or 270
};

struct OrientReport {
    Orientation orientation;
    int original_rows = 0;
    int original_cols = 0;
};

// Throws Error for a rotation other than 0, 90, 180 or 270 degrees.
OrientReport orient(Heightfield& field, const Orientation& orientation);

// Parses "0", "90", "180" or "270"; throws Error (without option name) on anything else.
int parse_rotation(const std::string& text);

// ---- ISO 16610-61 Gaussian filters (lib/src/prepare/gaussian_filter.cpp) ------------------

// The S-filter keeps the Gaussian mean surface of nesting index λs (removes wavelengths shorter
// than about λs); the L-filter subtracts that of λc (removes wavelengths longer than about λc).
// A sinusoid of wavelength λ passes at 50% amplitude. Missing points stay missing and, with the
// border of a non-periodic field, are left out of the weighted mean (a normalised
// convolution). Each records itself in the provenance. Throws Error for a nesting index that is
// not a positive length or is more than 20 times the field.
void apply_s_filter(Heightfield& field, double nesting_um);
void apply_l_filter(Heightfield& field, double nesting_um);

// ---- Reports -----------------------------------------------------------------------------

// One line each, e.g. "fill_missing: 1234 points (0.4%), biharmonic inpainting, ..." — the
// text recorded in provenance and printed by `convert`.
std::string describe(const FillReport& report);
std::string describe(const FormReport& report);
std::string describe(const CropReport& report);
std::string describe(const ResampleReport& report);
std::string describe(const OrientReport& report);

// Appends `description` to field.provenance as the next "prepare.N" entry.
void record_preparation(Heightfield& field, const std::string& description);

std::string to_string(FillMethod method);
FillMethod parse_fill_method(const std::string& text);  // "harmonic" or "biharmonic", else Error

}  // namespace glintscope
