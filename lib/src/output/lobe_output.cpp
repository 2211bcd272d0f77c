#include "glintscope/core/geometry.hpp"
#include "glintscope/output/lobe_output.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <set>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "glintscope/core/atomic_output.hpp"
#include "glintscope/output/colormap.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/output/figure.hpp"
#include "glintscope/core/text_format.hpp"
#include "output/image_files.hpp"

namespace glintscope {
namespace {

constexpr std::string_view output_prefix = "output.";  // keys the writer adds; not lobe metadata

std::vector<double> parse_list(const std::string& text, const std::string& path) {
    try {
        return parse_number_list(text);
    } catch (const Error&) {
        throw Error("cannot read lobe '" + path + "': invalid wavelength list '" + text + "'");
    }
}

// A metadata value as JSON: a number where the text is exactly a number's shortest form (so it
// reads back as the same text; whole numbers as integers), else a string.
nlohmann::ordered_json json_value(const std::string& value) {
    try {
        const double number = parse_number(value);
        if (shortest_text(number) == value)
            return std::trunc(number) == number && std::fabs(number) < 1e15 && !(number == 0.0 && std::signbit(number))
                       ? nlohmann::ordered_json(static_cast<long long>(number))  // "-0" stays a double
                       : nlohmann::ordered_json(number);
    } catch (const Error&) {
    }
    return value;
}

void check_lobe(const LobeImage& lobe) {
    const std::size_t pixels = std::size_t(lobe.resolution) * lobe.resolution;
    if (lobe.resolution < 1 || lobe.wavelengths_um.empty() || lobe.values.size() != pixels * lobe.wavelengths_um.size())
        throw Error("lobe image is empty or its values do not match its resolution and wavelengths");
}

bool is_spectral(const LobeImage& lobe) { return lobe.wavelengths_um.size() > 1; }

void check_colormap_option(const std::string& name) {
    if (name != "inferno" && name != "viridis" && name != "grey")
        throw Error("unknown lobe colour map '" + name + "' (available: inferno, viridis, grey)");
}

}  // namespace

void check_output_options(const LobeOutputOptions& options) {
    check_colormap_option(options.colormap);
    std::vector<float> black(3, 0.0f);  // one pixel through the config: it loads and knows the space
    convert_from_xyz(black, options.colour, options.colour.output_space);
    scene_linear_chromaticities(options.colour, options.colour.output_space);
}

namespace {

// The writer's own facts, in the reserved "output." namespace.
Provenance output_facts(const LobeImage& lobe, const LobeOutputOptions& options, const std::string& channels) {
    Provenance facts;
    facts["output.units"] = labels(lobe.quantity).units;
    facts["output.quantity"] = to_string(lobe.quantity);
    facts["output.wavelengths_um"] = join_numbers(lobe.wavelengths_um);
    facts["output.channels"] = channels;
    facts["output.image"] = "projected-disk map, row 0 = largest y, pixels outside the unit disk are 0";
    if (is_spectral(lobe)) {
        facts["output.illuminant"] = to_string(options.colour.illuminant);
        facts["output.colour_config"] = colour_config_name(options.colour);
    }
    return facts;
}

// Σ Y (2/N)² of the colour image: the luminous albedo of a spectral lobe.
double luminance_albedo(const LobeImage& lobe, Illuminant illuminant) {
    const std::vector<float> xyz = lobe_to_xyz(lobe, illuminant);
    double total = 0.0;
    for (std::size_t i = 1; i < xyz.size(); i += 3) total += xyz[i];
    return total * disk_pixel_area(lobe.resolution);
}

DisplayExposure write_colormap_png(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options) {
    const DisplayExposure exposure = display_exposure(lobe, options.colour);
    const int n = lobe.resolution;
    ScalarImage image;
    image.rows = image.cols = n;
    image.values.resize(std::size_t(n) * n);
    ColorLegend legend;
    legend.map = parse_colormap(options.colormap);
    const QuantityLabels& label = labels(lobe.quantity);
    const std::string value = label.symbol + (label.units == "1" ? "" : " [" + label.units + "]");
    const std::string at = lobe.quantity == Quantity::brdf ? " at " + shortest_text(lobe.wavelengths_um[0]) + " um" : "";
    if (exposure.log_scale) {
        legend.max_value = std::log10(exposure.white_level);
        legend.min_value = legend.max_value - exposure.log_decades;
        legend.label = "log10 " + value + at;
    } else {
        legend.min_value = 0.0;
        legend.max_value = exposure.white_level;
        legend.label = value + at;
    }
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            const DiskPoint p = disk_pixel_point(row, col, n);
            const float value = lobe.at(0, row, col);
            float shown = std::numeric_limits<float>::quiet_NaN();  // outside the disk: no direction
            if (inside_unit_disk(p) && std::isfinite(value))
                shown = !exposure.log_scale ? value
                        : value > 0.0f      ? float(std::max(std::log10(double(value)), legend.min_value))
                                            : float(legend.min_value);
            image.values[std::size_t(row) * n + col] = shown;
        }
    write_colormapped_png(path, image, legend);
    return exposure;
}

}  // namespace

std::vector<WavelengthSummary> summarize_lobe(const LobeImage& lobe) {
    check_lobe(lobe);
    const int n = lobe.resolution;
    std::vector<WavelengthSummary> summaries;
    for (std::size_t layer = 0; layer < lobe.wavelengths_um.size(); ++layer) {
        WavelengthSummary summary;
        summary.wavelength_um = lobe.wavelengths_um[layer];
        summary.peak_value = -std::numeric_limits<float>::infinity();
        summary.peak_row = summary.peak_col = n / 2;  // kept only if no finite value lies in the disk
        for (int row = 0; row < n; ++row)
            for (int col = 0; col < n; ++col) {
                const DiskPoint p = disk_pixel_point(row, col, n);
                const float value = lobe.at(layer, row, col);
                if (!inside_unit_disk(p) || !std::isfinite(value)) continue;
                if (value > summary.peak_value) {
                    summary.peak_value = value;
                    summary.peak_row = row;
                    summary.peak_col = col;
                }
            }
        if (!std::isfinite(summary.peak_value)) summary.peak_value = 0.0f;
        const DiskPoint p = disk_pixel_point(summary.peak_row, summary.peak_col, n);
        summary.peak_direction = direction_from_disk(p.x, p.y);
        summary.disk_sum = disk_sum(lobe, layer);  // conventions.md: Σ f_r (2/N)² is ∫ f_r cos θ_o dω_o
        summaries.push_back(summary);
    }
    return summaries;
}

std::string spectral_channel_name(double wavelength_um) {
    // Fichet et al. 2021 §3: "S0." + value + unit, the decimal mark written as a comma.
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.6f", wavelength_um * 1e3);
    std::string value = buffer;
    for (char& ch : value)
        if (ch == '.') ch = ',';
    return "S0." + value + "nm";
}

void write_lobe_exr(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options) {
    check_lobe(lobe);
    const int n = lobe.resolution;
    const std::size_t pixels = std::size_t(n) * n;
    std::vector<std::string> names;
    std::vector<float> interleaved;
    Provenance facts;
    if (!is_spectral(lobe)) {
        const QuantityLabels& label = labels(lobe.quantity);
        names = {label.channel};
        interleaved = lobe.values;
        facts = output_facts(lobe, options, label.channel + " = " + label.description);
    } else {
        const std::vector<float> rgb = lobe_to_rgb(lobe, options.colour);
        names = {"R", "G", "B"};
        if (options.spectral_channels)
            for (double lambda : lobe.wavelengths_um) names.push_back(spectral_channel_name(lambda));
        const std::size_t channels = names.size();
        interleaved.resize(pixels * channels);
        for (std::size_t i = 0; i < pixels; ++i) {
            for (int c = 0; c < 3; ++c) interleaved[i * channels + c] = rgb[i * 3 + c];
            for (std::size_t layer = 3; layer < channels; ++layer)
                interleaved[i * channels + layer] = lobe.values[(layer - 3) * pixels + i];
        }
        std::string description = "R, G, B linear " + options.colour.output_space;
        if (options.spectral_channels)
            description += "; S0.<nm> = " + labels(lobe.quantity).symbol + " per wavelength (Fichet et al. 2021)";
        facts = output_facts(lobe, options, description);
        facts["output.colour_space"] = options.colour.output_space;
    }
    if (std::set<std::string>(names.begin(), names.end()).size() != names.size())
        throw Error("cannot write '" + path + "': two wavelengths share the channel name " +
                    "(wavelengths closer than 1e-6 nm)");
    OIIO::ImageSpec spec(n, n, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    spec.attribute("compression", "zip");
    add_attributes(spec, lobe.metadata);
    add_attributes(spec, facts);
    if (is_spectral(lobe)) {
        const std::vector<float> primaries = scene_linear_chromaticities(options.colour, options.colour.output_space);
        if (!primaries.empty()) spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), primaries.data());
    }
    if (options.spectral_channels && is_spectral(lobe)) {
        spec.attribute("spectralLayoutVersion", "1.0");
        spec.attribute("emissiveUnits", "W.m^-2.sr^-1");
    }
    write_image_file(path, spec, interleaved.data(), OIIO::TypeDesc::FLOAT);
}

DisplayExposure write_lobe_png(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options) {
    check_lobe(lobe);
    if (file_extension(path) != "png") throw Error("cannot write '" + path + "': a PNG file name must end in .png");
    check_colormap_option(options.colormap);
    if (!options.bare) {
        write_lobe_picture(lobe, path, options);
        return display_exposure(lobe, options.colour);
    }
    if (!is_spectral(lobe) && options.colormap != "grey") return write_colormap_png(lobe, path, options);
    const DisplayImage display = lobe_to_display(lobe, options.colour);
    OIIO::ImageSpec spec(display.resolution, display.resolution, 3, OIIO::TypeDesc::UINT8);
    add_attributes(spec, lobe.metadata);
    Provenance facts = output_facts(lobe, options, "display-referred " + options.colour.display_space);
    facts["output.exposure_ev"] = shortest_text(display.exposure.ev);
    facts["output.exposure_rule"] = display.exposure.rule;
    facts["output.log_scale"] = display.exposure.log_scale ? "log10, " + shortest_text(display.exposure.log_decades) +
                                                                 " decades below the white level"
                                                           : "linear";
    add_attributes(spec, facts);
    write_image_file(path, spec, display.pixels.data(), OIIO::TypeDesc::UINT8);
    return display.exposure;
}

void write_lobe_json(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options) {
    check_lobe(lobe);
    const ColourSettings& colour = options.colour;
    const DisplayExposure exposure = display_exposure(lobe, colour);
    const std::string& sum_name = labels(lobe.quantity).sum_name;
    nlohmann::ordered_json summary = nlohmann::ordered_json::array();
    for (const WavelengthSummary& s : summarize_lobe(lobe)) {
        const Vec3 d = s.peak_direction;
        summary.push_back({{"wavelength_um", s.wavelength_um},
                           {"peak_value", s.peak_value},
                           {"peak_pixel", {s.peak_row, s.peak_col}},
                           {"peak_direction", {d.x, d.y, d.z}},
                           {"peak_theta_deg", std::acos(std::clamp(d.z, -1.0, 1.0)) * 180.0 / pi},
                           {"peak_phi_deg", std::atan2(d.y, d.x) * 180.0 / pi},
                           {sum_name, s.disk_sum}});
    }
    nlohmann::ordered_json colour_json = {
        {"config", colour_config_name(colour)},
        {"illuminant", to_string(colour.illuminant)},
        {"exr_colour_space", is_spectral(lobe) ? colour.output_space : "none (Y channel)"},
        {"png_colour_space", is_spectral(lobe) || options.colormap == "grey" ? colour.display_space
                                                                               : "colour map " + options.colormap}};
    if (is_spectral(lobe)) colour_json["luminance_" + sum_name] = luminance_albedo(lobe, colour.illuminant);
    colour_json["png_exposure_ev"] = exposure.ev;
    colour_json["png_white_level"] = exposure.white_level;
    colour_json["png_exposure_rule"] = exposure.rule;
    colour_json["png_log_scale"] = exposure.log_scale;
    colour_json["png_log_decades"] = exposure.log_decades;
    nlohmann::ordered_json metadata = nlohmann::ordered_json::object();
    for (const auto& [key, value] : lobe.metadata) metadata[key] = json_value(value);
    const nlohmann::ordered_json json = {{"format", "glintscope lobe"},
                                         {"resolution", lobe.resolution},
                                         {"quantity", to_string(lobe.quantity)},
                                         {"units", labels(lobe.quantity).units},
                                         {"wavelengths_um", lobe.wavelengths_um},
                                         {"summary", summary},
                                         {"colour", colour_json},
                                         {"metadata", metadata}};
    // Invalid UTF-8 in a recorded value (a file name, say) is replaced, not a reason to fail.
    write_text_file(path, json.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n");
}

double recorded_exposure_ev(const std::string& json_path) {
    std::ifstream stream(json_path);
    if (!stream) throw Error("cannot read '" + json_path + "': no such file");
    const nlohmann::json json = nlohmann::json::parse(stream, nullptr, false);
    if (json.is_discarded() || !json.contains("colour") || !json["colour"].contains("png_exposure_ev") ||
        !json["colour"]["png_exposure_ev"].is_number())
        throw Error("cannot read an exposure from '" + json_path + "': not a glintscope JSON sidecar");
    return json["colour"]["png_exposure_ev"].get<double>();
}

void write_lobe(const LobeImage& lobe, const std::string& path, const LobeOutputOptions& options) {
    const std::string extension = file_extension(path);
    if (extension == "exr") return write_lobe_exr(lobe, path, options);
    if (extension == "png") {
        write_lobe_png(lobe, path, options);
        return;
    }
    if (extension == "json") return write_lobe_json(lobe, path, options);
    throw Error("cannot write lobe '" + path + "': unsupported format (use .exr, .png or .json)");
}

LobeExrLayers load_lobe_exr_layers(const std::string& path) {
    auto input = OIIO::ImageInput::open(path);
    if (!input) throw Error("cannot read lobe '" + path + "': " + one_line_message(OIIO::geterror()));
    const OIIO::ImageSpec& spec = input->spec();
    if (spec.width != spec.height || spec.width < 1 || spec.depth > 1)
        throw Error("cannot read lobe '" + path + "': the image is not square");
    // No lobe the tool writes is larger (query.cpp: N ≤ 8192, 4 GB of values, plus R, G, B): a
    // header claiming more is refused before anything is allocated.
    if (spec.width > 8192 || 4.0 * double(spec.width) * spec.height * spec.nchannels > 5e9)
        throw Error("cannot read lobe '" + path + "': its header claims " + std::to_string(spec.width) + "² pixels x " +
                    std::to_string(spec.nchannels) + " channels, more than any lobe glintscope writes");
    const std::string wavelengths_key = std::string(attribute_prefix) + "output.wavelengths_um";
    const OIIO::ParamValue* wavelengths = spec.find_attribute(wavelengths_key, OIIO::TypeDesc::STRING);
    if (!wavelengths) throw Error("cannot read lobe '" + path + "': no " + wavelengths_key + " attribute");
    const OIIO::ParamValue* quantity =
        spec.find_attribute(std::string(attribute_prefix) + "output.quantity", OIIO::TypeDesc::STRING);

    LobeExrLayers lobe;
    lobe.resolution = spec.width;
    lobe.quantity = quantity ? parse_quantity(quantity->get_string()) : Quantity::brdf;
    lobe.wavelengths_um = parse_list(wavelengths->get_string(), path);
    std::vector<int> channels;
    if (lobe.wavelengths_um.size() == 1) {
        channels.push_back(spec.channelindex(labels(lobe.quantity).channel));
    } else {
        for (double lambda : lobe.wavelengths_um) channels.push_back(spec.channelindex(spectral_channel_name(lambda)));
    }
    if (std::find(channels.begin(), channels.end(), -1) == channels.end()) {
        for (double lambda : lobe.wavelengths_um) lobe.names.push_back(shortest_text(lambda) + " um");
    } else if (lobe.wavelengths_um.size() > 1) {  // a spectral lobe written as R, G, B only
        lobe.colour = true;
        lobe.names = {"R", "G", "B"};
        const auto recorded = [&](const std::string& key) {
            return std::string(spec.get_string_attribute(std::string(attribute_prefix) + key));
        };
        lobe.colour_encoding = recorded("output.colour_space") + " under " + recorded("output.illuminant");
        channels = {spec.channelindex("R"), spec.channelindex("G"), spec.channelindex("B")};
    }
    if (std::find(channels.begin(), channels.end(), -1) != channels.end())
        throw Error("cannot read lobe '" + path + "': it has neither per-wavelength channels (" +
                    (lobe.wavelengths_um.size() == 1 ? labels(lobe.quantity).channel : "S0.<nm>") + ") nor R, G, B");
    const std::size_t pixels = std::size_t(spec.width) * spec.height;
    std::vector<float> all(pixels * spec.nchannels);
    if (!input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, all.data()))
        throw Error("cannot read lobe '" + path + "': " + one_line_message(input->geterror()));
    lobe.values.resize(pixels * channels.size());
    for (std::size_t layer = 0; layer < channels.size(); ++layer)
        for (std::size_t i = 0; i < pixels; ++i) lobe.values[layer * pixels + i] = all[i * spec.nchannels + channels[layer]];
    for (const OIIO::ParamValue& attribute : spec.extra_attribs) {
        const std::string& name = attribute.name().string();
        if (!name.starts_with(attribute_prefix) || attribute.type() != OIIO::TypeDesc::STRING) continue;
        const std::string key = name.substr(attribute_prefix.size());
        if (!key.starts_with(output_prefix)) lobe.metadata[key] = attribute.get_string();
    }
    return lobe;
}

LobeImage load_lobe_exr(const std::string& path) {
    LobeExrLayers layers = load_lobe_exr_layers(path);
    if (layers.colour)
        throw Error("cannot read lobe '" + path + "': it has no per-wavelength channels (S0.<nm>), only R, G, B; "
                    "write spectral lobes with spectral channels to read them back");
    LobeImage lobe = make_lobe_image(layers.resolution, layers.wavelengths_um, layers.quantity);
    lobe.values = std::move(layers.values);
    lobe.metadata = std::move(layers.metadata);
    return lobe;
}

}  // namespace glintscope
