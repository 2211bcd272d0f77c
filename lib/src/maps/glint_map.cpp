// Glint maps: the discrete method's flakes counted for one pair of directions as the footprint
// moves over the surface (Jakob 2014 Fig. 1 as a map of positions).
#include "glintscope/maps/glint_map.hpp"

#include <algorithm>
#include <cmath>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "methods/discrete/discrete_lobe.hpp"

namespace glintscope {

ScalarImage discrete_glint_map(const LobeQuery& lobe_query, Vec3 omega_o, int size, double step_um,
                               const std::function<void(std::size_t done, std::size_t total)>& progress) {
    LobeQuery query = lobe_query;
    query.quantity = Quantity::brdf;
    plan_lobe("discrete", query);  // the checks every request of the method passes
    if (!(size >= 1 && size <= 4096)) throw Error("glint map size must be 1 to 4096 positions, got " + std::to_string(size));
    if (!(step_um > 0.0 && step_um <= 1e5))
        throw Error("glint map spacing must be above 0 and at most 10 cm, got " + shortest_text(step_um) + " um");
    if (!(std::isfinite(omega_o.z) && omega_o.z > 0.0 && std::abs(length(omega_o) - 1.0) < 1e-9))
        throw Error("the outgoing direction must point above the surface (theta below 90 degrees)");
    // Exact counts unless asked otherwise: eq. 10's estimates stand in for whole nodes of flakes,
    // which a moving footprint shows as the tree's squares.
    if (!query.method_options.contains("error")) query.method_options.insert_or_assign("error", std::string("0"));
    DiscreteSetup setup;
    setup_discrete(query, setup);
    const PixelQuery pixel = pixel_query(query, setup, DiskPoint{omega_o.x, omega_o.y});
    const double scale = pixel.scale * fresnel_at(query, pixel.h);
    ScalarImage map{size, size, std::vector<float>(static_cast<std::size_t>(size) * size, 0.0f)};
    const double middle = 0.5 * (size - 1);
    // Bands of rows, so that progress can be reported between them from this thread.
    constexpr std::size_t kBandRows = 16;
    for (std::size_t band = 0; band < static_cast<std::size_t>(size); band += kBandRows) {
        const std::size_t band_end = std::min<std::size_t>(size, band + kBandRows);
        parallel_for(band_end - band, 1, [&](std::size_t begin, std::size_t end) {
            SplitCache cache;
            for (std::size_t r = band + begin; r < band + end; ++r)
                for (int c = 0; c < size; ++c) {
                    FlakeFootprint footprint = setup.footprint;
                    footprint.centre_x += (c - middle) * step_um;
                    footprint.centre_y += (middle - static_cast<double>(r)) * step_um;
                    const FlakeCount count = count_flakes(setup.material, footprint, pixel.conic, setup.epsilon, &cache);
                    map.values[r * size + c] = static_cast<float>(scale * count.weighted);
                }
        });
        if (progress) progress(band_end, static_cast<std::size_t>(size));
    }
    return map;
}

}  // namespace glintscope
