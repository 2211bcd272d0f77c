// generate(): validates a recipe, runs the generator of its kind and records the provenance.
#include <algorithm>

#include "generators.hpp"
#include "glintscope/generate/generate.hpp"

namespace glintscope {
namespace {

// The generator family behind each kind; isotropic and brushed are presets of gaussian.
std::string generator_name(const std::string& kind) {
    return kind == "isotropic" || kind == "brushed" ? "gaussian" : kind;
}

void generate_heights(const Recipe& recipe, Heightfield& field) {
    if (recipe.kind == "grating") {
        field.heights_um = sinusoidal_grating(recipe.grid, recipe.grating);
    } else if (recipe.kind == "cd") {
        field.heights_um = cd_tracks(recipe.grid, recipe.cd, recipe.seed);
    } else if (recipe.kind != "scratched") {
        field.heights_um = gaussian_random_field(recipe.grid, recipe.gaussian, recipe.seed);
    } else {
        field.heights_um = recipe.gaussian.sigma_h_um > 0.0
                               ? gaussian_random_field(recipe.grid, recipe.gaussian, recipe.seed)
                               : std::vector<float>(static_cast<std::size_t>(recipe.grid.rows) * recipe.grid.cols);
        carve_scratches(field, place_scratches(recipe.grid, recipe.scratches, recipe.seed));
    }
}

}  // namespace

Heightfield generate(const Recipe& recipe) {
    validate_recipe(recipe);
    Heightfield field;
    field.rows = recipe.grid.rows;
    field.cols = recipe.grid.cols;
    set_spacing(field, recipe.grid.dx_um(), recipe.grid.dy_um());
    generate_heights(recipe, field);

    const std::string generator = generator_name(recipe.kind);
    field.periodic = true;  // every generator makes one tile of a periodic surface
    field.provenance["generator"] = generator;
    if (generator != recipe.kind) field.provenance["generator.preset"] = recipe.kind;
    for (const RecipeKey& key : recipe_keys()) {
        if (std::find(key.kinds.begin(), key.kinds.end(), recipe.kind) == key.kinds.end()) continue;
        field.provenance["generator." + key.name + (key.unit.empty() ? "" : "_" + key.unit)] =
            recipe_value(recipe, key.name);
    }
    if (const std::string warning = seamless_warning(recipe); !warning.empty())
        field.provenance["generator.warning"] = warning;
    return field;
}

Heightfield generate_builtin(const std::string& kind) { return generate(default_recipe(kind)); }

}  // namespace glintscope
