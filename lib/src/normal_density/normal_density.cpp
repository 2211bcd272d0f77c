#include "normal_density/normal_density.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"
#include "normal_density/triangle_model.hpp"

namespace glintscope {
namespace {

// Pixel coordinates of normals lie in [0, N]: for them truncation is the floor, and anything
// below 0 clamps to 0 either way (std::floor is a library call in the portable build).
// The helpers of the accumulation are always inlined: GCC does not inline ordinary functions
// into the AVX2 clone of accumulate_rows (its target differs), and calls would dominate.
[[gnu::always_inline]] inline int clamp_index(double coordinate, int resolution) {
    const int index = static_cast<int>(coordinate);
    return index < 0 ? 0 : index >= resolution ? resolution - 1 : index;
}
[[gnu::always_inline]] inline double lesser(double a, double b) { return b < a ? b : a; }
[[gnu::always_inline]] inline double greater(double a, double b) { return a < b ? b : a; }

// Pixel masses kept as second differences along one axis of the image: two running sums along
// that axis (the resolve step) turn them back into masses, so a mass m in pixel k is +m, −2m,
// +m at k, k + 1, k + 2, and a ramp starting anywhere costs three entries however far it runs.
// This lets a polygon deposit its exact coverage through its edges alone, at a constant cost per
// line of pixels an edge crosses: the edge adds the signed area between itself and the far end
// of each line, which in one line is a ramp (0 before the edge, rising across it, the full
// height beyond). `major` indexes the lines, `minor` the pixels along a line; the grid along
// rows has major = row, minor = column, the one along columns the reverse.
struct DifferenceGrid {
    double* data = nullptr;
    std::size_t major_step = 0;
    std::size_t minor_step = 0;

    [[gnu::always_inline]] void add(int major, int minor, double mass) const {
        double* at = data + major * major_step + minor * minor_step;
        at[0] += mass;
        at[minor_step] -= 2.0 * mass;
        at[2 * minor_step] += mass;
    }
    // A ramp of `slope` per pixel from position x on (0 before): its integral over pixel k is
    // a first difference of ½·max(0, u − x)², whose third differences vanish but for the three
    // pixels from floor(x) on, with the quadratic B-spline weights ½(1 − t)², ½ + t − t², ½t²
    // (t = x − floor(x)). x lies in [0, N] (up to rounding; truncation takes −1e-17 to 0), so
    // k ≤ N and the three entries fit the N + 3 of a line.
    [[gnu::always_inline]] void add_ramp(double* line, double x, double slope) const {
        const int k = static_cast<int>(x);
        const double t = x - k;
        double* at = line + k * minor_step;
        const double half_slope = 0.5 * slope;
        at[0] += half_slope * (1.0 - t) * (1.0 - t);
        at[minor_step] += half_slope + slope * t * (1.0 - t);
        at[2 * minor_step] += half_slope * t * t;
    }
    // The ramp ending at x on the line before (`previous`) and starting at x on `line`: the two
    // share their weights.
    [[gnu::always_inline]] void add_ramp_pair(double* previous, double* line, double x, double slope) const {
        const int k = static_cast<int>(x);
        const double t = x - k;
        const double w0 = 0.5 * slope * (1.0 - t) * (1.0 - t), w1 = slope * (0.5 + t * (1.0 - t)), w2 = 0.5 * slope * t * t;
        const std::size_t offset = k * minor_step;
        previous[offset] -= w0;
        previous[offset + minor_step] -= w1;
        previous[offset + 2 * minor_step] -= w2;
        line[offset] += w0;
        line[offset + minor_step] += w1;
        line[offset + 2 * minor_step] += w2;
    }
};

// The accumulation of one stripe of the surface, (N + 3)² entries per array so that every
// difference has a place: `along_rows` (two running sums along rows), `along_columns` (two
// running sums down columns) and `quadrants` (a running sum along rows, then one down columns).
struct CoverageGrids {
    int resolution = 0;
    DifferenceGrid along_rows;
    DifferenceGrid along_columns;
    double* quadrants = nullptr;

    // k times the area of each pixel right of and below the image point p: the pixel fractions
    // of p's column and row, as four differences of a summed-area table.
    [[gnu::always_inline]] void add_quadrant(Pixel p, double k) const {
        const int c = clamp_index(p.u, resolution), r = clamp_index(p.v, resolution);
        const double fu = p.u - c, fv = p.v - r;
        const std::size_t stride = static_cast<std::size_t>(resolution) + 3;
        double* at = quadrants + r * stride + c;
        at[0] += k * (1.0 - fu) * (1.0 - fv);
        at[1] += k * fu * (1.0 - fv);
        at[stride] += k * (1.0 - fu) * fv;
        at[stride + 1] += k * fu * fv;
    }
};

// A directed edge a → b that crosses no more lines than pixels along them (|Δv| ≤ |Δu|), in the
// grid's own coordinates (v along major, u along minor), weighted by `density`: in every line it
// crosses, the area of each pixel beyond the edge, signed by the edge's direction in v. In one
// line the edge runs from `left` to `right`, and that area as a function of u is a ramp of slope
// height/(right − left) = density/|du/dv| between them: one ramp up at left, one down at right.
[[gnu::always_inline]] inline void add_shallow_edge(const DifferenceGrid& grid, int n, Pixel a, Pixel b, double density) {
    if (a.v == b.v) return;  // no height, no area
    const double v_low = lesser(a.v, b.v), v_high = greater(a.v, b.v);
    const double du_dv = (b.u - a.u) / (b.v - a.v);
    const double slope = (b.v > a.v ? density : -density) / std::abs(du_dv);
    // Line L runs from u_L to u_{L+1} (its crossings of v = L and L + 1): it takes +σ·ramp(u_L)
    // − σ·ramp(u_{L+1}), σ = slope·sign(du/dv), so each crossing serves the lines on both sides.
    const double signed_slope = du_dv > 0.0 ? slope : -slope;
    const int line_first = clamp_index(v_low, n), line_last = clamp_index(v_high, n);
    double* line = grid.data + line_first * grid.major_step;
    grid.add_ramp(line, a.u + (v_low - a.v) * du_dv, signed_slope);
    for (int boundary = line_first + 1; boundary <= line_last; ++boundary, line += grid.major_step)
        grid.add_ramp_pair(line, line + grid.major_step, a.u + (boundary - a.v) * du_dv, signed_slope);
    grid.add_ramp(line, a.u + (v_high - a.v) * du_dv, -signed_slope);
}

// The directed edge a → b, weighted by `density`: in every pixel row it crosses, the area of
// each pixel right of the edge, signed by the edge's direction in v (R). Summed over a closed
// polygon's edges this is ± the polygon's exact overlap with each pixel (the signed-area
// coverage of scanline rasterisers). An edge steeper than the diagonal would cross more rows
// than columns; it is rasterised down the columns instead, as the area below it signed by its
// direction in u (B), which differs from R by a potential: per pixel, the area of the pixel
// right of and below a point, Φ, has dΦ = −(B's integrand) − (R's integrand) along any path, so
// R = −B + Φ(a) − Φ(b). The Φ terms are summed per corner (`quadrant_a`, `quadrant_b`) and
// deposited once per corner by the caller.
[[gnu::always_inline]] inline void add_edge(const CoverageGrids& grids, Pixel a, Pixel b, double density,
                                            double& quadrant_a, double& quadrant_b) {
    if (std::abs(b.u - a.u) >= std::abs(b.v - a.v)) {
        add_shallow_edge(grids.along_rows, grids.resolution, a, b, density);
        return;
    }
    add_shallow_edge(grids.along_columns, grids.resolution, {a.v, a.u}, {b.v, b.u}, -density);
    quadrant_a += density;
    quadrant_b -= density;
}

// A triangle whose image collapsed onto a line (a surface that is cylindrical there, like a
// grating, or a fold seen edge-on): the uniform triangle's image on the line has the tent
// density of its 1-D marginal, rising from the first to the middle corner and falling to the
// last, with cumulative mass (t − t0)²/((t2 − t0)(t1 − t0)) up to t1 and 1 − (t2 − t)²/((t2 −
// t0)(t2 − t1)) beyond. Each stretch between pixel-edge crossings gets its exact share.
void deposit_segment(const CoverageGrids& grids, Pixel a, Pixel b, Pixel c, double mass) {
    const int n = grids.resolution;
    const DifferenceGrid& rows = grids.along_rows;
    // Parametrise the line by the coordinate along which it spreads most.
    const bool along_u = std::max({a.u, b.u, c.u}) - std::min({a.u, b.u, c.u}) >=
                         std::max({a.v, b.v, c.v}) - std::min({a.v, b.v, c.v});
    std::array<Pixel, 3> corners{a, b, c};
    std::sort(corners.begin(), corners.end(),
              [&](Pixel p, Pixel q) { return along_u ? p.u < q.u : p.v < q.v; });
    const Pixel first = corners[0];
    const Pixel last = corners[2];
    const double span = along_u ? last.u - first.u : last.v - first.v;
    if (!(span > 0.0)) {
        rows.add(clamp_index(first.v, n), clamp_index(first.u, n), mass);
        return;
    }
    const double t1 = ((along_u ? corners[1].u : corners[1].v) - (along_u ? first.u : first.v)) / span;
    const auto cumulative = [t1](double t) {
        if (t <= 0.0) return 0.0;
        if (t >= 1.0) return 1.0;
        return t <= t1 ? t * t / t1 : 1.0 - (1.0 - t) * (1.0 - t) / (1.0 - t1);
    };
    // Parameters where the segment first → last crosses a pixel edge in u or in v.
    std::vector<double> cuts{0.0, 1.0};
    const double du = last.u - first.u;
    const double dv = last.v - first.v;
    for (int k = static_cast<int>(std::ceil(std::min(first.u, last.u))); k <= std::floor(std::max(first.u, last.u)); ++k)
        if (du != 0.0) cuts.push_back((k - first.u) / du);
    for (int k = static_cast<int>(std::ceil(std::min(first.v, last.v))); k <= std::floor(std::max(first.v, last.v)); ++k)
        if (dv != 0.0) cuts.push_back((k - first.v) / dv);
    std::sort(cuts.begin(), cuts.end());
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
        const double share = cumulative(cuts[k + 1]) - cumulative(cuts[k]);
        if (share <= 0.0) continue;
        const double middle = 0.5 * (cuts[k] + cuts[k + 1]);
        rows.add(clamp_index(first.v + middle * dv, n), clamp_index(first.u + middle * du, n), mass * share);
    }
}

// A triangle that needs no edges: one inside a single pixel takes its mass there, and one whose
// image collapsed onto a line its exact 1-D shares (deposit_segment). Returns false for the
// others, whose coverage is deposited through their edges with density −2·mass/cross (edges taken
// counter-clockwise in (u, v), cross > 0, give −coverage: the sign makes every triangle, folded or
// not, add positive mass).
[[gnu::always_inline]] inline bool deposit_small_triangle(const CoverageGrids& grids, Pixel a, Pixel b, Pixel c,
                                                          double mass, double& density) {
    const int n = grids.resolution;
    const int c0 = clamp_index(lesser(lesser(a.u, b.u), c.u), n);
    const int c1 = clamp_index(greater(greater(a.u, b.u), c.u), n);
    const int r0 = clamp_index(lesser(lesser(a.v, b.v), c.v), n);
    const int r1 = clamp_index(greater(greater(a.v, b.v), c.v), n);
    if (c0 == c1 && r0 == r1) {
        grids.along_rows.add(r0, c0, mass);
        return true;
    }
    const double cross = (b.u - a.u) * (c.v - a.v) - (c.u - a.u) * (b.v - a.v);
    const double extent = (c1 - c0 > r1 - r0 ? c1 - c0 : r1 - r0) + 1.0;
    if (std::abs(cross) < 2e-9 * extent * extent) {
        deposit_segment(grids, a, b, c, mass);
        return true;
    }
    density = -2.0 * mass / cross;
    return false;
}

constexpr long long kRowsPerEvaluation = 32;
constexpr long long kColumnsPerGrid = 8192;  // bounds one deposit_grid's scratch on wide fields

// A grid of cols × rows cells of sides hx × hy from (x, y), corner images p[b·stride + a] (b along
// y): two triangles per cell, (p00, p10, p11) and (p00, p11, p01), each carrying the weight at its
// centroid times its area hx·hy/2, spread uniformly over its image; each edge shared by two
// triangles is rasterised once with the difference of their densities (add_edge is linear in the
// density): 3 edges a cell instead of 6, plus the grid's border. The corners' potential terms
// are summed per corner and deposited once. `densities` and `quadrants` are scratch space.
[[gnu::always_inline]] inline void deposit_grid(const CoverageGrids& grids, const Weight& weight, double x, double y,
                                                double hx, double hy, int cols, int rows_of_cells, const Pixel* p,
                                                std::size_t stride,
                                                std::vector<double>& densities, std::vector<double>& quadrants) {
    const std::size_t cells = static_cast<std::size_t>(cols) * rows_of_cells;
    densities.assign(2 * cells, 0.0);
    double* lower = densities.data();          // triangle (p00, p10, p11) of cell (a, b)
    double* upper = densities.data() + cells;  // triangle (p00, p11, p01)
    const double half_area = 0.5 * hx * hy;
    for (int b = 0; b < rows_of_cells; ++b)
        for (int a = 0; a < cols; ++a) {
            const Pixel p00 = p[b * stride + a], p10 = p[b * stride + a + 1];
            const Pixel p01 = p[(b + 1) * stride + a], p11 = p[(b + 1) * stride + a + 1];
            const double xa = x + a * hx, yb = y + b * hy;
            const double lower_mass = half_area * weight(xa + hx * (2.0 / 3.0), yb + hy / 3.0);
            const double upper_mass = half_area * weight(xa + hx / 3.0, yb + hy * (2.0 / 3.0));
            if (lower_mass > 0.0) deposit_small_triangle(grids, p00, p10, p11, lower_mass, lower[b * cols + a]);
            if (upper_mass > 0.0) deposit_small_triangle(grids, p00, p11, p01, upper_mass, upper[b * cols + a]);
        }
    quadrants.assign(static_cast<std::size_t>(rows_of_cells + 1) * stride, 0.0);
    double* q = quadrants.data();
    for (int b = 0; b < rows_of_cells; ++b)
        for (int a = 0; a < cols; ++a) {
            const std::size_t i00 = b * stride + a, i10 = i00 + 1, i01 = i00 + stride, i11 = i01 + 1;
            const double d_lower = lower[b * cols + a], d_upper = upper[b * cols + a];
            // The diagonal: the lower triangle's p11 → p00 and the upper's p00 → p11.
            if (d_upper != d_lower) add_edge(grids, p[i00], p[i11], d_upper - d_lower, q[i00], q[i11]);
            // The bottom: this lower triangle's p00 → p10 and, reversed, the top of the cell below.
            const double bottom = d_lower - (b > 0 ? upper[(b - 1) * cols + a] : 0.0);
            if (bottom != 0.0) add_edge(grids, p[i00], p[i10], bottom, q[i00], q[i10]);
            // The left: the left cell's lower p10 → p11 and, reversed, this upper's p01 → p00.
            const double left = (a > 0 ? lower[b * cols + a - 1] : 0.0) - d_upper;
            if (left != 0.0) add_edge(grids, p[i00], p[i01], left, q[i00], q[i01]);
            if (b == rows_of_cells - 1 && d_upper != 0.0)  // the top row's tops
                add_edge(grids, p[i11], p[i01], d_upper, q[i11], q[i01]);
            if (a == cols - 1 && d_lower != 0.0)  // the right column's rights
                add_edge(grids, p[i10], p[i11], d_lower, q[i10], q[i11]);
        }
    for (int b = 0; b <= rows_of_cells; ++b)
        for (int a = 0; a <= cols; ++a)
            if (q[b * stride + a] != 0.0) grids.add_quadrant(p[b * stride + a], q[b * stride + a]);
}

// Accumulates the base-cell rows [j_begin, j_end) into `rows`.
// Compiled twice, for AVX2 + FMA and for the portable baseline (the hot loops above are inlined).
__attribute__((target_clones("arch=x86-64-v3", "default"))) void accumulate_rows(const BicubicInterpolant& surface, const Lattice& lattice, const Weight& weight,
                     const NormalDensitySettings& settings, long long j_begin, long long j_end, const CoverageGrids& grids) {
    const int resolution = grids.resolution;
    const long long corners_x = lattice.nx + 1;
    const double half_resolution = 0.5 * resolution;
    const double hx = lattice.step_x, hy = lattice.step_y;
    std::vector<SurfacePoint> corners, centres, sub;
    std::vector<Pixel> pixels, centre_pixels, sub_pixels;
    std::vector<double> densities, quadrants;
    const bool adaptive = settings.tolerance_pixels > 0.0;
    for (long long j0 = j_begin; j0 < j_end; j0 += kRowsPerEvaluation) {
        const long long block_rows = std::min(kRowsPerEvaluation, j_end - j0);
        corners.resize(static_cast<std::size_t>(corners_x * (block_rows + 1)));
        const double y_block = lattice.y0 + j0 * hy;
        surface.evaluate_grid(lattice.x0, y_block, hx, hy, static_cast<int>(corners_x), static_cast<int>(block_rows + 1),
                              corners.data());
        pixels.resize(corners.size());
        for (std::size_t k = 0; k < corners.size(); ++k) pixels[k] = normal_pixel(corners[k], half_resolution);
        if (!adaptive && settings.refinement == 1) {
            // Every cell is undivided: the block is a few grids, their inner edges shared.
            for (long long i0 = 0; i0 < lattice.nx; i0 += kColumnsPerGrid)
                deposit_grid(grids, weight, lattice.x0 + i0 * hx, y_block, hx, hy,
                             static_cast<int>(std::min(kColumnsPerGrid, lattice.nx - i0)), static_cast<int>(block_rows),
                             pixels.data() + i0, static_cast<std::size_t>(corners_x), densities, quadrants);
            continue;
        }
        // The cell centres' images, which decide the adaptive subdivision.
        centre_pixels.assign(adaptive ? static_cast<std::size_t>(lattice.nx * block_rows) : 0, Pixel{});
        if (adaptive) {
            centres.resize(centre_pixels.size());
            surface.evaluate_grid(lattice.x0 + 0.5 * hx, y_block + 0.5 * hy, hx, hy, static_cast<int>(lattice.nx),
                                  static_cast<int>(block_rows), centres.data());
            for (std::size_t k = 0; k < centres.size(); ++k) centre_pixels[k] = normal_pixel(centres[k], half_resolution);
        }
        for (long long j = 0; j < block_rows; ++j) {
            const double y = y_block + j * hy;
            const Pixel* lower = &pixels[static_cast<std::size_t>(j * corners_x)];
            const Pixel* upper = lower + corners_x;
            for (long long i = 0; i < lattice.nx; ++i) {
                const double x = lattice.x0 + i * hx;
                const int n = adaptive ? subdivisions(settings, lower[i], lower[i + 1], upper[i], upper[i + 1],
                                                      centre_pixels[static_cast<std::size_t>(j * lattice.nx + i)])
                                       : settings.refinement;
                if (n == 1) {
                    const Pixel cell[4] = {lower[i], lower[i + 1], upper[i], upper[i + 1]};
                    deposit_grid(grids, weight, x, y, hx, hy, 1, 1, cell, 2, densities, quadrants);
                    continue;
                }
                sub.resize(static_cast<std::size_t>(n + 1) * (n + 1));
                sub_pixels.resize(sub.size());
                surface.evaluate_grid(x, y, hx / n, hy / n, n + 1, n + 1, sub.data());
                for (std::size_t k = 0; k < sub.size(); ++k) sub_pixels[k] = normal_pixel(sub[k], half_resolution);
                deposit_grid(grids, weight, x, y, hx / n, hy / n, n, n, sub_pixels.data(), static_cast<std::size_t>(n) + 1,
                             densities, quadrants);
            }
        }
    }
}

// Fixed work split, independent of the thread count, so the ordered sum is bit-identical:
// stripes of base-cell rows, each with its own grids (3·(N + 3)² doubles, zeroed and summed
// whatever the stripe holds), one per 16 384 base cells, at least 2 and at most 16, and no more
// than fit in 512 MB (16 at 1024², 1 from 4096²).
constexpr long long kMaxStripes = 16;
constexpr long long kCellsPerStripe = 16384;
constexpr double kStripeBytes = 512e6;

std::size_t grid_stride(int resolution) { return static_cast<std::size_t>(resolution) + 3; }
std::size_t grid_area(int resolution) { return grid_stride(resolution) * grid_stride(resolution); }

long long stripe_count(int resolution, const Lattice& lattice) {
    const double per_stripe = 3.0 * sizeof(double) * static_cast<double>(grid_area(resolution));
    const long long fitting = static_cast<long long>(kStripeBytes / per_stripe);
    const long long wanted = std::clamp(lattice.nx * lattice.ny / kCellsPerStripe, 2LL, kMaxStripes);
    return std::max(1LL, std::min({wanted, lattice.ny, fitting}));
}

CoverageGrids grids_in(std::vector<double>& storage, int resolution) {
    const std::size_t stride = grid_stride(resolution), area = grid_area(resolution);
    storage.assign(3 * area, 0.0);
    // The column grid is stored by columns, so that a line of either grid is contiguous.
    return {resolution, {storage.data(), stride, 1}, {storage.data() + area, stride, 1}, storage.data() + 2 * area};
}

// Masses from the stripes' grids, stripes summed in order at every step: the column grid's double
// running sums down each column, the quadrants' running sums along rows and then down columns,
// and each row's double running sum of its row differences.
std::vector<double> resolve(std::vector<std::vector<double>>& stripes, int resolution) {
    const std::size_t n = static_cast<std::size_t>(resolution), stride = grid_stride(resolution);
    const std::size_t area = grid_area(resolution);
    double* columns = stripes[0].data() + area;  // stripe 0's grids take the sums
    double* quadrants = stripes[0].data() + 2 * area;
    parallel_for(n, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c) {
            double slope = 0.0, running = 0.0;
            for (std::size_t r = 0; r < n; ++r) {
                for (const auto& stripe : stripes) slope += stripe[area + c * stride + r];
                running += slope;
                columns[c * stride + r] = running;
            }
        }
    });
    parallel_for(n, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            double running = 0.0;
            for (std::size_t c = 0; c < n; ++c) {
                for (const auto& stripe : stripes) running += stripe[2 * area + r * stride + c];
                quadrants[r * stride + c] = running;
            }
        }
    });
    for (std::size_t r = 1; r < n; ++r)
        for (std::size_t c = 0; c < n; ++c) quadrants[r * stride + c] += quadrants[(r - 1) * stride + c];
    // Rounding leaves ~1e-16 of the masses where the true value is 0; negative residues are clipped.
    std::vector<double> density(n * n, 0.0);
    parallel_for(n, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            double slope_along = 0.0, running = 0.0;
            for (std::size_t c = 0; c < n; ++c) {
                for (const auto& stripe : stripes) slope_along += stripe[r * stride + c];
                running += slope_along;
                // conventions.md: a pixel whose centre lies outside the disk holds no normal;
                // the sliver of rim mass it caught (normals within a pixel of vertical) is dropped.
                const bool inside = inside_unit_disk(disk_pixel_point(static_cast<int>(r), static_cast<int>(c), resolution));
                const double mass = running + columns[c * stride + r] + quadrants[r * stride + c];
                density[r * n + c] = inside ? std::max(0.0, mass) : 0.0;
            }
        }
    });
    return density;
}

}  // namespace

double footprint_weight_sigma_um(const Footprint& footprint) {
    // |w|²/A_c with w of standard deviation σ_c is a normalised Gaussian of σ_c/√2.
    return footprint.sigma_um / std::numbers::sqrt2;
}

void check_normal_density_settings(int resolution, const NormalDensitySettings& settings) {
    if (resolution < 1 || resolution > 8192)
        throw Error("NDF resolution must be between 1 and 8192, got " + std::to_string(resolution));
    if (settings.refinement < 1 || settings.refinement > kMaxRefinement)
        throw Error("NDF refinement must be between 1 and 64, got " + std::to_string(settings.refinement));
    if (!(settings.intrinsic_roughness >= 0.0 && settings.intrinsic_roughness <= 1.0))
        throw Error("intrinsic_roughness must be between 0 and 1 radian, got " +
                    shortest_text(settings.intrinsic_roughness));
    if (!(settings.tolerance_pixels >= 0.0))
        throw Error("NDF tolerance must be a non-negative number of pixels, got " + shortest_text(settings.tolerance_pixels));
}

std::vector<double> normal_density(const BicubicInterpolant& surface, const Footprint& footprint, int resolution,
                                   const NormalDensitySettings& settings) {
    check_normal_density_settings(resolution, settings);
    const Lattice lattice = lattice_for(texel_grid(surface), footprint);
    const Weight weight = weight_for(texel_grid(surface), footprint);
    const long long stripes = stripe_count(resolution, lattice);
    std::vector<std::vector<double>> partial(static_cast<std::size_t>(stripes));
    parallel_for(static_cast<std::size_t>(stripes), 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t s = begin; s < end; ++s) {
            const CoverageGrids grids = grids_in(partial[s], resolution);
            const long long j_begin = lattice.ny * static_cast<long long>(s) / stripes;
            const long long j_end = lattice.ny * static_cast<long long>(s + 1) / stripes;
            accumulate_rows(surface, lattice, weight, settings, j_begin, j_end, grids);
        }
    });
    std::vector<double> density = resolve(partial, resolution);
    // The deposited weights sum to 1 up to the truncation (1.5e-8) and the centroid rule's
    // quadrature error where neighbouring cells are subdivided differently (~1e-5): one common
    // factor makes the image a normalised density, Σ D·(2/N)² = 1.
    double total = 0.0;
    for (double mass : density) total += mass;
    const double scale = total > 0.0 ? 1.0 / (total * disk_pixel_area(resolution)) : 0.0;
    for (double& value : density) value *= scale;
    if (settings.intrinsic_roughness > 0.0) blur_normal_density(density, resolution, settings.intrinsic_roughness);
    return density;
}

void blur_normal_density(std::vector<double>& density, int resolution, double roughness) {
    const double sigma_pixels = roughness * 0.5 * resolution;
    const int radius = static_cast<int>(std::ceil(4.0 * sigma_pixels));
    std::vector<double> kernel(2 * radius + 1);
    for (int k = -radius; k <= radius; ++k)
        kernel[k + radius] = std::exp(-0.5 * k * k / (sigma_pixels * sigma_pixels));
    double before = 0.0;
    for (double value : density) before += value;
    const std::size_t n = static_cast<std::size_t>(resolution);
    std::vector<double> pass(density.size(), 0.0);
    // Along rows, then along columns; each output pixel sums its taps in a fixed order.
    parallel_for(n, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < resolution; ++c) {
                double sum = 0.0;
                for (int k = std::max(-radius, -c); k <= std::min(radius, resolution - 1 - c); ++k)
                    sum += kernel[k + radius] * density[r * n + c + k];
                pass[r * n + c] = sum;
            }
    });
    parallel_for(n, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r)
            for (int c = 0; c < resolution; ++c) {
                const DiskPoint p = disk_pixel_point(static_cast<int>(r), c, resolution);
                double sum = 0.0;
                if (p.x * p.x + p.y * p.y < 1.0)
                    for (int k = std::max(-radius, -static_cast<int>(r));
                         k <= std::min(radius, resolution - 1 - static_cast<int>(r)); ++k)
                        sum += kernel[k + radius] * pass[(r + k) * n + c];
                density[r * n + c] = sum;
            }
    });
    // Mass blurred past the rim (and the kernel's own sum) is restored by one common factor.
    double after = 0.0;
    for (double value : density) after += value;
    if (after > 0.0)
        for (double& value : density) value *= before / after;
}

}  // namespace glintscope
