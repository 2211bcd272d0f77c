// compute_lobe: the one owner of the generic work around a method (find, check, run, label).
#include <algorithm>
#include <chrono>
#include <cmath>

#include "glintscope/error.hpp"
#include "glintscope/query_keys.hpp"
#include "glintscope/text_format.hpp"
#include "glintscope/units.hpp"
#include "glintscope/version.hpp"
#include "method.hpp"

namespace glintscope {
namespace {

const MethodEntry& find_method(const std::string& name) {
    for (const MethodEntry& entry : method_table())
        if (entry.info.name == name) return entry;
    std::vector<std::string> known;
    for (const MethodEntry& entry : method_table()) known.push_back(entry.info.name);
    throw Error("unknown method '" + name + "' (available: " + join(known) + ")");
}

void check_quantity(const MethodInfo& method, Quantity quantity) {
    if (method.answers(quantity)) return;
    std::vector<std::string> able;
    for (const MethodEntry& entry : method_table())
        if (entry.info.answers(quantity)) able.push_back(entry.info.name);
    throw Error("method '" + method.name + "' does not compute " + to_string(quantity) + " (methods that do: " +
                (able.empty() ? "none" : join(able)) + ")");
}

// The query keys (query_keys.hpp) in which a field is written.
std::vector<std::string> keys_of(QueryField field) {
    switch (field) {
        case QueryField::footprint: return {"footprint", "centre", "sigma_c", "box"};
        case QueryField::incident: return {"omega_i"};
        case QueryField::wavelengths: return {"lambda"};
        case QueryField::model: return {"model"};
        case QueryField::material: return {"material"};
        case QueryField::supersample: return {"supersample"};
    }
    return {};
}

void label(LobeImage& image, const MethodInfo& method, const LobeQuery& query) {
    for (const auto& [key, value] : describe_query(query)) image.metadata.emplace(key, value);
    // A method may add fields it ignores for one quantity only (e.g. the incident direction of an NDF).
    std::vector<std::string> not_applicable;
    if (image.metadata.count("not_applicable")) not_applicable = split(image.metadata.at("not_applicable"), ',');
    for (QueryField field : method.ignored)
        for (const std::string& key : keys_of(field)) not_applicable.push_back(key);
    if (!not_applicable.empty()) image.metadata["not_applicable"] = join(not_applicable);
    image.metadata["method"] = method.name;
    image.metadata["method.reference"] = method.reference;
    image.metadata["quantity"] = to_string(query.quantity);
    image.metadata["heightfield.tiling"] = query.field->periodic ? "periodic" : "non-periodic";
}

const std::string& option_text(const LobeQuery& query, const std::string& key) {
    return query.method_options.at(key);
}

}  // namespace

void check_footprint(const MethodInfo& method, const Footprint& footprint) {
    if (footprint.shape != FootprintShape::whole || method.whole_field) return;
    std::vector<std::string> able;
    for (const MethodEntry& entry : method_table())
        if (entry.info.whole_field) able.push_back(entry.info.name);
    throw Error("method '" + method.name + "' needs a finite footprint, not the whole field (methods that take it: " +
                (able.empty() ? "none" : join(able)) + ")");
}

void check_option_keys(const MethodInfo& method, const LobeQuery& query) {
    for (const auto& option_value : query.method_options) {
        const std::string& key = option_value.first;  // a plain reference: lambdas may capture it
        const bool known = std::any_of(method.options.begin(), method.options.end(),
                                       [&](const MethodOption& option) { return option.key == key; });
        if (known) continue;
        std::vector<std::string> keys;
        for (const MethodOption& option : method.options) keys.push_back(option.key);
        throw Error("method '" + method.name + "' has no option '" + key + "' (options: " +
                    (keys.empty() ? "none" : join(keys)) + ")");
    }
}

std::string to_string(QueryField field) {
    switch (field) {
        case QueryField::footprint: return "footprint";
        case QueryField::incident: return "incident direction";
        case QueryField::wavelengths: return "wavelengths";
        case QueryField::model: return "diffraction model";
        case QueryField::material: return "material";
        case QueryField::supersample: return "supersampling";
    }
    return "?";
}

bool MethodInfo::answers(Quantity quantity) const {
    return std::find(quantities.begin(), quantities.end(), quantity) != quantities.end();
}

std::vector<MethodInfo> lobe_methods() {
    std::vector<MethodInfo> infos;
    for (const MethodEntry& entry : method_table()) infos.push_back(entry.info);
    return infos;
}

MethodInfo lobe_method(const std::string& name) { return find_method(name).info; }

LobeImage compute_lobe(const std::string& method, const LobeQuery& query) {
    const MethodEntry& entry = find_method(method);
    validate(query);
    check_quantity(entry.info, query.quantity);
    check_footprint(entry.info, query.footprint);
    const auto& ignored = entry.info.ignored;
    if (std::find(ignored.begin(), ignored.end(), QueryField::footprint) == ignored.end()) check_footprint_inside(query);
    LobeImage image;
    const auto start = std::chrono::steady_clock::now();
    try {
        check_option_keys(entry.info, query);
        image = entry.compute(query);
    } catch (const Error& e) {
        // Once: messages shared with a method's other entry points may already name it.
        const std::string what = e.what();
        throw Error(what.starts_with(method + ": ") ? what : method + ": " + what);
    }
    image.quantity = query.quantity;
    label(image, entry.info, query);
    image.metadata["version"] = version();
    image.metadata["run.seconds"] = shortest_text(
        std::round(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() * 1e3) / 1e3);
    return image;
}

double method_option_number(const LobeQuery& query, const std::string& key, double fallback) {
    if (!query.method_options.count(key)) return fallback;
    try {
        return parse_number(option_text(query, key));
    } catch (const Error& e) {
        throw Error("option " + key + ": " + e.what());
    }
}

double method_option_length_um(const LobeQuery& query, const std::string& key, double fallback) {
    if (!query.method_options.count(key)) return fallback;
    try {
        return parse_length_um(option_text(query, key));
    } catch (const Error& e) {
        throw Error("option " + key + ": " + e.what());
    }
}

int method_option_integer(const LobeQuery& query, const std::string& key, int fallback, int min, int max) {
    if (!query.method_options.count(key)) return fallback;
    try {
        return static_cast<int>(parse_integer(option_text(query, key), min, max));
    } catch (const Error& e) {
        throw Error("option " + key + ": " + e.what());
    }
}

std::string method_option_text(const LobeQuery& query, const std::string& key, const std::string& fallback) {
    return query.method_options.count(key) ? option_text(query, key) : fallback;
}

LobeImage compute_mean_lobe(const std::string& method, const LobeQuery& query, const std::vector<Point2>& centres) {
    if (centres.empty()) throw Error("averaging over footprints needs at least one centre");
    LobeImage mean;
    std::vector<double> sums;
    Point2 low{INFINITY, INFINITY}, high{-INFINITY, -INFINITY};
    for (const Point2& centre : centres) {
        LobeQuery one = query;
        one.footprint.centre_um = centre;
        LobeImage image = compute_lobe(method, one);
        if (sums.empty()) {
            mean = std::move(image);
            sums.assign(mean.values.begin(), mean.values.end());
        } else {
            for (std::size_t i = 0; i < sums.size(); ++i) sums[i] += image.values[i];
        }
        low = {std::min(low.x, centre.x), std::min(low.y, centre.y)};
        high = {std::max(high.x, centre.x), std::max(high.y, centre.y)};
    }
    for (std::size_t i = 0; i < sums.size(); ++i) mean.values[i] = static_cast<float>(sums[i] / centres.size());
    mean.metadata["footprints.count"] = std::to_string(centres.size());
    mean.metadata["footprints.centres_um"] = shortest_text(low.x) + "," + shortest_text(low.y) + " to " +
                                             shortest_text(high.x) + "," + shortest_text(high.y);
    return mean;
}

}  // namespace glintscope
