#pragma once
// The mean sampling weight of a BSDF and its standard error, per wavelength: a Monte Carlo
// estimate of the albedo (the BSDF conformance suite and the methods' own sampler tests).
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/counter_rng.hpp"
#include "glintscope/bsdf/bsdf.hpp"

namespace glintscope::testing {

struct MeanWeight {
    std::vector<double> mean;
    std::vector<double> standard_error;
};

// Over `count` samples at ω_i from the uniforms rng.uniform(2k), rng.uniform(2k + 1).
inline MeanWeight mean_weight(const Bsdf& bsdf, Vec3 omega_i, long count, const CounterRng& rng) {
    const std::size_t layers = bsdf.wavelengths_um().size();
    std::vector<double> sum(layers, 0.0), sum_squares(layers, 0.0);
    for (long k = 0; k < count; ++k) {
        const BsdfSample s = bsdf.sample(omega_i, rng.uniform(2 * k), rng.uniform(2 * k + 1));
        for (std::size_t layer = 0; layer < layers; ++layer) {
            sum[layer] += s.weight[layer];
            sum_squares[layer] += s.weight[layer] * s.weight[layer];
        }
    }
    MeanWeight result;
    for (std::size_t layer = 0; layer < layers; ++layer) {
        const double mean = sum[layer] / count;
        result.mean.push_back(mean);
        result.standard_error.push_back(std::sqrt(std::max(0.0, sum_squares[layer] / count - mean * mean) / count));
    }
    return result;
}

}  // namespace glintscope::testing
