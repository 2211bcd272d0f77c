// The method vocabulary: what a MethodInfo answers and ignores, and method options as values.
#include "lobe/method.hpp"

#include <algorithm>

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope {
namespace {

template <typename Parse>
auto parse_option(const LobeQuery& query, const std::string& key, Parse parse) {
    try {
        return parse(query.method_options.at(key));
    } catch (const Error& e) {
        throw Error("option " + key + ": " + e.what());
    }
}

}  // namespace

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

bool MethodInfo::ignores(QueryField field) const { return std::find(ignored.begin(), ignored.end(), field) != ignored.end(); }

double method_option_number(const LobeQuery& query, const std::string& key, double fallback) {
    if (!query.method_options.count(key)) return fallback;
    return parse_option(query, key, [](const std::string& text) { return parse_number(text); });
}

double method_option_length_um(const LobeQuery& query, const std::string& key, double fallback) {
    if (!query.method_options.count(key)) return fallback;
    return parse_option(query, key, [](const std::string& text) { return parse_length_um(text); });
}

int method_option_integer(const LobeQuery& query, const std::string& key, int fallback, int min, int max) {
    if (!query.method_options.count(key)) return fallback;
    return parse_option(query, key, [&](const std::string& text) { return static_cast<int>(parse_integer(text, min, max)); });
}

std::string method_option_text(const LobeQuery& query, const std::string& key, const std::string& fallback) {
    return query.method_options.count(key) ? query.method_options.at(key) : fallback;
}

}  // namespace glintscope
