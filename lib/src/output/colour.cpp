#include "glintscope/output/colour.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iterator>
#include <span>
#include <sstream>

#include <OpenColorIO/OpenColorIO.h>

#include "core/embedded_data.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/parallel.hpp"

namespace OCIO = OCIO_NAMESPACE;

namespace glintscope {
namespace {

using Matrix3 = std::array<std::array<double, 3>, 3>;

constexpr const char* builtin_config_path = "ocio/config.ocio";

// Bradford cone response matrix (Lam 1985, as used in CIE 159 and the ICC profile format).
constexpr Matrix3 bradford{{{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};

std::array<double, 3> multiply(const Matrix3& m, std::array<double, 3> v) {
    return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
            m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

Matrix3 inverse(const Matrix3& m) {
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    Matrix3 r;
    r[0] = {(m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det,
            (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det};
    r[1] = {(m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det,
            (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det};
    r[2] = {(m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det,
            (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det};
    return r;
}

// OpenColorIO's messages may span lines; errors are one line.
std::string one_line(std::string text) {
    for (char& ch : text)
        if (ch == '\n' || ch == '\r') ch = ' ';
    return text;
}

std::string config_source(const ColourSettings& settings) {
    if (!settings.config_path.empty()) return settings.config_path;
    const char* environment = std::getenv("OCIO");
    return environment && *environment ? environment : "";
}

OCIO::ConstConfigRcPtr load_config(const ColourSettings& settings) {
    const std::string path = config_source(settings);
    try {
        if (path.empty()) {
            std::istringstream stream{std::string(embedded_data(builtin_config_path))};
            return OCIO::Config::CreateFromStream(stream);
        }
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec))
            throw Error("colour config '" + path + "' does not exist or is not a file");
        return OCIO::Config::CreateFromFile(path.c_str());
    } catch (const OCIO::Exception& e) {
        throw Error("colour config '" + colour_config_name(settings) + "' cannot be loaded: " + one_line(e.what()));
    }
}

std::string space_list(const OCIO::ConstConfigRcPtr& config) {
    std::string list;
    for (int i = 0; i < config->getNumColorSpaces(); ++i) {
        if (!list.empty()) list += ", ";
        list += config->getColorSpaceNameByIndex(i);
    }
    return list;
}

std::string xyz_space(const OCIO::ConstConfigRcPtr& config, const ColourSettings& settings) {
    for (const char* name : {"cie_xyz_d65_interchange", "CIE-XYZ-D65"})
        if (const OCIO::ConstColorSpaceRcPtr space = config->getColorSpace(name)) return space->getName();
    throw Error("colour config '" + colour_config_name(settings) +
                "' has neither the role cie_xyz_d65_interchange nor a colour space CIE-XYZ-D65");
}

std::string find_space(const OCIO::ConstConfigRcPtr& config, const ColourSettings& settings,
                       const std::string& name) {
    if (const OCIO::ConstColorSpaceRcPtr space = config->getColorSpace(name.c_str())) return space->getName();
    throw Error("unknown colour space '" + name + "' in colour config '" + colour_config_name(settings) +
                "' (available: " + space_list(config) + ")");
}

bool inside_disk(int row, int col, int resolution) {
    return inside_unit_disk(disk_pixel_point(row, col, resolution));
}

void check_lobe(const LobeImage& lobe) {
    const std::size_t pixels = std::size_t(lobe.resolution) * lobe.resolution;
    if (lobe.resolution < 1 || lobe.wavelengths_um.empty() || lobe.values.size() != pixels * lobe.wavelengths_um.size())
        throw Error("lobe image is empty or its values do not match its resolution and wavelengths");
}

// Nearest-rank percentile of `values` (not empty); reorders them.
double nearest_rank(std::vector<float>& values, double percentile) {
    const double rank = std::ceil(percentile / 100.0 * double(values.size()));
    const std::size_t index = std::size_t(std::clamp(rank, 1.0, double(values.size()))) - 1;
    std::nth_element(values.begin(), values.begin() + index, values.end());
    return values[index];
}

// The finite luminances of the pixels `counted` accepts.
std::vector<float> counted_luminances(const std::vector<float>& xyz, const std::function<bool(std::size_t)>& counted) {
    std::vector<float> luminance;
    for (std::size_t pixel = 0; pixel < xyz.size() / 3; ++pixel) {
        const float y = xyz[pixel * 3 + 1];
        if (counted(pixel) && std::isfinite(y)) luminance.push_back(y);
    }
    return luminance;
}

// The exposure for an XYZ image `xyz` over the pixels `counted` accepts, named `where` (see display_exposure).
DisplayExposure exposure_for(const std::vector<float>& xyz, const std::function<bool(std::size_t)>& counted,
                             const std::string& where, const ColourSettings& settings) {
    DisplayExposure exposure;
    exposure.log_scale = settings.log_scale;
    exposure.log_decades = settings.log_decades;
    if (settings.log_scale && !(settings.log_decades > 0.0 && settings.log_decades <= 30.0))
        throw Error("log scale decades must be between 0 and 30, got " + shortest_text(settings.log_decades));
    if (settings.exposure_ev) {
        if (!std::isfinite(*settings.exposure_ev) || std::fabs(*settings.exposure_ev) > 200.0)
            throw Error("exposure must be a finite EV within +-200, got " + shortest_text(*settings.exposure_ev));
        exposure.ev = *settings.exposure_ev;
        exposure.rule = "given";
    } else {
        if (!(settings.auto_percentile > 0.0 && settings.auto_percentile <= 100.0))
            throw Error("auto exposure percentile must be in (0, 100], got " + shortest_text(settings.auto_percentile));
        // A log scale exists to show the whole range, so there the maximum is the top.
        const double rank = settings.log_scale ? 100.0 : settings.auto_percentile;
        std::vector<float> luminance = counted_luminances(xyz, counted);
        const double level = luminance.empty() ? 0.0 : nearest_rank(luminance, rank);
        // Where fewer pixels than the percentile leaves above it are lit (a thin highlight in a
        // dark render), the percentile is 0: the same percentile of the lit pixels is the top
        // (the maximum, a single caustic spike, left the rest of the highlight black).
        std::vector<float> lit;
        if (level <= 0.0)
            std::copy_if(luminance.begin(), luminance.end(), std::back_inserter(lit), [](float y) { return y > 0.0f; });
        const std::string percentile = settings.log_scale ? "maximum luminance " + where
                                                          : shortest_text(rank) + "th percentile of luminance " + where;
        if (level > 0.0) {
            exposure.ev = -std::log2(level);
            exposure.rule = "auto: " + percentile + " maps to 1";
        } else if (!lit.empty()) {
            exposure.ev = -std::log2(nearest_rank(lit, rank));
            exposure.rule = "auto: the " + percentile + " is 0, so that percentile of the lit pixels maps to 1";
        } else {
            exposure.rule = "auto: the lobe is black, EV 0";
        }
    }
    exposure.white_level = std::exp2(-exposure.ev);
    return exposure;
}

}  // namespace

XYZ d65_white_xyz() {
    return {d65_white.x / d65_white.y, 1.0, (1.0 - d65_white.x - d65_white.y) / d65_white.y};
}

XYZ adapt_to_d65(XYZ colour, XYZ source_white) {
    // von Kries scaling in the Bradford cone space: the source white goes exactly to the target.
    const XYZ target = d65_white_xyz();
    const std::array<double, 3> source_cone = multiply(bradford, {source_white.X, source_white.Y, source_white.Z});
    const std::array<double, 3> target_cone = multiply(bradford, {target.X, target.Y, target.Z});
    std::array<double, 3> cone = multiply(bradford, {colour.X, colour.Y, colour.Z});
    for (int i = 0; i < 3; ++i) cone[i] *= target_cone[i] / source_cone[i];
    static const Matrix3 bradford_inverse = inverse(bradford);
    const std::array<double, 3> adapted = multiply(bradford_inverse, cone);
    return {adapted[0], adapted[1], adapted[2]};
}

std::string colour_config_name(const ColourSettings& settings) {
    const std::string path = config_source(settings);
    return path.empty() ? std::string("built-in data/") + builtin_config_path : path;
}

std::vector<std::string> colour_space_names(const ColourSettings& settings) {
    const OCIO::ConstConfigRcPtr config = load_config(settings);
    std::vector<std::string> names;
    for (int i = 0; i < config->getNumColorSpaces(); ++i) names.emplace_back(config->getColorSpaceNameByIndex(i));
    return names;
}

void convert_from_xyz(std::vector<float>& pixels, const ColourSettings& settings, const std::string& space) {
    const OCIO::ConstConfigRcPtr config = load_config(settings);
    const std::string source = xyz_space(config, settings);
    const std::string target = find_space(config, settings, space);
    if (pixels.size() % 3 != 0) throw Error("colour conversion needs packed RGB triples");
    if (pixels.empty()) return;
    try {
        const OCIO::ConstCPUProcessorRcPtr processor =
            config->getProcessor(source.c_str(), target.c_str())->getDefaultCPUProcessor();
        OCIO::PackedImageDesc image(pixels.data(), long(pixels.size() / 3), 1, 3);
        processor->apply(image);
    } catch (const OCIO::Exception& e) {
        throw Error("cannot convert " + source + " to " + target + " with colour config '" +
                    colour_config_name(settings) + "': " + one_line(e.what()));
    }
}

namespace {

// Per layer, the XYZ of a unit value: a single wavelength is achromatic, the D65 white; a spectrum
// goes through the weights, adapted (linearly, so once per bin) from the illuminant's white to D65.
std::vector<XYZ> layer_weights(const std::vector<double>& wavelengths_um, Illuminant illuminant) {
    std::vector<XYZ> weights;
    if (wavelengths_um.size() == 1) {
        weights.push_back(d65_white_xyz());
    } else {
        const SpectralWeights spectral = spectral_weights(wavelengths_um, illuminant);
        for (const XYZ& w : spectral.weights) weights.push_back(adapt_to_d65(w, spectral.white));
    }
    return weights;
}

// Packed XYZ of layers [layer][pixel]; pixels `counted` rejects stay 0.
std::vector<float> xyz_of_layers(std::span<const float> values, std::size_t pixels,
                                 const std::vector<double>& wavelengths_um, Illuminant illuminant,
                                 const std::function<bool(std::size_t)>& counted) {
    const std::vector<XYZ> weights = layer_weights(wavelengths_um, illuminant);
    std::vector<float> xyz(pixels * 3, 0.0f);
    parallel_for(pixels, 4096, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            if (!counted(i)) continue;
            XYZ total;
            for (std::size_t layer = 0; layer < weights.size(); ++layer) {
                const double value = values[layer * pixels + i];
                total = {total.X + value * weights[layer].X, total.Y + value * weights[layer].Y,
                         total.Z + value * weights[layer].Z};
            }
            xyz[i * 3] = float(total.X);
            xyz[i * 3 + 1] = float(total.Y);
            xyz[i * 3 + 2] = float(total.Z);
        }
    });
    return xyz;
}

// Whether pixel i (row-major) of an N×N lobe lies inside the disk.
std::function<bool(std::size_t)> disk_pixels(int resolution) {
    return [resolution](std::size_t i) { return inside_disk(int(i / resolution), int(i % resolution), resolution); };
}

bool every_pixel(std::size_t) { return true; }

}  // namespace

std::vector<float> lobe_to_xyz(const LobeImage& lobe, Illuminant illuminant) {
    check_lobe(lobe);
    const std::size_t pixels = std::size_t(lobe.resolution) * lobe.resolution;
    return xyz_of_layers(lobe.values, pixels, lobe.wavelengths_um, illuminant, disk_pixels(lobe.resolution));
}

std::vector<float> layers_to_xyz(std::span<const float> values, std::size_t pixels,
                                 const std::vector<double>& wavelengths_um, Illuminant illuminant) {
    if (pixels == 0 || wavelengths_um.empty() || values.size() != pixels * wavelengths_um.size())
        throw Error("image is empty or its values do not match its size and wavelengths");
    return xyz_of_layers(values, pixels, wavelengths_um, illuminant, every_pixel);
}

std::vector<float> scene_linear_chromaticities(const ColourSettings& settings, const std::string& space) {
    const OCIO::ConstConfigRcPtr config = load_config(settings);
    const std::string name = find_space(config, settings, space);
    const OCIO::ConstColorSpaceRcPtr colour_space = config->getColorSpace(name.c_str());
    const std::string encoding = colour_space->getEncoding() ? colour_space->getEncoding() : "";
    if (!encoding.empty() && encoding != "scene-linear")
        throw Error("colour space '" + name + "' is " + encoding + "-encoded; an EXR holds scene-linear values (e.g. lin_rec709)");
    // ITU-R BT.709, BT.2020, ACES AP1 (S-2014-004), and XYZ itself; D65 or the ACES white.
    if (name == "lin_rec709") return {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    if (name == "lin_rec2020") return {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
    if (name == "ACEScg") return {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
    if (name == "CIE-XYZ-D65") return {1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.3127f, 0.3290f};
    return {};
}

std::vector<float> lobe_to_rgb(const LobeImage& lobe, const ColourSettings& settings) {
    std::vector<float> pixels = lobe_to_xyz(lobe, settings.illuminant);
    convert_from_xyz(pixels, settings, settings.output_space);
    return pixels;
}

DisplayExposure display_exposure(const LobeImage& lobe, const ColourSettings& settings) {
    return exposure_for(lobe_to_xyz(lobe, settings.illuminant), disk_pixels(lobe.resolution), "in the disk", settings);
}

DisplayExposure xyz_exposure(const std::vector<float>& xyz, const ColourSettings& settings) {
    return exposure_for(xyz, every_pixel, "of the image", settings);
}

std::vector<std::uint8_t> xyz_to_display(std::vector<float> pixels, const DisplayExposure& exposure,
                                         const ColourSettings& settings) {
    for (std::size_t i = 0; i < pixels.size(); i += 3) {
        const double y = pixels[i + 1];
        double scale = 0.0;
        if (!exposure.log_scale)
            scale = 1.0 / exposure.white_level;
        else if (y > 0.0)
            scale = std::clamp(1.0 + std::log10(y / exposure.white_level) / exposure.log_decades, 0.0, 1.0) / y;
        for (int c = 0; c < 3; ++c) pixels[i + c] = float(pixels[i + c] * scale);
    }
    convert_from_xyz(pixels, settings, settings.display_space);
    std::vector<std::uint8_t> encoded(pixels.size());
    for (std::size_t i = 0; i < pixels.size(); ++i) {
        const float value = std::isfinite(pixels[i]) ? std::clamp(pixels[i], 0.0f, 1.0f) : 0.0f;
        encoded[i] = std::uint8_t(std::lround(value * 255.0f));
    }
    return encoded;
}

DisplayImage lobe_to_display(const LobeImage& lobe, const ColourSettings& settings) {
    std::vector<float> pixels = lobe_to_xyz(lobe, settings.illuminant);
    DisplayImage display;
    display.resolution = lobe.resolution;
    display.exposure = exposure_for(pixels, disk_pixels(lobe.resolution), "in the disk", settings);
    display.pixels = xyz_to_display(std::move(pixels), display.exposure, settings);
    return display;
}

}  // namespace glintscope
