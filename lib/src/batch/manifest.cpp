// Reading a batch manifest (TOML, through toml++) and checking it before any computation.
#include <filesystem>

#include <toml++/toml.h>

#include "glintscope/batch/batch.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/render/render_request.hpp"

namespace glintscope {
namespace {

// "FILE:LINE: key 'K': problem".
[[noreturn]] void fail(const std::string& path, const toml::source_region& where, const std::string& key,
                       const std::string& problem) {
    throw Error(path + ":" + std::to_string(where.begin.line) + ": " + (key.empty() ? "" : "key '" + key + "': ") +
                problem);
}

// A value as query-key text: strings as they are, numbers in shortest form, arrays joined by
// commas ([20, 0] → "20,0"); an array of lights (each "X,Y,Z:I") joined by ';'.
std::string value_text(const std::string& path, const std::string& key, const toml::node& node) {
    if (const auto* text = node.as_string()) return text->get();
    if (const auto* integer = node.as_integer()) return std::to_string(integer->get());
    if (const auto* real = node.as_floating_point()) return shortest_text(real->get());
    if (const auto* flag = node.as_boolean()) return flag->get() ? "true" : "false";
    if (const auto* array = node.as_array()) {
        std::vector<std::string> parts;
        for (const toml::node& element : *array) {
            if (element.is_array() || element.is_table()) fail(path, element.source(), key, "nested arrays or tables are not values");
            parts.push_back(value_text(path, key, element));
        }
        return join(parts, key == "light" ? ";" : ",");
    }
    fail(path, node.source(), key, "expected a string, a number or an array of them, got a table");
}

bool is_query_key(const std::string& key) {
    if (key.starts_with("option.") && key.size() > 7) return true;
    for (const QueryKey& known : query_keys())
        if (known.name == key) return true;
    return false;
}

// A method option of some method (e.g. kernels_per_texel): written in a manifest like a flag.
bool is_method_option(const std::string& key) {
    for (const MethodInfo& method : lobe_methods())
        for (const MethodOption& option : method.options)
            if (option.key == key) return true;
    return false;
}

// The keys of a [defaults], [[row]] or [[column]] table: label (rows and columns), method,
// query keys and method options (by name, or in an [option] sub-table).
struct Entry {
    std::string label;
    std::string method;
    std::string kind;  // "lobe", "render" or unset
    QueryText query;
    std::vector<toml::source_region> value_where;  // where each query value is written
    toml::source_region where;
};

void add_value(Entry& entry, const std::string& path, const std::string& key, const toml::node& node) {
    entry.query.emplace_back(key, value_text(path, key, node));
    entry.value_where.push_back(node.source());
}

Entry read_entry(const std::string& path, const toml::table& table, bool labelled) {
    Entry entry;
    entry.where = table.source();
    for (const auto& [name, node] : table) {
        const std::string key(name.str());
        if (labelled && key == "label") {
            if (!node.is_string()) fail(path, node.source(), key, "expected a string");
            entry.label = node.as_string()->get();
        } else if (key == "method") {
            if (!node.is_string()) fail(path, node.source(), key, "expected a string");
            entry.method = node.as_string()->get();
        } else if (key == "kind") {
            if (!node.is_string() || (node.as_string()->get() != "lobe" && node.as_string()->get() != "render"))
                fail(path, node.source(), key, "expected \"lobe\" or \"render\"");
            entry.kind = node.as_string()->get();
        } else if (key == "option" && node.is_table()) {
            for (const auto& [option, value] : *node.as_table()) add_value(entry, path, "option." + std::string(option.str()), value);
        } else if (is_query_key(key) || is_render_key(key)) {
            add_value(entry, path, key, node);
        } else if (is_method_option(key)) {
            add_value(entry, path, "option." + key, node);
        } else {
            fail(path, node.source(), key, std::string("unknown key (") + (labelled ? "label, " : "") +
                                               "kind, method, a method option, a query key: " + [] {
                                                   std::vector<std::string> names;
                                                   for (const QueryKey& known : query_keys()) names.push_back(known.name);
                                                   return join(names);
                                               }() + ", or a render key: " + join(render_keys()) + ")");
        }
    }
    return entry;
}

std::vector<Entry> read_entries(const std::string& path, const toml::table& root, const std::string& key) {
    const toml::node* node = root.get(key);
    if (!node) fail(path, root.source(), "", "the manifest has no [[" + key + "]] (a figure needs at least one)");
    const toml::array* array = node->as_array();
    if (!array || !array->is_array_of_tables()) fail(path, node->source(), key, "expected [[" + key + "]] tables");
    std::vector<Entry> entries;
    for (const toml::node& element : *array) entries.push_back(read_entry(path, *element.as_table(), true));
    return entries;
}

std::string string_value(const std::string& path, const toml::table& root, const std::string& key, bool required) {
    const toml::node* node = root.get(key);
    if (!node) {
        if (required) fail(path, root.source(), key, "missing");
        return "";
    }
    if (!node->is_string()) fail(path, node->source(), key, "expected a string");
    return node->as_string()->get();
}

SharedExposure parse_exposure(const std::string& path, const toml::table& root) {
    const std::string text = string_value(path, root, "exposure", false);
    if (text.empty() || text == "shared-per-row") return SharedExposure::per_row;
    if (text == "per-panel") return SharedExposure::per_panel;
    if (text == "shared") return SharedExposure::whole_figure;
    fail(path, root.get("exposure")->source(), "exposure", "'" + text + "' is not per-panel, shared-per-row or shared");
}

void check_heightfield(const std::string& argument, const std::string& base_dir) {
    if (argument.starts_with("builtin:")) {
        default_recipe(argument.substr(8));  // throws for unknown kinds
        return;
    }
    const std::filesystem::path file = std::filesystem::path(argument).is_absolute() ? std::filesystem::path(argument)
                                                                                      : std::filesystem::path(base_dir) / argument;
    if (!std::filesystem::is_regular_file(file)) throw Error("heightfield '" + argument + "' does not exist");
}

// Relative heightfield paths are relative to the manifest's folder; panels record them absolute,
// so that `lobe --from PANEL.exr` re-runs a panel from any folder.
void resolve_paths(QueryText& query, const std::string& base_dir) {
    for (auto& [key, value] : query)
        if (key == "heightfield" && !value.starts_with("builtin:") && !std::filesystem::path(value).is_absolute())
            value = std::filesystem::absolute(std::filesystem::path(base_dir) / value).lexically_normal().string();
}

bool parse_log_scale(const std::string& path, const toml::table& root) {
    const std::string text = string_value(path, root, "scale", false);
    if (text.empty() || text == "linear") return false;
    if (text == "log") return true;
    fail(path, root.get("scale")->source(), "scale", "'" + text + "' is not linear or log");
}

// "paper" needs a shared exposure (one colour bar per row), refused with per-panel at the style's line.
FigureStyle parse_style(const std::string& path, const toml::table& root, SharedExposure exposure) {
    const std::string text = string_value(path, root, "style", false);
    if (text.empty() || text == "standard") return FigureStyle::standard;
    if (text != "paper") fail(path, root.get("style")->source(), "style", "'" + text + "' is not standard or paper");
    if (exposure == SharedExposure::per_panel)
        fail(path, root.get("style")->source(), "style",
             "a paper figure has one colour bar per row, which needs exposure shared-per-row or shared, not per-panel");
    return FigureStyle::paper;
}

bool boolean_value(const std::string& path, const toml::table& root, const std::string& key) {
    const toml::node* node = root.get(key);
    if (!node) return false;
    if (!node->is_boolean()) fail(path, node->source(), key, "expected true or false");
    return node->as_boolean()->get();
}

// A render key's value in the Patch scene's defaults, as the render command would check it.
void check_render_value(const std::string& key, const std::string& value) {
    RenderRequest request;
    set_render_key(request, key, value);
    render_view(request);
    render_colour(request);
}

// The merged render cell: its keys, scene and colour as the render command checks them before
// loading the heightfield.
void check_render_cell(const ManifestPanel& panel) {
    const RenderRequest request = render_request(panel.method, panel.query);
    render_view(request);
    render_colour(request);
    render_query_text(request);
}

// The merged lobe cell: its query, a method that answers its quantity, and no render key.
void check_lobe_cell(const ManifestPanel& panel) {
    for (const auto& [key, value] : panel.query)
        if (is_render_key(key)) throw Error("key '" + key + "' is a render option: set kind = \"render\" for a render cell");
    const LobeQuery query = check_query_text(panel.query);
    const MethodInfo method = lobe_method(panel.method);
    if (!method.answers(query.quantity))
        throw Error("method '" + panel.method + "' does not compute " + to_string(query.quantity));
}

// Each value on its own, at the line it is written on ([defaults] included): its syntax and
// range, a material's name, a heightfield's existence. What only the merged panel can tell (keys
// that exclude each other, a method that does not answer the quantity) is named by cell.
void check_values(const std::string& path, const Entry& entry, const std::string& base_dir) {
    for (std::size_t k = 0; k < entry.query.size(); ++k) {
        const auto& [key, value] = entry.query[k];
        try {
            check_query_value(key, value);
            if (key == "heightfield") check_heightfield(value, base_dir);
            if (is_render_key(key)) check_render_value(key, value);
        } catch (const Error& e) {
            fail(path, entry.value_where[k], key, e.what());
        }
    }
}

const std::vector<std::string> kTopKeys = {"title",  "caption",  "output", "exposure", "scale",
                                           "style",  "insets",   "defaults", "row",    "column"};

}  // namespace

Manifest load_manifest(const std::string& path) {
    toml::table root;
    try {
        root = toml::parse_file(path);
    } catch (const toml::parse_error& e) {
        throw Error(path + ":" + std::to_string(e.source().begin.line) + ": " + std::string(e.description()));
    }
    for (const auto& [name, node] : root)
        if (std::find(kTopKeys.begin(), kTopKeys.end(), std::string(name.str())) == kTopKeys.end())
            fail(path, node.source(), std::string(name.str()), "unknown key (" + join(kTopKeys) + ")");
    Manifest manifest;
    manifest.path = path;
    manifest.title = string_value(path, root, "title", false);
    manifest.caption = string_value(path, root, "caption", false);
    manifest.output = string_value(path, root, "output", true);
    if (!manifest.output.ends_with(".png")) fail(path, root.get("output")->source(), "output", "the figure must be a .png");
    manifest.exposure = parse_exposure(path, root);
    manifest.log_scale = parse_log_scale(path, root);
    manifest.insets = boolean_value(path, root, "insets");
    manifest.style = parse_style(path, root, manifest.exposure);
    Entry defaults;
    if (const toml::node* node = root.get("defaults")) {
        if (!node->is_table()) fail(path, node->source(), "defaults", "expected a [defaults] table");
        defaults = read_entry(path, *node->as_table(), false);
    }
    const std::vector<Entry> rows = read_entries(path, root, "row");
    const std::vector<Entry> columns = read_entries(path, root, "column");
    const std::string base_dir = std::filesystem::path(path).parent_path().string();
    check_values(path, defaults, base_dir);
    for (const std::vector<Entry>* entries : {&rows, &columns})
        for (const Entry& entry : *entries) check_values(path, entry, base_dir);
    for (const Entry& row : rows) manifest.row_labels.push_back(row.label);
    for (const Entry& column : columns) manifest.column_labels.push_back(column.label);
    for (std::size_t r = 0; r < rows.size(); ++r)
        for (std::size_t c = 0; c < columns.size(); ++c) {
            ManifestPanel panel{r, c, "", merge_query_text(merge_query_text(defaults.query, rows[r].query), columns[c].query)};
            for (const Entry* entry : std::initializer_list<const Entry*>{&defaults, &rows[r], &columns[c]}) {
                if (!entry->method.empty()) panel.method = entry->method;
                if (!entry->kind.empty()) panel.render = entry->kind == "render";
            }
            if (panel.method.empty()) panel.method = panel.render ? RenderRequest{}.method : "fft";  // each command's default
            const toml::source_region& where = columns[c].where;
            const std::string cell = "row " + std::to_string(r + 1) + " ('" + rows[r].label + "'), column " +
                                     std::to_string(c + 1) + " ('" + columns[c].label + "'): ";
            try {
                if (panel.render) check_render_cell(panel);
                else check_lobe_cell(panel);
                const std::string* heightfield = nullptr;
                for (const auto& [key, value] : panel.query)
                    if (key == "heightfield") heightfield = &value;
                if (!heightfield) throw Error("no heightfield");
                check_heightfield(*heightfield, base_dir);
            } catch (const Error& e) {
                fail(path, where, "", cell + e.what());
            }
            resolve_paths(panel.query, base_dir);
            manifest.panels.push_back(std::move(panel));
        }
    // One figure, one lobe panel size: a grid of mixed resolutions cannot be laid out (renders are
    // drawn at their own size and aspect).
    int resolution = 0;
    for (const ManifestPanel& panel : manifest.panels) {
        if (panel.render) continue;
        const int own = check_query_text(panel.query).resolution;
        if (resolution && own != resolution) fail(path, root.source(), "res", "every panel of a figure needs the same resolution");
        resolution = own;
    }
    return manifest;
}

}  // namespace glintscope
