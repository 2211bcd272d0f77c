#pragma once
// The Gabor method's two whole-image evaluations of one query: the default grid (kernels summed
// in space and transformed like fft) against the closed-form sum of the kernels' transforms, uncut
// (evaluation=products, kernel_truncation 5), as the relative L2 of grid against products.
#include "glintscope/lobe/compare.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace glintscope::testing {

inline double grid_against_closed_form(LobeQuery query) {
    query.method_options["evaluation"] = std::string("products");
    query.method_options["kernel_truncation"] = std::string("5");
    const LobeImage products = compute_lobe("gabor", query);
    query.method_options.erase("evaluation");
    query.method_options.erase("kernel_truncation");
    return compare_lobes(compute_lobe("gabor", query), products).at(0).relative_l2;
}

}  // namespace glintscope::testing
