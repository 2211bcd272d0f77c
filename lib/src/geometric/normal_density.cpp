#include "geometric/normal_density.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "glintscope/error.hpp"
#include "glintscope/parallel.hpp"
#include "glintscope/text_format.hpp"

namespace glintscope {
namespace {

// Cell lattice over the integration domain: corners (x0 + i·step, y0 + j·step), 0 ≤ i ≤ nx,
// 0 ≤ j ≤ ny, on the periodically tiled surface.
struct Lattice {
    double x0 = 0.0;
    double y0 = 0.0;
    double step = 0.0;
    long long nx = 0;
    long long ny = 0;
};

// The footprint weight of a surface element at s (per µm²), zero outside the truncated support.
struct Weight {
    FootprintShape shape = FootprintShape::whole;
    Point2 centre;
    double inverse_two_variance = 0.0;  // Gaussian: 1/(2σ_w²)
    double cutoff_squared = 0.0;        // Gaussian: (kTruncationSigmas·σ_w)²
    double scale = 0.0;                 // normalisation: 1/(2πσ_w²), 1/side², 1/(W·H)

    double operator()(double x, double y) const {
        if (shape != FootprintShape::gaussian) return scale;
        const double r2 = (x - centre.x) * (x - centre.x) + (y - centre.y) * (y - centre.y);
        return r2 > cutoff_squared ? 0.0 : scale * std::exp(-r2 * inverse_two_variance);
    }
};

// First lattice index at or below `from` and the count of cells up to `to`, for a lattice
// through the sample positions (k + ½)·dx with step h.
void aligned_axis(double from, double to, double texel, double step, double& origin, long long& count) {
    const double first = std::floor((from - 0.5 * texel) / step);
    const double last = std::ceil((to - 0.5 * texel) / step);
    origin = 0.5 * texel + first * step;
    count = static_cast<long long>(last - first);
}

// The base lattice: one cell per texel, aligned with the samples (a box: with its edges, so
// the box's weight is integrated exactly); cells are subdivided further where needed.
Lattice lattice_for(const BicubicInterpolant& surface, const Footprint& footprint) {
    const double texel = surface.texel_um();
    Lattice lattice;
    lattice.step = texel;
    if (footprint.shape == FootprintShape::whole) {
        lattice.x0 = lattice.y0 = 0.5 * texel;
        lattice.nx = surface.cols();
        lattice.ny = surface.rows();
    } else if (footprint.shape == FootprintShape::box) {
        const double side = footprint.size_um;
        lattice.nx = lattice.ny = static_cast<long long>(std::ceil(side / texel));
        lattice.step = side / static_cast<double>(lattice.nx);
        lattice.x0 = footprint.centre_um.x - 0.5 * side;
        lattice.y0 = footprint.centre_um.y - 0.5 * side;
    } else {
        const double reach = kTruncationSigmas * footprint_weight_sigma_um(footprint);
        aligned_axis(footprint.centre_um.x - reach, footprint.centre_um.x + reach, texel, texel, lattice.x0, lattice.nx);
        aligned_axis(footprint.centre_um.y - reach, footprint.centre_um.y + reach, texel, texel, lattice.y0, lattice.ny);
    }
    return lattice;
}

Weight weight_for(const BicubicInterpolant& surface, const Footprint& footprint) {
    Weight weight;
    weight.shape = footprint.shape;
    weight.centre = footprint.centre_um;
    if (footprint.shape == FootprintShape::whole) {
        weight.scale = 1.0 / (surface.cols() * surface.texel_um() * surface.rows() * surface.texel_um());
    } else if (footprint.shape == FootprintShape::box) {
        weight.scale = 1.0 / (footprint.size_um * footprint.size_um);
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

// Pixel coordinates of normals lie in [0, N]: for them truncation is the floor, and anything
// below 0 clamps to 0 either way (std::floor is a library call in the portable build).
int clamp_index(double coordinate, int resolution) {
    return std::clamp(static_cast<int>(coordinate), 0, resolution - 1);
}

// Pixel masses kept as differences along each row (N + 1 entries a row): a mass m in pixel c
// is +m at c and −m at c + 1, and a running sum along the row (resolve) turns them back into
// masses. This lets a polygon deposit its exact coverage through its edges alone: an edge adds
// the signed area between itself and the right end of the row, which the running sum spreads.
struct RowDifferences {
    int resolution = 0;
    double* data = nullptr;  // resolution rows × (resolution + 1)

    void add(int row, int col, double mass) const {
        double* at = data + static_cast<std::size_t>(row) * (resolution + 1) + col;
        at[0] += mass;
        at[1] -= mass;
    }
    void add_right_of(int row, int col, double fraction_right, double signed_height) const {
        double* at = data + static_cast<std::size_t>(row) * (resolution + 1) + col;
        at[0] += signed_height * fraction_right;
        at[1] += signed_height * (1.0 - fraction_right);
    }
};

// The directed edge a → b, weighted by `density`: in every pixel row it crosses, the area of
// each pixel right of the edge, signed by the edge's direction in v. Summed over a closed
// polygon's edges this is ± the polygon's exact overlap with each pixel (the signed-area
// coverage of scanline rasterisers).
[[gnu::always_inline]] inline void add_edge(const RowDifferences& rows, Pixel a, Pixel b, double density) {
    if (a.v == b.v) return;
    const int n = rows.resolution;
    const double v_low = std::min(a.v, b.v), v_high = std::max(a.v, b.v);
    const double direction = b.v > a.v ? density : -density;
    const int row_first = clamp_index(v_low, n), row_last = clamp_index(v_high, n);
    if (row_first == row_last) {
        // Within one pixel row and column (most edges of small image triangles): no clipping.
        const double left = std::min(a.u, b.u), right = std::max(a.u, b.u);
        const int first = clamp_index(left, n);
        if (first == clamp_index(right, n)) {
            rows.add_right_of(row_first, first, first + 1.0 - 0.5 * (left + right), direction * (v_high - v_low));
            return;
        }
    }
    const double du_dv = (b.u - a.u) / (b.v - a.v);
    for (int row = row_first; row <= row_last; ++row) {
        const double v0 = std::max(v_low, double(row)), v1 = std::min(v_high, row + 1.0);
        if (v1 <= v0) continue;
        const double u0 = a.u + (v0 - a.v) * du_dv, u1 = a.u + (v1 - a.v) * du_dv;
        const double left = std::min(u0, u1), right = std::max(u0, u1);
        const double height = direction * (v1 - v0);
        const int first = clamp_index(left, n), last = clamp_index(right, n);
        if (first == last) {
            rows.add_right_of(row, first, first + 1.0 - 0.5 * (left + right), height);
            continue;
        }
        // Split at the column edges; each piece's height is its share of the u extent.
        for (int col = first; col <= last; ++col) {
            const double piece_left = std::max(left, double(col)), piece_right = std::min(right, col + 1.0);
            if (piece_right <= piece_left) continue;
            rows.add_right_of(row, col, col + 1.0 - 0.5 * (piece_left + piece_right),
                              height * (piece_right - piece_left) / (right - left));
        }
    }
}

// A triangle whose image collapsed onto a line (a surface that is cylindrical there, like a
// grating, or a fold seen edge-on): the uniform triangle's image on the line has the tent
// density of its 1-D marginal, rising from the first to the middle corner and falling to the
// last, with cumulative mass (t − t0)²/((t2 − t0)(t1 − t0)) up to t1 and 1 − (t2 − t)²/((t2 −
// t0)(t2 − t1)) beyond. Each stretch between pixel-edge crossings gets its exact share.
void deposit_segment(const RowDifferences& rows, Pixel a, Pixel b, Pixel c, double mass) {
    const int n = rows.resolution;
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
[[gnu::always_inline]] inline bool deposit_small_triangle(const RowDifferences& rows, Pixel a, Pixel b, Pixel c, double mass, double& density) {
    const int n = rows.resolution;
    const int c0 = clamp_index(std::min({a.u, b.u, c.u}), n);
    const int c1 = clamp_index(std::max({a.u, b.u, c.u}), n);
    const int r0 = clamp_index(std::min({a.v, b.v, c.v}), n);
    const int r1 = clamp_index(std::max({a.v, b.v, c.v}), n);
    if (c0 == c1 && r0 == r1) {
        rows.add(r0, c0, mass);
        return true;
    }
    const double cross = (b.u - a.u) * (c.v - a.v) - (c.u - a.u) * (b.v - a.v);
    const double extent = std::max(c1 - c0, r1 - r0) + 1.0;
    if (std::abs(cross) < 2e-9 * extent * extent) {
        deposit_segment(rows, a, b, c, mass);
        return true;
    }
    density = -2.0 * mass / cross;
    return false;
}

// Where the normal of gradient (H_x, H_y) lands in pixel units: m = (−H_x, −H_y, 1)/|…| at disk
// point (m_x, m_y), column u = (m_x + 1)·N/2, row v = (1 − m_y)·N/2 (conventions.md).
Pixel normal_pixel(const SurfacePoint& point, double half_resolution) {
    const double inverse_norm = 1.0 / std::sqrt(1.0 + point.dh_dx * point.dh_dx + point.dh_dy * point.dh_dy);
    return {(1.0 - point.dh_dx * inverse_norm) * half_resolution, (1.0 + point.dh_dy * inverse_norm) * half_resolution};
}

constexpr long long kRowsPerEvaluation = 32;

// A grid of cols × rows cells of side h from (x, y), corner images p[b·stride + a] (b along y):
// two triangles per cell, (p00, p10, p11) and (p00, p11, p01), each carrying the weight at its
// centroid times its area h²/2, spread uniformly over its image; each edge shared by two
// triangles is rasterised once with the difference of their densities (add_edge is linear in the
// density): 3 edges a cell instead of 6, plus the grid's border. `densities` is scratch space.
[[gnu::always_inline]] inline void deposit_grid(const RowDifferences& rows, const Weight& weight, double x, double y,
                                                double h, int cols, int rows_of_cells, const Pixel* p, std::size_t stride,
                                                std::vector<double>& densities) {
    const std::size_t cells = static_cast<std::size_t>(cols) * rows_of_cells;
    densities.assign(2 * cells, 0.0);
    double* lower = densities.data();          // triangle (p00, p10, p11) of cell (a, b)
    double* upper = densities.data() + cells;  // triangle (p00, p11, p01)
    const double half_area = 0.5 * h * h;
    for (int b = 0; b < rows_of_cells; ++b)
        for (int a = 0; a < cols; ++a) {
            const Pixel p00 = p[b * stride + a], p10 = p[b * stride + a + 1];
            const Pixel p01 = p[(b + 1) * stride + a], p11 = p[(b + 1) * stride + a + 1];
            const double xa = x + a * h, yb = y + b * h;
            const double lower_mass = half_area * weight(xa + h * (2.0 / 3.0), yb + h / 3.0);
            const double upper_mass = half_area * weight(xa + h / 3.0, yb + h * (2.0 / 3.0));
            if (lower_mass > 0.0) deposit_small_triangle(rows, p00, p10, p11, lower_mass, lower[b * cols + a]);
            if (upper_mass > 0.0) deposit_small_triangle(rows, p00, p11, p01, upper_mass, upper[b * cols + a]);
        }
    for (int b = 0; b < rows_of_cells; ++b)
        for (int a = 0; a < cols; ++a) {
            const Pixel p00 = p[b * stride + a], p10 = p[b * stride + a + 1], p01 = p[(b + 1) * stride + a];
            const Pixel p11 = p[(b + 1) * stride + a + 1];
            const double d_lower = lower[b * cols + a], d_upper = upper[b * cols + a];
            // The diagonal: the lower triangle's p11 → p00 and the upper's p00 → p11.
            if (d_upper != d_lower) add_edge(rows, p00, p11, d_upper - d_lower);
            // The bottom: this lower triangle's p00 → p10 and, reversed, the top of the cell below.
            const double bottom = d_lower - (b > 0 ? upper[(b - 1) * cols + a] : 0.0);
            if (bottom != 0.0) add_edge(rows, p00, p10, bottom);
            // The left: the left cell's lower p10 → p11 and, reversed, this upper's p01 → p00.
            const double left = (a > 0 ? lower[b * cols + a - 1] : 0.0) - d_upper;
            if (left != 0.0) add_edge(rows, p00, p01, left);
            if (b == rows_of_cells - 1 && d_upper != 0.0) add_edge(rows, p11, p01, d_upper);  // the top row's tops
            if (a == cols - 1 && d_lower != 0.0) add_edge(rows, p10, p11, d_lower);           // the right column's rights
        }
}

// Subdivisions of a base cell: at least settings.refinement, and the least n whose sub-cells'
// stray, the cell's own (its centre's image against the bilinear blend of the corner images)
// over n², is within the tolerance: the stray falls as the square of the subdivision.
int subdivisions(const NormalDensitySettings& settings, Pixel p00, Pixel p10, Pixel p01, Pixel p11, Pixel centre) {
    const int n = settings.refinement;
    if (settings.tolerance_pixels <= 0.0) return n;
    const double stray = std::hypot(centre.u - 0.25 * (p00.u + p10.u + p01.u + p11.u),
                                    centre.v - 0.25 * (p00.v + p10.v + p01.v + p11.v));
    if (stray <= settings.tolerance_pixels * n * n) return n;
    const double needed = std::ceil(std::sqrt(stray / settings.tolerance_pixels));
    return static_cast<int>(std::min<double>(needed, kMaxRefinement));
}

// Accumulates the base-cell rows [j_begin, j_end) into `rows`.
// Compiled twice, for AVX2 + FMA and for the portable baseline (the hot loops above are inlined).
__attribute__((target_clones("arch=x86-64-v3", "default"))) void accumulate_rows(const BicubicInterpolant& surface, const Lattice& lattice, const Weight& weight,
                     const NormalDensitySettings& settings, long long j_begin, long long j_end, const RowDifferences& rows) {
    const int resolution = rows.resolution;
    const long long corners_x = lattice.nx + 1;
    const double half_resolution = 0.5 * resolution;
    const double h = lattice.step;
    std::vector<SurfacePoint> corners, centres, sub;
    std::vector<Pixel> pixels, centre_pixels, sub_pixels;
    std::vector<double> densities;
    const bool adaptive = settings.tolerance_pixels > 0.0;
    for (long long j0 = j_begin; j0 < j_end; j0 += kRowsPerEvaluation) {
        const long long block_rows = std::min(kRowsPerEvaluation, j_end - j0);
        corners.resize(static_cast<std::size_t>(corners_x * (block_rows + 1)));
        const double y_block = lattice.y0 + j0 * h;
        surface.evaluate_grid(lattice.x0, y_block, h, static_cast<int>(corners_x), static_cast<int>(block_rows + 1),
                              corners.data());
        pixels.resize(corners.size());
        for (std::size_t k = 0; k < corners.size(); ++k) pixels[k] = normal_pixel(corners[k], half_resolution);
        if (!adaptive && settings.refinement == 1) {
            // Every cell is undivided: the block is one grid, its inner edges shared.
            deposit_grid(rows, weight, lattice.x0, y_block, h, static_cast<int>(lattice.nx), static_cast<int>(block_rows),
                         pixels.data(), static_cast<std::size_t>(corners_x), densities);
            continue;
        }
        // The cell centres' images, which decide the adaptive subdivision.
        centre_pixels.assign(adaptive ? static_cast<std::size_t>(lattice.nx * block_rows) : 0, Pixel{});
        if (adaptive) {
            centres.resize(centre_pixels.size());
            surface.evaluate_grid(lattice.x0 + 0.5 * h, y_block + 0.5 * h, h, static_cast<int>(lattice.nx),
                                  static_cast<int>(block_rows), centres.data());
            for (std::size_t k = 0; k < centres.size(); ++k) centre_pixels[k] = normal_pixel(centres[k], half_resolution);
        }
        for (long long j = 0; j < block_rows; ++j) {
            const double y = y_block + j * h;
            const Pixel* lower = &pixels[static_cast<std::size_t>(j * corners_x)];
            const Pixel* upper = lower + corners_x;
            for (long long i = 0; i < lattice.nx; ++i) {
                const double x = lattice.x0 + i * h;
                const int n = adaptive ? subdivisions(settings, lower[i], lower[i + 1], upper[i], upper[i + 1],
                                                      centre_pixels[static_cast<std::size_t>(j * lattice.nx + i)])
                                       : settings.refinement;
                if (n == 1) {
                    const Pixel cell[4] = {lower[i], lower[i + 1], upper[i], upper[i + 1]};
                    deposit_grid(rows, weight, x, y, h, 1, 1, cell, 2, densities);
                    continue;
                }
                const double step = h / n;
                sub.resize(static_cast<std::size_t>(n + 1) * (n + 1));
                sub_pixels.resize(sub.size());
                surface.evaluate_grid(x, y, step, n + 1, n + 1, sub.data());
                for (std::size_t k = 0; k < sub.size(); ++k) sub_pixels[k] = normal_pixel(sub[k], half_resolution);
                deposit_grid(rows, weight, x, y, step, n, n, sub_pixels.data(), static_cast<std::size_t>(n) + 1, densities);
            }
        }
    }
}

// Fixed work split, independent of the thread count, so the ordered sum is bit-identical.
constexpr long long kStripes = 16;

}  // namespace

double footprint_weight_sigma_um(const Footprint& footprint) {
    // |w|²/A_c with w of standard deviation σ_c is a normalised Gaussian of σ_c/√2.
    return footprint.sigma_um / std::numbers::sqrt2;
}

std::vector<double> normal_density(const BicubicInterpolant& surface, const Footprint& footprint, int resolution,
                                   const NormalDensitySettings& settings) {
    if (resolution < 1 || resolution > 8192)
        throw Error("NDF resolution must be between 1 and 8192, got " + std::to_string(resolution));
    if (settings.refinement < 1 || settings.refinement > kMaxRefinement)
        throw Error("NDF refinement must be between 1 and 64, got " + std::to_string(settings.refinement));
    if (!(settings.intrinsic_roughness >= 0.0 && settings.intrinsic_roughness <= 1.0))
        throw Error("intrinsic_roughness must be between 0 and 1 radian, got " +
                    shortest_text(settings.intrinsic_roughness));
    if (!(settings.tolerance_pixels >= 0.0))
        throw Error("NDF tolerance must be a non-negative number of pixels, got " + shortest_text(settings.tolerance_pixels));
    const Lattice lattice = lattice_for(surface, footprint);
    const Weight weight = weight_for(surface, footprint);
    const std::size_t pixels = static_cast<std::size_t>(resolution) * resolution;
    const std::size_t stride = static_cast<std::size_t>(resolution) + 1;
    const long long stripes = std::min(kStripes, lattice.ny);
    std::vector<std::vector<double>> partial(static_cast<std::size_t>(stripes));
    parallel_for(static_cast<std::size_t>(stripes), 1, [&](std::size_t begin, std::size_t end) {
        for (std::size_t s = begin; s < end; ++s) {
            partial[s].assign(resolution * stride, 0.0);
            const long long j_begin = lattice.ny * static_cast<long long>(s) / stripes;
            const long long j_end = lattice.ny * static_cast<long long>(s + 1) / stripes;
            accumulate_rows(surface, lattice, weight, settings, j_begin, j_end, {resolution, partial[s].data()});
        }
    });
    // Stripes summed in order, then each row's running sum; rounding leaves ~1e-16 of the row's
    // masses where the true value is 0, and negative such residues are clipped.
    std::vector<double> density(pixels, 0.0);
    parallel_for(static_cast<std::size_t>(resolution), 16, [&](std::size_t begin, std::size_t end) {
        for (std::size_t r = begin; r < end; ++r) {
            double running = 0.0;
            for (std::size_t c = 0; c < static_cast<std::size_t>(resolution); ++c) {
                for (const auto& stripe : partial) running += stripe[r * stride + c];
                // conventions.md: a pixel whose centre lies outside the disk holds no normal;
                // the sliver of rim mass it caught (normals within a pixel of vertical) is dropped.
                const bool inside = inside_unit_disk(disk_pixel_point(static_cast<int>(r), static_cast<int>(c), resolution));
                density[r * resolution + c] = inside ? std::max(0.0, running) : 0.0;
            }
        }
    });
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
