#include "glintscope/surface/slope_distribution.hpp"

#include <cmath>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "surface/field_transforms.hpp"

namespace glintscope {

using field_transforms::neighbour;

// Each chunk of rows keeps a whole histogram: large chunks keep their number (and memory) small.
// The counts are whole numbers, so their sum is exact in any order.
constexpr std::size_t kRowsPerChunk = 256;

std::vector<float> slope_distribution(const Heightfield& field, int resolution) {
    validate(field, "slope distribution", /*allow_missing=*/true);
    if (resolution < 2 || resolution > 4096)
        throw Error("the slope distribution's resolution must lie in [2, 4096], got " + std::to_string(resolution));
    const double dx = field.dx_um(), dy = field.dy_um();
    const std::size_t pixels = static_cast<std::size_t>(resolution) * resolution;
    const std::size_t chunks = (field.rows + kRowsPerChunk - 1) / kRowsPerChunk;
    std::vector<std::vector<double>> counts(chunks);
    parallel_for(field.rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        std::vector<double> count(pixels, 0.0);
        for (int r = static_cast<int>(begin); r < static_cast<int>(end); ++r) {
            const int up = neighbour(r, -1, field.rows, field.periodic), down = neighbour(r, 1, field.rows, field.periodic);
            if (up < 0 || down < 0) continue;
            for (int c = 0; c < field.cols; ++c) {
                const int left = neighbour(c, -1, field.cols, field.periodic);
                const int right = neighbour(c, 1, field.cols, field.periodic);
                if (left < 0 || right < 0 || std::isnan(field.at(r, c))) continue;
                const double zx = (double(field.at(r, right)) - field.at(r, left)) / (2.0 * dx);
                const double zy = (double(field.at(up, c)) - field.at(down, c)) / (2.0 * dy);  // row r − 1 is at larger y
                if (std::isnan(zx) || std::isnan(zy)) continue;
                const double norm = std::sqrt(1.0 + zx * zx + zy * zy);
                const int col = static_cast<int>(std::floor((-zx / norm + 1.0) * 0.5 * resolution));
                const int row = static_cast<int>(std::floor((1.0 + zy / norm) * 0.5 * resolution));
                count[static_cast<std::size_t>(std::min(row, resolution - 1)) * resolution + std::min(col, resolution - 1)] += 1.0;
            }
        }
        counts[begin / kRowsPerChunk] = std::move(count);
    });
    std::vector<double> total(pixels, 0.0);
    double samples = 0.0;
    for (const std::vector<double>& count : counts)
        for (std::size_t p = 0; p < count.size(); ++p) total[p] += count[p], samples += count[p];
    if (samples == 0.0) throw Error("the slope distribution needs valid slopes (no valid point has valid neighbours)");
    // Density per unit disk area: counts / samples / (2/N)².
    const double pixel_area = 4.0 / (double(resolution) * resolution);
    std::vector<float> density(pixels);
    for (std::size_t p = 0; p < pixels; ++p) density[p] = static_cast<float>(total[p] / samples / pixel_area);
    return density;
}

}  // namespace glintscope
