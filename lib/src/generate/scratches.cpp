// Scratched metal (Yan et al. 2018 §6.1: "drawing lines with randomized positions, depths, and
// widths"): straight grooves of random position, direction, length, width, depth and
// cross-section, carved into a weak Gaussian base noise. Each texel takes the area average of a
// groove's depth (4×4 subsamples), so grooves narrower than a texel do not alias; where grooves
// cross, the deepest one wins, as when a tool cuts through an earlier scratch. The tile is
// periodic: a groove leaving one edge re-enters at the opposite one.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/counter_rng.hpp"
#include "generators.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

constexpr std::size_t kRowsPerChunk = 16;
constexpr int kSubsamples = 4;  // per texel side
// The groove depth eases in and out over this fraction of the length at each end (smoothstep),
// as a tool entering and leaving the surface does, instead of ending in a vertical wall.
constexpr double kTaperFraction = 0.1;

double cross_section(ScratchProfile profile, double s) {
    switch (profile) {
        case ScratchProfile::parabolic: return 1.0 - s * s;
        case ScratchProfile::v: return 1.0 - std::fabs(s);
        case ScratchProfile::rounded: return std::sqrt(std::max(0.0, 1.0 - s * s));
        case ScratchProfile::mixed: break;
    }
    return 0.0;
}

double smoothstep(double t) { return t * t * (3.0 - 2.0 * t); }

// One periodic image of a scratch, with its bounding box in µm.
struct ScratchImage {
    const Scratch* scratch;
    Point2 centre;
    double cos_direction, sin_direction;
    double x_min, x_max, y_min, y_max;
};

std::vector<ScratchImage> periodic_images(const std::vector<Scratch>& scratches, double width, double height) {
    std::vector<ScratchImage> images;
    for (const Scratch& scratch : scratches) {
        const double c = std::fabs(std::cos(scratch.direction_rad));
        const double s = std::fabs(std::sin(scratch.direction_rad));
        const double half_x = 0.5 * (scratch.length_um * c + scratch.width_um * s);
        const double half_y = 0.5 * (scratch.length_um * s + scratch.width_um * c);
        const Point2 p = scratch.centre_um;
        for (int ix = static_cast<int>(std::ceil((-p.x - half_x) / width));
             ix <= static_cast<int>(std::floor((width - p.x + half_x) / width)); ++ix)
            for (int iy = static_cast<int>(std::ceil((-p.y - half_y) / height));
                 iy <= static_cast<int>(std::floor((height - p.y + half_y) / height)); ++iy) {
                const Point2 centre{p.x + ix * width, p.y + iy * height};
                images.push_back({&scratch, centre, std::cos(scratch.direction_rad), std::sin(scratch.direction_rad),
                                  centre.x - half_x, centre.x + half_x, centre.y - half_y,
                                  centre.y + half_y});
            }
    }
    return images;
}

// The groove depth at a point: cross-section across it, taper along it, zero outside.
double groove_depth(const ScratchImage& image, double x, double y) {
    const Scratch& scratch = *image.scratch;
    const double dx = x - image.centre.x;
    const double dy = y - image.centre.y;
    const double along = dx * image.cos_direction + dy * image.sin_direction;
    const double across = -dx * image.sin_direction + dy * image.cos_direction;
    const double half_length = 0.5 * scratch.length_um;
    const double s = 2.0 * across / scratch.width_um;
    if (std::fabs(along) >= half_length || std::fabs(s) >= 1.0) return 0.0;
    const double taper = std::min(1.0, (half_length - std::fabs(along)) / (kTaperFraction * scratch.length_um));
    return scratch.depth_um * cross_section(scratch.profile, s) * smoothstep(taper);
}

// The x-range covered by a scratch rectangle within the strip y ∈ [y0, y1]: its corners clipped
// to the strip (Sutherland–Hodgman against two horizontal lines).
bool strip_x_range(const ScratchImage& image, double y0, double y1, double& x_min, double& x_max) {
    const Scratch& scratch = *image.scratch;
    const Point2 along{image.cos_direction * 0.5 * scratch.length_um, image.sin_direction * 0.5 * scratch.length_um};
    const Point2 across{-image.sin_direction * 0.5 * scratch.width_um, image.cos_direction * 0.5 * scratch.width_um};
    const Point2 c = image.centre;
    const Point2 corners[4] = {{c.x - along.x - across.x, c.y - along.y - across.y},
                               {c.x + along.x - across.x, c.y + along.y - across.y},
                               {c.x + along.x + across.x, c.y + along.y + across.y},
                               {c.x - along.x + across.x, c.y - along.y + across.y}};
    x_min = std::numeric_limits<double>::infinity();
    x_max = -x_min;
    for (int k = 0; k < 4; ++k) {
        const Point2 a = corners[k];
        const Point2 b = corners[(k + 1) % 4];
        if (a.y >= y0 && a.y <= y1) {
            x_min = std::min(x_min, a.x);
            x_max = std::max(x_max, a.x);
        }
        for (double line : {y0, y1}) {
            if ((a.y - line) * (b.y - line) < 0.0) {
                const double x = a.x + (line - a.y) / (b.y - a.y) * (b.x - a.x);
                x_min = std::min(x_min, x);
                x_max = std::max(x_max, x);
            }
        }
    }
    return x_min <= x_max;
}

}  // namespace

std::vector<Scratch> place_scratches(const GridSpec& grid, const ScratchParameters& parameters, std::uint64_t seed) {
    const double width = grid.width_um();
    const double height = grid.height_um();
    const auto count = static_cast<std::size_t>(std::llround(parameters.density_per_mm2 * width * height * 1e-6));
    const CounterRng rng(seed, kStreamScratches);
    constexpr std::uint64_t kDraws = 8;  // random numbers per scratch
    std::vector<Scratch> scratches(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::uint64_t base = i * kDraws;
        Scratch& scratch = scratches[i];
        scratch.centre_um = {rng.uniform(base, 0.0, width), rng.uniform(base + 1, 0.0, height)};
        scratch.direction_rad = rng.uniform(base + 2, 0.0, pi);
        scratch.length_um = rng.uniform(base + 3, parameters.length_min_um, parameters.length_max_um);
        scratch.width_um = rng.uniform(base + 4, parameters.width_min_um, parameters.width_max_um);
        scratch.depth_um = rng.uniform(base + 5, parameters.depth_min_um, parameters.depth_max_um);
        if (parameters.profile == ScratchProfile::mixed) {
            constexpr ScratchProfile kProfiles[3] = {ScratchProfile::parabolic, ScratchProfile::v,
                                                     ScratchProfile::rounded};
            scratch.profile = kProfiles[std::min(2, static_cast<int>(3.0 * rng.uniform(base + 6)))];
        } else {
            scratch.profile = parameters.profile;
        }
    }
    return scratches;
}

void carve_scratches(Heightfield& field, const std::vector<Scratch>& scratches) {
    const double dx = field.dx_um();
    const double dy = field.dy_um();
    const int rows = field.rows;
    const int cols = field.cols;
    const std::vector<ScratchImage> images = periodic_images(scratches, cols * dx, rows * dy);
    parallel_for(rows, kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        // Rows begin..end−1 span y ∈ [(R − end)·dy, (R − begin)·dy].
        const double chunk_y0 = (rows - static_cast<double>(end)) * dy;
        const double chunk_y1 = (rows - static_cast<double>(begin)) * dy;
        std::vector<float> depth((end - begin) * cols, 0.0f);
        for (const ScratchImage& image : images) {
            if (image.y_max <= chunk_y0 || image.y_min >= chunk_y1 || image.x_max <= 0.0 || image.x_min >= cols * dx)
                continue;
            for (std::size_t r = begin; r < end; ++r) {
                const double y0 = (rows - static_cast<double>(r) - 1.0) * dy;
                double x_min = 0.0;
                double x_max = 0.0;
                if (!strip_x_range(image, y0, y0 + dy, x_min, x_max)) continue;
                const int c0 = std::max(0, static_cast<int>(std::floor(x_min / dx)));
                const int c1 = std::min(cols - 1, static_cast<int>(std::floor(x_max / dx)));
                for (int c = c0; c <= c1; ++c) {
                    double sum = 0.0;
                    for (int sy = 0; sy < kSubsamples; ++sy)
                        for (int sx = 0; sx < kSubsamples; ++sx)
                            sum += groove_depth(image, (c + (sx + 0.5) / kSubsamples) * dx,
                                                y0 + (sy + 0.5) / kSubsamples * dy);
                    float& texel = depth[(r - begin) * cols + c];
                    texel = std::max(texel, static_cast<float>(sum / (kSubsamples * kSubsamples)));
                }
            }
        }
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < cols; ++c) field.at(static_cast<int>(r), c) -= depth[(r - begin) * cols + c];
    });
}

}  // namespace glintscope
