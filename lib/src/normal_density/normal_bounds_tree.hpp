#pragma once
// The exact normal density (normal_density.hpp) at one normal, for any footprint, without an
// image: the point query of the patch NDF, as Yan 2014/2016 evaluate position-normal
// distributions by a hierarchy over normal bounds (Yan 2018 §2), here over the same triangle
// model as the image, so that the image's pixel is the mean of the point query over the pixel.
//
// Built once per interpolant, settings and image resolution (the resolution fixes the pixel
// units of the adaptive subdivision's tolerance, so the triangles are exactly the image's): the
// normal images of every texel sample, each texel's subdivision n, and a two-level index over
// the texel cells: tiles of 32 × 32 cells in space, bins of normal space per tile, each bin
// listing (in the tile's row-major order) the cells whose normal box overlaps it, with the box
// inline. A query reads, per tile of the footprint's truncated support, only the list of h's
// bin: a few contiguous cache lines, and independent misses after it (no chain of node visits).
// A divided cell's (n + 1)² sub-corners are not stored (a gigabyte per 1024² of field at the
// defaults); per quadrant (split at ⌊n/2⌋) the cell keeps its stray, the largest distance of a
// sub-corner's image from the bilinear blend of the quadrant's corner images, and the quadrants'
// corner images (quantised), so that a query evaluates only the sub-corners of sub-cells whose
// blended box, widened by the stray, holds h, from the cell's 4 × 4 samples read once when a
// quadrant passes (the image's values up to rounding).
//   D(h) = Σ over triangles whose image holds h of weight(centroid) · area / image area,
// divided by the footprint weight of the truncated domain (1 − e^{−K²/2} for a Gaussian), so
// that ∫ D dA_disk = 1 as the image's Σ D (2/N)² = 1 (the image also absorbs the centroid rule's
// ~1e-5 weight error into its normalisation; the query does not). Periodic as the image: a
// footprint straddling the field's edge reads the tiles on both sides.
//
// Intrinsic roughness σ (radians, as a disk distance): each triangle's uniform density is
// integrated against the Gaussian of σ by the three-edge-midpoint rule (exact for quadratics: a
// triangle much smaller than σ), truncated at the image blur's 4σ per axis. The image blurs the
// pixels instead and restores mass blurred past the rim by a common factor; the query does not
// (tests/lib/normal_density/normal_bounds_tree_test.cpp measures the difference).
//
// Gaussian (isotropic or elliptical: the weight of covariance Σ_c/2, triangle_model.hpp),
// whole-field and box footprints, a box axis-aligned or rotated (Footprint::axis_radians): the
// texels' lattice over the box's bounding rectangle, and the weight of a triangle whose image
// holds h is 1/(W·H) where the surface point whose normal is h, s = Σ barycentric(h) · corner,
// lies in the box (half-open, BoxRegion), else 0: D(h) is then exactly the density of the
// triangle model clipped by the box, boxes that tile a region partition every triangle's mass,
// and no truncation divides D. With intrinsic roughness (a blurred spread has no one preimage)
// the indicator is taken at the triangle's centroid. Tiles and cells wholly outside the box are
// skipped, so a box's query costs what its area does. The image's box lattice follows an
// axis-aligned box's edges instead (normal_density.cpp): the two agree at pixel centres only to
// the triangles' steps (tests/lib/normal_density/normal_bounds_tree_test.cpp). Immutable once
// built, safe from many threads, no allocation per query.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/lazy.hpp"
#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/surface/interpolant.hpp"
#include "normal_density/normal_density.hpp"
#include "normal_density/triangle_model.hpp"

namespace glintscope {

// A cell's entry in a bin: its place in the tile, its subdivision and its normal box (widened by
// the blur's reach), in quanta of NormalBoundsTree::quantum pixels
// from NormalBoundsTree::origin, rounded outward.
struct BinnedCell {
    std::uint16_t place = 0;  // (local row · 32 + local column) << 6 | (n − 1)
    std::uint16_t u_low = 0, u_high = 0, v_low = 0, v_high = 0;
};

// A divided cell's quadrants (split at m = ⌊n/2⌋), in quanta of NormalBoundsTree::quantum pixels
// from NormalBoundsTree::origin: their strays, rounded up, and the images of the five sub-corners
// the quadrants add to the cell's corners, (m, 0), (0, m), (m, m), (n, m), (m, n) as (u, v) pairs,
// rounded to the nearest quantum: a query tests the quadrants and their sub-cells' blended boxes
// with these, widened by a quantum more, and evaluates only the sub-corners of sub-cells that pass.
struct DividedCell {
    std::array<std::uint16_t, 4> strays{};
    std::array<std::uint16_t, 10> middles{};
};

struct NormalBoundsTree {
    static constexpr int kTileCells = 32;  // tiles of kTileCells × kTileCells texel cells
    TexelGrid grid;
    int resolution = 0;  // the pixel units of the normal images: those of an image of this resolution
    double intrinsic_roughness = 0.0;
    // Normal images, pixel units: sample (c, j) at j·cols + c (y-up rows, at ((c + ½)dx, (j + ½)dx)).
    std::vector<Pixel> samples;
    // Per texel cell (i, j) between samples (i, j) and (i + 1, j + 1), at j·cols + i: its subdivision n.
    std::vector<std::uint8_t> subdivision;
    // Per cell as `subdivision`: a divided cell's quadrants.
    std::vector<DividedCell> divided;
    std::shared_ptr<const BicubicInterpolant> surface;
    // Tiles: tile (tx, ty) at ty·tile_cols + tx holds cells [32 tx, 32 tx + 32) × [32 ty, …).
    int tile_cols = 0, tile_rows = 0;
    // Bins of normal space: bin (bu, bv) covers u in origin + [bu, bu + 1)·bin_pixels (v alike),
    // bins_across per axis over the widened boxes; bin_rows[bv·bins_across + bu] is the bin's row
    // of `offsets`, or −1 for a bin no cell overlaps.
    double origin = 0.0;
    double bin_pixels = 1.0;
    double quantum = 1.0;
    int bins_across = 0;
    std::vector<std::int32_t> bin_rows;
    // Row r's entries of tile t are cells[offsets[r·(tiles + 1) + t] … offsets[r·(tiles + 1) + t + 1]).
    std::vector<std::uint32_t> offsets;
    std::vector<BinnedCell> cells;
};

// Throws Error on bad settings or resolution as normal_density() does.
NormalBoundsTree make_normal_bounds_tree(std::shared_ptr<const BicubicInterpolant> surface,
                                         const NormalDensitySettings& settings, int resolution);

// Whether the query skips the nodes whose normal box or cell rectangle cannot contribute; off
// visits every triangle of the support (tests: pruning must not change the result).
enum class Pruning { on, off };

// D at the disk point (m_x, m_y) for the footprint, per unit area of the projected disk;
// 0 outside the disk.
double point_normal_density(const NormalBoundsTree& tree, const Footprint& footprint, DiskPoint normal,
                            Pruning pruning = Pruning::on);

// Normals drawn with the density of the point query for one footprint (no intrinsic roughness):
// the D(h) of the point query is the push-forward of the footprint weight through the piecewise
// affine normal map, so a draw picks a texel cell of the support by its weight (Σ of its
// triangles' centroid weight × area), a triangle of it by its weight, and a uniform point of
// the triangle's image. For a box a triangle weighs its area inside the box over W·H, and the
// point is uniform over the image of that part (the clipped polygon's), which is exactly the
// preimage rule's density: sampled and queried D agree but for rounding. Built once per footprint (its cost is one pass over the support's
// triangles' centroids, no normals evaluated); immutable, safe from many threads.
struct NormalSampler {
    Footprint footprint;
    Lattice lattice;
    Weight weight;
    long long first_x = 0, first_y = 0;
    std::vector<double> cumulative;  // running Σ of the lattice cells' weights, row by row
    // What the point query's D divides by (the truncated footprint weight) over what the
    // triangles weigh (the centroid rule's Σ): sampled density per disk area = D(h) × this.
    double density_scale = 1.0;
};

// Throws Error for a tree with intrinsic roughness, or a footprint that weighs no triangle.
NormalSampler make_normal_sampler(const NormalBoundsTree& tree, const Footprint& footprint);

// A normal from two uniforms in [0, 1); none where the drawn triangle's image is a segment (the
// point query gives it no density) or the draw leaves the disk.
std::optional<DiskPoint> sample_normal(const NormalBoundsTree& tree, const NormalSampler& sampler, double u1, double u2);

// The density per unit disk area with which sample_normal draws h.
double sampled_normal_density(const NormalBoundsTree& tree, const NormalSampler& sampler, DiskPoint normal);

// A drawn normal and the density per unit disk area with which it was drawn.
struct NormalDraw {
    DiskPoint normal;
    double density = 0.0;
};

// One footprint's sampler over a shared tree, made on the first draw or density (a caller that
// only evaluates D, such as a renderer's shading point, never pays for its pass over the
// support) and then shared by every thread. Without intrinsic roughness (the first use throws
// otherwise, as make_normal_sampler does).
class LazyNormalSampler {
public:
    LazyNormalSampler(std::shared_ptr<const NormalBoundsTree> tree, const Footprint& footprint);
    // sample_normal's normal and its sampled_normal_density.
    std::optional<NormalDraw> draw(double u1, double u2) const;
    double density(DiskPoint normal) const;

private:
    std::shared_ptr<const NormalBoundsTree> tree_;
    Lazy<NormalSampler> sampler_;
};

}  // namespace glintscope
