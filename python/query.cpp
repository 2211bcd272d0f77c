// Keyword arguments as query keys, and the query of a Python call: the one place where Python
// values become the text the library's query-key table reads (query_keys.hpp), so a keyword
// means exactly what the CLI flag of the same name means.
#include <algorithm>
#include <set>

#include "bindings.hpp"

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/surface/heightfield.hpp"
#include "glintscope/surface/interpolant.hpp"

namespace glintscope::python {

namespace {

// The keys that say how a file is read; a Heightfield object has been read already.
const std::vector<std::string> kLoadKeys = {"channel", "height_unit", "texel", "height_scale", "periodic"};

bool is_sequence(py::handle value) {
    return py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value) ||
           (py::isinstance<py::array>(value) && py::reinterpret_borrow<py::array>(value).ndim() > 0);
}

std::set<std::string> method_option_keys() {
    std::set<std::string> keys;
    for (const MethodInfo& info : lobe_methods())
        for (const MethodOption& option : info.options) keys.insert(option.key);
    return keys;
}

bool is_query_key(const std::string& name) {
    const auto& keys = query_keys();
    return std::any_of(keys.begin(), keys.end(), [&](const QueryKey& key) { return key.name == name; });
}

// The interpolant of a Heightfield object, built on its first query and kept on the object: a
// Heightfield never changes (its view is read-only; preparation steps return new objects), and
// rebuilding it on every call would cost more than a small lobe.
std::shared_ptr<const BicubicInterpolant> interpolant_of(py::handle heightfield) {
    using Held = std::shared_ptr<const BicubicInterpolant>;
    if (py::hasattr(heightfield, "_interpolant"))
        return *static_cast<Held*>(heightfield.attr("_interpolant").cast<py::capsule>().get_pointer());
    const auto field = heightfield.cast<std::shared_ptr<Heightfield>>();
    Held surface;
    {
        py::gil_scoped_release release;
        surface = std::make_shared<const BicubicInterpolant>(*field);
    }
    heightfield.attr("_interpolant") = py::capsule(new Held(surface), [](void* held) { delete static_cast<Held*>(held); });
    return surface;
}

}  // namespace

std::string value_text(py::handle value, const std::string& separator) {
    if (py::isinstance<py::str>(value)) return value.cast<std::string>();
    if (py::isinstance<py::bool_>(value) || py::isinstance(value, py::module_::import("numpy").attr("bool_")))
        return PyObject_IsTrue(value.ptr()) == 1 ? "yes" : "no";
    if (is_sequence(value)) {
        std::vector<std::string> parts;
        for (py::handle item : py::iter(value)) parts.push_back(value_text(item, separator));
        return join(parts, separator);
    }
    if (py::hasattr(value, "__index__")) return std::to_string(value.attr("__index__")().cast<long long>());
    if (py::hasattr(value, "__float__")) return shortest_text(value.attr("__float__")().cast<double>());
    throw Error("cannot use a value of type " + py::str(value.get_type().attr("__name__")).cast<std::string>() +
                " as a query value (give a str, a number or a sequence of them)");
}

QueryText keyword_query_text(const py::kwargs& keywords) {
    static const std::set<std::string> option_keys = method_option_keys();
    QueryText text;
    for (const auto& [key_object, value] : keywords) {
        if (value.is_none()) continue;  // not given, so that sweeps can pass optional keys through
        std::string key = key_object.cast<std::string>();
        if (key == "lambda_") key = "lambda";
        const std::string separator = key == "box" ? "x" : ",";
        if (!is_query_key(key) && option_keys.count(key)) key = "option." + key;
        text.emplace_back(key, value_text(value, separator));
    }
    return text;
}

LobeQuery python_query(py::handle heightfield, const py::kwargs& keywords, Quantity quantity) {
    QueryText text = keyword_query_text(keywords);
    for (const auto& [key, value] : text) {
        if (key == "quantity") throw Error("query key quantity is set by the function called (lobe: brdf, ndf: ndf)");
        if (key == "heightfield") throw Error("the heightfield is the first argument, not a keyword");
    }
    text.emplace_back("quantity", to_string(quantity));
    if (py::isinstance<py::str>(heightfield)) {
        text.insert(text.begin(), {"heightfield", heightfield.cast<std::string>()});
        py::gil_scoped_release release;  // a file to read, or a builtin surface to generate
        return make_query(text);
    }
    if (!py::isinstance<Heightfield>(heightfield))
        throw Error("the heightfield must be a glintscope.Heightfield or a file path / builtin:KIND string");
    for (const auto& [key, value] : text)
        if (std::find(kLoadKeys.begin(), kLoadKeys.end(), key) != kLoadKeys.end())
            throw Error("query key " + key + " says how a heightfield file is read; give it to glintscope.load, not "
                        "with a Heightfield object");
    text.insert(text.begin(), {"heightfield", "python"});
    LobeQuery query = check_query_text(text);
    query.source = HeightfieldSource{};  // an object in memory: no file to record
    query.field = heightfield.cast<std::shared_ptr<Heightfield>>();  // shared, not copied
    query.surface = interpolant_of(heightfield);
    if (std::none_of(text.begin(), text.end(), [](const auto& entry) { return entry.first == "centre"; }))
        query.footprint.centre_um = query.field->centre_um();
    return query;
}

std::string query_keys_doc(bool with_load_keys) {
    std::string doc = "Query keys (keyword arguments, the CLI's flags without --; lengths as \"10um\", \"500nm\" or a "
                      "number in um; pairs and lists as tuples; lambda as lambda_; a method's option KEY as KEY=...):\n";
    for (const QueryKey& key : query_keys()) {
        if (key.name == "heightfield" || key.name == "quantity") continue;
        const bool load_key = std::find(kLoadKeys.begin(), kLoadKeys.end(), key.name) != kLoadKeys.end();
        if (load_key && !with_load_keys) continue;
        doc += "    " + (key.name == "lambda" ? std::string("lambda_") : key.name) + " (" + key.value_name + "): " +
               key.help + (load_key ? " [heightfield given as a path only]" : "") + "\n";
    }
    return doc;
}

std::string methods_doc(Quantity quantity) {
    std::string doc = "Methods (" + to_string(quantity) + "):\n";
    for (const MethodInfo& info : lobe_methods()) {
        if (!info.answers(quantity)) continue;
        doc += "    " + info.name + " (" + info.reference + "): " + info.description + "\n";
        for (const MethodOption& option : info.options) doc += "        " + option.key + ": " + option.help + "\n";
    }
    return doc;
}

}  // namespace glintscope::python
