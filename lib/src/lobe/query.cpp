// The lobe query: its heightfield, its validation and the physics warnings about it.
#include <algorithm>
#include <cmath>

#include "glintscope/error.hpp"
#include "glintscope/lobe.hpp"
#include "glintscope/material.hpp"
#include "glintscope/text_format.hpp"
#include "glintscope/units.hpp"

namespace glintscope {

void set_heightfield(LobeQuery& query, Heightfield field) {
    auto shared_field = std::make_shared<const Heightfield>(std::move(field));
    query.surface = std::make_shared<const BicubicInterpolant>(*shared_field);
    query.field = std::move(shared_field);
}

void set_box(Footprint& footprint, std::string_view text) {
    const BoxSides sides = parse_box_sides(text);
    if (!(sides.height_um > 0.0))
        throw Error("box footprint sides must be between 0 and 100 mm, got " + shortest_text(sides.height_um) + " um");
    footprint.shape = FootprintShape::box;
    footprint.size_um = sides.width_um;
    footprint.size_y_um = sides.height_um == sides.width_um ? 0.0 : sides.height_um;  // a square: 0
}

void validate(const Footprint& footprint) {
    // 1 m: far beyond any heightfield, while kernel and sample indices stay exact in double.
    constexpr double max_centre_um = 1e6;
    if (!(std::fabs(footprint.centre_um.x) <= max_centre_um && std::fabs(footprint.centre_um.y) <= max_centre_um))
        throw Error("footprint centre must be finite and within +-1e6 um (1 m), got (" +
                    shortest_text(footprint.centre_um.x) + ", " + shortest_text(footprint.centre_um.y) + ") um");
    if (footprint.shape == FootprintShape::gaussian && !(footprint.sigma_um > 0.0 && footprint.sigma_um <= 1e4))
        throw Error("coherence sigma must be between 0 and 10 mm, got " + shortest_text(footprint.sigma_um) + " um");
    if (footprint.shape == FootprintShape::box)
        for (const double side : {footprint.size_um, box_height_um(footprint)})
            if (!(side > 0.0 && side <= 1e5))
                throw Error("box footprint sides must be between 0 and 100 mm, got " + shortest_text(side) + " um");
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
    validate(query.footprint);
    // The image alone holds N² floats per wavelength: refused here, before any method allocates.
    const auto image_gb = [&](double n) { return shortest_text(std::ceil(4.0 * n * n * query.wavelengths_um.size() / 1e8) / 10); };
    if (query.resolution < 4 || query.resolution > 8192)
        throw Error("lobe resolution must be between 4 and 8192, got " + std::to_string(query.resolution) +
                    (query.resolution > 8192 ? " (its image would need " + image_gb(query.resolution) + " GB)" : ""));
    constexpr double max_image_gb = 4.0;
    if (4.0 * double(query.resolution) * query.resolution * query.wavelengths_um.size() > max_image_gb * 1e9)
        throw Error("lobe image of " + std::to_string(query.resolution) + "^2 pixels x " +
                    std::to_string(query.wavelengths_um.size()) + " wavelengths would need " +
                    image_gb(query.resolution) + " GB, beyond the 4 GB limit (lower --res or the wavelength count)");
    // An unknown material, or a wavelength outside its table, fails here rather than mid-lobe.
    if (!query.material.name.empty())
        for (double lambda : query.wavelengths_um) complex_refractive_index(query.material.name, lambda);
    if (query.supersample < 1 || query.supersample > 16)
        throw Error("supersampling must be between 1 and 16, got " + std::to_string(query.supersample));
}

namespace {

// The coherence window blurs a wave lobe by about λ/(2πσ_c) in disk units (the shortest
// wavelength's is the sharpest); a pixel is 2/N wide.
double coherence_blur(const LobeQuery& query) {
    const double lambda = *std::min_element(query.wavelengths_um.begin(), query.wavelengths_um.end());
    return lambda / (2.0 * pi * query.footprint.sigma_um);
}

bool point_sampled(const std::string& method, const LobeQuery& query) {
    return lobe_method(method).wave_optics && query.footprint.shape == FootprintShape::gaussian &&
           coherence_blur(query) * query.supersample < 2.0 / query.resolution;
}

}  // namespace

std::vector<std::string> query_warnings(const std::string& method, const LobeQuery& query) {
    std::vector<std::string> warnings;
    if (point_sampled(method, query)) {
        const double pixel = 2.0 / (query.resolution * query.supersample);
        warnings.push_back("the coherence blur lambda/(2 pi sigma_c) = " + shortest_text(std::round(coherence_blur(query) * 1e5) / 1e5) +
                           " is smaller than a sub-pixel (" + shortest_text(std::round(pixel * 1e5) / 1e5) +
                           "): the lobe is point-sampled and its albedo and peak are off (use --supersample " +
                           std::to_string(recommended_supersample(method, query) * query.supersample) +
                           " or a larger --res)");
    }
    // Kirchhoff-based models ignore shadowing and masking, which dominate near grazing.
    if (lobe_method(method).wave_optics && query.omega_i.z < std::cos(80.0 * pi / 180.0))
        warnings.push_back("incidence beyond 80 degrees: the diffraction models ignore shadowing and masking, "
                           "which dominate there: the lobe is outside their validity");
    return warnings;
}

int recommended_supersample(const std::string& method, const LobeQuery& query) {
    if (!lobe_method(method).wave_optics || query.footprint.shape != FootprintShape::gaussian) return 1;
    const double pixel = 2.0 / query.resolution;
    return std::clamp(static_cast<int>(std::ceil(1.5 * pixel / coherence_blur(query))), 1, 8);
}

std::vector<std::string> image_warnings(const LobeImage& image) {
    std::vector<std::string> warnings;
    const double pixel_area = disk_pixel_area(image.resolution);
    const std::size_t pixels = std::size_t(image.resolution) * image.resolution;
    for (std::size_t layer = 0; layer < image.layers(); ++layer) {
        double sum = 0.0;
        for (std::size_t i = 0; i < pixels; ++i) sum += image.values[layer * pixels + i];
        sum *= pixel_area;
        const std::string at = "at " + shortest_text(image.wavelengths_um[layer]) + " um";
        if (image.quantity == Quantity::brdf && sum > 1.02) {
            warnings.push_back("albedo " + shortest_text(std::round(sum * 1e4) / 1e4) + " " + at +
                               " exceeds 1 by more than 2%: the model creates energy here (e.g. R-OHS's 1/cos "
                               "theta_o near grazing)");
            break;
        }
        if (image.quantity == Quantity::ndf && std::fabs(sum - 1.0) > 0.02) {
            warnings.push_back("the NDF integrates to " + shortest_text(std::round(sum * 1e4) / 1e4) +
                               " on the disk, not 1 (mass beyond the disk or the footprint, or peaks narrower "
                               "than a pixel that its centres miss: try --supersample)");
            break;
        }
    }
    return warnings;
}

}  // namespace glintscope
