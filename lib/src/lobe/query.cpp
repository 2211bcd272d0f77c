#include "glintscope/lobe.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "glintscope/error.hpp"
#include "glintscope/material.hpp"
#include "glintscope/text_format.hpp"
#include "glintscope/units.hpp"
#include "method_table.hpp"

namespace glintscope {
namespace {

std::string format_list(const std::vector<double>& values) {
    std::string text;
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (i > 0) text += ',';
        text += shortest_text(values[i]);
    }
    return text;
}

const LobeMethodEntry& find_method(const std::string& name) {
    for (const LobeMethodEntry& entry : lobe_method_table())
        if (entry.name == name) return entry;
    std::string known;
    for (const LobeMethodEntry& entry : lobe_method_table()) known += (known.empty() ? "" : ", ") + entry.name;
    throw Error("unknown lobe method '" + name + "' (available: " + known + ")");
}

}  // namespace

LobeImage make_lobe_image(int resolution, const std::vector<double>& wavelengths_um) {
    LobeImage image;
    image.resolution = resolution;
    image.wavelengths_um = wavelengths_um;
    image.values.assign(wavelengths_um.size() * resolution * static_cast<std::size_t>(resolution), 0.0f);
    return image;
}

void set_heightfield(LobeQuery& query, Heightfield field) {
    auto shared_field = std::make_shared<const Heightfield>(std::move(field));
    query.surface = std::make_shared<const BicubicInterpolant>(*shared_field);
    query.field = std::move(shared_field);
}

void validate(const LobeQuery& query) {
    if (!query.field || !query.surface) throw Error("lobe query has no heightfield");
    const Vec3 wi = query.omega_i;
    if (!std::isfinite(wi.x) || !std::isfinite(wi.y) || !std::isfinite(wi.z) ||
        std::fabs(length(wi) - 1.0) > 1e-9)
        throw Error("incident direction must be a finite unit vector");
    if (wi.z < 1e-3) throw Error("incident direction must lie above the surface (theta_i < 89.9 degrees)");
    if (query.wavelengths_um.empty()) throw Error("lobe query has no wavelength");
    for (double lambda : query.wavelengths_um)
        if (!(lambda >= 0.1 && lambda <= 20.0))
            throw Error("wavelength " + shortest_text(lambda) + " um is outside 0.1-20 um");
    const Footprint& footprint = query.footprint;
    if (!std::isfinite(footprint.centre_um.x) || !std::isfinite(footprint.centre_um.y))
        throw Error("footprint centre must be finite");
    if (footprint.shape == FootprintShape::gaussian && !(footprint.sigma_um > 0.0 && footprint.sigma_um <= 1e4))
        throw Error("coherence sigma must be between 0 and 10 mm, got " + shortest_text(footprint.sigma_um) + " um");
    if (footprint.shape == FootprintShape::box && !(footprint.size_um > 0.0 && footprint.size_um <= 1e5))
        throw Error("box footprint size must be between 0 and 100 mm, got " + shortest_text(footprint.size_um) +
                    " um");
    if (query.resolution < 4 || query.resolution > 8192)
        throw Error("lobe resolution must be between 4 and 8192, got " + std::to_string(query.resolution));
    // An unknown material, or a wavelength outside its table, fails here rather than mid-lobe.
    if (!query.material.name.empty())
        for (double lambda : query.wavelengths_um) complex_refractive_index(query.material.name, lambda);
    if (query.supersample < 1 || query.supersample > 16)
        throw Error("supersampling must be between 1 and 16, got " + std::to_string(query.supersample));
}

Provenance describe(const LobeQuery& query) {
    Provenance text;
    if (query.field)
        for (const auto& [key, value] : query.field->provenance) text["heightfield." + key] = value;
    if (query.field) {
        text["heightfield.size"] = std::to_string(query.field->cols) + "x" + std::to_string(query.field->rows);
        text["heightfield.texel_um"] = shortest_text(query.field->texel_um);
    }
    const Footprint& footprint = query.footprint;
    text["query.footprint.shape"] = footprint.shape == FootprintShape::gaussian ? "gaussian" : "box";
    text["query.footprint.centre_um"] = shortest_text(footprint.centre_um.x) + "," + shortest_text(footprint.centre_um.y);
    if (footprint.shape == FootprintShape::gaussian)
        text["query.footprint.sigma_um"] = shortest_text(footprint.sigma_um);
    else
        text["query.footprint.size_um"] = shortest_text(footprint.size_um);
    const Vec3 wi = query.omega_i;
    text["query.omega_i"] = shortest_text(wi.x) + "," + shortest_text(wi.y) + "," + shortest_text(wi.z);
    text["query.theta_i_deg"] = shortest_text(std::acos(std::fmin(1.0, wi.z)) * 180.0 / std::numbers::pi);
    text["query.phi_i_deg"] = shortest_text(std::atan2(wi.y, wi.x) * 180.0 / std::numbers::pi);
    text["query.wavelengths_um"] = format_list(query.wavelengths_um);
    text["query.model"] = to_string(query.model);
    text["query.material"] = query.material.name.empty() ? "none (F = 1)" : query.material.name;
    text["query.resolution"] = std::to_string(query.resolution);
    text["query.supersample"] = std::to_string(query.supersample);
    for (const auto& [key, value] : query.method_options) text["query.option." + key] = value;
    return text;
}

void check_method_options(const LobeQuery& query, const std::string& method, const std::vector<std::string>& known) {
    for (const auto& [key, value] : query.method_options) {
        bool found = false;
        for (const std::string& name : known) found = found || name == key;
        if (!found) {
            std::string list;
            for (const std::string& name : known) list += (list.empty() ? "" : ", ") + name;
            throw Error("method '" + method + "' has no option '" + key + "' (options: " +
                        (list.empty() ? "none" : list) + ")");
        }
    }
}

double method_option_number(const LobeQuery& query, const std::string& key, double fallback) {
    const auto it = query.method_options.find(key);
    if (it == query.method_options.end()) return fallback;
    char* end = nullptr;
    const double value = std::strtod(it->second.c_str(), &end);
    if (end == it->second.c_str() || *end != '\0' || !std::isfinite(value))
        throw Error("option " + key + "='" + it->second + "' is not a number");
    return value;
}

double method_option_length_um(const LobeQuery& query, const std::string& key, double fallback) {
    const auto it = query.method_options.find(key);
    if (it == query.method_options.end()) return fallback;
    try {
        return parse_length_um(it->second);
    } catch (const Error& e) {
        throw Error("option " + key + ": " + e.what());
    }
}

std::vector<std::string> lobe_method_names() {
    std::vector<std::string> names;
    for (const LobeMethodEntry& entry : lobe_method_table()) names.push_back(entry.name);
    return names;
}

std::string lobe_method_description(const std::string& name) { return find_method(name).description; }

LobeImage compute_lobe(const std::string& method, const LobeQuery& query) {
    const LobeMethodEntry& entry = find_method(method);
    validate(query);
    LobeImage image = entry.compute(query);
    for (const auto& [key, value] : describe(query)) image.metadata.emplace(key, value);
    image.metadata["method"] = method;
    return image;
}

}  // namespace glintscope
