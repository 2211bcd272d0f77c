#pragma once
// The triangle model of the exact normal density (normal_density.hpp "Algorithm"), shared by the
// image (normal_density.cpp) and the point query (normal_bounds_tree.cpp) so that both integrate
// the same triangles: the base lattice of a footprint, the footprint weight, the images of
// normals in pixel units and the adaptive subdivision of a base cell.
#include <algorithm>
#include <cmath>

#include "glintscope/core/geometry.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/surface/interpolant.hpp"
#include "normal_density/normal_density.hpp"

namespace glintscope {

// The sample grid of a field: cols × rows samples at ((c + ½)·dx, (j + ½)·dy).
struct TexelGrid {
    int cols = 0;
    int rows = 0;
    double dx_um = 0.0;
    double dy_um = 0.0;
};

inline TexelGrid texel_grid(const BicubicInterpolant& surface) {
    return {surface.cols(), surface.rows(), surface.texel_um(), surface.texel_y_um()};
}

// Cell lattice over the integration domain: corners (x0 + i·step_x, y0 + j·step_y), 0 ≤ i ≤ nx,
// 0 ≤ j ≤ ny, on the periodically tiled surface.
struct Lattice {
    double x0 = 0.0;
    double y0 = 0.0;
    double step_x = 0.0;
    double step_y = 0.0;
    long long nx = 0;
    long long ny = 0;
};

// The footprint weight of a surface element at s (per µm²), zero outside the truncated support.
struct Weight {
    FootprintShape shape = FootprintShape::whole;
    Point2 centre;
    double inverse_two_variance = 0.0;  // Gaussian: 1/(2σ_w²)
    double cutoff_squared = 0.0;        // Gaussian: (kTruncationSigmas·σ_w)²
    double scale = 0.0;                 // normalisation: 1/(2πσ_w²) (ellipse: 1/(2π√det Σ_w)), 1/side², 1/(W·H)
    // An elliptical Gaussian (is_elliptical): the exponent ½ dᵀ Σ_w⁻¹ d = q_xx dx² + 2 q_xy dx dy +
    // q_yy dy², zero past K²/2 (d at K Mahalanobis units); cutoff_squared is then the circle of the
    // major axis, which holds that ellipse (for tests that a region lies beyond it).
    bool elliptical = false;
    double q_xx = 0.0, q_xy = 0.0, q_yy = 0.0;
    double exponent_cutoff = 0.0;

    [[gnu::always_inline]] double operator()(double x, double y) const {
        if (shape != FootprintShape::gaussian) return scale;
        if (elliptical) {
            const double dx = x - centre.x, dy = y - centre.y;
            const double exponent = q_xx * dx * dx + 2.0 * q_xy * dx * dy + q_yy * dy * dy;
            return exponent > exponent_cutoff ? 0.0 : scale * std::exp(-exponent);
        }
        const double r2 = (x - centre.x) * (x - centre.x) + (y - centre.y) * (y - centre.y);
        return r2 > cutoff_squared ? 0.0 : scale * std::exp(-r2 * inverse_two_variance);
    }

    // Whether the weight is zero all over the rectangle [x0, x1] × [y0, y1]: a Gaussian's
    // rectangle lies beyond its truncation circle (an ellipse's: beyond the circle of its major
    // axis, which holds it) by a margin far above the rounding of the exponent, so that a cell
    // there, whose triangles would all carry zero mass, can be skipped unevaluated.
    bool vanishes_on(double x0, double y0, double x1, double y1) const {
        if (shape != FootprintShape::gaussian) return false;
        const double dx = std::max({x0 - centre.x, 0.0, centre.x - x1});
        const double dy = std::max({y0 - centre.y, 0.0, centre.y - y1});
        return dx * dx + dy * dy > cutoff_squared * (1.0 + 1e-6);
    }
};

// A box footprint's rectangle on the surface (the point query's box, which may be rotated): its
// centre, its width's axis (cos, sin of Footprint::axis_radians) and half sides. A point belongs
// to it when its coordinates along the axes lie in [−half, half): half-open, so that boxes tiling
// a region hold each point exactly once.
struct BoxRegion {
    Point2 centre;
    double cos_axis = 1.0, sin_axis = 0.0;
    double half_width = 0.0, half_height = 0.0;
    Point2 reach;  // half sides of its bounding rectangle along x and y (footprint_support_um)

    // (x, y) in the box's frame: along its width, along its height.
    [[gnu::always_inline]] DiskPoint local(double x, double y) const {
        const double dx = x - centre.x, dy = y - centre.y;
        return {cos_axis * dx + sin_axis * dy, cos_axis * dy - sin_axis * dx};
    }

    [[gnu::always_inline]] bool holds(double x, double y) const {
        const DiskPoint p = local(x, y);
        return p.x >= -half_width && p.x < half_width && p.y >= -half_height && p.y < half_height;
    }

    // Whether the rectangle [x0, x1] × [y0, y1] lies wholly outside the box, by a margin far above
    // rounding (separating axes: x and y, then the box's own two), so that a cell there, whose
    // triangles' points all lie outside, can be skipped unevaluated.
    bool misses(double x0, double y0, double x1, double y1) const {
        const Point2 r = reach;
        const double margin = 1e-9 * (half_width + half_height);
        if (x0 > centre.x + r.x + margin || x1 < centre.x - r.x - margin || y0 > centre.y + r.y + margin ||
            y1 < centre.y - r.y - margin)
            return true;
        const double c = std::abs(cos_axis), s = std::abs(sin_axis), hx = 0.5 * (x1 - x0), hy = 0.5 * (y1 - y0);
        const DiskPoint middle = local(0.5 * (x0 + x1), 0.5 * (y0 + y1));
        return std::abs(middle.x) > half_width + hx * c + hy * s + margin ||
               std::abs(middle.y) > half_height + hx * s + hy * c + margin;
    }

    // Whether the rectangle [x0, x1] × [y0, y1] lies wholly inside the box (all four corners do).
    bool contains(double x0, double y0, double x1, double y1) const {
        for (const DiskPoint p : {local(x0, y0), local(x1, y0), local(x0, y1), local(x1, y1)})
            if (!(std::abs(p.x) < half_width && std::abs(p.y) < half_height)) return false;
        return true;
    }
};

inline BoxRegion box_region(const Footprint& footprint) {
    return {footprint.centre_um, std::cos(footprint.axis_radians), std::sin(footprint.axis_radians),
            0.5 * box_width_um(footprint), 0.5 * box_height_um(footprint), footprint_support_um(footprint)};
}

// First lattice index at or below `from` and the count of cells up to `to`, for a lattice
// through the sample positions (k + ½)·dx with step h.
inline void aligned_axis(double from, double to, double texel, double step, double& origin, long long& count) {
    const double first = std::floor((from - 0.5 * texel) / step);
    const double last = std::ceil((to - 0.5 * texel) / step);
    origin = 0.5 * texel + first * step;
    count = static_cast<long long>(last - first);
}

// The covariance Σ_w = Σ_c/2 of an elliptical footprint's weight |w|²/A_c (footprint.hpp,
// conventions.md "Coherence / footprint"): R diag(σ_c², σ_minor²) Rᵀ / 2, R the rotation by the axis.
struct WeightCovariance {
    double xx = 0.0, xy = 0.0, yy = 0.0;
};

inline WeightCovariance weight_covariance(const Footprint& footprint) {
    const double c = std::cos(footprint.axis_radians), s = std::sin(footprint.axis_radians);
    const double major = 0.5 * footprint.sigma_um * footprint.sigma_um;
    const double minor = 0.5 * footprint.sigma_minor_um * footprint.sigma_minor_um;
    return {c * c * major + s * s * minor, c * s * (major - minor), s * s * major + c * c * minor};
}

// The base lattice: one cell per texel, aligned with the samples (a box: with its edges, so
// the box's weight is integrated exactly); cells are subdivided further where needed.
inline Lattice lattice_for(const TexelGrid& surface, const Footprint& footprint) {
    const double dx = surface.dx_um, dy = surface.dy_um;
    Lattice lattice;
    lattice.step_x = dx;
    lattice.step_y = dy;
    if (footprint.shape == FootprintShape::whole) {
        lattice.x0 = 0.5 * dx;
        lattice.y0 = 0.5 * dy;
        lattice.nx = surface.cols;
        lattice.ny = surface.rows;
    } else if (footprint.shape == FootprintShape::box) {
        const double width = box_width_um(footprint), height = box_height_um(footprint);
        lattice.nx = static_cast<long long>(std::ceil(width / dx));
        lattice.ny = static_cast<long long>(std::ceil(height / dy));
        lattice.step_x = width / static_cast<double>(lattice.nx);
        lattice.step_y = height / static_cast<double>(lattice.ny);
        lattice.x0 = footprint.centre_um.x - 0.5 * width;
        lattice.y0 = footprint.centre_um.y - 0.5 * height;
    } else if (is_elliptical(footprint)) {
        // The truncated ellipse dᵀ Σ_w⁻¹ d ≤ K² reaches K √(Σ_w)_xx along x and K √(Σ_w)_yy along y.
        const WeightCovariance sigma = weight_covariance(footprint);
        const double reach_x = kTruncationSigmas * std::sqrt(sigma.xx), reach_y = kTruncationSigmas * std::sqrt(sigma.yy);
        aligned_axis(footprint.centre_um.x - reach_x, footprint.centre_um.x + reach_x, dx, dx, lattice.x0, lattice.nx);
        aligned_axis(footprint.centre_um.y - reach_y, footprint.centre_um.y + reach_y, dy, dy, lattice.y0, lattice.ny);
    } else {
        const double reach = kTruncationSigmas * footprint_weight_sigma_um(footprint);
        aligned_axis(footprint.centre_um.x - reach, footprint.centre_um.x + reach, dx, dx, lattice.x0, lattice.nx);
        aligned_axis(footprint.centre_um.y - reach, footprint.centre_um.y + reach, dy, dy, lattice.y0, lattice.ny);
    }
    return lattice;
}

inline Weight weight_for(const TexelGrid& surface, const Footprint& footprint) {
    Weight weight;
    weight.shape = footprint.shape;
    weight.centre = footprint.centre_um;
    if (footprint.shape == FootprintShape::whole) {
        weight.scale = 1.0 / (surface.cols * surface.dx_um * surface.rows * surface.dy_um);
    } else if (footprint.shape == FootprintShape::box) {
        weight.scale = 1.0 / (box_width_um(footprint) * box_height_um(footprint));
    } else if (is_elliptical(footprint)) {
        // Σ_w⁻¹/2 = R diag(1/σ_c², 1/σ_minor²) Rᵀ; √det Σ_w = σ_c σ_minor / 2.
        const double c = std::cos(footprint.axis_radians), s = std::sin(footprint.axis_radians);
        const double major = 1.0 / (footprint.sigma_um * footprint.sigma_um);
        const double minor = 1.0 / (footprint.sigma_minor_um * footprint.sigma_minor_um);
        weight.elliptical = true;
        weight.q_xx = c * c * major + s * s * minor;
        weight.q_xy = c * s * (major - minor);
        weight.q_yy = s * s * major + c * c * minor;
        weight.exponent_cutoff = 0.5 * kTruncationSigmas * kTruncationSigmas;
        const double major_sigma = footprint_weight_sigma_um(footprint);
        weight.cutoff_squared = kTruncationSigmas * kTruncationSigmas * major_sigma * major_sigma;
        weight.scale = 1.0 / (pi * footprint.sigma_um * footprint.sigma_minor_um);
    } else {
        const double sigma = footprint_weight_sigma_um(footprint);
        weight.inverse_two_variance = 0.5 / (sigma * sigma);
        weight.cutoff_squared = kTruncationSigmas * kTruncationSigmas * sigma * sigma;
        weight.scale = 1.0 / (2.0 * pi * sigma * sigma);
    }
    return weight;
}

// Image-plane points in pixel units: u along columns, v along rows (down).
struct Pixel {
    double u = 0.0;
    double v = 0.0;
};

// Where the normal of gradient (H_x, H_y) lands in pixel units: m = (−H_x, −H_y, 1)/|…| at disk
// point (m_x, m_y), column u = (m_x + 1)·N/2, row v = (1 − m_y)·N/2 (conventions.md).
[[gnu::always_inline]] inline Pixel normal_pixel(const SurfacePoint& point, double half_resolution) {
    const double inverse_norm = 1.0 / std::sqrt(1.0 + point.dh_dx * point.dh_dx + point.dh_dy * point.dh_dy);
    return {(1.0 - point.dh_dx * inverse_norm) * half_resolution, (1.0 + point.dh_dy * inverse_norm) * half_resolution};
}

// Subdivisions of a base cell: at least settings.refinement, and the least n whose sub-cells'
// stray, the cell's own (its centre's image against the bilinear blend of the corner images)
// over n², is within the tolerance: the stray falls as the square of the subdivision.
inline int subdivisions(const NormalDensitySettings& settings, Pixel p00, Pixel p10, Pixel p01, Pixel p11, Pixel centre) {
    const int n = settings.refinement;
    if (settings.tolerance_pixels <= 0.0) return n;
    const double stray = std::hypot(centre.u - 0.25 * (p00.u + p10.u + p01.u + p11.u),
                                    centre.v - 0.25 * (p00.v + p10.v + p01.v + p11.v));
    if (stray <= settings.tolerance_pixels * n * n) return n;
    const double needed = std::ceil(std::sqrt(stray / settings.tolerance_pixels));
    return static_cast<int>(std::min<double>(needed, kMaxRefinement));
}

}  // namespace glintscope
