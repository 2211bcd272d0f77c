// CD-like bump tracks (Stam 1999 §5): h(x, y) = Σ_n Σ_m b(x − x_n, y − y_m) (Stam 1999 eq. 18) with
// b = h0 g(x/a) rect(x/a) rect(y/b) (Stam 1999 eq. 19), tracks along y at x_n = (n + 1/2)Δx and bump
// centres y_m a Poisson process of density ν_y on each track.
// Poisson bumps overlap. BumpOverlap::add keeps Stam 1999 eq. 18's sum (stacked bumps reach 2h0, 3h0, ...);
// it is the surface whose phase exp(ikwh) Stam 1999 eq. 21 expands to first order, so it matches his
// spectrum (Stam 1999 eq. 23) for weak phases. BumpOverlap::merge takes the union of a track's bumps
// instead, like the pits of a real disc, which are never deeper than h0.
// Each texel holds the area average of h over its rectangle (the rect edges integrated exactly),
// so the sharp bump edges do not alias and the volume Σ h·dx·dy is exact.
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/counter_rng.hpp"
#include "generators.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kRowsPerChunk = 32;

int track_count(const GridSpec& grid, const CdParameters& parameters) {
    return static_cast<int>(std::floor(grid.width_um() / parameters.track_spacing_um + 1e-9));
}

double track_centre(const CdParameters& parameters, int track) { return (track + 0.5) * parameters.track_spacing_um; }

// Bump centres of each track in increasing y: exponential gaps of mean 1/ν_y from y = 0 give a
// Poisson process on the periodic interval [0, H).
std::vector<std::vector<double>> bump_centres_by_track(const GridSpec& grid, const CdParameters& parameters,
                                                       std::uint64_t seed) {
    const double height = grid.height_um();
    const CounterRng rng(seed, kStreamCdTracks);
    std::vector<std::vector<double>> tracks(track_count(grid, parameters));
    for (std::size_t n = 0; n < tracks.size(); ++n) {
        const std::uint64_t base = static_cast<std::uint64_t>(n) << 32;
        double y = 0.0;
        for (std::uint64_t k = 0;; ++k) {
            y -= std::log(rng.uniform(base + k)) / parameters.bump_density_per_um;
            if (y >= height) break;
            tracks[n].push_back(y);
        }
    }
    return tracks;
}

struct Interval {
    double start;
    double end;
};

// The y-extents the bumps of one track cover, sorted by start and by end: one per bump (add), or
// their union (merge), where an interval running past y = H may absorb the first one's image.
std::vector<Interval> track_intervals(const std::vector<double>& centres, const CdParameters& parameters,
                                      double height) {
    const double half = 0.5 * parameters.bump_length_um;
    std::vector<Interval> intervals;
    for (double y : centres) {
        if (parameters.overlap == BumpOverlap::merge && !intervals.empty() && y - half <= intervals.back().end)
            intervals.back().end = y + half;
        else
            intervals.push_back({y - half, y + half});
    }
    if (parameters.overlap != BumpOverlap::merge || intervals.empty()) return intervals;
    // On the periodic track the last union may reach round to the first ones.
    if (intervals.size() > 1 && intervals.back().end >= intervals.front().start + height) {
        intervals.front() = {intervals.back().start - height,
                             std::max(intervals.front().end, intervals.back().end - height)};
        intervals.pop_back();
        while (intervals.size() > 1 && intervals[1].start <= intervals.front().end) {
            intervals.front().end = std::max(intervals.front().end, intervals[1].end);
            intervals.erase(intervals.begin() + 1);
        }
    }
    if (intervals.size() == 1 && intervals.front().end - intervals.front().start >= height) intervals.front() = {0.0, height};
    return intervals;
}

double overlap(double a0, double a1, double b0, double b1) { return std::max(0.0, std::min(a1, b1) - std::max(a0, b0)); }

// ∫ g(x/a) over the part of [x0, x1] inside the bump, for a bump centred at x = 0 (Stam 1999 eq. 20:
// g⁰ = 1; g¹ = 1/2 + x/a, which rises from 0 to 1 across the bump).
double profile_integral(const CdParameters& parameters, double x0, double x1) {
    const double half = 0.5 * parameters.bump_width_um;
    const double lo = std::max(x0, -half);
    const double hi = std::min(x1, half);
    if (hi <= lo) return 0.0;
    if (parameters.shape == BumpShape::flat) return hi - lo;
    return 0.5 * (hi - lo) + (hi * hi - lo * lo) / (2.0 * parameters.bump_width_um);
}

}  // namespace

std::vector<Point2> place_cd_bumps(const GridSpec& grid, const CdParameters& parameters, std::uint64_t seed) {
    std::vector<Point2> bumps;
    const auto tracks = bump_centres_by_track(grid, parameters, seed);
    for (std::size_t n = 0; n < tracks.size(); ++n)
        for (double y : tracks[n]) bumps.push_back({track_centre(parameters, static_cast<int>(n)), y});
    return bumps;
}

std::vector<float> cd_tracks(const GridSpec& grid, const CdParameters& parameters, std::uint64_t seed) {
    const int rows = grid.rows;
    const int cols = grid.cols;
    const double dx = grid.dx_um();
    const double dy = grid.dy_um();
    const double height = grid.height_um();
    const auto centres = bump_centres_by_track(grid, parameters, seed);
    std::vector<std::vector<Interval>> tracks;
    for (const std::vector<double>& track : centres) tracks.push_back(track_intervals(track, parameters, height));

    // Every bump of a track covers the same columns with the same weights ∫g/dx.
    struct Column {
        int index;
        double weight;
    };
    std::vector<std::vector<Column>> track_columns(tracks.size());
    for (std::size_t n = 0; n < tracks.size(); ++n) {
        const double centre = track_centre(parameters, static_cast<int>(n));
        const double half_width = 0.5 * parameters.bump_width_um;
        const int c0 = std::max(0, static_cast<int>(std::floor((centre - half_width) / dx)));
        const int c1 = std::min(cols - 1, static_cast<int>(std::floor((centre + half_width) / dx)));
        for (int c = c0; c <= c1; ++c) {
            const double weight = profile_integral(parameters, c * dx - centre, (c + 1) * dx - centre) / dx;
            if (weight > 0.0) track_columns[n].push_back({c, weight});
        }
    }

    std::vector<float> heights(static_cast<std::size_t>(rows) * cols, 0.0f);
    parallel_for(rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        const double chunk_y0 = (rows - static_cast<double>(end)) * dy;
        const double chunk_y1 = (rows - static_cast<double>(begin)) * dy;
        std::vector<double> sum((end - begin) * cols, 0.0);
        for (std::size_t n = 0; n < tracks.size(); ++n) {
            const std::vector<Interval>& intervals = tracks[n];
            for (double shift : {-height, 0.0, height}) {  // the periodic images of the track
                auto first = std::partition_point(intervals.begin(), intervals.end(),
                                                  [&](const Interval& i) { return i.end + shift <= chunk_y0; });
                for (auto it = first; it != intervals.end() && it->start + shift < chunk_y1; ++it) {
                    for (std::size_t r = begin; r < end; ++r) {
                        const double row_y0 = (rows - static_cast<double>(r) - 1.0) * dy;
                        const double row_weight = overlap(it->start + shift, it->end + shift, row_y0, row_y0 + dy) / dy;
                        if (row_weight <= 0.0) continue;
                        for (const Column& column : track_columns[n])
                            sum[(r - begin) * cols + column.index] +=
                                parameters.bump_height_um * row_weight * column.weight;
                    }
                }
            }
        }
        for (std::size_t i = 0; i < sum.size(); ++i) heights[begin * cols + i] = static_cast<float>(sum[i]);
    });
    return heights;
}

}  // namespace glintscope
