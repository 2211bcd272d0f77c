#pragma once
// The exact normal density (normal_density.hpp) at one normal, for any footprint, without an
// image: the point query of the patch NDF, as Yan 2014/2016 evaluate position-normal
// distributions by a hierarchy over normal bounds (Yan 2018 §2), here over the same triangle
// model as the image, so that the image's pixel is the mean of the point query over the pixel.
//
// Built once per interpolant, settings and image resolution (the resolution fixes the pixel
// units of the adaptive subdivision's tolerance, so the triangles are exactly the image's): the
// normal images of every texel sample, each texel's subdivision (a divided texel's sub-corners
// are evaluated again by the query that reaches it), and a quadtree over the texel cells (mip levels, like GaborSurface's) whose nodes hold the bounding
// box of their triangles' normal images. A query visits only the nodes that overlap the
// footprint's truncated support and whose box holds the normal:
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
// Gaussian and whole-field footprints only: a box's lattice follows its edges, not the texels
// (point_normal_density throws Error for one). Immutable once built, safe from many threads, no
// allocation per query.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/surface/interpolant.hpp"
#include "normal_density/normal_density.hpp"
#include "normal_density/triangle_model.hpp"

namespace glintscope {

// A bounding box of normal images in pixel units (u along columns, v down rows), rounded outward.
struct NormalBox {
    float u_low = 0.0f;
    float u_high = 0.0f;
    float v_low = 0.0f;
    float v_high = 0.0f;
};

struct NormalBoundsTree {
    TexelGrid grid;
    int resolution = 0;  // the pixel units of the normal images: those of an image of this resolution
    double intrinsic_roughness = 0.0;
    // Normal images, pixel units: sample (c, j) at j·cols + c (y-up rows, at ((c + ½)dx, (j + ½)dx)).
    std::vector<Pixel> samples;
    // Per texel cell (i, j) between samples (i, j) and (i + 1, j + 1), at j·cols + i: its
    // subdivision n. A divided cell's (n + 1)² sub-corners are evaluated again when a query
    // reaches it (the same calls as the image's, so the same values): on the isotropic builtin
    // at the 256² defaults most texels are divided 5–9 times, and storing their corners would
    // take a gigabyte per 1024² of field.
    std::vector<std::uint8_t> subdivision;
    std::shared_ptr<const BicubicInterpolant> surface;
    // Level 0 holds one node per texel cell, level k one per block of 2^k × 2^k cells,
    // level_cols[k] × level_rows[k] of them (ceil of the halving), up to a 1 × 1 level.
    // children[k − 1][j·level_cols[k] + i] holds the boxes of node (i, j)'s children (level k − 1)
    // together, as 4 × 16 bytes in one cache line: a query's cost is its cache misses (the
    // boxes of a 1024² field take 21 MB), one per node whose children it tests. A child past the
    // field's edge has an empty box.
    struct alignas(64) Children {
        std::array<NormalBox, 4> boxes;  // child (2i + a, 2j + b) at 2b + a
    };
    std::vector<std::vector<Children>> children;
    std::vector<int> level_cols, level_rows;
    NormalBox root;
};

// Throws Error on bad settings or resolution as normal_density() does.
NormalBoundsTree make_normal_bounds_tree(std::shared_ptr<const BicubicInterpolant> surface,
                                         const NormalDensitySettings& settings, int resolution);

// Whether the query skips the nodes whose normal box or cell rectangle cannot contribute; off
// visits every triangle of the support (tests: pruning must not change the result).
enum class Pruning { on, off };

// Whether point_normal_density answers the footprint (Gaussian or whole field, not a box).
inline bool answers_points(const Footprint& footprint) { return footprint.shape != FootprintShape::box; }

// D at the disk point (m_x, m_y) for the footprint, per unit area of the projected disk;
// 0 outside the disk. Throws Error for a box footprint.
double point_normal_density(const NormalBoundsTree& tree, const Footprint& footprint, DiskPoint normal,
                            Pruning pruning = Pruning::on);

}  // namespace glintscope
