// The directional geometry of the discrete model: Jakob 2014 eq. 8's conic is the set of normals
// that reflect ω_i into the cone about ω_o; triangles split into four of a quarter the area;
// the overlap classes and the inside share agree with brute-force sampling.
#include "methods/discrete/spherical_geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/counter_rng.hpp"

namespace glintscope {
namespace {

Vec3 random_direction(const CounterRng& rng, std::uint64_t i) {
    const double z = rng.uniform(2 * i), phi = 2.0 * pi * rng.uniform(2 * i + 1);
    const double s = std::sqrt(1.0 - z * z);
    return {s * std::cos(phi), s * std::sin(phi), z};
}

bool reflects_into_cone(Vec3 m, Vec3 omega_i, Vec3 omega_o, double gamma) {
    if (dot(m, omega_i) <= 0.0) return false;
    const Vec3 reflected = 2.0 * dot(m, omega_i) * m - omega_i;  // Jakob 2014 eq. 7
    return dot(reflected, omega_o) > std::cos(gamma);
}

TEST(SphericalConic, HoldsExactlyTheNormalsThatReflectIntoTheCone) {
    const CounterRng rng(7, 1);
    const Vec3 omega_i = direction_from_spherical(0.5, 0.2);
    const Vec3 omega_o = direction_from_spherical(0.9, 2.5);
    const SphericalConic conic = spherical_conic(omega_i, omega_o, 0.3);
    int inside = 0, disagreements = 0;
    for (std::uint64_t k = 0; k < 200000; ++k) {
        const Vec3 m = random_direction(rng, k);
        const bool expected = reflects_into_cone(m, omega_i, omega_o, 0.3);
        inside += expected ? 1 : 0;
        disagreements += expected != contains(conic, m) ? 1 : 0;
    }
    EXPECT_GT(inside, 100);
    EXPECT_EQ(disagreements, 0);
    EXPECT_TRUE(conic.elliptic);
    EXPECT_TRUE(contains(conic, conic.axis));
}

TEST(SphericalConic, EqualDirectionsGiveTheCapOfHalfTheConeAngle) {
    const Vec3 h = direction_from_spherical(0.4, 1.0);
    const SphericalConic conic = spherical_conic(h, h, 0.2);
    const Vec3 side = normalize(Vec3{-h.y, h.x, 0.0});
    EXPECT_TRUE(contains(conic, std::cos(0.099) * h + std::sin(0.099) * side));
    EXPECT_FALSE(contains(conic, std::cos(0.101) * h + std::sin(0.101) * side));
}

TEST(SphericalTriangle, QuadrantsTileTheHemisphereAndChildrenTileTheirParent) {
    double total = 0.0;
    for (const SphericalTriangle& quadrant : hemisphere_quadrants()) {
        total += solid_angle(quadrant);
        double children = 0.0;
        for (const SphericalTriangle& child : split(quadrant)) children += solid_angle(child);
        EXPECT_NEAR(children, solid_angle(quadrant), 1e-12);
        EXPECT_TRUE(contains(quadrant, centre(quadrant)));
    }
    EXPECT_NEAR(total, 2.0 * pi, 1e-12);
}

// Brute force: the share of random points of the triangle inside the conic, against the class and
// the planar estimate of the share.
TEST(SphericalConic, OverlapClassesAndInsideShareMatchSampling) {
    const Vec3 omega_i = direction_from_spherical(0.3, 0.0);
    const Vec3 omega_o = direction_from_spherical(0.25, pi);
    const SphericalConic conic = spherical_conic(omega_i, omega_o, 0.02);
    // Cells around the conic at a depth where they are about its size: walk down from a quadrant.
    const std::array<SphericalTriangle, 4> quadrants = hemisphere_quadrants();
    std::vector<SphericalTriangle> cells(quadrants.begin(), quadrants.end());
    for (int level = 0; level < 7; ++level) {
        std::vector<SphericalTriangle> next;
        for (const SphericalTriangle& cell : cells)
            if (overlap(conic, cell) != Overlap::disjoint)
                for (const SphericalTriangle& child : split(cell)) next.push_back(child);
        cells = next;
    }
    const CounterRng rng(3, 2);
    int partial = 0;
    for (const SphericalTriangle& cell : cells) {
        // Uniform barycentric points, normalised: the density differs from uniform on the sphere
        // by far less than the tolerance for triangles this small.
        int inside = 0;
        const int samples = 40000;
        for (int k = 0; k < samples; ++k) {
            double a = rng.uniform(2 * k), b = rng.uniform(2 * k + 1);
            if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
            inside += contains(conic, normalize(cell.v[0] + a * (cell.v[1] - cell.v[0]) + b * (cell.v[2] - cell.v[0]))) ? 1 : 0;
        }
        const double sampled = static_cast<double>(inside) / samples;
        switch (overlap(conic, cell)) {
            case Overlap::inside: EXPECT_EQ(sampled, 1.0); break;
            case Overlap::disjoint: EXPECT_EQ(sampled, 0.0); break;
            case Overlap::partial:
                ++partial;
                EXPECT_NEAR(inside_fraction(conic, cell), sampled, 0.01);
                break;
        }
    }
    EXPECT_GT(partial, 4);
}

TEST(SphericalConic, InsideShareWeighsALinearDensity) {
    // A triangle holding the whole (tiny) conic: the share is the conic's area times the weight at
    // its centre over the triangle's integral of the weight.
    const Vec3 h = normalize(Vec3{0.01, 0.02, 1.0});
    const SphericalConic conic = spherical_conic(h, h, 0.002);
    const SphericalTriangle cell{{normalize(Vec3{0.2, 0.0, 1.0}), normalize(Vec3{-0.1, 0.2, 1.0}), normalize(Vec3{-0.1, -0.2, 1.0})}};
    const double uniform = inside_fraction(conic, cell);
    const std::array<double, 3> weights{1.0, 2.0, 3.0};
    // The weight at h by barycentric coordinates in the plane of the vertices.
    const Vec3 n = cross(cell.v[1] - cell.v[0], cell.v[2] - cell.v[0]);
    const Vec3 p = (dot(cell.v[0], n) / dot(h, n)) * h;
    const double area = length(n);
    const double b0 = length(cross(cell.v[1] - p, cell.v[2] - p)) / area;
    const double b1 = length(cross(cell.v[2] - p, cell.v[0] - p)) / area;
    const double b2 = 1.0 - b0 - b1;
    const double weight_at_h = b0 * weights[0] + b1 * weights[1] + b2 * weights[2];
    EXPECT_NEAR(inside_fraction(conic, cell, weights), uniform * weight_at_h / 2.0, 1e-3 * uniform);
}

}  // namespace
}  // namespace glintscope
