#pragma once
// A projected-disk image (N×N, row 0 at the top, conventions.md "Frames and images") read
// bilinearly between pixel centres at any disk point: how a lobe looks up an NDF it computed at
// a finer resolution, so that the lookup does not blur the lobe.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace glintscope {

struct DiskTable {
    int resolution = 0;
    std::vector<double> values;
    bool extend_edges = false;  // read beyond the image as its nearest edge pixel, else as 0

    double at(double x, double y) const {
        const double u = (x + 1.0) * 0.5 * resolution - 0.5;
        const double v = (1.0 - y) * 0.5 * resolution - 0.5;
        const int c = static_cast<int>(std::floor(u));
        const int r = static_cast<int>(std::floor(v));
        const double fu = u - c;
        const double fv = v - r;
        return (1.0 - fv) * ((1.0 - fu) * pixel(r, c) + fu * pixel(r, c + 1)) +
               fv * ((1.0 - fu) * pixel(r + 1, c) + fu * pixel(r + 1, c + 1));
    }

    double pixel(int r, int c) const {
        if (extend_edges) {
            r = std::clamp(r, 0, resolution - 1);
            c = std::clamp(c, 0, resolution - 1);
        }
        if (r < 0 || c < 0 || r >= resolution || c >= resolution) return 0.0;
        return values[static_cast<std::size_t>(r) * resolution + c];
    }
};

}  // namespace glintscope
