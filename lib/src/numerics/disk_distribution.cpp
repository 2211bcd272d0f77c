#include "numerics/disk_distribution.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <utility>

#include "core/counter_rng.hpp"

namespace glintscope {
namespace {

double half_chord(double x) { return std::sqrt(std::max(0.0, 1.0 - x * x)); }

// ∫ half_chord dx for |x| ≤ 1.
double half_chord_integral(double x) {
    const double t = std::clamp(x, -1.0, 1.0);
    return 0.5 * (t * half_chord(t) + std::asin(t));
}

// ∫ over [x0, x1] of the chord's overlap with [y0, y1], max(0, min(y1, s) − max(y0, −s)) with
// s = √(1 − x²), in closed form: between the x where s crosses |y0|, |y1| or 0, each bound is
// either the constant or ±s throughout.
double chord_overlap_integral(double x0, double x1, double y0, double y1) {
    std::vector<double> cuts = {x0, x1};
    for (double y : {y0, y1, 0.0})
        for (double x : {-half_chord(y), half_chord(y)})
            if (x > x0 && x < x1) cuts.push_back(x);
    std::sort(cuts.begin(), cuts.end());
    double sum = 0.0;
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
        const double a = cuts[k], b = cuts[k + 1];
        const double s = half_chord(0.5 * (a + b));
        const bool top_is_chord = s < y1, bottom_is_chord = -s > y0;
        if ((top_is_chord ? s : y1) <= (bottom_is_chord ? -s : y0)) continue;
        const double chord = half_chord_integral(b) - half_chord_integral(a);
        sum += (top_is_chord ? chord : y1 * (b - a)) - (bottom_is_chord ? -chord : y0 * (b - a));
    }
    return sum;
}

bool corner_inside(double x, double y) { return x * x + y * y <= 1.0; }

}  // namespace

double area_inside_disk(double x0, double x1, double y0, double y1) {
    if (corner_inside(x0, y0) && corner_inside(x1, y0) && corner_inside(x0, y1) && corner_inside(x1, y1))
        return (x1 - x0) * (y1 - y0);
    const double dx = std::max({x0, -x1, 0.0});  // distance from the centre to the square
    const double dy = std::max({y0, -y1, 0.0});
    if (dx * dx + dy * dy >= 1.0) return 0.0;
    return chord_overlap_integral(x0, x1, y0, y1);
}

DiskDistribution make_disk_distribution(int resolution, std::size_t layers, std::vector<double> values) {
    DiskDistribution table;
    const int n = resolution;
    const std::size_t pixels = std::size_t(n) * n;
    table.resolution = n;
    table.layers = layers;
    table.values = std::move(values);
    table.area.assign(pixels, 0.0);
    table.cumulative.assign(pixels, 0.0);
    table.integral.assign(table.layers, 0.0);
    const double side = 2.0 / n;
    double running = 0.0;
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col) {
            const std::size_t p = std::size_t(row) * n + col;
            if (inside_unit_disk(disk_pixel_point(row, col, n))) {
                const double x0 = -1.0 + col * side, y1 = 1.0 - row * side;
                table.area[p] = area_inside_disk(x0, x0 + side, y1 - side, y1);
            }
            double mean = 0.0;
            for (std::size_t layer = 0; layer < table.layers; ++layer) {
                const double value = table.values[layer * pixels + p];
                table.integral[layer] += value * table.area[p];
                mean += value;
            }
            running += mean / double(table.layers) * table.area[p];
            table.cumulative[p] = running;
        }
    table.total = running;
    if (running > 0.0)
        for (double& c : table.cumulative) c /= running;
    return table;
}

long pixel_of(const DiskDistribution& table, double x, double y) {
    if (!(x * x + y * y < 1.0)) return -1;
    const int n = table.resolution;
    const int col = std::clamp(static_cast<int>(std::floor((x + 1.0) * 0.5 * n)), 0, n - 1);
    const int row = std::clamp(static_cast<int>(std::floor((1.0 - y) * 0.5 * n)), 0, n - 1);
    return long(row) * n + col;
}

std::vector<double> values_at(const DiskDistribution& table, double x, double y) {
    std::vector<double> values(table.layers, 0.0);
    const long p = pixel_of(table, x, y);
    if (p < 0) return values;
    const std::size_t pixels = std::size_t(table.resolution) * table.resolution;
    for (std::size_t layer = 0; layer < table.layers; ++layer) values[layer] = table.values[layer * pixels + p];
    return values;
}

double disk_density(const DiskDistribution& table, double x, double y) {
    const long p = pixel_of(table, x, y);
    if (p < 0 || table.total <= 0.0 || table.area[p] <= 0.0) return 0.0;
    const double previous = p == 0 ? 0.0 : table.cumulative[p - 1];
    return (table.cumulative[p] - previous) / table.area[p];
}

std::optional<DiskPoint> sample_disk(const DiskDistribution& table, double u1, double u2) {
    if (table.total <= 0.0) return std::nullopt;
    // The pixel whose cumulative range holds u1; zero-probability pixels have empty ranges.
    const auto found = std::upper_bound(table.cumulative.begin(), table.cumulative.end(), u1);
    const std::size_t p = std::min<std::size_t>(found - table.cumulative.begin(), table.cumulative.size() - 1);
    const double previous = p == 0 ? 0.0 : table.cumulative[p - 1];
    const double width = table.cumulative[p] - previous;
    double su = width > 0.0 ? std::clamp((u1 - previous) / width, 0.0, 1.0) : 0.5;  // u1 reused within the pixel
    double sv = u2;
    const int n = table.resolution;
    const double side = 2.0 / n;
    const double x0 = -1.0 + double(p % n) * side, y1 = 1.0 - double(p / n) * side;
    // Uniform in the pixel's part of the disk: the first try keeps the caller's stratification;
    // a rim pixel rejects points beyond the rim and draws again from a stream seeded by (u1, u2).
    const CounterRng rng(std::bit_cast<std::uint64_t>(u1), std::bit_cast<std::uint64_t>(u2));
    for (std::uint64_t attempt = 0; attempt < 256; ++attempt) {
        const DiskPoint point{x0 + su * side, y1 - sv * side};
        if (inside_unit_disk(point)) return point;
        su = rng.uniform(2 * attempt);
        sv = rng.uniform(2 * attempt + 1);
    }
    return disk_pixel_point(int(p / n), int(p % n), n);  // the centre is inside; 256 misses ≈ never
}

}  // namespace glintscope
