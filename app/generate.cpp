// glintscope generate KIND [options] -o FILE: procedural heightfields (lib/include/glintscope/generate.hpp).
// Every recipe key is also an option (--sigma-h for sigma_h), so recipe files and command lines
// name parameters alike; options override the recipe or the kind's defaults.
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "glintscope/core/atomic_output.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/core/units.hpp"
#include "options.hpp"

namespace glintscope::cli {
namespace {

struct GenerateOptions {
    std::string kind;
    std::string recipe_path;
    std::string output;
    std::string size;
    std::map<std::string, double> lengths_um;                 // recipe key → value of a length option
    std::map<std::string, std::string> texts;                 // recipe key → text of any other option
    std::vector<std::pair<std::string, CLI::Option*>> given;  // recipe key → its option
};

std::string option_name(const std::string& key) {
    std::string name = "--" + key;
    for (char& ch : name)
        if (ch == '_') ch = '-';
    return name;
}

std::string join(const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
    return text;
}

std::string unit_suffix(const RecipeKey& key) {
    if (key.unit == "um") return " um";
    if (key.unit == "deg") return " deg";
    if (key.unit == "per_mm2") return " /mm^2";
    if (key.unit == "per_um") return " /um";
    return "";
}

// "[isotropic, brushed: 1.2 um; scratched: 0.02 um]": the defaults of every kind the key applies to.
std::string defaults_text(const RecipeKey& key) {
    std::vector<std::pair<std::string, std::vector<std::string>>> groups;  // value → kinds, in kind order
    for (const std::string& kind : key.kinds) {
        const std::string value = recipe_value(default_recipe(kind), key.name) + unit_suffix(key);
        auto group = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == value; });
        if (group == groups.end())
            groups.push_back({value, {kind}});
        else
            group->second.push_back(kind);
    }
    if (groups.size() == 1) return " [default " + groups.front().first + "; kinds: " + join(key.kinds) + "]";
    std::string text;
    for (const auto& [value, kinds] : groups) text += (text.empty() ? "" : "; ") + join(kinds) + ": " + value;
    return " [defaults " + text + "]";
}

std::string type_name(RecipeValueType type) {
    switch (type) {
        case RecipeValueType::length: return "LENGTH";
        case RecipeValueType::angle: return "DEGREES";
        case RecipeValueType::number: return "NUMBER";
        case RecipeValueType::integer: return "INT";
        case RecipeValueType::choice: return "NAME";
    }
    return "VALUE";
}

// A length in µm as text that parse_length_um reads back as the same double.
std::string exact_text(double value_um) {
    char buffer[64];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, value_um);
    return std::string(buffer, result.ptr);
}

void run_generate(const GenerateOptions& options) {
    if (!options.recipe_path.empty() && !options.kind.empty())
        throw Error("generate: give either a KIND or --recipe FILE, not both");
    if (options.recipe_path.empty() && options.kind.empty())
        throw Error("generate: give a KIND (" + join(generator_kinds()) + ") or --recipe FILE");
    check_output_path(options.output, {"exr", "x3p", "npy"}, "-o");  // before the work
    Recipe recipe = options.recipe_path.empty() ? default_recipe(options.kind) : load_recipe(options.recipe_path);
    if (!options.size.empty()) set_recipe_value(recipe, "size", options.size);
    for (const auto& [key, option] : options.given) {
        if (option->count() == 0) continue;
        const auto length = options.lengths_um.find(key);
        set_recipe_value(recipe, key, length != options.lengths_um.end() ? exact_text(length->second) : options.texts.at(key));
    }
    if (const std::string warning = seamless_warning(recipe); !warning.empty())
        std::fprintf(stderr, "glintscope: warning: %s\n", warning.c_str());
    const Heightfield field = generate(recipe);
    save_heightfield(options.output, field);
    std::printf("wrote %s: %s, %dx%d samples of %s (%s x %s)\n", options.output.c_str(), recipe.kind.c_str(), field.cols,
                field.rows, texel_text(field).c_str(), format_length(field.width_um()).c_str(),
                format_length(field.height_um()).c_str());
}

}  // namespace

void add_generate_command(CLI::App& app) {
    auto options = std::make_shared<GenerateOptions>();
    auto* command = app.add_subcommand(
        "generate",
        "Generate a procedural heightfield: " + join(generator_kinds()) +
            ".\nisotropic, brushed and scratched are the surfaces of Yan et al. 2018 Fig. 8; gaussian has Stam's "
            "correlation functions c1-c3; cd follows Stam 1999 Table 1. heightfields/*.recipe hold the 8192^2 "
            "versions. Lengths are um unless suffixed (0.5um, 500nm, 2mm); angles are degrees. Every option below is "
            "also a recipe key (--sigma-h is sigma_h).");
    command->add_option("kind", options->kind, "Surface kind: " + join(generator_kinds()));
    command->add_option("--recipe", options->recipe_path, "Recipe file of 'key = value' lines (see heightfields/)");
    command->add_option("-o,--output", options->output, "Output heightfield (.exr, .x3p or .npy)")->required();
    command->add_option("--size", options->size, "Sets rows and cols together")->type_name("INT");
    for (const RecipeKey& key : recipe_keys()) {
        const std::string description = key.description + defaults_text(key);
        CLI::Option* option = nullptr;
        if (key.type == RecipeValueType::length) {
            option = add_length_option(*command, option_name(key.name), options->lengths_um[key.name], description);
        } else {
            option = command->add_option(option_name(key.name), options->texts[key.name], description)
                         ->type_name(type_name(key.type));
        }
        options->given.emplace_back(key.name, option);
    }
    command->callback([options] { run_generate(*options); });
}

}  // namespace glintscope::cli
