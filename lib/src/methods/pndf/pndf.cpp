#include "methods/pndf/pndf.hpp"

#include <cstdio>
#include <string>

#include "glintscope/error.hpp"

namespace glintscope {
namespace {

std::string format_number(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
    return buffer;
}

}  // namespace

NormalDensitySettings normal_density_settings(const LobeQuery& query, const std::string& method,
                                              const std::vector<std::string>& other_keys) {
    std::vector<std::string> known{"intrinsic_roughness", "refinement", "tolerance"};
    known.insert(known.end(), other_keys.begin(), other_keys.end());
    check_method_options(query, method, known);
    NormalDensitySettings settings;
    const double refinement = method_option_number(query, "refinement", settings.refinement);
    if (!(refinement >= 1.0 && refinement <= 64.0 && refinement == static_cast<int>(refinement)))
        throw Error("option refinement must be a whole number between 1 and 64, got " + format_number(refinement));
    settings.refinement = static_cast<int>(refinement);
    settings.tolerance_pixels = method_option_number(query, "tolerance", settings.tolerance_pixels);
    if (!(settings.tolerance_pixels >= 0.0 && settings.tolerance_pixels <= 10.0))
        throw Error("option tolerance must be between 0 and 10 pixels, got " + format_number(settings.tolerance_pixels));
    settings.intrinsic_roughness = method_option_number(query, "intrinsic_roughness", 0.0);
    if (!(settings.intrinsic_roughness >= 0.0 && settings.intrinsic_roughness <= 1.0))
        throw Error("option intrinsic_roughness must be between 0 and 1 radian, got " +
                    format_number(settings.intrinsic_roughness));
    return settings;
}

LobeImage density_image(const LobeQuery& query, const std::vector<double>& density) {
    LobeImage image = make_lobe_image(query.resolution, query.wavelengths_um);
    const std::size_t layer = density.size();
    for (std::size_t l = 0; l < query.wavelengths_um.size(); ++l)
        for (std::size_t k = 0; k < layer; ++k) image.values[l * layer + k] = static_cast<float>(density[k]);
    image.metadata = describe(query);
    if (query.footprint.shape == FootprintShape::whole) image.metadata["query.footprint.shape"] = "whole";
    return image;
}

LobeImage pndf(const LobeQuery& query) {
    if (!query.surface) throw Error("pndf: the query has no heightfield");
    const NormalDensitySettings settings = normal_density_settings(query, "pndf", {});
    LobeImage image =
        density_image(query, normal_density(*query.surface, query.footprint, query.resolution, settings));
    image.metadata["pndf.refinement"] = std::to_string(settings.refinement);
    image.metadata["pndf.tolerance_pixels"] = format_number(settings.tolerance_pixels);
    image.metadata["pndf.intrinsic_roughness_rad"] = format_number(settings.intrinsic_roughness);
    if (query.footprint.shape == FootprintShape::gaussian)
        image.metadata["pndf.weight_sigma_um"] = format_number(footprint_weight_sigma_um(query.footprint));
    return image;
}

}  // namespace glintscope
