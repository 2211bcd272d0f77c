#pragma once
// The footprint-weighted density of surface normals on the projected disk (conventions.md
// "Geometric NDFs"): the patch NDF (P-NDF) of Yan 2014 as summarised in Yan 2018 §2, computed
// exactly rather than by sampling.
//
// Algorithm. The integration domain (the truncated footprint, on the tiled surface) is cut into
// base cells of one texel aligned with the sample lattice (a box footprint: with its edges).
// Each base cell is subdivided into n×n cells, n the least integer ≥ refinement for which
// the image of the cell centre lies within `tolerance_pixels` of the bilinear blend of the
// corner images, divided by n² (that stray is the map's second-order part, which shrinks as the
// square of the cell size); n ≤ 64. Each cell is cut into two triangles. On a triangle the
// normal map s ↦ (m_x, m_y), m = (−H_x, −H_y, 1)/|…|, is replaced by the affine map through its
// three corner images, so the triangle's weight (taken at its centroid) spreads uniformly over
// the image triangle; that triangle is clipped against every pixel it touches and each pixel
// receives the exact area share (a triangle whose image is a segment: the exact shares of its
// 1-D tent marginal). Nothing is sampled: folds of the normal map (the caustics of the P-NDF)
// are edges of image triangles and come out sharp at any resolution.
//
// Error. Replacing the map by its corner interpolant on a triangle of side h moves the image of
// each point by O(h² |∇²m|), and the centroid weight errs by O(h² |∇²weight|); both are second
// order, so doubling the subdivision divides the error of pixel-integrated quantities by about 4
// (tests/lib/geometric/normal_density_test.cpp: 0.21 → 0.055 → 0.013 relative L2 at n = 1, 2, 4
// on a 10 µm footprint at 128², against n = 16). The tolerance bounds the remaining image
// displacement at about tolerance_pixels per cell. The Gaussian is truncated at
// kTruncationSigmas = 6 standard deviations, losing e^{−18} ≈ 1.5e-8 of the mass; the image is
// renormalised to Σ D·(2/N)² = 1 (which also absorbs the centroid rule's ~1e-5 weight error).
#include <vector>

#include "glintscope/surface/interpolant.hpp"
#include "glintscope/lobe/query.hpp"

namespace glintscope {

struct NormalDensitySettings {
    int refinement = 1;                // least cells per texel along each axis
    double tolerance_pixels = 0.02;    // adaptive subdivision threshold; 0: exactly `refinement`
    double intrinsic_roughness = 0.0;  // radians: Gaussian blur of that angular width (Yan 2014)
};

constexpr double kTruncationSigmas = 6.0;
constexpr int kMaxRefinement = 64;

// The weight of surface element ds (conventions.md "Coherence / footprint"): a Gaussian
// footprint of σ_c weighs by |w(s − x_c)|²/A_c, a normalised Gaussian of standard deviation
// σ_c/√2 (an ellipse: along its major axis; triangle_model.hpp weighs by its covariance); a box
// by 1/side² inside it; `whole` by 1/(W·H) over one period of the field.
double footprint_weight_sigma_um(const Footprint& footprint);

// Throws Error naming a bad resolution, refinement, tolerance or roughness.
void check_normal_density_settings(int resolution, const NormalDensitySettings& settings);

// D on the N×N projected-disk image, row-major with row 0 at the top (largest m_y), normalised
// so that Σ D·(2/N)² = 1. Throws Error naming a bad resolution, refinement or roughness.
std::vector<double> normal_density(const BicubicInterpolant& surface, const Footprint& footprint, int resolution,
                                   const NormalDensitySettings& settings);

// A deterministic blur of an NDF image by a Gaussian of angular standard deviation `roughness`
// (radians, taken as a disk distance: exact near the normal, small angles), keeping Σ D
// unchanged and the pixels outside the disk zero.
void blur_normal_density(std::vector<double>& density, int resolution, double roughness);

}  // namespace glintscope
