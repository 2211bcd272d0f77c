// The exact normal density against closed forms (a plane, a sphere cap, a sinusoid's arcsine
// law), its normalisation, an independent dense-sampling estimate, its resolution consistency,
// its second-order convergence in the refinement and its independence of the thread count.
#include "normal_density/normal_density.hpp"

#include <gtest/gtest.h>

#include "relative_l2.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>

#include "glintscope/generate/generate.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"

#include "sampled_field.hpp"

namespace glintscope {
namespace {

constexpr double kPi = std::numbers::pi;

using testing::isotropic_field;
using testing::sampled_field;

double total_mass(const std::vector<double>& density, int resolution) {
    double sum = 0.0;
    for (double value : density) sum += value;
    return sum * disk_pixel_area(resolution);
}

using testing::relative_l2;

Footprint gaussian_at(Point2 centre, double sigma) {
    Footprint footprint;
    footprint.centre_um = centre;
    footprint.sigma_um = sigma;
    return footprint;
}

Footprint whole_field() {
    Footprint footprint;
    footprint.shape = FootprintShape::whole;
    return footprint;
}


TEST(NormalDensity, PlanePutsAllWeightInThePixelOfItsNormal) {
    const double a = 0.3, b = -0.2;
    const BicubicInterpolant surface(sampled_field(64, 64, 1.0, [&](double x, double y) { return a * x + b * y; }));
    const int n = 64;
    // Well inside the tile, away from the plane's wrap-around step.
    const std::vector<double> density = normal_density(surface, gaussian_at({32.0, 32.0}, 4.0), n, {});
    const double norm = std::sqrt(1.0 + a * a + b * b);
    const double mx = -a / norm, my = -b / norm;
    const int col = static_cast<int>(std::floor((mx + 1.0) * 0.5 * n));
    const int row = static_cast<int>(std::floor((1.0 - my) * 0.5 * n));
    EXPECT_NEAR(density[row * n + col] * disk_pixel_area(n), 1.0, 1e-7);
    EXPECT_NEAR(total_mass(density, n), 1.0, 1e-7);
}

// Mass of a normal distribution of mean μ and deviation σ over [lo, hi].
double normal_mass(double lo, double hi, double mean, double sigma) {
    return 0.5 * (std::erf((hi - mean) / (std::numbers::sqrt2 * sigma)) - std::erf((lo - mean) / (std::numbers::sqrt2 * sigma)));
}

TEST(NormalDensity, SphereCapUnderGaussianFootprintIsGaussianOfCentreOverRadius) {
    // On a cap H = √(R² − |s − o|²) the normal is (s − o)/R exactly, so the footprint weight (a
    // normalised Gaussian of σ_c/√2 about x_c) maps to a Gaussian of centre (x_c − o)/R and
    // deviation (σ_c/√2)/R on the projected disk.
    const double radius = 200.0;
    const Point2 origin{128.0, 128.0};
    const BicubicInterpolant surface(sampled_field(256, 256, 1.0, [&](double x, double y) {
        return std::sqrt(radius * radius - (x - origin.x) * (x - origin.x) - (y - origin.y) * (y - origin.y));
    }));
    const Point2 centre{origin.x + 20.0, origin.y - 10.0};
    const double sigma_c = 20.0;
    const int n = 128;
    const std::vector<double> density = normal_density(surface, gaussian_at(centre, sigma_c), n, {});
    const double sigma = sigma_c / std::numbers::sqrt2 / radius;
    std::vector<double> expected(density.size());
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const double x0 = c * 2.0 / n - 1.0, y1 = 1.0 - r * 2.0 / n;
            expected[r * n + c] = normal_mass(x0, x0 + 2.0 / n, (centre.x - origin.x) / radius, sigma) *
                                  normal_mass(y1 - 2.0 / n, y1, (centre.y - origin.y) / radius, sigma) /
                                  disk_pixel_area(n);
        }
    const double error = relative_l2(density, expected);
    RecordProperty("relative_l2", std::to_string(error));
    EXPECT_LT(error, 0.01);
}

TEST(NormalDensity, ParaboloidIsAGaussianInSlopeSpace) {
    // H = ½ a (x−x0)² + ½ b (y−y0)² + c (x−x0)(y−y0): the slope (H_x, H_y) = J (s − o) is linear in
    // position (J the Hessian), so the footprint weight (a normalised Gaussian of σ_w = σ_c/√2)
    // maps to a Gaussian in slope space of mean J (x_c − o) and covariance σ_w² J Jᵀ. On the
    // projected disk h_xy = −s/√(1 + |s|²), whose Jacobian is (1 + |s|²)⁻², so
    // D(h) = p(s) (1 + |s|²)². The bicubic reproduces quadratics exactly.
    const double a = 0.008, b = 0.006, c = 0.002;  // Hessian eigenvalues 0.0092, 0.0048
    const Point2 origin{118.0, 135.0}, centre{128.0, 128.0};
    const BicubicInterpolant surface(sampled_field(256, 256, 1.0, [&](double x, double y) {
        const double u = x - origin.x, v = y - origin.y;
        return 0.5 * a * u * u + 0.5 * b * v * v + c * u * v;
    }));
    const int n = 256;
    const std::vector<double> density = normal_density(surface, gaussian_at(centre, 10.0), n, {});
    const double sigma_w = 10.0 / std::numbers::sqrt2;
    const double mean_x = a * (centre.x - origin.x) + c * (centre.y - origin.y);
    const double mean_y = c * (centre.x - origin.x) + b * (centre.y - origin.y);
    // Covariance σ_w² J Jᵀ of the symmetric J = [[a, c], [c, b]].
    const double cxx = sigma_w * sigma_w * (a * a + c * c), cyy = sigma_w * sigma_w * (c * c + b * b);
    const double cxy = sigma_w * sigma_w * (a * c + c * b);
    const double det = cxx * cyy - cxy * cxy;
    std::vector<double> expected(density.size(), 0.0);
    for (int r = 0; r < n; ++r)
        for (int col = 0; col < n; ++col) {
            const DiskPoint h = disk_pixel_point(r, col, n);
            if (!inside_unit_disk(h)) continue;
            const double hz = std::sqrt(1.0 - h.x * h.x - h.y * h.y);
            const double sx = -h.x / hz - mean_x, sy = -h.y / hz - mean_y;
            const double quadratic = (cyy * sx * sx - 2.0 * cxy * sx * sy + cxx * sy * sy) / det;
            const double slope_density = std::exp(-0.5 * quadratic) / (2.0 * std::numbers::pi * std::sqrt(det));
            expected[r * n + col] = slope_density / std::pow(hz, 4);  // (1 + |s|²)² = 1/h_z⁴
        }
    const double error = relative_l2(density, expected);
    RecordProperty("relative_l2", std::to_string(error));
    EXPECT_LT(error, 0.01);
}

TEST(NormalDensity, RectangularBoxOfAParaboloidSpreadsTheSlopesOverEachSide) {
    // H = ½ a |s − o|²: the slope a (s − o) is uniform over the box's image, a rectangle of sides
    // a·W and a·H, so its variances are a²W²/12 and a²H²/12 (Dong 2015 measures 70 × 53 µm patches).
    const double a = 0.004;
    const Point2 origin{128.0, 128.0};
    const BicubicInterpolant surface(sampled_field(256, 256, 1.0, [&](double x, double y) {
        return 0.5 * a * ((x - origin.x) * (x - origin.x) + (y - origin.y) * (y - origin.y));
    }));
    Footprint box;
    box.shape = FootprintShape::box;
    box.centre_um = origin;
    box.size_um = 60.0;
    box.size_y_um = 30.0;
    const int n = 256;
    const std::vector<double> density = normal_density(surface, box, n, {});
    double mass = 0.0, var_x = 0.0, var_y = 0.0;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const DiskPoint h = disk_pixel_point(r, c, n);
            if (!inside_unit_disk(h)) continue;
            const double hz = std::sqrt(1.0 - h.x * h.x - h.y * h.y);
            const double m = density[r * n + c] * disk_pixel_area(n);
            mass += m;
            var_x += m * (h.x / hz) * (h.x / hz);
            var_y += m * (h.y / hz) * (h.y / hz);
        }
    EXPECT_NEAR(mass, 1.0, 1e-9);
    EXPECT_NEAR(var_x / (a * a * 60.0 * 60.0 / 12.0), 1.0, 0.01);
    EXPECT_NEAR(var_y / (a * a * 30.0 * 30.0 / 12.0), 1.0, 0.01);
    // The image's lattice runs along x and y: a turned box is refused, not drawn axis-aligned
    // (a quarter turn would otherwise swap the two variances above).
    box.axis_radians = 0.5 * std::numbers::pi;
    EXPECT_THROW(normal_density(surface, box, n, {}), Error);
}

TEST(NormalDensity, SinusoidOverWholePeriodsFollowsTheArcsineLawWithSharpEdges) {
    // H = A sin(2πx/Λ): the slope s = H_x is s_max cos(2πx/Λ), uniformly distributed in phase,
    // so its law is the arcsine law with CDF ½ + asin(s/s_max)/π, and all normals have m_y = 0.
    const double period = 64.0, s_max = 0.45;
    const double amplitude = s_max * period / (2.0 * kPi);
    const BicubicInterpolant surface(
        sampled_field(4, 256, 0.25, [&](double x, double) { return amplitude * std::sin(2.0 * kPi * x / period); }));
    const int n = 127;  // odd: m_y = 0 is the centre of row 63
    const std::vector<double> density = normal_density(surface, whole_field(), n, {});
    const auto cdf = [&](double m) {  // mass with m_x ≤ m; m_x = −s/√(1 + s²) and the law is even
        const double s = m / std::sqrt(1.0 - m * m);
        return 0.5 + std::asin(std::clamp(s / s_max, -1.0, 1.0)) / kPi;
    };
    double row_mass = 0.0, worst = 0.0;
    const double edge = s_max / std::sqrt(1.0 + s_max * s_max);
    for (int c = 0; c < n; ++c) {
        const double x0 = c * 2.0 / n - 1.0, x1 = x0 + 2.0 / n;
        const double mass = density[63 * n + c] * disk_pixel_area(n);
        row_mass += mass;
        worst = std::max(worst, std::abs(mass - (cdf(x1) - cdf(x0))));
        if (x0 > edge + 1e-3 || x1 < -edge - 1e-3) {
            EXPECT_EQ(mass, 0.0) << "column " << c;
        }
    }
    RecordProperty("worst_column_error", std::to_string(worst));
    EXPECT_NEAR(row_mass, 1.0, 1e-9);
    EXPECT_LT(worst, 2e-3);
    // Sharp caustic: the column holding the edge carries more than its inner neighbour.
    const int edge_col = static_cast<int>(std::floor((edge + 1.0) * 0.5 * n));
    EXPECT_GT(density[63 * n + edge_col], density[63 * n + edge_col - 1]);
}

// Area of the triangle (a, b, c) inside the pixel [col, col + 1] × [row, row + 1] (pixel units),
// by clipping it against the pixel's four sides (Sutherland–Hodgman) and the shoelace formula.
double overlap_with_pixel(std::vector<std::array<double, 2>> polygon, int row, int col) {
    const auto clip = [&](int axis, double bound, bool keep_above) {
        std::vector<std::array<double, 2>> kept;
        for (std::size_t k = 0; k < polygon.size(); ++k) {
            const auto& p = polygon[k];
            const auto& q = polygon[(k + 1) % polygon.size()];
            const bool p_in = keep_above ? p[axis] >= bound : p[axis] <= bound;
            const bool q_in = keep_above ? q[axis] >= bound : q[axis] <= bound;
            if (p_in) kept.push_back(p);
            if (p_in != q_in) {
                const double t = (bound - p[axis]) / (q[axis] - p[axis]);
                kept.push_back({p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])});
            }
        }
        polygon = kept;
    };
    clip(0, col, true);
    clip(0, col + 1.0, false);
    clip(1, row, true);
    clip(1, row + 1.0, false);
    double twice_area = 0.0;
    for (std::size_t k = 0; k < polygon.size(); ++k) {
        const auto& p = polygon[k];
        const auto& q = polygon[(k + 1) % polygon.size()];
        twice_area += p[0] * q[1] - q[0] * p[1];
    }
    return 0.5 * std::abs(twice_area);
}

// The normal density of a box footprint (its lattice aligned with the box's corner) with every
// texel cut into `cuts` × `cuts` undivided cells, computed independently: by construction the
// method's image is each cell's two triangles (p00, p10, p11) and (p00, p11, p01) mapped
// affinely through their corners' normals, each spreading its weight (equal under a box)
// uniformly; here every image triangle is clipped against every pixel it touches.
std::vector<double> clipped_triangle_density(const BicubicInterpolant& surface, const Footprint& box, int cuts, int n) {
    const int cells = static_cast<int>(box.size_um) * cuts;  // 1 µm texels
    const double step = 1.0 / cuts;
    std::vector<std::array<double, 2>> corner((cells + 1) * (cells + 1));
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i) {
            const SurfacePoint point = surface.evaluate(box.centre_um.x - 0.5 * box.size_um + i * step,
                                                        box.centre_um.y - 0.5 * box.size_um + j * step);
            const double inverse_norm = 1.0 / std::sqrt(1.0 + point.dh_dx * point.dh_dx + point.dh_dy * point.dh_dy);
            corner[j * (cells + 1) + i] = {(1.0 - point.dh_dx * inverse_norm) * 0.5 * n,
                                           (1.0 + point.dh_dy * inverse_norm) * 0.5 * n};
        }
    std::vector<double> expected(static_cast<std::size_t>(n) * n, 0.0);
    const auto deposit = [&](const std::vector<std::array<double, 2>>& triangle) {
        const double twice_area = std::abs((triangle[1][0] - triangle[0][0]) * (triangle[2][1] - triangle[0][1]) -
                                           (triangle[2][0] - triangle[0][0]) * (triangle[1][1] - triangle[0][1]));
        int r0 = n, r1 = 0, c0 = n, c1 = 0;
        for (const auto& p : triangle) {
            c0 = std::min(c0, static_cast<int>(p[0])), c1 = std::max(c1, std::min(n - 1, static_cast<int>(p[0])));
            r0 = std::min(r0, static_cast<int>(p[1])), r1 = std::max(r1, std::min(n - 1, static_cast<int>(p[1])));
        }
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c)
                expected[r * n + c] += overlap_with_pixel(triangle, r, c) / (0.5 * twice_area);  // equal masses
    };
    for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
            const auto& p00 = corner[j * (cells + 1) + i];
            const auto& p10 = corner[j * (cells + 1) + i + 1];
            const auto& p01 = corner[(j + 1) * (cells + 1) + i];
            const auto& p11 = corner[(j + 1) * (cells + 1) + i + 1];
            deposit({p00, p10, p11});
            deposit({p00, p11, p01});
        }
    double total = 0.0;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            if (!inside_unit_disk(disk_pixel_point(r, c, n))) expected[r * n + c] = 0.0;
            total += expected[r * n + c];
        }
    for (double& value : expected) value /= total * disk_pixel_area(n);
    return expected;
}

TEST(NormalDensity, IsTheExactCoverageOfTheCornerImageTriangles) {
    // The rasteriser's edges, second differences, row or column choice and corner potentials
    // must reproduce the clipped triangles to rounding, folds included (the random field has
    // saddles, where image triangles flip), from triangles inside one pixel (64²) to edges
    // crossing dozens (512²).
    const BicubicInterpolant surface(isotropic_field(128));
    Footprint box;
    box.shape = FootprintShape::box;
    box.size_um = 40.0;
    box.centre_um = {64.0, 60.0};
    for (const int n : {64, 512}) {
        const std::vector<double> density = normal_density(surface, box, n, {1, 0.0, 0.0});
        const double error = relative_l2(density, clipped_triangle_density(surface, box, 1, n));
        RecordProperty("relative_l2_" + std::to_string(n), ::testing::PrintToString(error));  // 3e-12, 7e-11
        EXPECT_LT(error, 1e-9) << "at " << n << "²";
    }
}

TEST(NormalDensity, GridsFollowTheNormalsFromTheRimInward) {
    // The coverage grids cover only the box of the normals each stripe of rows has reached,
    // grown as they reach further. Here ∂H/∂y = 12 sin(2πy/128): the box's lower half (y from
    // 16 to 64, one stripe) has its normals from within 0.4° of one rim (slope 12) to the centre,
    // its upper half (the other stripe) the same towards the opposite rim, so the two stripes'
    // boxes do not overlap, and each grows from its first block of rows to its second and
    // between subdivided cells (2 × 2 per texel); a gentler sine along x spreads the normals
    // sideways. Every triangle must land where the clipped triangles put it, to the rounding of
    // the difference sums, which grows with the density of the squeezed image triangles near the
    // rim (1.4e-9 here, as over the whole disk before the grids had boxes).
    const double period = 128.0;
    const BicubicInterpolant surface(sampled_field(128, 128, 1.0, [&](double x, double y) {
        return -12.0 * period / (2.0 * kPi) * std::cos(2.0 * kPi * y / period) + 3.0 * std::sin(2.0 * kPi * x / period);
    }));
    Footprint box;
    box.shape = FootprintShape::box;
    box.size_um = 96.0;
    box.centre_um = {64.0, 64.0};
    const int n = 128;
    const std::vector<double> density = normal_density(surface, box, n, {2, 0.0, 0.0});
    const double error = relative_l2(density, clipped_triangle_density(surface, box, 2, n));
    RecordProperty("relative_l2", ::testing::PrintToString(error));
    EXPECT_LT(error, 1e-8);
}

TEST(NormalDensity, IsNormalisedOnARoughSurface) {
    const BicubicInterpolant surface(isotropic_field(256));
    for (const Footprint& footprint : {gaussian_at({100.0, 50.0}, 10.0), whole_field()}) {
        const std::vector<double> density = normal_density(surface, footprint, 128, {});
        EXPECT_NEAR(total_mass(density, 128), 1.0, 1e-6);
    }
}

TEST(NormalDensity, AgreesWithDenseSamplingOnTheIsotropicBuiltin) {
    // Independent estimate: 8×8 gradient samples per texel over a 384 µm box, binned.
    const BicubicInterpolant surface(generate_builtin("isotropic"));
    const int n = 128, per_axis = 8, side = 384;
    Footprint box;
    box.shape = FootprintShape::box;
    box.centre_um = {300.0, 700.0};
    box.size_um = side;
    const std::vector<double> exact = normal_density(surface, box, n, {});
    std::vector<double> binned(exact.size(), 0.0);
    const int samples = side * per_axis;
    std::vector<SurfacePoint> row(samples);
    const double step = 1.0 / per_axis;
    const double x0 = box.centre_um.x - 0.5 * side, y0 = box.centre_um.y - 0.5 * side;
    for (int j = 0; j < samples; ++j) {
        surface.evaluate_grid(x0 + 0.5 * step, y0 + (j + 0.5) * step, step, samples, 1, row.data());
        for (const SurfacePoint& p : row) {
            const double norm = std::sqrt(1.0 + p.dh_dx * p.dh_dx + p.dh_dy * p.dh_dy);
            const int c = static_cast<int>(std::floor((1.0 - p.dh_dx / norm) * 0.5 * n));
            const int r = static_cast<int>(std::floor((1.0 + p.dh_dy / norm) * 0.5 * n));
            binned[r * n + c] += 1.0;
        }
    }
    const double scale = 1.0 / (double(samples) * samples * disk_pixel_area(n));
    for (double& value : binned) value *= scale;
    const double error = relative_l2(exact, binned);
    RecordProperty("relative_l2", std::to_string(error));
    EXPECT_LT(error, 0.01);
}

TEST(NormalDensity, FinerImageAveragedDownMatches) {
    const BicubicInterpolant surface(isotropic_field(256));
    const Footprint footprint = gaussian_at({128.0, 128.0}, 10.0);
    const std::vector<double> coarse = normal_density(surface, footprint, 128, {});
    const std::vector<double> fine = normal_density(surface, footprint, 256, {});
    std::vector<double> averaged(coarse.size());
    for (int r = 0; r < 128; ++r)
        for (int c = 0; c < 128; ++c)
            averaged[r * 128 + c] = 0.25 * (fine[2 * r * 256 + 2 * c] + fine[2 * r * 256 + 2 * c + 1] +
                                            fine[(2 * r + 1) * 256 + 2 * c] + fine[(2 * r + 1) * 256 + 2 * c + 1]);
    const double error = relative_l2(averaged, coarse);
    RecordProperty("relative_l2", std::to_string(error));
    EXPECT_LT(error, 0.01);
}

TEST(NormalDensity, ErrorFallsAtLeastByHalfPerRefinementDoubling) {
    const BicubicInterpolant surface(isotropic_field(128));
    const Footprint footprint = gaussian_at({64.0, 64.0}, 10.0);
    const int n = 128;
    const std::vector<double> reference = normal_density(surface, footprint, n, {16, 0.0, 0.0});
    double previous = 0.0;
    for (int refinement : {1, 2, 4}) {
        const double error = relative_l2(normal_density(surface, footprint, n, {refinement, 0.0, 0.0}), reference);
        RecordProperty("error_refinement_" + std::to_string(refinement), std::to_string(error));
        if (refinement > 1) {
            EXPECT_LT(error, 0.5 * previous) << "refinement " << refinement;
        }
        previous = error;
    }
    // The adaptive default reaches the accuracy of a uniform refinement well beyond 4.
    const double adaptive = relative_l2(normal_density(surface, footprint, n, {}), reference);
    RecordProperty("error_adaptive_default", std::to_string(adaptive));
    EXPECT_LT(adaptive, 0.01);
}

TEST(NormalDensity, IntrinsicRoughnessBlursAPlaneIntoAGaussianOfThatWidth) {
    const BicubicInterpolant surface(sampled_field(32, 32, 1.0, [](double, double) { return 0.0; }));
    const int n = 128;
    const double roughness = 0.05;
    const std::vector<double> density = normal_density(surface, whole_field(), n, {1, 0.05, roughness});
    double mass = 0.0, second = 0.0;
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, n);
            mass += density[r * n + c] * disk_pixel_area(n);
            second += density[r * n + c] * disk_pixel_area(n) * p.x * p.x;
        }
    EXPECT_NEAR(mass, 1.0, 1e-9);
    // The flat NDF sits on the corner of four pixels; the blur's variance adds the pixel's (1/12 px²)
    // of the initial split: σ² = roughness² + (2/N)²/4 (the mass sits ½ px from the centres).
    const double expected = roughness * roughness + 0.25 * disk_pixel_area(n);
    EXPECT_NEAR(second / expected, 1.0, 0.01);
}

TEST(NormalDensity, SameBitsForOneAndFourThreads) {
    const BicubicInterpolant surface(isotropic_field(128));
    const Footprint footprint = gaussian_at({30.0, 90.0}, 10.0);
    const std::vector<double> one = with_threads(1, [&] { return normal_density(surface, footprint, 96, {}); });
    const std::vector<double> four = with_threads(4, [&] { return normal_density(surface, footprint, 96, {}); });
    EXPECT_EQ(one, four);
}

}  // namespace
}  // namespace glintscope
