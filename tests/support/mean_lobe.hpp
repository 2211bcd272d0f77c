#pragma once
// The pixel mean of a method's single-footprint lobes at given centres, computed independently
// of the pipeline's footprint averaging (which tests compare against it).
#include <vector>

#include "glintscope/pipeline/pipeline.hpp"

namespace glintscope::testing {

inline LobeImage mean_of_single_lobes(const std::string& method, const LobeQuery& query,
                                      const std::vector<Point2>& centres) {
    LobeImage mean;
    std::vector<double> sums;
    for (const Point2& centre : centres) {
        LobeQuery one = query;
        one.footprints = {};
        one.footprint.centre_um = centre;
        const LobeImage image = compute_lobe(method, one);
        if (sums.empty()) {
            mean = image;
            sums.assign(image.values.size(), 0.0);
        }
        for (std::size_t i = 0; i < sums.size(); ++i) sums[i] += image.values[i];
    }
    for (std::size_t i = 0; i < sums.size(); ++i) mean.values[i] = static_cast<float>(sums[i] / centres.size());
    return mean;
}

}  // namespace glintscope::testing
