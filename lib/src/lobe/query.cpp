// The lobe query: its heightfield, its validation and the physics warnings about it.
#include <cmath>

#include "glintscope/error.hpp"
#include "glintscope/lobe.hpp"
#include "glintscope/material.hpp"
#include "glintscope/text_format.hpp"

namespace glintscope {

void set_heightfield(LobeQuery& query, Heightfield field) {
    auto shared_field = std::make_shared<const Heightfield>(std::move(field));
    query.surface = std::make_shared<const BicubicInterpolant>(*shared_field);
    query.field = std::move(shared_field);
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
    const Footprint& footprint = query.footprint;
    if (!std::isfinite(footprint.centre_um.x) || !std::isfinite(footprint.centre_um.y))
        throw Error("footprint centre must be finite");
    if (footprint.shape == FootprintShape::gaussian && !(footprint.sigma_um > 0.0 && footprint.sigma_um <= 1e4))
        throw Error("coherence sigma must be between 0 and 10 mm, got " + shortest_text(footprint.sigma_um) + " um");
    if (footprint.shape == FootprintShape::box && !(footprint.size_um > 0.0 && footprint.size_um <= 1e5))
        throw Error("box footprint size must be between 0 and 100 mm, got " + shortest_text(footprint.size_um) +
                    " um");
    if (query.resolution < 4 || query.resolution > 8192)
        throw Error("lobe resolution must be between 4 and 8192, got " + std::to_string(query.resolution));
    // An unknown material, or a wavelength outside its table, fails here rather than mid-lobe.
    if (!query.material.name.empty())
        for (double lambda : query.wavelengths_um) complex_refractive_index(query.material.name, lambda);
    if (query.supersample < 1 || query.supersample > 16)
        throw Error("supersampling must be between 1 and 16, got " + std::to_string(query.supersample));
}

std::vector<std::string> query_warnings(const std::string& method, const LobeQuery& query) {
    std::vector<std::string> warnings;
    // The coherence window blurs a wave lobe by about λ/(2πσ_c) in disk units; a pixel is 2/N
    // wide. Below a pixel the lobe is point-sampled, and its albedo and peak are off.
    if (lobe_method(method).wave_optics && query.supersample == 1 && query.footprint.shape == FootprintShape::gaussian) {
        const double blur = query.wavelengths_um.front() / (2.0 * pi * query.footprint.sigma_um);
        const double pixel = 2.0 / query.resolution;
        if (blur < pixel)
            warnings.push_back("the coherence blur lambda/(2 pi sigma_c) = " + shortest_text(blur) +
                               " is smaller than a pixel (" + shortest_text(pixel) +
                               "); the lobe is point-sampled (use --supersample or a larger --res)");
    }
    return warnings;
}

}  // namespace glintscope
