#pragma once
// Queries and calls that several library tests share: a small flat query, the one-line error a
// computation gives, and a computation at a given thread count.
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace glintscope::testing {

// A flat 32² field of 1 µm texels, a σ_c = 3 µm footprint at its centre, a 16² image: every
// method answers it quickly.
inline LobeQuery flat_query() {
    LobeQuery query;
    set_heightfield(query, make_heightfield(32, 32, 1.0));
    query.footprint.centre_um = {16.0, 16.0};
    query.footprint.sigma_um = 3.0;
    query.resolution = 16;
    return query;
}

// The message compute_lobe throws for `query`, or "" when it succeeds.
inline std::string compute_error(const std::string& method, const LobeQuery& query) {
    try {
        compute_lobe(method, query);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

// compute_lobe with `threads` workers.
inline LobeImage compute_with_threads(const std::string& method, const LobeQuery& query, int threads) {
    return with_threads(threads, [&] { return compute_lobe(method, query); });
}

}  // namespace glintscope::testing
