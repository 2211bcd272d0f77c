#pragma once
// Procedural heightfields: Gaussian random fields with Stam's correlation functions (Stam 1999
// §4.1), the isotropic, brushed and scratched metals of Yan et al. 2018 (Fig. 8, §6.1),
// sinusoidal gratings and CD-like bump tracks (Stam 1999 §5).
//
// A Recipe says what to make: a kind, a grid, a seed and the parameters of that kind. Recipes
// come from default_recipe(kind), from `key = value` text files (heightfields/*.recipe) or from
// the command line; the same key names serve all three and the provenance of the result.
// Every generator is deterministic: a recipe gives the same bits on any thread count (random
// numbers are a hash of (seed, stream, index), never a stream shared between threads).
// Lengths are µm; angles are radians here and degrees in recipe text and provenance.
#include <cstdint>
#include <string>
#include <vector>

#include "glintscope/surface/heightfield.hpp"

namespace glintscope {

// Stam 1999 §4.1: C1 = exp(−x²/T_x² − y²/T_y²) (smooth), C2 = exp(−√(x²/T_x² + y²/T_y²))
// (fractal-looking), C3 = exp(−|x|/T_x − |y|/T_y) (anisotropic even when T_x = T_y).
enum class CorrelationFunction { c1, c2, c3 };

struct GaussianFieldParameters {
    CorrelationFunction correlation = CorrelationFunction::c1;
    double sigma_h_um = 0.1;                 // rms height; every tile is rescaled to exactly this Sq
    double correlation_length_x_um = 10.0;   // T_x, along the direction `orientation_rad`
    double correlation_length_y_um = 10.0;   // T_y, perpendicular to it
    double orientation_rad = 0.0;            // from +x toward +y
};

// Cross-sections of a scratch, with s = 2u/w ∈ [−1, 1] across a groove of width w:
// parabolic 1 − s², v 1 − |s|, rounded √(1 − s²); mixed picks one at random per scratch.
enum class ScratchProfile { parabolic, v, rounded, mixed };

struct ScratchParameters {
    double density_per_mm2 = 50.0;  // scratch centres per mm² of tile
    double depth_min_um = 0.02;
    double depth_max_um = 0.25;
    double width_min_um = 1.0;
    double width_max_um = 5.0;
    double length_min_um = 100.0;
    double length_max_um = 1000.0;
    ScratchProfile profile = ScratchProfile::mixed;
};

// H = A sin(2π u/Λ) with u the distance along the direction `angle_rad` from +x.
struct GratingParameters {
    double period_um = 4.0;        // Λ
    double amplitude_um = 0.1;     // A
    double angle_rad = 0.0;        // θ
};

// Stam 1999 eq. 20: g⁰ = 1 (flat-topped CD bumps), g¹ = 1/2 + x/a (a ramp across the bump).
enum class BumpShape { flat, ramp };

// Overlapping Poisson bumps either add, as in Stam 1999 eq. 18 (matching his spectrum, Stam 1999 eq. 23, for
// weak phases), or merge into one bump of height h0, like the pits of a real disc.
enum class BumpOverlap { add, merge };

// Stam 1999 §5 and Table 1: bumps b(x, y) = h0 g(x/a) rect(x/a) rect(y/b) (Stam 1999 eq. 19) summed over
// tracks along y at x_n = (n + 1/2)Δx, Poisson distributed along each track (Stam 1999 eq. 18).
struct CdParameters {
    double bump_height_um = 0.15;       // h0
    double bump_width_um = 0.5;         // a (across the track, along x)
    double bump_length_um = 1.0;        // b (along the track, along y)
    double track_spacing_um = 2.5;      // Δx
    double bump_density_per_um = 0.5;   // ν_y
    BumpShape shape = BumpShape::flat;
    BumpOverlap overlap = BumpOverlap::add;
};

// Texels may be rectangular: every generator works in µm per axis, so the same recipe at 1 × 1 µm
// and at 1 × 2 µm describes the same surface, sampled twice as coarsely along y.
struct GridSpec {
    int rows = 1024;
    int cols = 1024;
    double texel_um = 1.0;    // dx, along x (columns)
    double texel_y_um = 0.0;  // dy, along y (rows); 0 means square texels (dy = dx)

    double dx_um() const { return texel_um; }
    double dy_um() const { return texel_y_um > 0.0 ? texel_y_um : texel_um; }
    double width_um() const { return cols * dx_um(); }
    double height_um() const { return rows * dy_um(); }
};

// kind: "isotropic", "brushed", "gaussian" (Gaussian random fields), "scratched" (scratches
// over a Gaussian base noise), "grating" or "cd". Only the parameters of the kind are used.
struct Recipe {
    std::string kind = "gaussian";
    GridSpec grid;
    std::uint64_t seed = 1;
    GaussianFieldParameters gaussian;
    ScratchParameters scratches;
    GratingParameters grating;
    CdParameters cd;
};

std::vector<std::string> generator_kinds();

// What a kind's built-in surface is, in one line (for `info builtin:KIND`); throws Error for
// unknown kinds as default_recipe does.
std::string kind_description(const std::string& kind);

// The built-in recipe of a kind (throws Error for unknown kinds). Sizes are modest so that
// `builtin:KIND` loads quickly: isotropic, brushed, scratched and gaussian 1024² at 1 µm,
// grating 1024² at 0.25 µm, cd 1000² at 0.1 µm. heightfields/*.recipe hold the 8192² surfaces.
Recipe default_recipe(const std::string& kind);

// ---- Recipe keys (lib/src/generate_recipe.cpp) -------------------------------------------

enum class RecipeValueType { length, angle, number, integer, choice };

struct RecipeKey {
    std::string name;                  // "sigma_h"; command-line option --sigma-h
    RecipeValueType type = RecipeValueType::number;
    std::string unit;                  // unit of the canonical value: "um", "deg", "per_mm2", ...
    std::string description;
    std::vector<std::string> kinds;    // the kinds it applies to
};

// Every key a recipe can set, in a fixed order. "size" sets rows and cols together.
const std::vector<RecipeKey>& recipe_keys();

// Sets one key from text (lengths take unit suffixes, angles are degrees). Throws Error naming
// the key if it is unknown, does not apply to recipe.kind, or the text is not a valid value.
void set_recipe_value(Recipe& recipe, const std::string& key, const std::string& text);

// The value of a key as canonical text (µm, degrees, plain numbers).
std::string recipe_value(const Recipe& recipe, const std::string& key);

// Reads `key = value` lines ('#' starts a comment). The kind line selects default_recipe(kind);
// the other lines override it. Throws Error naming the file and line for unknown or repeated
// keys, keys that do not apply to the kind, bad values, or a missing kind.
Recipe parse_recipe_text(const std::string& text, const std::string& source_name);
Recipe load_recipe(const std::string& path);

// Throws Error with a one-line message naming the key for absurd parameters: non-positive or
// non-finite lengths, min > max, correlation lengths beyond the tile, too many samples, ...
void validate_recipe(const Recipe& recipe);

// Empty, or a one-line warning when the surface is not seamless on its tile (a grating whose
// period does not divide the tile, CD tracks that do not fit a whole number of times).
std::string seamless_warning(const Recipe& recipe);

// ---- Generation ---------------------------------------------------------------------------

// Validates and generates. The provenance holds "generator" (gaussian, scratched, grating or
// cd), "generator.preset" (isotropic, brushed) and "generator.KEY_UNIT" for every key of the
// kind, e.g. "generator.sigma_h_um" = "0.05", "generator.seed" = "1".
Heightfield generate(const Recipe& recipe);

// generate(default_recipe(kind)).
Heightfield generate_builtin(const std::string& kind);

// The random placements behind the scratched and cd kinds, exposed so their statistics can be
// checked against the request.
struct Scratch {
    Point2 centre_um;
    double direction_rad = 0.0;
    double length_um = 0.0;
    double width_um = 0.0;
    double depth_um = 0.0;
    ScratchProfile profile = ScratchProfile::parabolic;  // never mixed
};
std::vector<Scratch> place_scratches(const GridSpec& grid, const ScratchParameters& parameters, std::uint64_t seed);

// Bump centres of the cd kind, track by track (x = (n + 1/2)Δx), y ∈ [0, tile height).
std::vector<Point2> place_cd_bumps(const GridSpec& grid, const CdParameters& parameters, std::uint64_t seed);

}  // namespace glintscope
