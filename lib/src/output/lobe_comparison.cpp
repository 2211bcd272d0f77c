#include "glintscope/output/lobe_comparison.hpp"

#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "glintscope/core/error.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

std::string layers_text(const LobeExrLayers& file) {
    if (file.colour) return "R, G, B in " + file.colour_encoding;
    if (file.layers() == 1) return "lambda " + file.names.front();
    return std::to_string(file.layers()) + " wavelengths " + shortest_text(file.wavelengths_um.front()) + "-" +
           shortest_text(file.wavelengths_um.back()) + " um";
}

// One line naming both files and the first thing in which they differ, or "" when comparable.
std::string difference_of(const LobeFileComparison& c) {
    const auto refuse = [&](const std::string& what, const std::string& test, const std::string& reference) {
        return "cannot compare '" + c.test_path + "' (" + test + ") with '" + c.reference_path + "' (" + reference +
               "): different " + what;
    };
    if (c.test.quantity != c.reference.quantity)
        return refuse("quantities", to_string(c.test.quantity), to_string(c.reference.quantity));
    if (c.test.resolution != c.reference.resolution)
        return refuse("sizes", std::to_string(c.test.resolution) + "x" + std::to_string(c.test.resolution) + " pixels",
                      std::to_string(c.reference.resolution) + "x" + std::to_string(c.reference.resolution) + " pixels");
    // Colour channels compare across spectral samplings (that is how one measures them); only
    // their encoding must agree.
    const bool same_layers = c.test.colour ? c.reference.colour && c.test.colour_encoding == c.reference.colour_encoding
                                           : !c.reference.colour && c.test.wavelengths_um == c.reference.wavelengths_um;
    if (same_layers) return "";
    std::string test = layers_text(c.test), reference = layers_text(c.reference);
    if (test == reference) test = join_numbers(c.test.wavelengths_um), reference = join_numbers(c.reference.wavelengths_um);
    return refuse("layers", test, reference);
}

// Layer k as a one-layer image for the figure; a colour channel has no wavelength, so its
// caption leaves lambda out (figure.hpp reads not_applicable).
LobeImage layer_image(const LobeExrLayers& file, std::size_t k) {
    LobeImage image = make_lobe_image(file.resolution, {file.colour ? 0.0 : file.wavelengths_um[k]}, file.quantity);
    const std::span<const float> values = file.layer(k);
    image.values.assign(values.begin(), values.end());
    image.metadata = file.metadata;
    if (file.colour) {
        std::string& ignored = image.metadata["not_applicable"];
        ignored += (ignored.empty() ? "" : ",") + std::string("lambda");
    }
    return image;
}

std::string recorded(const LobeExrLayers& file, const std::string& key) {
    const auto it = file.metadata.find(key);
    return it == file.metadata.end() ? "" : it->second;
}

nlohmann::json input_json(const std::string& path, const LobeExrLayers& file) {
    nlohmann::json query = nlohmann::json::object();
    for (const auto& [key, value] : file.metadata)
        if (key.starts_with("query.")) query[key.substr(6)] = value;
    return {{"path", path},
            {"quantity", to_string(file.quantity)},
            {"resolution", file.resolution},
            {"layers", file.names},
            {"wavelengths_um", file.wavelengths_um},
            {"method", recorded(file, "method")},
            {"query", query}};
}

}  // namespace

LobeFileComparison compare_lobe_exrs(const std::string& test_path, const std::string& reference_path) {
    LobeFileComparison comparison{test_path, reference_path, load_lobe_exr_layers(test_path),
                                  load_lobe_exr_layers(reference_path), {}};
    if (const std::string problem = difference_of(comparison); !problem.empty()) throw Error(problem);
    for (std::size_t k = 0; k < comparison.test.layers(); ++k) {
        comparison.layers.push_back(
            compare_layer(comparison.test.layer(k), comparison.reference.layer(k), comparison.test.resolution));
        if (!comparison.test.colour) comparison.layers.back().wavelength_um = comparison.test.wavelengths_um[k];
    }
    return comparison;
}

std::size_t worst_layer(const LobeFileComparison& comparison) {
    std::size_t worst = 0;
    for (std::size_t k = 1; k < comparison.layers.size(); ++k)
        if (comparison.layers[k].relative_l2 > comparison.layers[worst].relative_l2) worst = k;
    return worst;
}

std::string comparison_table(const LobeFileComparison& comparison) {
    const QuantityLabels& label = labels(comparison.test.quantity);
    std::string text = "A = " + comparison.test_path + ", B = " + comparison.reference_path + " (" +
                       to_string(comparison.test.quantity) + ", " + label.units + ")\n";
    char line[256];
    std::snprintf(line, sizeof line, "%-12s %10s %11s %16s %15s %12s %11s %9s\n", "layer", "rel L2", "max |A-B|",
                  "at row,col", "disk x,y", "energy A/B", "peak shift", "log err");
    text += line;
    const int n = comparison.test.resolution;
    for (std::size_t k = 0; k < comparison.layers.size(); ++k) {
        const LayerComparison& c = comparison.layers[k];
        const DiskPoint p = disk_pixel_point(c.max_row, c.max_col, n);
        char at[32] = "-", point[40] = "-";  // no difference: no place
        if (c.max_abs_difference > 0.0) {
            std::snprintf(at, sizeof at, "%d,%d", c.max_row, c.max_col);
            std::snprintf(point, sizeof point, "%.4f,%.4f", p.x, p.y);
        }
        std::snprintf(line, sizeof line, "%-12.12s %9.4f%% %11.4g %16s %15s %12.6f %9.2fpx %9.4f\n",
                      comparison.test.names[k].c_str(), 100.0 * c.relative_l2, c.max_abs_difference, at, point,
                      c.energy_ratio(), c.peak_offset_pixels, c.log_rms_error);
        text += line;
    }
    return text;
}

std::string comparison_json(const LobeFileComparison& comparison) {
    nlohmann::json layers = nlohmann::json::array();
    const int n = comparison.test.resolution;
    for (std::size_t k = 0; k < comparison.layers.size(); ++k) {
        const LayerComparison& c = comparison.layers[k];
        const DiskPoint p = disk_pixel_point(c.max_row, c.max_col, n);
        const bool differs = c.max_abs_difference > 0.0;  // else there is no place of the largest difference
        layers.push_back({{"layer", comparison.test.names[k]},
                          {"wavelength_um", comparison.test.colour ? nlohmann::json(nullptr) : nlohmann::json(c.wavelength_um)},
                          {"relative_l2", c.relative_l2},
                          {"max_abs_difference", c.max_abs_difference},
                          {"max_pixel", differs ? nlohmann::json{c.max_row, c.max_col} : nlohmann::json(nullptr)},
                          {"max_disk_point", differs ? nlohmann::json{p.x, p.y} : nlohmann::json(nullptr)},
                          {"sum_a", c.test_sum},
                          {"sum_b", c.reference_sum},
                          {"energy_ratio", c.energy_ratio()},
                          {"peak_offset_pixels", c.peak_offset_pixels},
                          {"peak_relative_error", c.peak_relative_error},
                          {"log_rms_error", c.log_rms_error}});
    }
    const nlohmann::json report = {{"format", "glintscope comparison"},
                                   {"a", input_json(comparison.test_path, comparison.test)},
                                   {"b", input_json(comparison.reference_path, comparison.reference)},
                                   {"sum", labels(comparison.test.quantity).sum_name + ": sum of value (2/N)^2 over the disk"},
                                   {"layers", layers}};
    return report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";  // paths need not be UTF-8
}

FigureLayout write_comparison_figure(const LobeFileComparison& comparison, const std::string& path) {
    const std::size_t k = worst_layer(comparison);
    const LobeImage a = layer_image(comparison.test, k);
    const LobeImage b = layer_image(comparison.reference, k);
    const LayerComparison& c = comparison.layers[k];
    char title[256];
    std::snprintf(title, sizeof title, "layer %s: relative L2 %.4g%%, energy ratio A/B %.6g, max |A-B| %.4g %s",
                  comparison.test.names[k].c_str(), 100.0 * c.relative_l2, c.energy_ratio(), c.max_abs_difference,
                  labels(comparison.test.quantity).units.c_str());
    const std::string caption =
        comparison.layers.size() > 1 ? "the layer of largest relative L2 of " + std::to_string(comparison.layers.size()) : "";
    const std::string name_a = "A: " + std::filesystem::path(comparison.test_path).filename().string();
    const std::string name_b = "B: " + std::filesystem::path(comparison.reference_path).filename().string();
    const LobeOutputOptions options;  // the default colour settings: both panels exposed by one rule
    return write_difference_figure(a, b, {title, caption, name_a, name_b, "A - B"}, path, options);
}

}  // namespace glintscope
