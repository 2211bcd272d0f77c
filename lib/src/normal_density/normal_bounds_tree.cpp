#include "normal_density/normal_bounds_tree.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "core/target_clones.hpp"
#include "numerics/small_polygon.hpp"
#include "surface/catmull_rom.hpp"

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

// The Catmull–Rom weights at a/n for a = 0 … n, for every n up to kMaxRefinement, made once when
// the library loads (a function-local table would test its guard on every use): each is
// catmull_rom(a/n) itself, so a sub-corner's image is what it was without the table.
const std::vector<CubicWeights> kSubCornerWeights = [] {
    std::vector<CubicWeights> weights;
    for (int m = 1; m <= kMaxRefinement; ++m)
        for (int a = 0; a <= m; ++a) weights.push_back(catmull_rom(static_cast<double>(a) / m));
    return weights;
}();

const CubicWeights* sub_corner_weights(int n) {
    return kSubCornerWeights.data() + static_cast<std::size_t>(n - 1) * (n + 2) / 2;  // Σ_{m<n} (m + 1) entries before n
}

// The interpolant on texel cell (i, j) (BicubicInterpolant::evaluate, Catmull–Rom along each
// axis) with its 4 × 4 samples read once: the normal images of the cell's sub-corners at
// (a/n, b/n), as the image evaluates them up to rounding (the image's grid steps from the cell's
// sample in dx/n; here the fraction is a/n of this cell even at a = n, the next cell's edge).
struct CellPatch {
    double taps[4][4];  // taps[m][k]: sample (i − 1 + k, j − 1 + m), wrapped
    double inverse_dx = 0.0, inverse_dy = 0.0, half_resolution = 0.0;

    CellPatch(const NormalBoundsTree& tree, int i, int j) {
        const BicubicInterpolant& surface = *tree.surface;
        const int cols = surface.cols(), rows = surface.rows();
        // Indices lie within one period of the field's (−1 … count + 1); a field of one sample wraps further.
        const auto wrapped = [](int index, int count) {
            if (count < 2) return 0;
            return index < 0 ? index + count : index >= count ? index - count : index;
        };
        // Away from the field's edges (nearly every cell) a row's four taps are contiguous.
        const bool inside_columns = i >= 1 && i + 2 < cols;
        for (int m = 0; m < 4; ++m) {
            const float* row = surface.sample_row(wrapped(j - 1 + m, rows));
            if (inside_columns)
                for (int k = 0; k < 4; ++k) taps[m][k] = row[i - 1 + k];
            else
                for (int k = 0; k < 4; ++k) taps[m][k] = row[wrapped(i - 1 + k, cols)];
        }
        inverse_dx = 1.0 / surface.texel_um();
        inverse_dy = 1.0 / surface.texel_y_um();
        half_resolution = 0.5 * tree.resolution;
    }

    // The four sample rows convolved along x at one fraction: values and their x derivatives.
    struct Column {
        double along[4], along_du[4];
    };

    Column column(const CubicWeights& x) const {
        Column c;
        for (int m = 0; m < 4; ++m) {
            double along_x = 0.0, along_x_du = 0.0;
            for (int k = 0; k < 4; ++k) {
                along_x += x.w[k] * taps[m][k];
                along_x_du += x.dw[k] * taps[m][k];
            }
            c.along[m] = along_x, c.along_du[m] = along_x_du;
        }
        return c;
    }

    // The image of the point at the column's x and the fraction whose weights are y.
    Pixel at(const Column& c, const CubicWeights& y) const {
        double dh_du = 0.0, dh_dv = 0.0;
        for (int m = 0; m < 4; ++m) {
            dh_du += y.w[m] * c.along_du[m];
            dh_dv += y.dw[m] * c.along[m];
        }
        return normal_pixel({0.0, dh_du * inverse_dx, dh_dv * inverse_dy}, half_resolution);
    }
};

// The four corner images of texel cell (i, j): samples (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1).
struct CellCorners {
    Pixel p00, p10, p01, p11;
};

CellCorners cell_corners(const NormalBoundsTree& tree, int i, int j) {
    const TexelGrid& grid = tree.grid;
    const std::size_t row = static_cast<std::size_t>(j) * grid.cols;
    const std::size_t above = static_cast<std::size_t>(j + 1 == grid.rows ? 0 : j + 1) * grid.cols;
    const int right = i + 1 == grid.cols ? 0 : i + 1;
    return {tree.samples[row + i], tree.samples[row + right], tree.samples[above + i], tree.samples[above + right]};
}

// Storage for a divided cell's sub-corner images, one per thread, sized for the largest n
// (kMaxRefinement) once: stamps tell which images belong to the cell in use.
struct SubCornerStore {
    std::vector<Pixel> images;
    std::vector<std::uint32_t> stamps;
    std::uint32_t generation = 0;
    // Per sub-column a of the cell in use (stamped alike): its rows convolved along x, shared by
    // the sub-corners of that column.
    std::vector<CellPatch::Column> columns = std::vector<CellPatch::Column>(kMaxRefinement + 1);
    std::vector<std::uint32_t> column_stamps = std::vector<std::uint32_t>(kMaxRefinement + 1, 0);
};

// This thread's store: looked up once per query (a thread_local access in a shared library is a call).
SubCornerStore& sub_corner_store() {
    thread_local SubCornerStore store{std::vector<Pixel>((kMaxRefinement + 1) * (kMaxRefinement + 1)),
                                      std::vector<std::uint32_t>((kMaxRefinement + 1) * (kMaxRefinement + 1), 0), 0};
    return store;
}

// The images of a divided cell's sub-corners: its four corners are the samples' images (as an
// undivided neighbour's), stored up front; the others evaluated once per use of the cell, on
// first need.
class SubCorners {
public:
    [[gnu::always_inline]] SubCorners(const CellPatch& patch, const CellCorners& corners, int n, SubCornerStore& store)
        : patch_(patch), n_(n) {
        if (++store.generation == 0) {
            std::fill(store.stamps.begin(), store.stamps.end(), 0), store.generation = 1;
            std::fill(store.column_stamps.begin(), store.column_stamps.end(), 0);
        }
        images_ = store.images.data(), stamps_ = store.stamps.data(), generation_ = store.generation;
        columns_ = store.columns.data(), column_stamps_ = store.column_stamps.data(), weights_ = sub_corner_weights(n);
        const std::size_t top = static_cast<std::size_t>(n) * (n + 1);
        images_[0] = corners.p00, images_[n] = corners.p10, images_[top] = corners.p01, images_[top + n] = corners.p11;
        stamps_[0] = stamps_[n] = stamps_[top] = stamps_[top + n] = generation_;
    }

    Pixel at(int a, int b) const {
        const std::size_t k = static_cast<std::size_t>(b) * (n_ + 1) + a;
        if (stamps_[k] != generation_) {
            if (column_stamps_[a] != generation_) columns_[a] = patch_.column(weights_[a]), column_stamps_[a] = generation_;
            images_[k] = patch_.at(columns_[a], weights_[b]), stamps_[k] = generation_;
        }
        return images_[k];
    }

private:
    const CellPatch& patch_;
    int n_;
    Pixel* images_;
    std::uint32_t* stamps_;
    std::uint32_t generation_;
    CellPatch::Column* columns_;
    std::uint32_t* column_stamps_;
    const CubicWeights* weights_;
};

// Quadrant q (bit 0: right, bit 1: top) of a divided cell: sub-corners [a0, a1] × [b0, b1],
// split at m = ⌊n/2⌋.
struct Quadrant {
    int a0, a1, b0, b1;
};

Quadrant quadrant(int n, int q) {
    const int m = n / 2;
    return {q & 1 ? m : 0, q & 1 ? n : m, q & 2 ? m : 0, q & 2 ? n : m};
}

// The bilinear blend of four images at fractions (s, t): where a point's image would be if the
// normal map were bilinear over them.
[[gnu::always_inline]] inline Pixel bilinear(Pixel p00, Pixel p10, Pixel p01, Pixel p11, double s, double t) {
    const double w00 = (1.0 - s) * (1.0 - t), w10 = s * (1.0 - t), w01 = (1.0 - s) * t, w11 = s * t;
    return {w00 * p00.u + w10 * p10.u + w01 * p01.u + w11 * p11.u, w00 * p00.v + w10 * p10.v + w01 * p01.v + w11 * p11.v};
}

// A cell's normal box (the hull of its sub-corners' images, those of its triangles) and, divided,
// each quadrant's stray: the largest per-axis distance of a sub-corner's image from the blend
// of the quadrant's corner images (pixels), which bounds its triangles' images to the box of
// those corners widened by the stray.
struct CellBounds {
    double u_low, u_high, v_low, v_high;
    std::array<double, 4> strays{};
    std::array<Pixel, 5> middles{};  // divided: sub-corners (m, 0), (0, m), (m, m), (n, m), (m, n)
};

GLINTSCOPE_OUT_OF_LINE_CLONES CellBounds cell_bounds(const NormalBoundsTree& tree, int i, int j) {
    const int n = tree.subdivision[static_cast<std::size_t>(j) * tree.grid.cols + i];
    const CellCorners c = cell_corners(tree, i, j);
    CellBounds bounds{c.p00.u, c.p00.u, c.p00.v, c.p00.v};
    const auto include = [&](Pixel p) {
        bounds.u_low = std::min(bounds.u_low, p.u), bounds.u_high = std::max(bounds.u_high, p.u);
        bounds.v_low = std::min(bounds.v_low, p.v), bounds.v_high = std::max(bounds.v_high, p.v);
    };
    if (n == 1) {
        for (Pixel p : {c.p10, c.p01, c.p11}) include(p);
        return bounds;
    }
    const CellPatch patch(tree, i, j);
    const SubCorners corners(patch, c, n, sub_corner_store());
    for (int q = 0; q < 4; ++q) {
        const Quadrant r = quadrant(n, q);
        const Pixel p00 = corners.at(r.a0, r.b0), p10 = corners.at(r.a1, r.b0);
        const Pixel p01 = corners.at(r.a0, r.b1), p11 = corners.at(r.a1, r.b1);
        for (int b = r.b0; b <= r.b1; ++b)
            for (int a = r.a0; a <= r.a1; ++a) {
                const Pixel p = corners.at(a, b);
                const Pixel blend = bilinear(p00, p10, p01, p11, static_cast<double>(a - r.a0) / (r.a1 - r.a0),
                                             static_cast<double>(b - r.b0) / (r.b1 - r.b0));
                include(p);
                bounds.strays[q] = std::max({bounds.strays[q], std::abs(p.u - blend.u), std::abs(p.v - blend.v)});
            }
    }
    const int m = n / 2;
    bounds.middles = {corners.at(m, 0), corners.at(0, m), corners.at(m, m), corners.at(n, m), corners.at(m, n)};
    return bounds;
}

// The bins' side: half the median extent of the cells' widened boxes (at least a pixel), so that
// a cell overlaps about nine bins and a bin's list holds about (1 + ½)² ≈ 2.25 times the cells
// whose box holds a normal of it (the median extent itself: 4 bins, 4 times, a sixth more
// instructions in the scans of the Patch scene's queries, for 15% less memory).
double bin_side(const std::vector<CellBounds>& bounds, double reach) {
    std::vector<double> extents(bounds.size());
    for (std::size_t k = 0; k < bounds.size(); ++k)
        extents[k] = std::max(bounds[k].u_high - bounds[k].u_low, bounds[k].v_high - bounds[k].v_low) + 2.0 * reach;
    std::nth_element(extents.begin(), extents.begin() + extents.size() / 2, extents.end());
    return std::max(1.0, 0.5 * extents[extents.size() / 2]);
}

// The bins a cell's widened box overlaps, [bu0, bu1] × [bv0, bv1].
struct BinRange {
    int bu0, bu1, bv0, bv1;
};

BinRange bin_range(const NormalBoundsTree& tree, const CellBounds& b, double reach) {
    const auto bin = [&](double x) {
        return std::clamp(static_cast<int>(std::floor((x - tree.origin) / tree.bin_pixels)), 0, tree.bins_across - 1);
    };
    return {bin(b.u_low - reach), bin(b.u_high + reach), bin(b.v_low - reach), bin(b.v_high + reach)};
}

// Quanta of `tree.quantum` pixels from the origin, rounded down or up (one quantum further,
// against the rounding of the division), saturated to 16 bits.
std::uint16_t quantised(const NormalBoundsTree& tree, double x, bool up) {
    const double q = (x - tree.origin) / tree.quantum;
    const double rounded = up ? std::ceil(q) + 1.0 : std::floor(q) - 1.0;
    return static_cast<std::uint16_t>(std::clamp(rounded, 0.0, 65535.0));
}

// The nearest quantum of x (pixels), which lies within the quanta's range (images of normals).
std::uint16_t nearest_quantum(const NormalBoundsTree& tree, double x) {
    return static_cast<std::uint16_t>(std::clamp(std::nearbyint((x - tree.origin) / tree.quantum), 0.0, 65535.0));
}

// Calls visit(i, j, place) for the cells of tile t in row-major order, place = local row · 32 + column.
template <typename Visit>
void for_cells_of_tile(const NormalBoundsTree& tree, int t, const Visit& visit) {
    const int tile_x = t % tree.tile_cols, tile_y = t / tree.tile_cols, side = NormalBoundsTree::kTileCells;
    for (int ly = 0; ly < side && tile_y * side + ly < tree.grid.rows; ++ly)
        for (int lx = 0; lx < side && tile_x * side + lx < tree.grid.cols; ++lx)
            visit(tile_x * side + lx, tile_y * side + ly, ly * side + lx);
}

// The bins of every cell's box (widened by the blur's reach), listed per bin and tile.
void build_bins(NormalBoundsTree& tree, double reach) {
    const TexelGrid& grid = tree.grid;
    std::vector<CellBounds> bounds(tree.subdivision.size());
    parallel_for(static_cast<std::size_t>(grid.rows), kRowsPerChunk, [&](std::size_t begin, std::size_t end) {
        for (std::size_t j = begin; j < end; ++j)
            for (int i = 0; i < grid.cols; ++i)
                bounds[j * grid.cols + i] = cell_bounds(tree, i, static_cast<int>(j));
    });
    const int side = NormalBoundsTree::kTileCells;
    tree.tile_cols = (grid.cols + side - 1) / side;
    tree.tile_rows = (grid.rows + side - 1) / side;
    // Normal images lie within the disk's square [0, N]², strays and the reach widen it.
    double stray = 0.0;
    for (const CellBounds& b : bounds) stray = std::max(stray, *std::max_element(b.strays.begin(), b.strays.end()));
    tree.origin = -reach - 1.0;
    const double span = tree.resolution + 2.0 * reach + 2.0;
    tree.bin_pixels = bin_side(bounds, reach);
    tree.bins_across = static_cast<int>(std::ceil(span / tree.bin_pixels));
    tree.quantum = (span + stray) / 60000.0;
    const std::size_t tiles = static_cast<std::size_t>(tree.tile_cols) * tree.tile_rows;
    // Count each bin's cells, give the bins that have any a row, count per row and tile, list.
    std::vector<std::size_t> per_bin(static_cast<std::size_t>(tree.bins_across) * tree.bins_across, 0);
    for (const CellBounds& b : bounds) {
        const BinRange r = bin_range(tree, b, reach);
        for (int bv = r.bv0; bv <= r.bv1; ++bv)
            for (int bu = r.bu0; bu <= r.bu1; ++bu) ++per_bin[static_cast<std::size_t>(bv) * tree.bins_across + bu];
    }
    tree.bin_rows.assign(per_bin.size(), -1);
    std::int32_t rows = 0;
    for (std::size_t k = 0; k < per_bin.size(); ++k)
        if (per_bin[k] > 0) tree.bin_rows[k] = rows++;
    const std::size_t stride = tiles + 1;
    std::vector<std::size_t> counts(static_cast<std::size_t>(rows) * stride + 1, 0);
    const auto for_bins = [&](const CellBounds& b, const auto& visit) {
        const BinRange r = bin_range(tree, b, reach);
        for (int bv = r.bv0; bv <= r.bv1; ++bv)
            for (int bu = r.bu0; bu <= r.bu1; ++bu)
                visit(static_cast<std::size_t>(tree.bin_rows[static_cast<std::size_t>(bv) * tree.bins_across + bu]));
    };
    // Tile t writes only its own column (t + 1, then t) of counts and cursors: the tiles run in
    // parallel, and each tile's entries keep their row-major order whatever the thread count.
    const auto per_tile = [&](const auto& body) {
        parallel_for(tiles, 1, [&](std::size_t begin, std::size_t end) {
            for (std::size_t t = begin; t < end; ++t) body(t);
        });
    };
    per_tile([&](std::size_t t) {
        for_cells_of_tile(tree, static_cast<int>(t), [&](int i, int j, int) {
            for_bins(bounds[static_cast<std::size_t>(j) * grid.cols + i], [&](std::size_t row) { ++counts[row * stride + t + 1]; });
        });
    });
    for (std::size_t k = 1; k < counts.size(); ++k) counts[k] += counts[k - 1];
    if (counts.back() > std::numeric_limits<std::uint32_t>::max())
        throw Error("the field is too large for the point query's index of normal bounds");
    tree.offsets.assign(counts.begin(), counts.end());
    tree.cells.resize(counts.back());
    tree.divided.resize(bounds.size());
    parallel_for(bounds.size(), std::size_t{kRowsPerChunk} * grid.cols, [&](std::size_t begin, std::size_t end) {
        for (std::size_t cell = begin; cell < end; ++cell) {
            if (tree.subdivision[cell] == 1) continue;
            DividedCell& divided = tree.divided[cell];
            for (int q = 0; q < 4; ++q) divided.strays[q] = quantised(tree, tree.origin + bounds[cell].strays[q], true);
            for (int k = 0; k < 5; ++k) {
                divided.middles[2 * k] = nearest_quantum(tree, bounds[cell].middles[k].u);
                divided.middles[2 * k + 1] = nearest_quantum(tree, bounds[cell].middles[k].v);
            }
        }
    });
    std::vector<std::size_t> cursor = std::move(counts);
    per_tile([&](std::size_t t) {
        for_cells_of_tile(tree, static_cast<int>(t), [&](int i, int j, int place) {
            const std::size_t cell = static_cast<std::size_t>(j) * grid.cols + i;
            const CellBounds& b = bounds[cell];
            BinnedCell entry;
            entry.place = static_cast<std::uint16_t>(place << 6 | (tree.subdivision[cell] - 1));
            entry.u_low = quantised(tree, b.u_low - reach, false), entry.u_high = quantised(tree, b.u_high + reach, true);
            entry.v_low = quantised(tree, b.v_low - reach, false), entry.v_high = quantised(tree, b.v_high + reach, true);
            for_bins(b, [&](std::size_t row) { tree.cells[cursor[row * stride + t]++] = entry; });
        });
    });
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

// Where p lies in the triangle abc (pixels): the density there (per pixel area) of a unit mass
// spread uniformly over it, 0 outside it or where its image is (numerically) a segment (as the
// image deposits it along a line), and p's barycentric weights of b and of c.
struct TriangleHit {
    double density = 0.0;
    double second = 0.0, third = 0.0;
};

[[gnu::always_inline]] inline TriangleHit triangle_hit(Pixel a, Pixel b, Pixel c, Pixel p) {
    const double cross = (b.u - a.u) * (c.v - a.v) - (c.u - a.u) * (b.v - a.v);
    const double d1 = (b.u - a.u) * (p.v - a.v) - (p.u - a.u) * (b.v - a.v);  // twice the area of abp: c's weight
    const double d2 = (c.u - b.u) * (p.v - b.v) - (p.u - b.u) * (c.v - b.v);  // bcp: a's
    const double d3 = (a.u - c.u) * (p.v - c.v) - (p.u - c.u) * (a.v - c.v);  // cap: b's
    const bool inside = cross > 0.0 ? (d1 >= 0.0 && d2 >= 0.0 && d3 >= 0.0) : (d1 <= 0.0 && d2 <= 0.0 && d3 <= 0.0);
    if (!inside) return {};
    // The image's segment threshold (normal_density.cpp, deposit_small_triangle), in its pixels.
    const double extent = 1.0 + std::max(std::max({a.u, b.u, c.u}) - std::min({a.u, b.u, c.u}),
                                         std::max({a.v, b.v, c.v}) - std::min({a.v, b.v, c.v}));
    if (std::abs(cross) < 2e-9 * extent * extent) return {};
    return {2.0 / std::abs(cross), d3 / cross, d1 / cross};
}

// The density at p (per pixel area) of a unit mass spread uniformly over the triangle abc; with
// a blur, that spread convolved with the Gaussian by the edge-midpoint rule.
double triangle_spread(Pixel a, Pixel b, Pixel c, Pixel p, const Blur& blur) {
    if (blur.sigma > 0.0) {
        const auto gaussian_at = [&](Pixel x, Pixel y) { return blur.at(p.u - 0.5 * (x.u + y.u), p.v - 0.5 * (x.v + y.v)); };
        return (gaussian_at(a, b) + gaussian_at(b, c) + gaussian_at(c, a)) / 3.0;
    }
    return triangle_hit(a, b, c, p).density;
}

// The sub-cells of side h × k of a cell at (x, y): the weights (footprint weight at the
// centroid × area) of sub-cell (a, b)'s two triangles, lower (p00, p10, p11), upper (p00, p11, p01).
struct SubCells {
    const Weight& weight;
    double x, y, h, k;

    double lower(int a, int b) const { return 0.5 * h * k * weight(x + a * h + h * (2.0 / 3.0), y + b * k + k / 3.0); }
    double upper(int a, int b) const { return 0.5 * h * k * weight(x + a * h + h / 3.0, y + b * k + k * (2.0 / 3.0)); }
};

// A box's sampler weights of the sub-cells' triangles: each triangle's area inside the box × 1/(W·H),
// what the query's preimage rule gives it over its image. Clipped in the box's frame, where the
// box's sides run along the axes (a rotation keeps areas).
struct BoxTriangles {
    const BoxRegion& box;
    const SubCells& cells;
    double scale = 0.0;

    // Sub-cell (a, b)'s lower triangle (its corners (0, 0), (1, 0), (1, 1)) or upper one ((0, 0),
    // (1, 1), (0, 1)), in the box's frame, clipped by the box.
    SmallPolygon clipped(int a, int b, bool upper) const {
        return clip_to_rectangle(corners(a, b, upper), -box.half_width, box.half_width, -box.half_height, box.half_height);
    }

    SmallPolygon corners(int a, int b, bool upper) const {
        const double x = cells.x + a * cells.h, y = cells.y + b * cells.k;
        const DiskPoint p00 = box.local(x, y), p11 = box.local(x + cells.h, y + cells.k);
        const DiskPoint second = upper ? p11 : box.local(x + cells.h, y), third = upper ? box.local(x, y + cells.k) : p11;
        return {{p00, second, third}, 3};
    }

    double lower(int a, int b) const { return scale * polygon_area(clipped(a, b, false)); }
    double upper(int a, int b) const { return scale * polygon_area(clipped(a, b, true)); }
};

// Σ of the weights of a cell's 2n² triangles, one by one.
template <typename Triangles>
double cell_weight(const Triangles& cells, int n) {
    double sum = 0.0;
    for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) sum += cells.lower(a, b) + cells.upper(a, b);
    return sum;
}

// The same for a cell wholly within a Gaussian weight's cutoff, by its separability:
// e^{−(dx² + dy²)/(2σ²)} = e^{−dx²/(2σ²)} e^{−dy²/(2σ²)}, so the sum over the sub-cells' lower
// centroids (a + ⅔, b + ⅓) is (Σ_a e_x)(Σ_b e_y), the upper ones' alike: 4n exponentials, not 2n².
double separable_cell_weight(const SubCells& cells, int n) {
    const Weight& w = cells.weight;
    double x_lower = 0.0, x_upper = 0.0, y_lower = 0.0, y_upper = 0.0;
    const auto e = [&](double d) { return std::exp(-d * d * w.inverse_two_variance); };
    for (int a = 0; a < n; ++a) {
        x_lower += e(cells.x + a * cells.h + cells.h * (2.0 / 3.0) - w.centre.x);
        x_upper += e(cells.x + a * cells.h + cells.h / 3.0 - w.centre.x);
        y_lower += e(cells.y + a * cells.k + cells.k / 3.0 - w.centre.y);
        y_upper += e(cells.y + a * cells.k + cells.k * (2.0 / 3.0) - w.centre.y);
    }
    return 0.5 * cells.h * cells.k * w.scale * (x_lower * y_lower + x_upper * y_upper);
}

// One footprint's query: the lattice of its support, its weight, the normal in pixel units and
// in the index's quanta, and the row of `offsets` of its bin (−1: no cell's box reaches it).
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
    Pixel normal_quanta;
    std::int64_t bin_row = -1;
    SubCornerStore& store;
    bool boxed = false;  // a box footprint: weight.scale where the preimage rule puts h's point in `box`
    BoxRegion box{};

    // The lattice's x of the unwrapped cell I (as the image computes it, from its origin).
    double cell_x(long long cell) const { return lattice.x0 + static_cast<double>(cell - first_x) * lattice.step_x; }
    double cell_y(long long cell) const { return lattice.y0 + static_cast<double>(cell - first_y) * lattice.step_y; }

    // Σ mass / image area over the triangles of texel cell (i, j) placed at unwrapped (I, J);
    // pruned, a divided cell evaluates only the sub-corners of sub-cells whose blended corners'
    // box, widened by the cell's stray (pixels) and the reach, holds the normal.
    GLINTSCOPE_OUT_OF_LINE_CLONES double cell_density(int i, int j, long long unwrapped_i, long long unwrapped_j, int n) const {
        const SubCells cells{weight, cell_x(unwrapped_i), cell_y(unwrapped_j), lattice.step_x / n, lattice.step_y / n};
        // Centroid weights only of triangles whose spread reaches the normal: exp is costly.
        const auto pair = [&](Pixel p00, Pixel p10, Pixel p01, Pixel p11, int a, int b) {
            if (boxed) return box_pair(cells, p00, p10, p01, p11, a, b);
            double sum = 0.0;
            const double lower = triangle_spread(p00, p10, p11, normal, blur);
            if (lower > 0.0) sum += lower * cells.lower(a, b);
            const double upper = triangle_spread(p00, p11, p01, normal, blur);
            if (upper > 0.0) sum += upper * cells.upper(a, b);
            return sum;
        };
        const CellCorners c = cell_corners(tree, i, j);
        if (n == 1) return pair(c.p00, c.p10, c.p01, c.p11, 0, 0);
        const DividedCell& divided = tree.divided[static_cast<std::size_t>(j) * tree.grid.cols + i];
        // The quadrants' corners (a, b ∈ {0, m, n}): the cell's own, and the stored middles
        // within half a quantum of their images (the widening below adds a quantum for them).
        const auto middle = [&](int k) {
            return Pixel{tree.origin + divided.middles[2 * k] * tree.quantum, tree.origin + divided.middles[2 * k + 1] * tree.quantum};
        };
        const Pixel grid[3][3] = {{c.p00, middle(0), c.p10}, {middle(1), middle(2), middle(3)}, {c.p01, middle(4), c.p11}};
        // The cell's samples are read and its sub-corners evaluated once a quadrant passes.
        std::optional<CellPatch> patch;
        std::optional<SubCorners> corners;
        double sum = 0.0;
        for (int q = 0; q < 4; ++q) {
            const Quadrant r = quadrant(n, q);
            const int qa = q & 1, qb = q >> 1;
            const Pixel q00 = grid[qb][qa], q10 = grid[qb][qa + 1], q01 = grid[qb + 1][qa], q11 = grid[qb + 1][qa + 1];
            const double widening = (divided.strays[q] + 1) * tree.quantum + reach;
            if (prune && !quad_holds(q00, q10, q01, q11, widening)) continue;
            if (!corners) patch.emplace(tree, i, j), corners.emplace(*patch, c, n, store);
            const double inverse_height = 1.0 / (r.b1 - r.b0);
            // The blend along sub-rows b and b + 1: linear in a from the quadrant's left edge
            // (q00–q01) to its right (q10–q11); row b + 1's ends are the next row's lower ones.
            // (Only tests read the blend: rounding differences are far inside their quantum's margin.)
            const auto lerp = [](Pixel p, Pixel q, double t) { return Pixel{p.u + t * (q.u - p.u), p.v + t * (q.v - p.v)}; };
            Pixel bottom_left = q00, bottom_right = q10;
            for (int b = r.b0; b < r.b1; ++b) {
                const double t = (b + 1 - r.b0) * inverse_height;
                const Pixel left0 = bottom_left, right0 = bottom_right;
                const Pixel left1 = lerp(q00, q01, t), right1 = lerp(q10, q11, t);
                bottom_left = left1, bottom_right = right1;
                // The row's sub-cells' blended corners lie on the segments left0–right0 and
                // left1–right1, so within their ends' box: a row whose widened box misses h is skipped whole.
                if (prune && !quad_holds(left0, right0, left1, right1, widening)) continue;
                const std::uint64_t passing = prune ? sub_cells_holding(left0, right0, left1, right1, r.a1 - r.a0, widening)
                                                    : (std::uint64_t{1} << (r.a1 - r.a0)) - 1;
                for (std::uint64_t left = passing; left != 0; left &= left - 1) {
                    const int a = r.a0 + std::countr_zero(left);
                    const Pixel p00 = corners->at(a, b), p10 = corners->at(a + 1, b);
                    const Pixel p01 = corners->at(a, b + 1), p11 = corners->at(a + 1, b + 1);
                    if (prune && !quad_holds(p00, p10, p01, p11, reach)) continue;
                    sum += pair(p00, p10, p01, p11, a, b);
                }
            }
        }
        return sum;
    }

    // A box's share of sub-cell (a, b)'s two triangles, lower (p00, p10, p11) and upper (p00, p11,
    // p01): a triangle's density where the surface point whose normal is h, s = Σ barycentric(h) ·
    // corner (exact for the affine map of the triangle model), lies in the box, times
    // area/(W·H); with a blur, where the triangle's centroid does.
    double box_pair(const SubCells& cells, Pixel p00, Pixel p10, Pixel p01, Pixel p11, int a, int b) const {
        const double x = cells.x + a * cells.h, y = cells.y + b * cells.k, mass = 0.5 * cells.h * cells.k * weight.scale;
        double sum = 0.0;
        if (blur.sigma > 0.0) {
            if (box.holds(x + cells.h * (2.0 / 3.0), y + cells.k / 3.0)) sum += triangle_spread(p00, p10, p11, normal, blur) * mass;
            if (box.holds(x + cells.h / 3.0, y + cells.k * (2.0 / 3.0))) sum += triangle_spread(p00, p11, p01, normal, blur) * mass;
            return sum;
        }
        // The lower triangle's corners are the sub-cell's (0, 0), (1, 0), (1, 1); the upper's (0, 0), (1, 1), (0, 1).
        const TriangleHit lower = triangle_hit(p00, p10, p11, normal);
        if (lower.density > 0.0 && box.holds(x + (lower.second + lower.third) * cells.h, y + lower.third * cells.k))
            sum += lower.density * mass;
        const TriangleHit upper = triangle_hit(p00, p11, p01, normal);
        if (upper.density > 0.0 && box.holds(x + upper.second * cells.h, y + (upper.second + upper.third) * cells.k))
            sum += upper.density * mass;
        return sum;
    }

    // Of the `count` sub-cells of a sub-row (count ≤ 32), whose blended corners lie evenly spaced
    // on the segments left0–right0 (below) and left1–right1 (above), those whose corners' box,
    // widened by `by` pixels, holds the normal, as bits. A box holds it where some corner lies at
    // or below it and some at or above it, per axis: flags of the count + 1 corner columns,
    // then a sub-cell's is its left column's or its right's.
    std::uint64_t sub_cells_holding(Pixel left0, Pixel right0, Pixel left1, Pixel right1, int count, double by) const {
        const double inverse_count = 1.0 / count;
        const double u_high = normal.u + by, u_low = normal.u - by, v_high = normal.v + by, v_low = normal.v - by;
        std::uint64_t u_below = 0, u_above = 0, v_below = 0, v_above = 0;
        // Without branches: which way each comparison goes varies from column to column.
        for (int x = 0; x <= count; ++x) {
            const double f = x * inverse_count;
            const double u0 = left0.u + f * (right0.u - left0.u), u1 = left1.u + f * (right1.u - left1.u);
            const double v0 = left0.v + f * (right0.v - left0.v), v1 = left1.v + f * (right1.v - left1.v);
            u_below |= static_cast<std::uint64_t>((u0 <= u_high) | (u1 <= u_high)) << x;
            u_above |= static_cast<std::uint64_t>((u0 >= u_low) | (u1 >= u_low)) << x;
            v_below |= static_cast<std::uint64_t>((v0 <= v_high) | (v1 <= v_high)) << x;
            v_above |= static_cast<std::uint64_t>((v0 >= v_low) | (v1 >= v_low)) << x;
        }
        const auto either_side = [](std::uint64_t columns) { return columns | columns >> 1; };
        return either_side(u_below) & either_side(u_above) & either_side(v_below) & either_side(v_above) &
               ((std::uint64_t{1} << count) - 1);
    }

    // Whether the corners' bounding box, widened by `by` pixels, holds the normal.
    bool quad_holds(Pixel a, Pixel b, Pixel c, Pixel d, double by) const {
        return normal.u >= std::min({a.u, b.u, c.u, d.u}) - by && normal.u <= std::max({a.u, b.u, c.u, d.u}) + by &&
               normal.v >= std::min({a.v, b.v, c.v, d.v}) - by && normal.v <= std::max({a.v, b.v, c.v, d.v}) + by;
    }

    // Whether the unwrapped cells [x0, x1) × [y0, y1) lie wholly beyond the weight's cutoff (a box: outside it).
    bool beyond_cutoff(long long x0, long long x1, long long y0, long long y1) const {
        const double left = cell_x(x0), right = cell_x(x1), bottom = cell_y(y0), top = cell_y(y1);
        if (boxed) return box.misses(left, bottom, right, top);
        if (weight.shape != FootprintShape::gaussian) return false;
        const double dx = std::max({0.0, left - weight.centre.x, weight.centre.x - right});
        const double dy = std::max({0.0, bottom - weight.centre.y, weight.centre.y - top});
        return dx * dx + dy * dy > weight.cutoff_squared * (1.0 + 1e-9);
    }

    // Of a tile's entries [begin, end) of one bin, those of the tile's local rows [row0, row1):
    // the entries run in row-major order of their places, so these are contiguous. A footprint
    // smaller than a tile reads only its own rows' entries.
    std::pair<std::uint32_t, std::uint32_t> entries_of_rows(std::uint32_t begin, std::uint32_t end, int row0, int row1) const {
        const int side = NormalBoundsTree::kTileCells;
        const BinnedCell* const cells = tree.cells.data();
        const auto first_of_row = [&](int row) {
            if (row <= 0) return begin;
            if (row >= side) return end;
            return static_cast<std::uint32_t>(
                std::partition_point(cells + begin, cells + end,
                                     [&](const BinnedCell& entry) { return (entry.place >> 6) < row * side; }) -
                cells);
        };
        return {first_of_row(row0), first_of_row(row1)};
    }

    // The cells of the field [x0, x1) × [y0, y1), which stand at unwrapped (I + ox, J + oy), tile
    // by tile and in each tile row by row; pruned, only the cells of the normal's bin whose box
    // holds it and which reach within the cutoff (the others' triangles add exactly 0).
    GLINTSCOPE_OUT_OF_LINE_CLONES double piece(int x0, int x1, int y0, int y1, long long ox, long long oy) const {
        const int side = NormalBoundsTree::kTileCells;
        const std::size_t stride = static_cast<std::size_t>(tree.tile_cols) * tree.tile_rows + 1;
        double sum = 0.0;
        for (int tile_y = y0 / side; tile_y * side < y1; ++tile_y)
            for (int tile_x = x0 / side; tile_x * side < x1; ++tile_x) {
                const int lo_x = std::max(x0, tile_x * side), hi_x = std::min(x1, (tile_x + 1) * side);
                const int lo_y = std::max(y0, tile_y * side), hi_y = std::min(y1, (tile_y + 1) * side);
                if (!prune) {
                    for (int j = lo_y; j < hi_y; ++j)
                        for (int i = lo_x; i < hi_x; ++i) sum += cell_density(i, j, i + ox, j + oy, tree.subdivision[static_cast<std::size_t>(j) * tree.grid.cols + i]);
                    continue;
                }
                if (bin_row < 0 || beyond_cutoff(lo_x + ox, hi_x + ox, lo_y + oy, hi_y + oy)) continue;
                const std::size_t t = static_cast<std::size_t>(tile_y) * tree.tile_cols + tile_x;
                const auto [begin, end] = entries_of_rows(tree.offsets[bin_row * stride + t], tree.offsets[bin_row * stride + t + 1],
                                                          lo_y - tile_y * side, hi_y - tile_y * side);
                // The tile's candidates first, their samples' images and strays prefetched, so
                // that their cache misses overlap instead of following one another.
                struct Candidate {
                    int i, j, n;
                };
                std::array<Candidate, 64> candidates;
                int count = 0;
                const auto flush = [&] {
                    for (int k = 0; k < count; ++k) {
                        const Candidate& c = candidates[k];
                        sum += cell_density(c.i, c.j, c.i + ox, c.j + oy, c.n);
                    }
                    count = 0;
                };
                for (std::uint32_t e = begin; e < end; ++e) {
                    const BinnedCell& entry = tree.cells[e];
                    if (normal_quanta.u < entry.u_low || normal_quanta.u > entry.u_high || normal_quanta.v < entry.v_low ||
                        normal_quanta.v > entry.v_high)
                        continue;
                    const int place = entry.place >> 6;
                    const int i = tile_x * side + place % side, j = tile_y * side + place / side;
                    if (i < lo_x || i >= hi_x || j < lo_y || j >= hi_y || beyond_cutoff(i + ox, i + 1 + ox, j + oy, j + 1 + oy))
                        continue;
                    const std::size_t cell = static_cast<std::size_t>(j) * tree.grid.cols + i;
                    const int above = j + 1 == tree.grid.rows ? 0 : j + 1;
                    __builtin_prefetch(&tree.samples[cell]);
                    __builtin_prefetch(&tree.samples[static_cast<std::size_t>(above) * tree.grid.cols + i]);
                    const int n = (entry.place & 63) + 1;
                    if (n > 1) __builtin_prefetch(&tree.divided[cell]);
                    candidates[count++] = {i, j, n};
                    if (count == static_cast<int>(candidates.size())) flush();
                }
                flush();
            }
        return sum;
    }
};

long long floor_div(long long a, long long b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// The unwrapped index of a lattice's first cell along one axis (the lattice runs through the samples).
long long first_cell(double origin, double texel) { return std::llround((origin - 0.5 * texel) / texel); }

// The point query's lattice: the texels' for every footprint; a box's over its bounding rectangle
// (the preimage rule cuts the texels' triangles at its edges), unlike the image's box lattice,
// which follows the edges of an axis-aligned box.
Lattice point_lattice(const TexelGrid& grid, const Footprint& footprint) {
    if (footprint.shape != FootprintShape::box) return lattice_for(grid, footprint);
    const Point2 reach = footprint_support_um(footprint);
    Lattice lattice;
    lattice.step_x = grid.dx_um;
    lattice.step_y = grid.dy_um;
    aligned_axis(footprint.centre_um.x - reach.x, footprint.centre_um.x + reach.x, grid.dx_um, grid.dx_um, lattice.x0, lattice.nx);
    aligned_axis(footprint.centre_um.y - reach.y, footprint.centre_um.y + reach.y, grid.dy_um, grid.dy_um, lattice.y0, lattice.ny);
    return lattice;
}

// The footprint weight of the truncated domain: a Gaussian truncated at K σ keeps 1 − e^{−K²/2}.
double truncated_weight(const Footprint& footprint) {
    return footprint.shape == FootprintShape::gaussian ? 1.0 - std::exp(-0.5 * kTruncationSigmas * kTruncationSigmas) : 1.0;
}

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
    build_bins(tree, blur_for(tree.intrinsic_roughness, tree.resolution).radius);
    return tree;
}

double point_normal_density(const NormalBoundsTree& tree, const Footprint& footprint, DiskPoint normal, Pruning pruning) {
    if (!inside_unit_disk(normal)) return 0.0;
    const double half_resolution = 0.5 * tree.resolution;
    const TexelGrid& grid = tree.grid;
    const Lattice lattice = point_lattice(grid, footprint);
    const Blur blur = blur_for(tree.intrinsic_roughness, tree.resolution);
    const Pixel pixel{(normal.x + 1.0) * half_resolution, (1.0 - normal.y) * half_resolution};
    Query query{tree,
                lattice,
                weight_for(grid, footprint),
                first_cell(lattice.x0, grid.dx_um),
                first_cell(lattice.y0, grid.dy_um),
                pixel,
                blur,
                blur.radius,
                pruning == Pruning::on,
                {(pixel.u - tree.origin) / tree.quantum, (pixel.v - tree.origin) / tree.quantum},
                -1,
                sub_corner_store(),
                footprint.shape == FootprintShape::box,
                box_region(footprint)};
    const double bin_u = std::floor((pixel.u - tree.origin) / tree.bin_pixels);
    const double bin_v = std::floor((pixel.v - tree.origin) / tree.bin_pixels);
    if (bin_u >= 0.0 && bin_v >= 0.0 && bin_u < tree.bins_across && bin_v < tree.bins_across)
        query.bin_row = tree.bin_rows[static_cast<std::size_t>(bin_v) * tree.bins_across + static_cast<std::size_t>(bin_u)];
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
    return sum * half_resolution * half_resolution / truncated_weight(footprint);
}

NormalSampler make_normal_sampler(const NormalBoundsTree& tree, const Footprint& footprint) {
    if (tree.intrinsic_roughness > 0.0) throw Error("normals are drawn from the point query without intrinsic roughness only");
    const TexelGrid& grid = tree.grid;
    NormalSampler sampler;
    sampler.footprint = footprint;
    sampler.lattice = point_lattice(grid, footprint);
    sampler.weight = weight_for(grid, footprint);
    sampler.first_x = first_cell(sampler.lattice.x0, grid.dx_um);
    sampler.first_y = first_cell(sampler.lattice.y0, grid.dy_um);
    const Lattice& lattice = sampler.lattice;
    const BoxRegion box = box_region(footprint);
    sampler.cumulative.resize(static_cast<std::size_t>(lattice.nx * lattice.ny));
    double sum = 0.0;
    for (long long cj = 0; cj < lattice.ny; ++cj)
        for (long long ci = 0; ci < lattice.nx; ++ci) {
            const int i = static_cast<int>((sampler.first_x + ci) - floor_div(sampler.first_x + ci, grid.cols) * grid.cols);
            const int j = static_cast<int>((sampler.first_y + cj) - floor_div(sampler.first_y + cj, grid.rows) * grid.rows);
            const int n = tree.subdivision[static_cast<std::size_t>(j) * grid.cols + i];
            const SubCells cells{sampler.weight, lattice.x0 + static_cast<double>(ci) * lattice.step_x,
                                 lattice.y0 + static_cast<double>(cj) * lattice.step_y, lattice.step_x / n, lattice.step_y / n};
            const Weight& w = sampler.weight;
            if (footprint.shape == FootprintShape::box) {
                const double x1 = cells.x + lattice.step_x, y1 = cells.y + lattice.step_y;
                if (box.contains(cells.x, cells.y, x1, y1)) sum += w.scale * lattice.step_x * lattice.step_y;
                else if (!box.misses(cells.x, cells.y, x1, y1)) sum += cell_weight(BoxTriangles{box, cells, w.scale}, n);
            } else {
                const double far_x = std::max(std::abs(cells.x - w.centre.x), std::abs(cells.x + lattice.step_x - w.centre.x));
                const double far_y = std::max(std::abs(cells.y - w.centre.y), std::abs(cells.y + lattice.step_y - w.centre.y));
                const bool within = w.shape == FootprintShape::gaussian && !w.elliptical && far_x * far_x + far_y * far_y < w.cutoff_squared;
                sum += within ? separable_cell_weight(cells, n) : cell_weight(cells, n);
            }
            sampler.cumulative[static_cast<std::size_t>(cj * lattice.nx + ci)] = sum;
        }
    if (!(sum > 0.0)) throw Error("the footprint weighs no triangle of the field");
    sampler.density_scale = truncated_weight(footprint) / sum;
    return sampler;
}

namespace {

// The barycentric weights of a point drawn uniformly over a triangle of the chosen cell from two
// uniforms: over the whole triangle by √s (Turk 1990); for a box, over its part inside the box
// (the clipped polygon's fan triangle by area, then uniformly in it, in the box's frame).
struct Barycentric {
    double first = 1.0, second = 0.0, third = 0.0;
};

Barycentric uniform_in_triangle(double share, double u2) {
    const double root = std::sqrt(share);
    return {1.0 - root, root * (1.0 - u2), root * u2};
}

Barycentric uniform_in_clipped(const BoxTriangles& triangles, int a, int b, bool upper, double share, double u2) {
    const SmallPolygon whole = triangles.corners(a, b, upper), piece = triangles.clipped(a, b, upper);
    if (piece.count < 3) return {};
    // The fan (0, k, k + 1) triangle where the running area passes the share of the polygon's.
    const auto fan_area = [&](int k) { return polygon_area({{piece.corners[0], piece.corners[k], piece.corners[k + 1]}, 3}); };
    double total = 0.0;
    for (int k = 1; k + 1 < piece.count; ++k) total += fan_area(k);
    const double goal = share * total;
    double running = 0.0;
    int fan = piece.count - 2;
    for (int k = 1; k + 1 < piece.count; ++k) {
        if (running + fan_area(k) > goal) {
            fan = k;
            break;
        }
        running += fan_area(k);
    }
    const double within = std::clamp((goal - running) / fan_area(fan), 0.0, 1.0);
    const Barycentric in_fan = uniform_in_triangle(within, u2);
    const DiskPoint p0 = piece.corners[0], p1 = piece.corners[fan], p2 = piece.corners[fan + 1];
    const DiskPoint q{in_fan.first * p0.x + in_fan.second * p1.x + in_fan.third * p2.x,
                      in_fan.first * p0.y + in_fan.second * p1.y + in_fan.third * p2.y};
    // q's weights in the whole triangle ABC: areas of AqC and ABq over ABC's.
    const DiskPoint A = whole.corners[0], B = whole.corners[1], C = whole.corners[2];
    const double twice = (B.x - A.x) * (C.y - A.y) - (C.x - A.x) * (B.y - A.y);
    const double second = ((q.x - A.x) * (C.y - A.y) - (C.x - A.x) * (q.y - A.y)) / twice;
    const double third = ((B.x - A.x) * (q.y - A.y) - (q.x - A.x) * (B.y - A.y)) / twice;
    return {1.0 - second - third, second, third};
}

}  // namespace

std::optional<DiskPoint> sample_normal(const NormalBoundsTree& tree, const NormalSampler& sampler, double u1, double u2) {
    // A cell by its weight (u1), a triangle of it by its weight (u1's remainder), a uniform
    // point of the triangle's image (that remainder and u2).
    const std::vector<double>& cumulative = sampler.cumulative;
    const double target = u1 * cumulative.back();
    const std::size_t cell = std::min<std::size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin(),
                                                   cumulative.size() - 1);
    const double before = cell == 0 ? 0.0 : cumulative[cell - 1];
    const double remainder = std::clamp((target - before) / (cumulative[cell] - before), 0.0, 1.0);
    const TexelGrid& grid = tree.grid;
    const Lattice& lattice = sampler.lattice;
    const long long ci = static_cast<long long>(cell) % lattice.nx, cj = static_cast<long long>(cell) / lattice.nx;
    const int i = static_cast<int>((sampler.first_x + ci) - floor_div(sampler.first_x + ci, grid.cols) * grid.cols);
    const int j = static_cast<int>((sampler.first_y + cj) - floor_div(sampler.first_y + cj, grid.rows) * grid.rows);
    const int n = tree.subdivision[static_cast<std::size_t>(j) * grid.cols + i];
    const SubCells cells{sampler.weight, lattice.x0 + static_cast<double>(ci) * lattice.step_x,
                         lattice.y0 + static_cast<double>(cj) * lattice.step_y, lattice.step_x / n, lattice.step_y / n};
    const bool boxed = sampler.footprint.shape == FootprintShape::box;
    const BoxRegion box = box_region(sampler.footprint);
    const BoxTriangles box_triangles{box, cells, sampler.weight.scale};
    // The triangle: 2(b·n + a) + (0 lower, 1 upper), where the running weight passes the goal.
    const auto triangle_weight = [&](int a, int b, bool upper) {
        if (boxed) return upper ? box_triangles.upper(a, b) : box_triangles.lower(a, b);
        return upper ? cells.upper(a, b) : cells.lower(a, b);
    };
    const double goal = remainder * (boxed ? cell_weight(box_triangles, n) : cell_weight(cells, n));
    double running = 0.0, share = 0.0;
    int chosen = -1;
    for (int t = 0; t < 2 * n * n && chosen < 0; ++t) {
        const double w = triangle_weight((t / 2) % n, (t / 2) / n, t % 2 == 1);
        if (w > 0.0 && (running + w > goal || t == 2 * n * n - 1)) chosen = t, share = std::clamp((goal - running) / w, 0.0, 1.0);
        running += w;
    }
    if (chosen < 0) return std::nullopt;
    const int a = (chosen / 2) % n, b = (chosen / 2) / n;
    const CellCorners c = cell_corners(tree, i, j);
    Pixel p00 = c.p00, p10 = c.p10, p01 = c.p01, p11 = c.p11;
    if (n > 1) {
        const CellPatch patch(tree, i, j);
        const SubCorners corners(patch, c, n, sub_corner_store());
        p00 = corners.at(a, b), p10 = corners.at(a + 1, b), p01 = corners.at(a, b + 1), p11 = corners.at(a + 1, b + 1);
    }
    const bool upper = chosen % 2 == 1;
    const Pixel first = p00, second = upper ? p11 : p10, third = upper ? p01 : p11;
    // The affine map of the triangle takes a uniform point of it (or of its part in the box) to a
    // uniform point of its image (of that part's image).
    const Barycentric w = boxed ? uniform_in_clipped(box_triangles, a, b, upper, share, u2) : uniform_in_triangle(share, u2);
    const Pixel point{w.first * first.u + w.second * second.u + w.third * third.u,
                      w.first * first.v + w.second * second.v + w.third * third.v};
    if (!(triangle_spread(first, second, third, point, Blur{}) > 0.0)) return std::nullopt;
    const double half_resolution = 0.5 * tree.resolution;
    const DiskPoint normal{point.u / half_resolution - 1.0, 1.0 - point.v / half_resolution};
    if (!inside_unit_disk(normal)) return std::nullopt;
    return normal;
}

double sampled_normal_density(const NormalBoundsTree& tree, const NormalSampler& sampler, DiskPoint normal) {
    return point_normal_density(tree, sampler.footprint, normal) * sampler.density_scale;
}

LazyNormalSampler::LazyNormalSampler(std::shared_ptr<const NormalBoundsTree> tree, const Footprint& footprint)
    : tree_(std::move(tree)), sampler_([tree = tree_, footprint] { return make_normal_sampler(*tree, footprint); }) {}

std::optional<NormalDraw> LazyNormalSampler::draw(double u1, double u2) const {
    const NormalSampler& sampler = sampler_.get();
    const std::optional<DiskPoint> normal = sample_normal(*tree_, sampler, u1, u2);
    if (!normal) return std::nullopt;
    return NormalDraw{*normal, sampled_normal_density(*tree_, sampler, *normal)};
}

double LazyNormalSampler::density(DiskPoint normal) const {
    return sampled_normal_density(*tree_, sampler_.get(), normal);
}

}  // namespace glintscope
