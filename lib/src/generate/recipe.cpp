// Recipes: the built-in defaults of every kind, the key table shared by recipe files, the command
// line and provenance, parsing, and validation.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <sstream>

#include "glintscope/core/geometry.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "glintscope/surface/square_texels.hpp"

namespace glintscope {
namespace {

const std::vector<std::string> kAllKinds = {"isotropic", "brushed", "scratched", "gaussian", "grating", "cd"};
const std::vector<std::string> kGaussianKinds = {"isotropic", "brushed", "scratched", "gaussian"};
const std::vector<std::string> kRandomKinds = {"isotropic", "brushed", "scratched", "gaussian", "cd"};

constexpr int kMaxSide = 65536;
constexpr std::size_t kMaxSamples = std::size_t{1} << 30;  // 4 GB of heights plus 4 GB of spectrum
constexpr double kMaxScratches = 1e6;
constexpr double kMaxBumps = 1e8;

int parse_side(const std::string& text) {
    const long long value = parse_integer(text, std::numeric_limits<long long>::min(), std::numeric_limits<long long>::max());
    if (value < 1 || value > kMaxSide)
        throw Error("'" + text + "' is not a grid size between 1 and " + std::to_string(kMaxSide));
    return static_cast<int>(value);
}

template <typename Enum>
struct ChoiceName {
    Enum value;
    const char* name;
};

constexpr ChoiceName<CorrelationFunction> kCorrelationNames[] = {
    {CorrelationFunction::c1, "c1"}, {CorrelationFunction::c2, "c2"}, {CorrelationFunction::c3, "c3"}};
constexpr ChoiceName<ScratchProfile> kProfileNames[] = {{ScratchProfile::parabolic, "parabolic"},
                                                        {ScratchProfile::v, "v"},
                                                        {ScratchProfile::rounded, "rounded"},
                                                        {ScratchProfile::mixed, "mixed"}};
constexpr ChoiceName<BumpShape> kBumpShapeNames[] = {{BumpShape::flat, "flat"}, {BumpShape::ramp, "ramp"}};
constexpr ChoiceName<BumpOverlap> kBumpOverlapNames[] = {{BumpOverlap::add, "add"}, {BumpOverlap::merge, "merge"}};

template <typename Enum, std::size_t N>
Enum parse_choice(const ChoiceName<Enum> (&names)[N], const std::string& text) {
    const std::string_view trimmed = trim(text);
    std::string expected;
    for (const auto& entry : names) {
        if (trimmed == entry.name) return entry.value;
        expected += (expected.empty() ? "" : ", ") + std::string(entry.name);
    }
    throw Error("'" + text + "' is not one of " + expected);
}

template <typename Enum, std::size_t N>
std::string choice_name(const ChoiceName<Enum> (&names)[N], Enum value) {
    for (const auto& entry : names)
        if (entry.value == value) return entry.name;
    return "?";
}

struct KeyBinding {
    RecipeKey key;
    std::function<void(Recipe&, const std::string&)> set;
    std::function<std::string(const Recipe&)> get;
};

using DoubleField = std::function<double&(Recipe&)>;

KeyBinding length_key(const std::string& name, const std::string& description, const std::vector<std::string>& kinds,
                      const DoubleField& field) {
    return {{name, RecipeValueType::length, "um", description, kinds},
            [field](Recipe& recipe, const std::string& text) { field(recipe) = parse_length_um(text); },
            [field](const Recipe& recipe) { return shortest_text(field(const_cast<Recipe&>(recipe))); }};
}

KeyBinding number_key(const std::string& name, const std::string& unit, const std::string& description,
                      const std::vector<std::string>& kinds, const DoubleField& field) {
    return {{name, RecipeValueType::number, unit, description, kinds},
            [field](Recipe& recipe, const std::string& text) { field(recipe) = parse_number(text); },
            [field](const Recipe& recipe) { return shortest_text(field(const_cast<Recipe&>(recipe))); }};
}

// Degrees in text, radians in the recipe; %.12g hides the round trip's last-digit noise.
KeyBinding angle_key(const std::string& name, const std::string& description, const std::vector<std::string>& kinds,
                     const DoubleField& field) {
    return {{name, RecipeValueType::angle, "deg", description, kinds},
            [field](Recipe& recipe, const std::string& text) { field(recipe) = degrees_to_radians(parse_number(text)); },
            [field](const Recipe& recipe) {
                char buffer[64];
                std::snprintf(buffer, sizeof buffer, "%.12g",
                              field(const_cast<Recipe&>(recipe)) * 180.0 / pi);
                return std::string(buffer);
            }};
}

template <typename Enum, std::size_t N>
KeyBinding choice_key(const std::string& name, const std::string& description, const std::vector<std::string>& kinds,
                      const ChoiceName<Enum> (&names)[N], const std::function<Enum&(Recipe&)>& field) {
    return {{name, RecipeValueType::choice, "", description, kinds},
            [field, &names](Recipe& recipe, const std::string& text) { field(recipe) = parse_choice(names, text); },
            [field, &names](const Recipe& recipe) { return choice_name(names, field(const_cast<Recipe&>(recipe))); }};
}

const std::vector<KeyBinding>& bindings() {
    static const std::vector<KeyBinding> table = {
        {{"rows", RecipeValueType::integer, "", "grid rows (along y)", kAllKinds},
         [](Recipe& r, const std::string& text) { r.grid.rows = parse_side(text); },
         [](const Recipe& r) { return std::to_string(r.grid.rows); }},
        {{"cols", RecipeValueType::integer, "", "grid columns (along x)", kAllKinds},
         [](Recipe& r, const std::string& text) { r.grid.cols = parse_side(text); },
         [](const Recipe& r) { return std::to_string(r.grid.cols); }},
        length_key("texel", "sample spacing dx (along x; also dy unless texel_y is given)", kAllKinds,
                   [](Recipe& r) -> double& { return r.grid.texel_um; }),
        // Read back as the effective dy, so a recipe written out and read again keeps its grid.
        {{"texel_y", RecipeValueType::length, "um", "sample spacing dy along y, for rectangular texels (as texel unless given)",
          kAllKinds},
         [](Recipe& r, const std::string& text) {
             r.grid.texel_y_um = parse_length_um(text);
             if (!(r.grid.texel_y_um > 0.0) || !std::isfinite(r.grid.texel_y_um))  // 0 would mean "square"
                 throw Error("must be a positive length, got '" + text + "'");
         },
         [](const Recipe& r) { return shortest_text(r.grid.dy_um()); }},
        {{"seed", RecipeValueType::integer, "", "random seed (same seed, same surface on any thread count)",
          kRandomKinds},
         [](Recipe& r, const std::string& text) { r.seed = parse_unsigned(text); },
         [](const Recipe& r) { return std::to_string(r.seed); }},
        choice_key<CorrelationFunction>(
            "correlation",
            "correlation function (Stam 1999): c1 exp(-x²/Tx²-y²/Ty²) smooth, c2 exp(-sqrt(x²/Tx²+y²/Ty²)) "
            "fractal-looking, c3 exp(-|x|/Tx-|y|/Ty)",
            kGaussianKinds, kCorrelationNames, [](Recipe& r) -> CorrelationFunction& { return r.gaussian.correlation; }),
        length_key("sigma_h", "rms height Sq of the Gaussian field (scratched: of the base noise)", kGaussianKinds,
                   [](Recipe& r) -> double& { return r.gaussian.sigma_h_um; }),
        length_key("correlation_length_x", "correlation length Tx, along the orientation", kGaussianKinds,
                   [](Recipe& r) -> double& { return r.gaussian.correlation_length_x_um; }),
        length_key("correlation_length_y", "correlation length Ty, across the orientation", kGaussianKinds,
                   [](Recipe& r) -> double& { return r.gaussian.correlation_length_y_um; }),
        angle_key("orientation", "direction of Tx, degrees from +x toward +y", kGaussianKinds,
                  [](Recipe& r) -> double& { return r.gaussian.orientation_rad; }),
        number_key("scratch_density", "per_mm2", "scratches per mm² of tile", {"scratched"},
                   [](Recipe& r) -> double& { return r.scratches.density_per_mm2; }),
        length_key("scratch_depth_min", "smallest scratch depth", {"scratched"},
                   [](Recipe& r) -> double& { return r.scratches.depth_min_um; }),
        length_key("scratch_depth_max", "largest scratch depth", {"scratched"},
                   [](Recipe& r) -> double& { return r.scratches.depth_max_um; }),
        length_key("scratch_width_min", "smallest scratch width", {"scratched"},
                   [](Recipe& r) -> double& { return r.scratches.width_min_um; }),
        length_key("scratch_width_max", "largest scratch width", {"scratched"},
                   [](Recipe& r) -> double& { return r.scratches.width_max_um; }),
        length_key("scratch_length_min", "shortest scratch", {"scratched"},
                   [](Recipe& r) -> double& { return r.scratches.length_min_um; }),
        length_key("scratch_length_max", "longest scratch", {"scratched"},
                   [](Recipe& r) -> double& { return r.scratches.length_max_um; }),
        choice_key<ScratchProfile>("scratch_profile",
                                   "groove cross-section: parabolic, v, rounded, or mixed (random per scratch)",
                                   {"scratched"}, kProfileNames,
                                   [](Recipe& r) -> ScratchProfile& { return r.scratches.profile; }),
        length_key("period", "grating period Λ", {"grating"}, [](Recipe& r) -> double& { return r.grating.period_um; }),
        length_key("amplitude", "grating amplitude A in H = A sin(2π u/Λ)", {"grating"},
                   [](Recipe& r) -> double& { return r.grating.amplitude_um; }),
        angle_key("angle", "direction of u, degrees from +x toward +y", {"grating"},
                  [](Recipe& r) -> double& { return r.grating.angle_rad; }),
        length_key("bump_height", "bump height h0", {"cd"}, [](Recipe& r) -> double& { return r.cd.bump_height_um; }),
        length_key("bump_width", "bump width a, across the track (x)", {"cd"},
                   [](Recipe& r) -> double& { return r.cd.bump_width_um; }),
        length_key("bump_length", "bump length b, along the track (y)", {"cd"},
                   [](Recipe& r) -> double& { return r.cd.bump_length_um; }),
        length_key("track_spacing", "track separation Δx", {"cd"},
                   [](Recipe& r) -> double& { return r.cd.track_spacing_um; }),
        number_key("bump_density", "per_um", "bumps per µm along a track, Poisson distributed (ν_y)", {"cd"},
                   [](Recipe& r) -> double& { return r.cd.bump_density_per_um; }),
        choice_key<BumpShape>("bump_shape", "flat (Stam's g⁰ = 1) or ramp (g¹ = 1/2 + x/a)", {"cd"}, kBumpShapeNames,
                              [](Recipe& r) -> BumpShape& { return r.cd.shape; }),
        choice_key<BumpOverlap>("bump_overlap",
                                "overlapping bumps: add (Stam 1999 eq. 18 sum) or merge (one pit of height h0)", {"cd"},
                                kBumpOverlapNames, [](Recipe& r) -> BumpOverlap& { return r.cd.overlap; }),
    };
    return table;
}

const KeyBinding& binding(const std::string& key) {
    for (const KeyBinding& entry : bindings())
        if (entry.key.name == key) return entry;
    throw Error("unknown key '" + key + "'");
}

bool applies(const RecipeKey& key, const std::string& kind) {
    return std::find(key.kinds.begin(), key.kinds.end(), kind) != key.kinds.end();
}

bool is_gaussian_kind(const std::string& kind) {
    return std::find(kGaussianKinds.begin(), kGaussianKinds.end(), kind) != kGaussianKinds.end();
}

void require_positive(const std::string& key, double value_um) {
    if (!(value_um > 0.0) || !std::isfinite(value_um))
        throw Error(key + " must be a positive length, got " + format_length(value_um));
}

void require_range(const std::string& min_key, double min_um, const std::string& max_key, double max_um) {
    require_positive(min_key, min_um);
    require_positive(max_key, max_um);
    if (min_um > max_um)
        throw Error(min_key + " (" + format_length(min_um) + ") is larger than " + max_key + " (" +
                    format_length(max_um) + ")");
}

void validate_grid(const GridSpec& grid) {
    if (grid.rows < 1 || grid.cols < 1 || grid.rows > kMaxSide || grid.cols > kMaxSide)
        throw Error("grid " + std::to_string(grid.cols) + "x" + std::to_string(grid.rows) +
                    ": rows and cols must be between 1 and " + std::to_string(kMaxSide));
    if (static_cast<std::size_t>(grid.rows) * static_cast<std::size_t>(grid.cols) > kMaxSamples)
        throw Error("grid " + std::to_string(grid.cols) + "x" + std::to_string(grid.rows) +
                    " has more than 2^30 samples, the limit for generated heightfields (it would need about " +
                    shortest_text(std::ceil(8.0 * grid.rows * double(grid.cols) / 1e8) / 10.0) +
                    " GB: 4 bytes of height and 4 of spectrum per sample)");
    require_positive("texel", grid.texel_um);
    if (grid.texel_y_um != 0.0) require_positive("texel_y", grid.texel_y_um);
    const double aspect = std::max(grid.dx_um(), grid.dy_um()) / std::min(grid.dx_um(), grid.dy_um());
    if (aspect > kMaxTexelAspect)
        throw Error("texel " + format_length(grid.dx_um()) + " and texel_y " + format_length(grid.dy_um()) +
                    " differ by more than " + shortest_text(kMaxTexelAspect) + " times");
}

void validate_gaussian(const Recipe& recipe) {
    const GaussianFieldParameters& g = recipe.gaussian;
    const bool base_noise = recipe.kind == "scratched";
    if (!(g.sigma_h_um > 0.0 || (base_noise && g.sigma_h_um == 0.0)) || !std::isfinite(g.sigma_h_um))
        throw Error(std::string("sigma_h must be a ") + (base_noise ? "non-negative" : "positive") +
                    " length, got " + format_length(g.sigma_h_um));
    require_positive("correlation_length_x", g.correlation_length_x_um);
    require_positive("correlation_length_y", g.correlation_length_y_um);
    if (!std::isfinite(g.orientation_rad)) throw Error("orientation must be a finite angle");
    // The half-extents of the correlation ellipse along x and y must fit in the tile, or the
    // tile cannot hold even one correlation length and the field is not what was asked for.
    const double c = std::cos(g.orientation_rad);
    const double s = std::sin(g.orientation_rad);
    const double extent_x = std::hypot(g.correlation_length_x_um * c, g.correlation_length_y_um * s);
    const double extent_y = std::hypot(g.correlation_length_x_um * s, g.correlation_length_y_um * c);
    const double width = recipe.grid.width_um();
    const double height = recipe.grid.height_um();
    if (extent_x > width || extent_y > height)
        throw Error("correlation lengths (" + format_length(g.correlation_length_x_um) + ", " +
                    format_length(g.correlation_length_y_um) + ") exceed the " + format_length(width) + " x " +
                    format_length(height) + " tile");
}

void validate_scratches(const Recipe& recipe) {
    const ScratchParameters& s = recipe.scratches;
    if (!(s.density_per_mm2 >= 0.0) || !std::isfinite(s.density_per_mm2))
        throw Error("scratch_density must be a non-negative number per mm^2");
    const double area_mm2 = recipe.grid.width_um() * recipe.grid.height_um() * 1e-6;
    if (s.density_per_mm2 * area_mm2 > kMaxScratches)
        throw Error("scratch_density " + shortest_text(s.density_per_mm2) + " per mm^2 asks for more than 10^6 scratches");
    require_range("scratch_depth_min", s.depth_min_um, "scratch_depth_max", s.depth_max_um);
    require_range("scratch_width_min", s.width_min_um, "scratch_width_max", s.width_max_um);
    require_range("scratch_length_min", s.length_min_um, "scratch_length_max", s.length_max_um);
}

void validate_grating(const Recipe& recipe) {
    const GratingParameters& g = recipe.grating;
    require_positive("period", g.period_um);
    require_positive("amplitude", g.amplitude_um);
    if (!std::isfinite(g.angle_rad)) throw Error("angle must be a finite angle");
    // Two samples per period along the axis the grating varies along (or the longer texel side
    // when it is oblique), so its wave vector lies inside the sampling band.
    const double spacing = std::fabs(std::sin(g.angle_rad)) < 1e-12   ? recipe.grid.dx_um()
                           : std::fabs(std::cos(g.angle_rad)) < 1e-12 ? recipe.grid.dy_um()
                                                                      : std::max(recipe.grid.dx_um(), recipe.grid.dy_um());
    if (g.period_um < 2.0 * spacing)
        throw Error("period (" + format_length(g.period_um) + ") is shorter than two texels (" +
                    format_length(2.0 * spacing) + "); the grating cannot be sampled");
}

void validate_cd(const Recipe& recipe) {
    const CdParameters& cd = recipe.cd;
    require_positive("bump_height", cd.bump_height_um);
    require_positive("bump_width", cd.bump_width_um);
    require_positive("bump_length", cd.bump_length_um);
    require_positive("track_spacing", cd.track_spacing_um);
    if (!(cd.bump_density_per_um > 0.0) || !std::isfinite(cd.bump_density_per_um))
        throw Error("bump_density must be a positive number per um, got " + shortest_text(cd.bump_density_per_um));
    const double width = recipe.grid.width_um();
    const double height = recipe.grid.height_um();
    if (cd.bump_width_um > cd.track_spacing_um)
        throw Error("bump_width (" + format_length(cd.bump_width_um) + ") is wider than track_spacing (" +
                    format_length(cd.track_spacing_um) + ")");
    if (cd.track_spacing_um > width)
        throw Error("track_spacing (" + format_length(cd.track_spacing_um) + ") exceeds the tile width (" +
                    format_length(width) + ")");
    if (cd.bump_length_um >= height)
        throw Error("bump_length (" + format_length(cd.bump_length_um) + ") is not shorter than the tile height (" +
                    format_length(height) + ")");
    if (cd.bump_density_per_um * height * std::floor(width / cd.track_spacing_um) > kMaxBumps)
        throw Error("bump_density " + shortest_text(cd.bump_density_per_um) + " per um asks for more than 10^8 bumps");
}

bool near_integer(double value) { return std::fabs(value - std::round(value)) < 1e-6; }

}  // namespace

std::vector<std::string> generator_kinds() { return kAllKinds; }

std::string kind_description(const std::string& kind) {
    default_recipe(kind);  // refuses unknown kinds
    if (kind == "isotropic")
        return "Yan 2018 Fig. 8 (left): isotropic Gaussian bumps, correlation c1, sigma_h 1.2 um, T 10 um (rms slope "
               "0.17 per axis)";
    if (kind == "brushed")
        return "Yan 2018 Fig. 8 (middle): brushed metal, grooves along x, correlation c1, sigma_h 0.3 um, T 256 x 4 um "
               "(rms slope 0.11 across, 0.002 along)";
    if (kind == "scratched")
        return "Yan 2018 Fig. 8 (right): random scratches, 50 per mm^2, over a weak base noise (rms slope 0.006)";
    if (kind == "gaussian") return "a Gaussian random field with Stam 1999's correlation c1, sigma_h 0.1 um, T 10 um";
    if (kind == "grating") return "a sinusoidal grating H = A sin(2 pi x / period), A 0.1 um, period 4 um";
    return "a compact disc: Stam 1999 Table 1's bumps (0.15 um high, 0.5 x 1 um) on tracks 2.5 um apart";
}

Recipe default_recipe(const std::string& kind) {
    Recipe recipe;
    recipe.kind = kind;
    if (kind == "isotropic") {
        // Yan 2018 Fig. 8 (left), isotropic bumps: for C1 the rms slope along each axis is
        // √2 σ_h/T = 0.17 (the rms of |∇H| is 2σ_h/T = 0.24).
        recipe.gaussian = {CorrelationFunction::c1, 1.2, 10.0, 10.0, 0.0};
    } else if (kind == "brushed") {
        // Yan 2018 Fig. 8 (middle), brushed metal: grooves along x, 64× longer than wide; rms
        // slope √2 σ_h/T_y = 0.11 across them, 0.002 along them.
        recipe.gaussian = {CorrelationFunction::c1, 0.3, 256.0, 4.0, 0.0};
    } else if (kind == "scratched") {
        // Yan 2018 Fig. 8 (right): scratches over a weak base noise (rms slope 0.006).
        recipe.gaussian = {CorrelationFunction::c1, 0.02, 5.0, 5.0, 0.0};
    } else if (kind == "gaussian") {
        recipe.gaussian = {CorrelationFunction::c1, 0.1, 10.0, 10.0, 0.0};
    } else if (kind == "grating") {
        recipe.grid = {1024, 1024, 0.25};  // 64 periods of 4 µm: seamless
    } else if (kind == "cd") {
        recipe.grid = {1000, 1000, 0.1};   // 40 tracks of 2.5 µm: seamless; a bump is 5 × 10 texels
    } else {
        std::string kinds;
        for (const std::string& known : kAllKinds) kinds += (kinds.empty() ? "" : ", ") + known;
        throw Error("unknown heightfield kind '" + kind + "' (expected " + kinds + ")");
    }
    return recipe;
}

const std::vector<RecipeKey>& recipe_keys() {
    static const std::vector<RecipeKey> keys = [] {
        std::vector<RecipeKey> result;
        for (const KeyBinding& entry : bindings()) result.push_back(entry.key);
        return result;
    }();
    return keys;
}

void set_recipe_value(Recipe& recipe, const std::string& key, const std::string& text) {
    if (key == "size") {
        try {
            recipe.grid.rows = recipe.grid.cols = parse_side(text);
        } catch (const Error& e) {
            throw Error("size: " + std::string(e.what()));
        }
        return;
    }
    const KeyBinding& entry = binding(key);
    if (!applies(entry.key, recipe.kind)) {
        std::string kinds;
        for (const std::string& kind : entry.key.kinds) kinds += (kinds.empty() ? "" : ", ") + kind;
        throw Error(key + " does not apply to kind '" + recipe.kind + "' (only to " + kinds + ")");
    }
    try {
        entry.set(recipe, text);
    } catch (const Error& e) {
        throw Error(key + ": " + e.what());
    }
}

std::string recipe_value(const Recipe& recipe, const std::string& key) { return binding(key).get(recipe); }

Recipe parse_recipe_text(const std::string& text, const std::string& source_name) {
    struct Line {
        int number;
        std::string key;
        std::string value;
    };
    std::vector<Line> lines;
    std::istringstream stream(text);
    std::string raw;
    for (int number = 1; std::getline(stream, raw); ++number) {
        const std::string_view content = trim(std::string_view(raw).substr(0, raw.find('#')));
        if (content.empty()) continue;
        const std::size_t equals = content.find('=');
        if (equals == std::string_view::npos)
            throw Error(source_name + " line " + std::to_string(number) + ": expected 'key = value', got '" +
                        std::string(content) + "'");
        lines.push_back({number, std::string(trim(content.substr(0, equals))),
                         std::string(trim(content.substr(equals + 1)))});
    }
    std::set<std::string> seen;
    const Line* kind_line = nullptr;
    for (const Line& line : lines) {
        if (!seen.insert(line.key).second)
            throw Error(source_name + " line " + std::to_string(line.number) + ": '" + line.key + "' is set twice");
        if (line.key == "kind") kind_line = &line;
    }
    if (!kind_line) throw Error(source_name + ": no 'kind = ...' line");
    Recipe recipe;
    try {
        recipe = default_recipe(kind_line->value);
    } catch (const Error& e) {
        throw Error(source_name + " line " + std::to_string(kind_line->number) + ": " + e.what());
    }
    for (const Line& line : lines) {
        if (&line == kind_line) continue;
        try {
            set_recipe_value(recipe, line.key, line.value);
        } catch (const Error& e) {
            throw Error(source_name + " line " + std::to_string(line.number) + ": " + e.what());
        }
    }
    return recipe;
}

Recipe load_recipe(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw Error("cannot read recipe '" + path + "': no such file");
    std::ifstream file(path, std::ios::binary);
    std::ostringstream text;
    text << file.rdbuf();
    if (!file) throw Error("cannot read recipe '" + path + "'");
    return parse_recipe_text(text.str(), path);
}

void validate_recipe(const Recipe& recipe) {
    default_recipe(recipe.kind);  // throws for unknown kinds
    validate_grid(recipe.grid);
    if (is_gaussian_kind(recipe.kind)) validate_gaussian(recipe);
    if (recipe.kind == "scratched") validate_scratches(recipe);
    if (recipe.kind == "grating") validate_grating(recipe);
    if (recipe.kind == "cd") validate_cd(recipe);
}

std::string seamless_warning(const Recipe& recipe) {
    const double width = recipe.grid.width_um();
    const double height = recipe.grid.height_um();
    if (recipe.kind == "grating") {
        const double periods_x = width * std::cos(recipe.grating.angle_rad) / recipe.grating.period_um;
        const double periods_y = height * std::sin(recipe.grating.angle_rad) / recipe.grating.period_um;
        if (!near_integer(periods_x) || !near_integer(periods_y))
            return "the grating is not seamless: the tile holds " + shortest_text(std::fabs(periods_x)) + " x " +
                   shortest_text(std::fabs(periods_y)) + " periods along x and y, not whole numbers";
    }
    if (recipe.kind == "cd" && !near_integer(width / recipe.cd.track_spacing_um))
        return "the cd tracks are not seamless: the tile width " + format_length(width) +
               " is not a multiple of track_spacing " + format_length(recipe.cd.track_spacing_um);
    return {};
}

}  // namespace glintscope
