#pragma once
// Tolerances for comparing GaborSurface's second-order queries, whose terms are single precision
// (gabor_kernels.hpp: sum_wavelength_free_terms for several wavelengths,
// sum_chirped_transforms_single for one), with a double path. A term's error is
// below 2^−20 of its size, so a wavelength's sum S moves by δ ≤ 2^−20 Σ_k |t_k| and f = c|S|² by
// at most c(2|S|δ + δ²). The terms' magnitudes are not visible from outside; across a lobe they
// add incoherently, so Σ|t_k| ≈ √n |S| where f is near the lobe's brightest: the bound used here
// is 2^−16 √(f · brightest) + 2^−32 brightest, with `brightest` the largest f of the footprint and
// wavelength compared. A kernel left out or added moves f by about 2|S||t_k|, far beyond it.
#include <algorithm>
#include <cmath>
#include <vector>

namespace glintscope {

inline double single_precision_tolerance(double expected, double brightest) {
    return std::ldexp(1.0, -16) * std::sqrt(std::max(expected, 0.0) * brightest) + std::ldexp(1.0, -32) * brightest;
}

}  // namespace glintscope
