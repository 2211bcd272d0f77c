#include "glintscope/lobe/query_keys.hpp"
#include "glintscope/optics/material.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "core/md5.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/optics/spectrum.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"

namespace glintscope {
namespace {

constexpr std::string_view kOptionPrefix = "option.";

struct KeyBinding {
    QueryKey key;
    std::function<void(LobeQuery&, const std::string&)> set;
    std::function<std::optional<std::string>(const LobeQuery&)> get;  // nullopt: not written
};

Point2 parse_length_pair(const std::string& text) {
    const std::vector<std::string> parts = split(text, ',');
    if (parts.size() != 2) throw Error("'" + text + "' is not X,Y");
    return {parse_length_um(parts[0]), parse_length_um(parts[1])};
}

std::vector<double> parse_pair(const std::string& text) {
    const std::vector<double> values = parse_number_list(text);
    if (values.size() != 2) throw Error("'" + text + "' is not two numbers A,B");
    return values;
}

Vec3 incident_from_angles(const std::string& text) {
    const std::vector<double> angles = parse_pair(text);
    if (!(angles[0] >= 0.0 && angles[0] < 90.0))
        throw Error("theta must be in [0, 90) degrees, got " + shortest_text(angles[0]));
    return direction_from_spherical(degrees_to_radians(angles[0]), degrees_to_radians(angles[1]));
}

Vec3 incident_from_disk(const std::string& text) {
    const std::vector<double> xy = parse_pair(text);
    if (!(xy[0] * xy[0] + xy[1] * xy[1] < 1.0)) throw Error("X,Y must lie inside the unit disk, got " + text);
    return direction_from_disk(xy[0], xy[1]);
}

Vec3 exact_direction(const std::string& text) {
    const std::vector<double> v = parse_number_list(text);
    if (v.size() != 3) throw Error("'" + text + "' is not X,Y,Z");
    return {v[0], v[1], v[2]};
}

// Ranges are checked by validate(LobeQuery), with the parameter's own message.
int parse_int(const std::string& text) {
    return static_cast<int>(parse_integer(text, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
}

std::vector<double> parse_wavelengths(const std::string& text) {
    std::vector<double> values;
    for (const std::string& part : split(text, ',')) values.push_back(parse_length_um(part));
    return values;
}

std::string footprint_shape_name(FootprintShape shape) {
    switch (shape) {
        case FootprintShape::gaussian: return "gaussian";
        case FootprintShape::box: return "box";
        case FootprintShape::whole: return "whole";
    }
    return "?";
}

FootprintShape parse_footprint_shape(const std::string& text) {
    if (text == "gaussian") return FootprintShape::gaussian;
    if (text == "box") return FootprintShape::box;
    if (text == "whole") return FootprintShape::whole;
    throw Error("'" + text + "' is not a footprint shape (gaussian, box, whole)");
}

const std::vector<KeyBinding>& bindings() {
    static const std::vector<KeyBinding> table = {
        {{"heightfield", "FILE", "heightfield file (EXR, TIFF, PNG, NPY, X3P) or builtin:KIND", ""},
         [](LobeQuery& q, const std::string& t) { q.source.argument = t; },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (q.source.argument.empty()) return std::nullopt;  // set in code, not from a source
             return q.source.argument;
         }},
        {{"channel", "NAME|INDEX", "image channel holding the heights (default: Z, Y, R or the first)", ""},
         [](LobeQuery& q, const std::string& t) { q.source.load.channel = t; },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (q.source.load.channel.empty()) return std::nullopt;
             return q.source.load.channel;
         }},
        {{"height_unit", "UNIT", "unit of the stored heights: um, nm, mm, m or texel (default: the file's, else um)", ""},
         [](LobeQuery& q, const std::string& t) { q.source.load.height_unit = parse_length_unit(t); },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (!q.source.load.height_unit) return std::nullopt;
             return to_string(*q.source.load.height_unit);
         }},
        {{"texel", "LENGTH[xLENGTH]",
          "declared sample spacing, overriding the file's: 0.5um, or 1x2um for dx by dy (default: the file's, else 1 "
          "um)",
          ""},
         [](LobeQuery& q, const std::string& t) {
             const BoxSides spacing = parse_box_sides(t);
             if (!(spacing.width_um > 0.0) || !(spacing.height_um > 0.0))
                 throw Error("the texel size must be positive, got '" + t + "'");
             q.source.load.texel_um = spacing.width_um;
             q.source.load.texel_y_um.reset();
             if (spacing.height_um != spacing.width_um) q.source.load.texel_y_um = spacing.height_um;
         },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (!q.source.load.texel_um) return std::nullopt;
             if (!q.source.load.texel_y_um) return shortest_text(*q.source.load.texel_um);
             return shortest_text(*q.source.load.texel_um) + "x" + shortest_text(*q.source.load.texel_y_um);
         }},
        {{"height_scale", "K", "multiply the heights by K after the unit conversion (default 1)", ""},
         [](LobeQuery& q, const std::string& t) { q.source.load.height_scale = parse_number(t); },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (q.source.load.height_scale == 1.0) return std::nullopt;
             return shortest_text(q.source.load.height_scale);
         }},
        {{"periodic", "yes|no",
          "the heightfield file holds one tile of a periodic surface: footprints may cross its borders (not given: "
          "no for files, builtin fields always tile; a bare --periodic means yes, the =yes shown)",
          "yes"},
         [](LobeQuery& q, const std::string& t) {
             if (t != "yes" && t != "no") throw Error("periodic must be yes or no, got '" + t + "'");
             q.source.load.periodic = t == "yes";
         },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (!q.source.load.periodic) return std::nullopt;
             return std::string("yes");
         }},
        {{"quantity", "brdf|ndf", "what a pixel holds: brdf (f_r at omega_o) or ndf (D at h) (default brdf)", ""},
         [](LobeQuery& q, const std::string& t) { q.quantity = parse_quantity(t); },
         [](const LobeQuery& q) { return to_string(q.quantity); }},
        {{"footprint", "gaussian|box|whole",
          "footprint shape (default gaussian; --box sets box; whole: the entire field, geometric methods)", ""},
         [](LobeQuery& q, const std::string& t) { q.footprint.shape = parse_footprint_shape(t); },
         [](const LobeQuery& q) { return footprint_shape_name(q.footprint.shape); }},
        {{"centre", "X,Y", "footprint centre, lengths (default: the heightfield's centre)", ""},
         [](LobeQuery& q, const std::string& t) { q.footprint.centre_um = parse_length_pair(t); },
         [](const LobeQuery& q) {
             return shortest_text(q.footprint.centre_um.x) + "," + shortest_text(q.footprint.centre_um.y);
         }},
        {{"sigma_c", "LENGTH", "coherence sigma of the Gaussian footprint (default 10um)", ""},
         [](LobeQuery& q, const std::string& t) { q.footprint.sigma_um = parse_length_um(t); },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (q.footprint.shape != FootprintShape::gaussian) return std::nullopt;
             return shortest_text(q.footprint.sigma_um);
         }},
        {{"box", "LENGTH[xLENGTH]",
          "use a box footprint of this side (or these sides along x and y, e.g. 70x53um, Dong 2015's patches) "
          "instead of a Gaussian",
          ""},
         [](LobeQuery& q, const std::string& t) { set_box(q.footprint, t); },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (q.footprint.shape != FootprintShape::box) return std::nullopt;
             const double width = box_width_um(q.footprint), height = box_height_um(q.footprint);
             return width == height ? shortest_text(width) : shortest_text(width) + "x" + shortest_text(height);
         }},
        {{"omega_i", "X,Y,Z", "incident direction as an exact unit vector (written by the tool for re-runs)", ""},
         [](LobeQuery& q, const std::string& t) { q.omega_i = exact_direction(t); },
         [](const LobeQuery& q) {
             return shortest_text(q.omega_i.x) + "," + shortest_text(q.omega_i.y) + "," + shortest_text(q.omega_i.z);
         }},
        {{"incident", "THETA,PHI", "incident direction in degrees (default 0,0: normal incidence)", ""},
         [](LobeQuery& q, const std::string& t) { q.omega_i = incident_from_angles(t); },
         [](const LobeQuery&) { return std::nullopt; }},
        {{"incident_xy", "X,Y", "incident direction as a point of the projected disk", ""},
         [](LobeQuery& q, const std::string& t) { q.omega_i = incident_from_disk(t); },
         [](const LobeQuery&) { return std::nullopt; }},
        {{"lambda", "LENGTH[,LENGTH...]", "wavelength(s) (default 0.5um)", ""},
         [](LobeQuery& q, const std::string& t) { q.wavelengths_um = parse_wavelengths(t); },
         [](const LobeQuery& q) { return join_numbers(q.wavelengths_um); }},
        {{"spectral", "N", "N equal bins over 360-830 nm instead of --lambda (default N 16)", "16"},
         [](LobeQuery& q, const std::string& t) {
             q.wavelengths_um = spectral_bin_centres_um(static_cast<int>(parse_integer(t, 1, 256)));
         },
         [](const LobeQuery&) { return std::nullopt; }},
        {{"model", "NAME", "diffraction model: ohs, ghs, rohs, rghs, kirchhoff (default rohs)", ""},
         [](LobeQuery& q, const std::string& t) { q.model = parse_diffraction_model(t); },
         [](const LobeQuery& q) { return to_string(q.model); }},
        {{"material", "NAME", "Fresnel from tabulated n+ik: Ag, Al, Au, Cr, Cu, Fe, or none (default none: F = 1)", ""},
         [](LobeQuery& q, const std::string& t) { q.material.name = t == "none" ? "" : t; },
         [](const LobeQuery& q) { return q.material.name.empty() ? std::string("none") : q.material.name; }},
        {{"res", "N", "image resolution N (N x N) (default 256)", ""},
         [](LobeQuery& q, const std::string& t) { q.resolution = parse_int(t); },
         [](const LobeQuery& q) { return std::to_string(q.resolution); }},
        {{"supersample", "K|auto|exact",
          "K x K sub-pixel average, or exact: pixels integrated exactly (geometric) (default auto: exact where the "
          "method can, else enough that a wave lobe's coherence blur spans 1.5 sub-pixels, else 1)",
          ""},
         [](LobeQuery& q, const std::string& t) {
             q.supersample = t == "auto" ? 0 : t == "exact" ? kExactPixels : parse_int(t);
         },
         [](const LobeQuery& q) {
             return q.supersample == 0 ? std::string("auto")
                                       : q.supersample == kExactPixels ? std::string("exact") : std::to_string(q.supersample);
         }},
        {{"memory", "GB",
          "memory budget of a method's working grids in GB, e.g. the FFT footprint grid of a large sigma_c "
          "(default 4; over it the FFT lowers its oversampling, then refuses)",
          ""},
         [](LobeQuery& q, const std::string& t) { q.memory_budget_gb = parse_number(t); },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (q.memory_budget_gb == 4.0) return std::nullopt;
             return shortest_text(q.memory_budget_gb);
         }},
        {{"footprints", "N|grid|grid:N",
          "average over footprints: N seeded random centres, grid (3 x 3) or grid:N (N x N) spread over the field "
          "(large-area NDFs, expected lobes; default 1: the footprint alone)",
          ""},
         [](LobeQuery& q, const std::string& t) { q.footprints = parse_footprint_set(t); },
         [](const LobeQuery& q) -> std::optional<std::string> {
             if (q.footprints.single()) return std::nullopt;
             return to_string(q.footprints);
         }},
    };
    return table;
}

const std::vector<std::vector<std::string>>& exclusive_groups() {
    static const std::vector<std::vector<std::string>> groups = {{"omega_i", "incident", "incident_xy"},
                                                                 {"lambda", "spectral"}};
    return groups;
}

std::vector<std::string> excluded_by(const std::string& key) {
    for (const auto& group : exclusive_groups())
        if (std::find(group.begin(), group.end(), key) != group.end()) return group;
    return {key};
}

bool is_option_key(const std::string& key) { return key.starts_with(kOptionPrefix) && key.size() > kOptionPrefix.size(); }

const KeyBinding* find_binding(const std::string& key) {
    for (const KeyBinding& binding : bindings())
        if (binding.key.name == key) return &binding;
    return nullptr;
}

void check_keys(const QueryText& text) {
    std::vector<std::string> seen;
    for (const auto& [key, value] : text) {
        if (!find_binding(key) && !is_option_key(key)) {
            std::vector<std::string> names;
            for (const KeyBinding& binding : bindings()) names.push_back(binding.key.name);
            throw Error("unknown query key '" + key + "' (keys: " + join(names) + ", option.KEY)");
        }
        for (const std::string& other : excluded_by(key))
            if (std::find(seen.begin(), seen.end(), other) != seen.end())
                throw Error(other == key ? "query key '" + key + "' is given twice"
                                         : "query keys '" + other + "' and '" + key + "' exclude each other");
        seen.push_back(key);
    }
}

const std::string* find_value(const QueryText& text, const std::string& key) {
    for (const auto& [name, value] : text)
        if (name == key) return &value;
    return nullptr;
}

}  // namespace

const std::vector<QueryKey>& query_keys() {
    static const std::vector<QueryKey> keys = [] {
        std::vector<QueryKey> list;
        for (const KeyBinding& binding : bindings()) list.push_back(binding.key);
        return list;
    }();
    return keys;
}

LobeQuery check_query_text(const QueryText& text) {
    check_keys(text);
    LobeQuery query;
    for (const KeyBinding& binding : bindings()) {
        const std::string* value = find_value(text, binding.key.name);
        if (!value) continue;
        try {
            binding.set(query, *value);
        } catch (const Error& e) {
            throw Error("query key " + binding.key.name + ": " + e.what());
        }
    }
    for (const auto& [key, value] : text)
        if (is_option_key(key)) query.method_options[key.substr(kOptionPrefix.size())] = value;
    if (query.source.argument.empty()) throw Error("the query names no heightfield");
    return query;
}

void check_query_value(const std::string& key, const std::string& value) {
    for (const KeyBinding& binding : bindings())
        if (binding.key.name == key) try {
                LobeQuery query;
                binding.set(query, value);
                if (!query.material.name.empty()) check_material_name(query.material.name);
            } catch (const Error& e) {
                throw Error("query key " + key + ": " + e.what());
            }
}

LobeQuery make_query(const QueryText& text) {
    LobeQuery query = check_query_text(text);
    set_heightfield(query, load_heightfield_source(query.source));
    if (!query.source.argument.starts_with("builtin:")) {
        // The file's content hash, so that an output names exactly the data it came from.
        std::ifstream stream(query.source.argument, std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
        query.source.content_md5 = md5_hex(bytes.data(), bytes.size());
    }
    if (!find_value(text, "centre")) query.footprint.centre_um = query.field->centre_um();
    return query;
}

RecordedRun recorded_run(const std::string& record_path, const QueryText& overrides, bool allow_changed_heightfield) {
    const Provenance recorded = read_output_metadata(record_path);
    RecordedRun run;
    if (recorded.count("method")) run.method = recorded.at("method");
    QueryText text = query_text_from_metadata(recorded);
    // A relative heightfield path was written relative to where the record was made; read it
    // relative to the record, so that a figure's panels re-run from anywhere.
    for (auto& [key, value] : text)
        if (key == "heightfield" && !value.starts_with("builtin:") && std::filesystem::path(value).is_relative()) {
            const std::filesystem::path beside = std::filesystem::path(record_path).parent_path() / value;
            if (std::filesystem::exists(beside)) value = beside.string();
        }
    const bool same_heightfield = std::none_of(overrides.begin(), overrides.end(), [](const auto& entry) {
        return entry.first == "heightfield";
    });
    run.query = make_query(merge_query_text(text, overrides));
    const auto md5 = recorded.find("heightfield.md5");
    if (same_heightfield && md5 != recorded.end() && !allow_changed_heightfield &&
        md5->second != run.query.source.content_md5)
        throw Error("the heightfield '" + run.query.source.argument + "' has changed since '" + record_path +
                    "' was written (MD5 " + run.query.source.content_md5 + ", recorded " + md5->second +
                    "); re-run on it anyway with --allow-changed-heightfield");
    return run;
}

QueryText query_text(const LobeQuery& query) {
    QueryText text;
    for (const KeyBinding& binding : bindings())
        if (std::optional<std::string> value = binding.get(query)) text.emplace_back(binding.key.name, *value);
    for (const auto& [key, value] : query.method_options) text.emplace_back(std::string(kOptionPrefix) + key, value);
    return text;
}

QueryText merge_query_text(const QueryText& base, const QueryText& overrides) {
    QueryText merged;
    for (const auto& entry : base) {
        bool replaced = false;
        for (const auto& [key, value] : overrides)
            for (const std::string& excluded : excluded_by(key)) replaced = replaced || excluded == entry.first;
        if (!replaced) merged.push_back(entry);
    }
    merged.insert(merged.end(), overrides.begin(), overrides.end());
    return merged;
}

Provenance describe_query(const LobeQuery& query) {
    Provenance text;
    if (query.field) {
        for (const auto& [key, value] : query.field->provenance) text["heightfield." + key] = value;
        text["heightfield.size"] = std::to_string(query.field->cols) + "x" + std::to_string(query.field->rows);
        text["heightfield.texel_um"] = shortest_text(query.field->texel_um);
        if (!query.field->square_texels()) text["heightfield.texel_y_um"] = shortest_text(query.field->dy_um());
    }
    if (!query.source.content_md5.empty()) text["heightfield.md5"] = query.source.content_md5;
    for (const auto& [key, value] : query_text(query)) text["query." + key] = value;
    const Vec3 wi = query.omega_i;
    text["info.theta_i_deg"] = shortest_text(std::acos(std::fmin(1.0, wi.z)) * 180.0 / pi);
    text["info.phi_i_deg"] = shortest_text(std::atan2(wi.y, wi.x) * 180.0 / pi);
    return text;
}

QueryText query_text_from_metadata(const Provenance& metadata) {
    QueryText text;
    for (const KeyBinding& binding : bindings()) {
        const auto it = metadata.find("query." + binding.key.name);
        if (it != metadata.end()) text.emplace_back(binding.key.name, it->second);
    }
    for (const auto& [key, value] : metadata)
        if (key.starts_with("query.") && is_option_key(key.substr(6))) text.emplace_back(key.substr(6), value);
    if (text.empty()) throw Error("the metadata holds no query (no query.* keys)");
    return text;
}

Provenance read_output_metadata(const std::string& path) {
    Provenance metadata;
    if (path.ends_with(".json")) {
        std::ifstream stream(path);
        if (!stream) throw Error("cannot read '" + path + "': no such file");
        const nlohmann::json json = nlohmann::json::parse(stream, nullptr, false);
        if (json.is_discarded() || !json.is_object() || !json.contains("metadata") || !json["metadata"].is_object())
            throw Error("cannot read '" + path + "': not a glintscope JSON sidecar (no metadata object)");
        for (const auto& [key, value] : json["metadata"].items()) {
            if (value.is_string()) metadata[key] = value.get<std::string>();
            if (value.is_number()) metadata[key] = value.is_number_integer() ? std::to_string(value.get<long long>())
                                                                             : shortest_text(value.get<double>());
        }
        return metadata;
    }
    auto input = OIIO::ImageInput::open(path);
    if (!input) throw Error("cannot read '" + path + "': " + split(OIIO::geterror(), '\n').front());
    for (const OIIO::ParamValue& attribute : input->spec().extra_attribs) {
        const std::string name = attribute.name().string();
        if (name.starts_with("glintscope:") && !name.starts_with("glintscope:output.") &&
            attribute.type() == OIIO::TypeDesc::STRING)
            metadata[name.substr(11)] = attribute.get_string();
    }
    return metadata;
}

Heightfield load_heightfield_source(const HeightfieldSource& source) {
    const std::string builtin_prefix = "builtin:";
    if (source.argument.starts_with(builtin_prefix)) return generate_builtin(source.argument.substr(builtin_prefix.size()));
    return load_heightfield(source.argument, source.load);
}

}  // namespace glintscope
