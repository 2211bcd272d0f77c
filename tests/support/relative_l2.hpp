#pragma once
// ‖a − b‖ / ‖b‖ over two arrays of the same size: the tests' relative L2 error of a against b.
#include <cmath>
#include <cstddef>
#include <vector>

namespace glintscope::testing {

inline double relative_l2(const std::vector<double>& a, const std::vector<double>& b) {
    double difference = 0.0, norm = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        difference += (a[k] - b[k]) * (a[k] - b[k]);
        norm += b[k] * b[k];
    }
    return std::sqrt(difference / norm);
}

}  // namespace glintscope::testing
