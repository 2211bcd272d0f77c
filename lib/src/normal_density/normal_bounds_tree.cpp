#include "normal_density/normal_bounds_tree.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope {
namespace {

constexpr int kRowsPerChunk = 16;

// The images of the samples, of the cell centres (which decide the subdivision) and the
// subdivision of every cell, as normal_density's accumulate_rows decides it.
void image_samples(const BicubicInterpolant& surface, const NormalDensitySettings& settings, NormalBoundsTree& tree) {
    const TexelGrid& grid = tree.grid;
    const double tx = grid.dx_um, ty = grid.dy_um, half_resolution = 0.5 * tree.resolution;
    const std::size_t cells = static_cast<std::size_t>(grid.cols) * grid.rows;
    tree.samples.resize(cells);
    tree.subdivision.assign(cells, static_cast<std::uint8_t>(settings.refinement));
    const bool adaptive = settings.tolerance_pixels > 0.0;
    parallel_for(static_cast<std::size_t>(grid.rows), kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        std::vector<SurfacePoint> points(static_cast<std::size_t>(grid.cols) * (end - begin));
        surface.evaluate_grid(0.5 * tx, (static_cast<double>(begin) + 0.5) * ty, tx, ty, grid.cols, static_cast<int>(end - begin),
                              points.data());
        for (std::size_t k = 0; k < points.size(); ++k)
            tree.samples[begin * grid.cols + k] = normal_pixel(points[k], half_resolution);
    });
    if (!adaptive) return;
    parallel_for(static_cast<std::size_t>(grid.rows), kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        std::vector<SurfacePoint> centres(static_cast<std::size_t>(grid.cols) * (end - begin));
        surface.evaluate_grid(tx, (static_cast<double>(begin) + 1.0) * ty, tx, ty, grid.cols, static_cast<int>(end - begin),
                              centres.data());
        for (std::size_t j = begin; j < end; ++j) {
            const std::size_t above = (j + 1) % grid.rows;
            for (int i = 0; i < grid.cols; ++i) {
                const int right = (i + 1) % grid.cols;
                const Pixel centre = normal_pixel(centres[(j - begin) * grid.cols + i], half_resolution);
                const int n = subdivisions(settings, tree.samples[j * grid.cols + i], tree.samples[j * grid.cols + right],
                                           tree.samples[above * grid.cols + i], tree.samples[above * grid.cols + right], centre);
                tree.subdivision[j * grid.cols + i] = static_cast<std::uint8_t>(n);
            }
        }
    });
}

// The normal images of the (n + 1)² sub-corners of texel cell (i, j), row by row from its
// sample (i, j) in steps of dx/n, dy/n: the image's evaluation (normal_density.cpp, accumulate_rows).
void image_sub_corners(const NormalBoundsTree& tree, int i, int j, int n, std::vector<SurfacePoint>& points,
                       std::vector<Pixel>& pixels) {
    const double tx = tree.grid.dx_um, ty = tree.grid.dy_um;
    points.resize(static_cast<std::size_t>(n + 1) * (n + 1));
    pixels.resize(points.size());
    tree.surface->evaluate_grid((i + 0.5) * tx, (j + 0.5) * ty, tx / n, ty / n, n + 1, n + 1, points.data());
    for (std::size_t k = 0; k < points.size(); ++k) pixels[k] = normal_pixel(points[k], 0.5 * tree.resolution);
}

NormalBox box_of(const Pixel* corners, std::size_t count) {
    double u_low = corners[0].u, u_high = u_low, v_low = corners[0].v, v_high = v_low;
    for (std::size_t k = 1; k < count; ++k) {
        const Pixel& p = corners[k];
        u_low = std::min(u_low, p.u), u_high = std::max(u_high, p.u);
        v_low = std::min(v_low, p.v), v_high = std::max(v_high, p.v);
    }
    constexpr float kDown = -std::numeric_limits<float>::infinity(), kUp = std::numeric_limits<float>::infinity();
    return {std::nextafter(static_cast<float>(u_low), kDown), std::nextafter(static_cast<float>(u_high), kUp),
            std::nextafter(static_cast<float>(v_low), kDown), std::nextafter(static_cast<float>(v_high), kUp)};
}

NormalBox united(const NormalBox& a, const NormalBox& b) {
    return {std::min(a.u_low, b.u_low), std::max(a.u_high, b.u_high), std::min(a.v_low, b.v_low),
            std::max(a.v_high, b.v_high)};
}

// Level 0: the box of each cell's corners (its triangles' images are their convex hulls);
// above: the union of up to 2 × 2 boxes of the level below, until one box remains.
void build_levels(NormalBoundsTree& tree) {
    const TexelGrid& grid = tree.grid;
    std::vector<NormalBox> leaves(tree.subdivision.size());
    parallel_for(static_cast<std::size_t>(grid.rows), kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        std::vector<SurfacePoint> points;
        std::vector<Pixel> pixels;
        for (std::size_t j = begin; j < end; ++j) {
            const std::size_t above = (j + 1) % grid.rows;
            for (int i = 0; i < grid.cols; ++i) {
                const std::size_t cell = j * grid.cols + i;
                const int n = tree.subdivision[cell];
                if (n > 1) {
                    image_sub_corners(tree, i, static_cast<int>(j), n, points, pixels);
                    leaves[cell] = box_of(pixels.data(), pixels.size());
                    continue;
                }
                const int right = (i + 1) % grid.cols;
                const std::array<Pixel, 4> corners = {tree.samples[cell], tree.samples[j * grid.cols + right],
                                                      tree.samples[above * grid.cols + i],
                                                      tree.samples[above * grid.cols + right]};
                leaves[cell] = box_of(corners.data(), 4);
            }
        }
    });
    tree.level_cols = {grid.cols};
    tree.level_rows = {grid.rows};
    tree.children.clear();
    std::vector<NormalBox> below = std::move(leaves);
    constexpr float kInfinity = std::numeric_limits<float>::infinity();
    const NormalBox empty{kInfinity, -kInfinity, kInfinity, -kInfinity};
    while (tree.level_cols.back() > 1 || tree.level_rows.back() > 1) {
        const int below_cols = tree.level_cols.back(), below_rows = tree.level_rows.back();
        const int cols = (below_cols + 1) / 2, rows = (below_rows + 1) / 2;
        std::vector<NormalBoundsTree::Children> blocks(static_cast<std::size_t>(cols) * rows);
        std::vector<NormalBox> level(blocks.size());
        for (int j = 0; j < rows; ++j)
            for (int i = 0; i < cols; ++i) {
                NormalBoundsTree::Children& block = blocks[static_cast<std::size_t>(j) * cols + i];
                NormalBox box = empty;
                for (int b = 0; b < 2; ++b)
                    for (int a = 0; a < 2; ++a) {
                        const bool inside = 2 * i + a < below_cols && 2 * j + b < below_rows;
                        block.boxes[2 * b + a] =
                            inside ? below[static_cast<std::size_t>(2 * j + b) * below_cols + 2 * i + a] : empty;
                        if (inside) box = united(box, block.boxes[2 * b + a]);
                    }
                level[static_cast<std::size_t>(j) * cols + i] = box;
            }
        tree.children.push_back(std::move(blocks));
        below = std::move(level);
        tree.level_cols.push_back(cols);
        tree.level_rows.push_back(rows);
    }
    tree.root = below[0];
}

// ---- The query ------------------------------------------------------------------------------

// A normalised Gaussian of σ (pixels) over the image plane, truncated per axis at the image
// blur's kernel radius ⌈4σ⌉ (normal_density.cpp, blur_normal_density); σ = 0: no blur.
struct Blur {
    double sigma = 0.0;
    double radius = 0.0;
    double inverse_two_variance = 0.0;
    double scale = 0.0;

    double at(double du, double dv) const {
        if (std::abs(du) > radius || std::abs(dv) > radius) return 0.0;
        return scale * std::exp(-(du * du + dv * dv) * inverse_two_variance);
    }
};

Blur blur_for(double roughness, int resolution) {
    Blur blur;
    blur.sigma = roughness * 0.5 * resolution;
    if (blur.sigma <= 0.0) return blur;
    blur.radius = std::ceil(4.0 * blur.sigma);
    blur.inverse_two_variance = 0.5 / (blur.sigma * blur.sigma);
    blur.scale = 1.0 / (2.0 * pi * blur.sigma * blur.sigma);
    return blur;
}

// The density at p (mass per pixel area) of `mass` spread uniformly over the triangle abc; with
// a blur, that spread convolved with the Gaussian by the edge-midpoint rule. A triangle whose
// image is (numerically) a segment is skipped unblurred, as the image deposits it along a line.
double triangle_density(Pixel a, Pixel b, Pixel c, double mass, Pixel p, const Blur& blur) {
    if (blur.sigma > 0.0) {
        const auto gaussian_at = [&](Pixel x, Pixel y) { return blur.at(p.u - 0.5 * (x.u + y.u), p.v - 0.5 * (x.v + y.v)); };
        return mass * (gaussian_at(a, b) + gaussian_at(b, c) + gaussian_at(c, a)) / 3.0;
    }
    const double cross = (b.u - a.u) * (c.v - a.v) - (c.u - a.u) * (b.v - a.v);
    const double d1 = (b.u - a.u) * (p.v - a.v) - (p.u - a.u) * (b.v - a.v);
    const double d2 = (c.u - b.u) * (p.v - b.v) - (p.u - b.u) * (c.v - b.v);
    const double d3 = (a.u - c.u) * (p.v - c.v) - (p.u - c.u) * (a.v - c.v);
    const bool inside = cross > 0.0 ? (d1 >= 0.0 && d2 >= 0.0 && d3 >= 0.0) : (d1 <= 0.0 && d2 <= 0.0 && d3 <= 0.0);
    if (!inside) return 0.0;
    // The image's segment threshold (normal_density.cpp, deposit_small_triangle), in its pixels.
    const double extent = 1.0 + std::max(std::max({a.u, b.u, c.u}) - std::min({a.u, b.u, c.u}),
                                         std::max({a.v, b.v, c.v}) - std::min({a.v, b.v, c.v}));
    if (std::abs(cross) < 2e-9 * extent * extent) return 0.0;
    return 2.0 * mass / std::abs(cross);
}

// One footprint's query: the lattice of its support, its weight, the normal in pixel units.
struct Query {
    const NormalBoundsTree& tree;
    Lattice lattice;
    Weight weight;
    long long first_x = 0;  // the lattice's first cell, unwrapped
    long long first_y = 0;
    Pixel normal;
    Blur blur;
    double reach = 0.0;  // pixels a normal box is widened by: the blur's radius
    bool prune = true;

    // The lattice's x of the unwrapped cell I (as the image computes it, from its origin).
    double cell_x(long long cell) const { return lattice.x0 + static_cast<double>(cell - first_x) * lattice.step_x; }
    double cell_y(long long cell) const { return lattice.y0 + static_cast<double>(cell - first_y) * lattice.step_y; }

    // Σ mass / image area over the triangles of texel cell (i, j) placed at unwrapped (I, J).
    double cell_density(int i, int j, long long unwrapped_i, long long unwrapped_j) const {
        const TexelGrid& grid = tree.grid;
        const std::size_t cell = static_cast<std::size_t>(j) * grid.cols + i;
        const int n = tree.subdivision[cell];
        const double x = cell_x(unwrapped_i), y = cell_y(unwrapped_j);
        const double h = lattice.step_x / n, k = lattice.step_y / n;
        const double half_area = 0.5 * h * k;
        const auto pair = [&](Pixel p00, Pixel p10, Pixel p01, Pixel p11, double xa, double yb) {
            const double lower = half_area * weight(xa + h * (2.0 / 3.0), yb + k / 3.0);
            const double upper = half_area * weight(xa + h / 3.0, yb + k * (2.0 / 3.0));
            double sum = 0.0;
            if (lower > 0.0) sum += triangle_density(p00, p10, p11, lower, normal, blur);
            if (upper > 0.0) sum += triangle_density(p00, p11, p01, upper, normal, blur);
            return sum;
        };
        if (n == 1) {
            const int right = i + 1 == grid.cols ? 0 : i + 1;
            const std::size_t above = static_cast<std::size_t>(j + 1 == grid.rows ? 0 : j + 1) * grid.cols;
            const std::size_t row = static_cast<std::size_t>(j) * grid.cols;
            return pair(tree.samples[row + i], tree.samples[row + right], tree.samples[above + i],
                        tree.samples[above + right], x, y);
        }
        // Scratch kept per thread: no allocation once a thread has met its largest subdivision.
        thread_local std::vector<SurfacePoint> points;
        thread_local std::vector<Pixel> pixels;
        image_sub_corners(tree, i, j, n, points, pixels);
        const Pixel* p = pixels.data();
        const std::size_t stride = static_cast<std::size_t>(n) + 1;
        double sum = 0.0;
        for (int b = 0; b < n; ++b)
            for (int a = 0; a < n; ++a) {
                const std::size_t q = b * stride + a;
                if (prune && !quad_holds(p[q], p[q + 1], p[q + stride], p[q + stride + 1])) continue;
                sum += pair(p[q], p[q + 1], p[q + stride], p[q + stride + 1], x + a * h, y + b * k);
            }
        return sum;
    }

    bool holds(const NormalBox& box) const {
        return normal.u >= box.u_low - reach && normal.u <= box.u_high + reach && normal.v >= box.v_low - reach &&
               normal.v <= box.v_high + reach;
    }
    // Whether a sub-cell's corners' bounding box, widened by the reach, holds the normal.
    bool quad_holds(Pixel a, Pixel b, Pixel c, Pixel d) const {
        return normal.u >= std::min({a.u, b.u, c.u, d.u}) - reach && normal.u <= std::max({a.u, b.u, c.u, d.u}) + reach &&
               normal.v >= std::min({a.v, b.v, c.v, d.v}) - reach && normal.v <= std::max({a.v, b.v, c.v, d.v}) + reach;
    }

    // Whether the unwrapped cells [x0, x1) × [y0, y1) lie wholly beyond the weight's cutoff.
    bool beyond_cutoff(long long x0, long long x1, long long y0, long long y1) const {
        if (weight.shape != FootprintShape::gaussian) return false;
        const double left = cell_x(x0), right = cell_x(x1), bottom = cell_y(y0), top = cell_y(y1);
        const double dx = std::max({0.0, left - weight.centre.x, weight.centre.x - right});
        const double dy = std::max({0.0, bottom - weight.centre.y, weight.centre.y - top});
        return dx * dx + dy * dy > weight.cutoff_squared * (1.0 + 1e-9);
    }

    // Whether node (i, j) of a level with this box, whose cells are [lo, hi) clipped to the
    // piece, may contribute.
    bool may_contribute(const NormalBox& box, int lo_x, int hi_x, int lo_y, int hi_y, long long ox, long long oy) const {
        if (lo_x >= hi_x || lo_y >= hi_y) return false;
        return !prune || (holds(box) && !beyond_cutoff(lo_x + ox, hi_x + ox, lo_y + oy, hi_y + oy));
    }

    // The cells of the field [x0, x1) × [y0, y1), which stand at unwrapped (I + ox, J + oy):
    // depth first through the levels, testing a node's four children together and skipping
    // those that cannot contribute; cells are summed in the same order with pruning or without.
    double piece(int x0, int x1, int y0, int y1, long long ox, long long oy) const {
        struct Node {
            int level, i, j;
        };
        const int top_level = static_cast<int>(tree.level_cols.size()) - 1;
        const auto clipped = [&](int level, int i, int j, int& lo_x, int& hi_x, int& lo_y, int& hi_y) {
            lo_x = std::max(x0, i << level), hi_x = std::min(x1, (i + 1) << level);
            lo_y = std::max(y0, j << level), hi_y = std::min(y1, (j + 1) << level);
        };
        int lo_x, hi_x, lo_y, hi_y;
        clipped(top_level, 0, 0, lo_x, hi_x, lo_y, hi_y);
        if (!may_contribute(tree.root, lo_x, hi_x, lo_y, hi_y, ox, oy)) return 0.0;
        if (top_level == 0) return cell_density(0, 0, ox, oy);
        std::array<Node, 4 * 40> stack;
        int top = 0;
        stack[top++] = {top_level, 0, 0};
        double sum = 0.0;
        while (top > 0) {
            const Node node = stack[--top];
            const NormalBoundsTree::Children& block =
                tree.children[node.level - 1][static_cast<std::size_t>(node.j) * tree.level_cols[node.level] + node.i];
            const int child_level = node.level - 1;
            Node passed[4];
            int count = 0;
            for (int b = 0; b < 2; ++b)
                for (int a = 0; a < 2; ++a) {
                    const int i = 2 * node.i + a, j = 2 * node.j + b;
                    clipped(child_level, i, j, lo_x, hi_x, lo_y, hi_y);
                    if (may_contribute(block.boxes[2 * b + a], lo_x, hi_x, lo_y, hi_y, ox, oy))
                        passed[count++] = {child_level, i, j};
                }
            if (child_level == 0) {
                for (int k = 0; k < count; ++k) sum += cell_density(passed[k].i, passed[k].j, passed[k].i + ox, passed[k].j + oy);
                continue;
            }
            while (count > 0) stack[top++] = passed[--count];  // reversed: popped in order
        }
        return sum;
    }
};

long long floor_div(long long a, long long b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

}  // namespace

NormalBoundsTree make_normal_bounds_tree(std::shared_ptr<const BicubicInterpolant> surface,
                                         const NormalDensitySettings& settings, int resolution) {
    check_normal_density_settings(resolution, settings);
    NormalBoundsTree tree;
    tree.grid = texel_grid(*surface);
    tree.resolution = resolution;
    tree.intrinsic_roughness = settings.intrinsic_roughness;
    tree.surface = std::move(surface);
    image_samples(*tree.surface, settings, tree);
    build_levels(tree);
    return tree;
}

double point_normal_density(const NormalBoundsTree& tree, const Footprint& footprint, DiskPoint normal, Pruning pruning) {
    if (!answers_points(footprint))
        throw Error("the point query of the normal density takes Gaussian and whole-field footprints, not a box");
    if (!inside_unit_disk(normal)) return 0.0;
    const double half_resolution = 0.5 * tree.resolution;
    const TexelGrid& grid = tree.grid;
    const Lattice lattice = lattice_for(grid, footprint);
    const Blur blur = blur_for(tree.intrinsic_roughness, tree.resolution);
    const Query query{tree,
                      lattice,
                      weight_for(grid, footprint),
                      std::llround((lattice.x0 - 0.5 * grid.dx_um) / grid.dx_um),
                      std::llround((lattice.y0 - 0.5 * grid.dy_um) / grid.dy_um),
                      {(normal.x + 1.0) * half_resolution, (1.0 - normal.y) * half_resolution},
                      blur,
                      blur.radius,
                      pruning == Pruning::on};
    // The unwrapped cells [first, first + n) in pieces of one tile each, in the image's order.
    double sum = 0.0;
    const long long last_y = query.first_y + query.lattice.ny, last_x = query.first_x + query.lattice.nx;
    for (long long ty = floor_div(query.first_y, grid.rows); ty * grid.rows < last_y; ++ty)
        for (long long tx = floor_div(query.first_x, grid.cols); tx * grid.cols < last_x; ++tx) {
            const long long ox = tx * grid.cols, oy = ty * grid.rows;
            const int x0 = static_cast<int>(std::max(query.first_x, ox) - ox);
            const int x1 = static_cast<int>(std::min(last_x, ox + grid.cols) - ox);
            const int y0 = static_cast<int>(std::max(query.first_y, oy) - oy);
            const int y1 = static_cast<int>(std::min(last_y, oy + grid.rows) - oy);
            sum += query.piece(x0, x1, y0, y1, ox, oy);
        }
    // The footprint weight of the truncated domain: a Gaussian truncated at K σ keeps 1 − e^{−K²/2}.
    const double total = footprint.shape == FootprintShape::gaussian
                             ? 1.0 - std::exp(-0.5 * kTruncationSigmas * kTruncationSigmas)
                             : 1.0;
    return sum * half_resolution * half_resolution / total;
}

}  // namespace glintscope
