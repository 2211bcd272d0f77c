// The lobe query: its heightfield and its validation.
#include <algorithm>
#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"

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
    validate(query.footprint);
    if (is_elliptical(query.footprint))
        throw Error("an elliptical footprint is answered only by a point query that takes one (a geometric render's "
                    "pixel footprint, BsdfField::at), not by a lobe query");
    if (is_rotated_box(query.footprint))
        throw Error("a rotated box footprint (axis " + shortest_text(query.footprint.axis_radians) +
                    " rad) is answered only by a point query that takes one (a geometric render's pixel cell, "
                    "BsdfField::at), not by a lobe query, whose boxes are axis-aligned");
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
    if (query.supersample < kExactPixels || query.supersample > 16)
        throw Error("supersampling must be between 1 and 16 (or auto, exact), got " + std::to_string(query.supersample));
    if (!(query.memory_budget_gb >= 0.01 && query.memory_budget_gb <= 1e4))
        throw Error("the memory budget must be 0.01 to 10000 GB, got " + shortest_text(query.memory_budget_gb));
    if (query.footprints.count < 0 || query.footprints.count > 100000)
        throw Error("the number of footprints must be 1 to 100000, got " + std::to_string(query.footprints.count));
}

}  // namespace glintscope
