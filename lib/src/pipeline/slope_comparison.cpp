#include "glintscope/pipeline/slope_comparison.hpp"

#include "glintscope/lobe/query.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/surface/slope_distribution.hpp"

namespace glintscope {

SlopeComparison compare_slopes_with_pndf(const Heightfield& field, int resolution) {
    SlopeComparison comparison;
    const std::vector<float> slopes = slope_distribution(field, resolution);  // refuses bad input first
    LobeQuery query;
    set_heightfield(query, field);
    query.quantity = Quantity::ndf;
    query.footprint.shape = FootprintShape::whole;
    query.resolution = resolution;
    query.method_options["tolerance"] = "0";
    comparison.pndf = compute_lobe("pndf", query);
    comparison.slopes = make_lobe_image(resolution, comparison.pndf.wavelengths_um, Quantity::ndf);
    comparison.slopes.values = slopes;
    comparison.slopes.metadata = comparison.pndf.metadata;
    comparison.slopes.metadata["method"] = "slopes (central differences)";
    return comparison;
}

}  // namespace glintscope
