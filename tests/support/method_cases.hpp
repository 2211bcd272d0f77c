#pragma once
// The cases of the per-method suites (tests/lib/pipeline and tests/lib/bsdf conformance tests):
// every method of the table with a quantity it answers, and the query they all run on.
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "glintscope/generate/generate.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace glintscope::testing {

struct MethodCase {
    MethodInfo method;
    Quantity quantity;
};

inline void PrintTo(const MethodCase& c, std::ostream* os) { *os << c.method.name << " " << to_string(c.quantity); }

// Every (method, quantity) of the table in table order, for the quantities `wanted` accepts.
inline std::vector<MethodCase> method_cases(const std::function<bool(Quantity)>& wanted) {
    std::vector<MethodCase> all;
    for (const MethodInfo& method : lobe_methods())
        for (Quantity quantity : method.quantities)
            if (wanted(quantity)) all.push_back({method, quantity});
    return all;
}

// The isotropic builtin (Yan 2018 Fig. 8 statistics) under a 10 µm footprint at its centre, at
// 0.45 and 0.6 µm; each suite sets the incidence, resolution and supersampling it needs.
inline LobeQuery isotropic_builtin_query(Quantity quantity) {
    static const Heightfield field = generate_builtin("isotropic");
    LobeQuery query;
    set_heightfield(query, field);
    query.quantity = quantity;
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = 10.0;
    query.wavelengths_um = {0.45, 0.6};
    return query;
}

}  // namespace glintscope::testing
