#pragma once
// A line of samples continued beyond its ends, for kernels that read past a border: a periodic
// line wraps; any other is continued by point reflection about its end samples,
// h(−k) = 2 h(0) − h(k), so that a local trend runs on without a kink (an even mirror would
// flatten the slope at the edge, wrapping would pull in the opposite edge).
#include <cstddef>

namespace glintscope {

// Sample i of a line of n samples (at `line`, `stride` apart), for any integer i.
inline double extended_sample(const float* line, std::size_t stride, long long i, int n, bool periodic) {
    if (periodic) return line[static_cast<std::size_t>(((i % n) + n) % n) * stride];
    if (n == 1) return line[0];
    const auto at = [&](long long k) { return static_cast<double>(line[static_cast<std::size_t>(k) * stride]); };
    // Each reflection about an end sample maps i closer to the line; point reflection negates
    // the deviation from that sample, so the signs alternate.
    double offset = 0.0;
    double sign = 1.0;
    while (i < 0 || i >= n) {
        const long long end = i < 0 ? 0 : n - 1;
        offset += sign * 2.0 * at(end);
        sign = -sign;
        i = 2 * end - i;
    }
    return offset + sign * at(i);
}

}  // namespace glintscope
