#include "normal_density/normal_density.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

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
    std::ptrdiff_t origin = 0;  // data[origin + major·major_step + minor·minor_step]: the grids cover a box
    std::ptrdiff_t major_step = 0;
    std::ptrdiff_t minor_step = 0;

    [[gnu::always_inline]] std::ptrdiff_t line(int major) const { return origin + major * major_step; }
    [[gnu::always_inline]] void add(int major, int minor, double mass) const {
        double* at = data + (line(major) + minor * minor_step);
        at[0] += mass;
        at[minor_step] -= 2.0 * mass;
        at[2 * minor_step] += mass;
    }
    // A ramp of `slope` per pixel from position x on (0 before) on the line at data[line]: its
    // integral over pixel k is a first difference of ½·max(0, u − x)², whose third differences
    // vanish but for the three pixels from floor(x) on, with the quadratic B-spline weights
    // ½(1 − t)², ½ + t − t², ½t² (t = x − floor(x)). x lies in [0, N] (up to rounding; truncation
    // takes −1e-17 to 0), so k ≤ N and the three entries fit the N + 3 of a line.
    [[gnu::always_inline]] void add_ramp(std::ptrdiff_t line, double x, double slope) const {
        const int k = static_cast<int>(x);
        const double t = x - k;
        double* at = data + (line + k * minor_step);
        const double half_slope = 0.5 * slope;
        at[0] += half_slope * (1.0 - t) * (1.0 - t);
        at[minor_step] += half_slope + slope * t * (1.0 - t);
        at[2 * minor_step] += half_slope * t * t;
    }
    // The ramp ending at x on the line before (`previous`) and starting at x on `line`: the two
    // share their weights.
    [[gnu::always_inline]] void add_ramp_pair(std::ptrdiff_t previous, std::ptrdiff_t line, double x, double slope) const {
        const int k = static_cast<int>(x);
        const double t = x - k;
        const double w0 = 0.5 * slope * (1.0 - t) * (1.0 - t), w1 = slope * (0.5 + t * (1.0 - t)), w2 = 0.5 * slope * t * t;
        double* before = data + (previous + k * minor_step);
        double* at = data + (line + k * minor_step);
        before[0] -= w0;
        before[minor_step] -= w1;
        before[2 * minor_step] -= w2;
        at[0] += w0;
        at[minor_step] += w1;
        at[2 * minor_step] += w2;
    }
};

// The accumulation of one stripe of the surface: `along_rows` (two running sums along rows),
// `along_columns` (two running sums down columns) and `quadrants` (a running sum along rows, then
// one down columns), each over the same box of entries (rows and columns in 0 … N + 2, so that
// every difference has a place).
struct CoverageGrids {
    int resolution = 0;
    DifferenceGrid along_rows;
    DifferenceGrid along_columns;
    double* quadrants = nullptr;
    std::ptrdiff_t quadrant_origin = 0;  // quadrants[quadrant_origin + r·quadrant_stride + c]
    std::ptrdiff_t quadrant_stride = 0;

    // k times the area of each pixel right of and below the image point p: the pixel fractions
    // of p's column and row, as four differences of a summed-area table.
    [[gnu::always_inline]] void add_quadrant(Pixel p, double k) const {
        const int c = clamp_index(p.u, resolution), r = clamp_index(p.v, resolution);
        const double fu = p.u - c, fv = p.v - r;
        double* at = quadrants + (quadrant_origin + r * quadrant_stride + c);
        at[0] += k * (1.0 - fu) * (1.0 - fv);
        at[1] += k * fu * (1.0 - fv);
        at[quadrant_stride] += k * (1.0 - fu) * fv;
        at[quadrant_stride + 1] += k * fu * fv;
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
    std::ptrdiff_t line = grid.line(line_first);
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

// Grid entries [row_begin, row_end) × [column_begin, column_end) of an N-pixel image, within
// 0 … N + 2 both ways.
struct EntryBox {
    int row_begin = 0, row_end = 0, column_begin = 0, column_end = 0;

    int rows() const { return row_end - row_begin; }
    int columns() const { return column_end - column_begin; }
    bool empty() const { return rows() <= 0 || columns() <= 0; }
    bool holds(const EntryBox& other) const {
        return other.row_begin >= row_begin && other.row_end <= row_end && other.column_begin >= column_begin &&
               other.column_end <= column_end;
    }
};

// The entries that triangles with corners among the image points p can touch: from the pixel of
// the least coordinate to two past the pixel of the greatest (the ramps' and quadrants' reach),
// one more each way for the rounding of points interpolated along edges.
EntryBox entries_reached(const Pixel* p, std::size_t count, int resolution) {
    double u_low = p[0].u, u_high = p[0].u, v_low = p[0].v, v_high = p[0].v;
    for (std::size_t k = 1; k < count; ++k) {
        u_low = lesser(u_low, p[k].u), u_high = greater(u_high, p[k].u);
        v_low = lesser(v_low, p[k].v), v_high = greater(v_high, p[k].v);
    }
    const auto begin = [&](double low) { return std::max(0, clamp_index(low, resolution) - 1); };
    const auto end = [&](double high) { return std::min(resolution + 3, clamp_index(high, resolution) + 4); };
    return {begin(v_low), end(v_high), begin(u_low), end(u_high)};
}

// One stripe's grids, over the box of entries its triangles have reached (the box of its
// footprint's normals on the projected disk, not the whole disk: a σ_c = 10 µm footprint of the
// isotropic builtin has its normals in about 190 × 220 of 512² pixels), so that zeroing, first
// touches and the resolve cost that box's area. Stored as three box-sized arrays: along_rows and quadrants by
// rows, along_columns by columns (a line of either difference grid is contiguous).
struct StripeGrids {
    EntryBox box;
    std::vector<double> storage;
    CoverageGrids grids;

    std::size_t area() const { return static_cast<std::size_t>(box.rows()) * box.columns(); }
    const double* row_differences() const { return storage.data(); }
    const double* column_differences() const { return storage.data() + area(); }
    const double* quadrant_differences() const { return storage.data() + 2 * area(); }
};

// Moves the stripe's grids to `box` (which holds the old one), keeping every entry.
void regrid(StripeGrids& stripe, const EntryBox& box, int resolution) {
    const EntryBox old = stripe.box;
    const std::size_t old_area = stripe.area();
    const std::vector<double> old_storage = std::exchange(stripe.storage, {});
    stripe.box = box;
    const std::ptrdiff_t area = static_cast<std::ptrdiff_t>(stripe.area());
    stripe.storage.assign(static_cast<std::size_t>(3 * area), 0.0);
    const std::ptrdiff_t width = box.columns(), height = box.rows();
    double* data = stripe.storage.data();
    const std::ptrdiff_t by_rows = -(box.row_begin * width + box.column_begin);
    const std::ptrdiff_t by_columns = -(box.column_begin * height + box.row_begin);
    stripe.grids = {resolution, {data, by_rows, width, 1}, {data + area, by_columns, height, 1}, data + 2 * area, by_rows, width};
    for (int r = old.row_begin; r < old.row_end; ++r)
        for (int c = old.column_begin; c < old.column_end; ++c) {
            const std::size_t by_row = static_cast<std::size_t>(r - old.row_begin) * old.columns() + (c - old.column_begin);
            const std::size_t by_column = static_cast<std::size_t>(c - old.column_begin) * old.rows() + (r - old.row_begin);
            data[by_rows + r * width + c] = old_storage[by_row];
            data[area + by_columns + c * height + r] = old_storage[old_area + by_column];
            data[2 * area + by_rows + r * width + c] = old_storage[2 * old_area + by_row];
        }
}

// Grows the stripe's box to hold the entries that triangles with corners among p can touch;
// a side that grows takes a sixteenth of the image more, so that a stripe regrids a few times.
void reach(StripeGrids& stripe, const Pixel* p, std::size_t count) {
    const int resolution = stripe.grids.resolution;
    const EntryBox needed = entries_reached(p, count, resolution);
    if (stripe.box.holds(needed)) return;
    const int slack = resolution / 16 + 1;
    const EntryBox& old = stripe.box;
    const bool first = old.empty();
    const auto low = [&](int wanted, int held) { return first || wanted < held ? std::max(0, wanted - slack) : held; };
    const auto high = [&](int wanted, int held) {
        return first || wanted > held ? std::min(resolution + 3, wanted + slack) : held;
    };
    regrid(stripe,
           {low(needed.row_begin, old.row_begin), high(needed.row_end, old.row_end), low(needed.column_begin, old.column_begin),
            high(needed.column_end, old.column_end)},
           resolution);
}

// Accumulates the base-cell rows [j_begin, j_end) into the stripe's grids, growing their box as
// the triangles' images reach further.
// Compiled twice, for AVX2 + FMA and for the portable baseline (the hot loops above are inlined).
__attribute__((target_clones("arch=x86-64-v3", "default"))) void accumulate_rows(const BicubicInterpolant& surface, const Lattice& lattice, const Weight& weight,
                     const NormalDensitySettings& settings, long long j_begin, long long j_end, StripeGrids& stripe) {
    const CoverageGrids& grids = stripe.grids;  // replaced by reach() when the box grows
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
        reach(stripe, pixels.data(), pixels.size());
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
                // A cell past the footprint's truncation (the lattice's corners, a fifth of a
                // Gaussian's square) deposits nothing; skipping it spares its subdivision.
                if (weight.vanishes_on(x, y, x + hx, y + hy)) continue;
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
                reach(stripe, sub_pixels.data(), sub_pixels.size());
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

// The union of the stripes' boxes, within the image's N × N pixels.
EntryBox pixels_reached(const std::vector<StripeGrids>& stripes, int resolution) {
    EntryBox all{resolution, 0, resolution, 0};
    for (const StripeGrids& stripe : stripes) {
        if (stripe.box.empty()) continue;
        all.row_begin = std::min(all.row_begin, stripe.box.row_begin);
        all.row_end = std::max(all.row_end, std::min(resolution, stripe.box.row_end));
        all.column_begin = std::min(all.column_begin, stripe.box.column_begin);
        all.column_end = std::max(all.column_end, std::min(resolution, stripe.box.column_end));
    }
    return all;
}

// Adds to `sum`, stripe after stripe (the order fixes the rounding), their entries (r, c) of one
// grid (`by_rows`: a grid stored by rows); a stripe has none outside its box.
template <typename Grid>
[[gnu::always_inline]] inline void add_stripes_entry(double& sum, const std::vector<StripeGrids>& stripes, Grid grid,
                                                     bool by_rows, int r, int c) {
    for (const StripeGrids& stripe : stripes) {
        const EntryBox& box = stripe.box;
        if (r < box.row_begin || r >= box.row_end || c < box.column_begin || c >= box.column_end) continue;
        const std::size_t at = by_rows ? static_cast<std::size_t>(r - box.row_begin) * box.columns() + (c - box.column_begin)
                                       : static_cast<std::size_t>(c - box.column_begin) * box.rows() + (r - box.row_begin);
        sum += (stripe.*grid)()[at];
    }
}

// Masses from the stripes' grids, stripes summed in order at every step: the column grid's double
// running sums down each column, the quadrants' running sums along rows and then down columns,
// and each row's double running sum of its row differences. No triangle reached beyond `box`
// (the union of the stripes' boxes), so the sums only start there; but they run on to the
// image's last row and column, as over the whole disk: where a line's differences cancel, their
// rounding leaves a residue (up to 4e-10 of the peak) that the running sums carry on, and the
// image keeps those bits. Returns the pixels [box.row_begin, N) × [box.column_begin, N), which
// hold every nonzero one.
EntryBox resolve(const std::vector<StripeGrids>& stripes, int resolution, const EntryBox& box, std::vector<double>& density) {
    const std::size_t n = static_cast<std::size_t>(resolution);
    density.assign(n * n, 0.0);
    if (box.empty()) return {};
    const EntryBox tail{box.row_begin, resolution, box.column_begin, resolution};
    const std::size_t rows = box.rows(), cols = box.columns(), tail_rows = tail.rows();
    std::vector<double> sums(cols * tail_rows + rows * cols);
    double* columns = sums.data();  // by columns, rows box.row_begin … N − 1
    double* quadrants = sums.data() + cols * tail_rows;
    parallel_for(cols, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c) {
            double slope = 0.0, running = 0.0;
            for (std::size_t r = 0; r < tail_rows; ++r) {
                if (r < rows)
                    add_stripes_entry(slope, stripes, &StripeGrids::column_differences, false,
                                           box.row_begin + static_cast<int>(r), box.column_begin + static_cast<int>(c));
                running += slope;
                columns[c * tail_rows + r] = running;
            }
        }
    });
    parallel_for(rows, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            double running = 0.0;
            for (std::size_t c = 0; c < cols; ++c) {
                add_stripes_entry(running, stripes, &StripeGrids::quadrant_differences, true, box.row_begin + static_cast<int>(r),
                                         box.column_begin + static_cast<int>(c));
                quadrants[r * cols + c] = running;
            }
        }
    });
    for (std::size_t r = 1; r < rows; ++r)
        for (std::size_t c = 0; c < cols; ++c) quadrants[r * cols + c] += quadrants[(r - 1) * cols + c];
    // Past the box the quadrant sums stay those of its last row or column (they add zeros), and
    // each row's running sum goes on adding its last slope. Rounding leaves ~1e-16 of the masses
    // where the true value is 0; negative residues are clipped.
    parallel_for(tail_rows, 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            const int row = tail.row_begin + static_cast<int>(r);
            const bool in_box = r < rows;
            const double* quadrant_row = quadrants + std::min(r, rows - 1) * cols;
            double slope_along = 0.0, running = 0.0;
            for (std::size_t c = 0; c < static_cast<std::size_t>(tail.columns()); ++c) {
                const int column = tail.column_begin + static_cast<int>(c);
                if (in_box) {
                    if (c < cols) add_stripes_entry(slope_along, stripes, &StripeGrids::row_differences, true, row, column);
                    running += slope_along;
                }
                // conventions.md: a pixel whose centre lies outside the disk holds no normal;
                // the sliver of rim mass it caught (normals within a pixel of vertical) is dropped.
                if (!inside_unit_disk(disk_pixel_point(row, column, resolution))) continue;
                const double mass = running + (c < cols ? columns[c * tail_rows + r] : 0.0) + quadrant_row[std::min(c, cols - 1)];
                density[row * n + column] = std::max(0.0, mass);
            }
        }
    });
    return tail;
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
    // The image's box lattice runs along x and y; a turned box is the point query's (normal_bounds_tree).
    if (is_rotated_box(footprint))
        throw Error("the P-NDF image takes axis-aligned boxes only, not a box turned by " +
                    shortest_text(footprint.axis_radians) + " rad (its point query takes one)");
    const Lattice lattice = lattice_for(texel_grid(surface), footprint);
    const Weight weight = weight_for(texel_grid(surface), footprint);
    const long long stripes = stripe_count(resolution, lattice);
    std::vector<StripeGrids> partial(static_cast<std::size_t>(stripes));
    for (StripeGrids& stripe : partial) stripe.grids.resolution = resolution;
    parallel_for(static_cast<std::size_t>(stripes), 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t s = begin; s < end; ++s) {
            const long long j_begin = lattice.ny * static_cast<long long>(s) / stripes;
            const long long j_end = lattice.ny * static_cast<long long>(s + 1) / stripes;
            accumulate_rows(surface, lattice, weight, settings, j_begin, j_end, partial[s]);
        }
    });
    std::vector<double> density;
    const EntryBox nonzero = resolve(partial, resolution, pixels_reached(partial, resolution), density);
    // The deposited weights sum to 1 up to the truncation (1.5e-8) and the centroid rule's
    // quadrature error where neighbouring cells are subdivided differently (~1e-5): one common
    // factor makes the image a normalised density, Σ D·(2/N)² = 1.
    const std::size_t n = static_cast<std::size_t>(resolution);
    double total = 0.0;
    for (int r = nonzero.row_begin; r < nonzero.row_end; ++r)
        for (int c = nonzero.column_begin; c < nonzero.column_end; ++c) total += density[r * n + c];
    const double scale = total > 0.0 ? 1.0 / (total * disk_pixel_area(resolution)) : 0.0;
    for (int r = nonzero.row_begin; r < nonzero.row_end; ++r)
        for (int c = nonzero.column_begin; c < nonzero.column_end; ++c) density[r * n + c] *= scale;
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
