// Jakob 2014's stochastic process, tested as a random variable: counts in a query are
// Binomial(N, p) with p the integral of D over it (χ² over seeds, mean, variance), the same query
// gives the same count, children sum to their parent, and the integration of D over spherical
// triangles (Algorithm 2) matches a fine quadrature.
#include "methods/discrete/flake_hierarchy.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <vector>

#include "glintscope/fit/ndf_models.hpp"

namespace glintscope {
namespace {

NormalDensity beckmann(double alpha_x, double alpha_y) {
    return [=](Vec3 m) { return m.z > 0.0 ? beckmann_ndf(alpha_x, alpha_y, m) * m.z : 0.0; };
}

FlakeMaterial small_material(const TriangleIntegrals& integrals, double flakes, std::uint64_t seed) {
    FlakeMaterial material;
    material.normals = &integrals;
    material.tile_um = 100.0;
    material.flakes = flakes;
    material.seed = seed;
    material.query_area_um2 = 400.0;
    material.query_solid_angle = 0.01;
    return material;
}

FlakeFootprint box(double x, double y, double side) {
    FlakeFootprint footprint;
    footprint.gaussian = false;
    footprint.centre_x = x;
    footprint.centre_y = y;
    footprint.size_um = footprint.size_y_um = side;
    return footprint;
}

// ∫ D m_z over a set, by recursive subdivision with the centroid rule on 4^depth triangles.
double fine_integral(const NormalDensity& density, const SphericalTriangle& t, int depth) {
    if (depth == 0) return solid_angle(t) * density(centre(t));
    double sum = 0.0;
    for (const SphericalTriangle& child : split(t)) sum += fine_integral(density, child, depth - 1);
    return sum;
}

TEST(TriangleIntegrals, MatchAFineQuadratureWithinTheirTolerance) {
    const TriangleIntegrals integrals = integrate_distribution(beckmann(0.15, 0.3));
    EXPECT_GT(integrals.table.size(), 10u);
    // Every cell down to depth 4, table entries and vertex-rule cells alike.
    std::vector<DirectionCell> cells{DirectionCell{}};
    double total = 0.0, worst = 0.0;
    for (int level = 0; level < 4; ++level) {
        std::vector<DirectionCell> next;
        for (const DirectionCell& cell : cells)
            for (const DirectionCell& child : split(cell, integrals.density)) next.push_back(child);
        cells = next;
        if (level == 0)
            for (const DirectionCell& quadrant : cells) total += integrals.integral(quadrant);
    }
    for (const DirectionCell& cell : cells) {
        const double fine = fine_integral(integrals.density, cell.triangle, 6);
        const double error = std::abs(integrals.integral(cell) - fine);
        // The stated tolerance: relative δ_rel, or δ_abs for cells holding almost nothing.
        EXPECT_LE(error, std::max(2.0 * integrals.relative_tolerance * fine, 1e-6)) << "cell " << cell.label;
        if (fine > 1e-3) worst = std::max(worst, error / fine);
    }
    EXPECT_NEAR(total, 1.0, 0.5 * integrals.relative_tolerance);  // ∫ D m_z dω = 1 (measured 0.9977)
    EXPECT_LT(worst, 0.02);
}

TEST(FlakeHierarchy, ChildrenSumToTheirParentAndCountsAreWholeNumbers) {
    const TriangleIntegrals integrals = integrate_distribution(beckmann(0.2, 0.2));
    const FlakeMaterial material = small_material(integrals, 123456789.0, 5);
    std::vector<FlakeNode> nodes{root_node(material)};
    int directional = 0, spatial = 0;
    for (int level = 0; level < 6; ++level) {
        std::vector<FlakeNode> next;
        for (const FlakeNode& node : nodes) {
            const std::array<FlakeNode, 4> children = split(material, node);
            double sum = 0.0;
            for (const FlakeNode& child : children) {
                EXPECT_GE(child.count, 0.0);
                EXPECT_EQ(child.count, std::floor(child.count));
                sum += child.count;
            }
            EXPECT_EQ(sum, node.count);
            (children[0].size != node.size ? spatial : directional) += 1;
            // The same node draws the same children.
            const std::array<FlakeNode, 4> again = split(material, node);
            for (int j = 0; j < 4; ++j) EXPECT_EQ(again[j].count, children[j].count);
            if (next.size() < 64)
                for (const FlakeNode& child : children) next.push_back(child);
        }
        nodes = next;
    }
    EXPECT_GT(directional, 0);
    EXPECT_GT(spatial, 0);
}

TEST(FlakeHierarchy, TheSameQueryGivesTheSameCount) {
    const TriangleIntegrals integrals = integrate_distribution(beckmann(0.2, 0.2));
    const FlakeMaterial material = small_material(integrals, 1e7, 9);
    const SphericalConic conic = spherical_conic(direction_from_spherical(0.2, 0.0), direction_from_spherical(0.3, 3.0), 0.02);
    FlakeFootprint gaussian;
    gaussian.centre_x = 40.0;
    gaussian.centre_y = 60.0;
    SplitCache cache;
    const FlakeCount first = count_flakes(material, gaussian, conic, 0.1);
    const FlakeCount cached = count_flakes(material, gaussian, conic, 0.1, &cache);
    const FlakeCount again = count_flakes(material, gaussian, conic, 0.1, &cache);
    EXPECT_GT(first.weighted, 10.0);
    EXPECT_EQ(first.weighted, cached.weighted);
    EXPECT_EQ(first.weighted, again.weighted);
    // A footprint moved by a whole tile sees the same flakes (the tile repeats).
    gaussian.centre_x += 100.0;
    EXPECT_EQ(count_flakes(material, gaussian, conic, 0.1).weighted, first.weighted);
}

// χ² statistic's 99% point by Wilson & Hilferty (1931).
double chi_square_99(int degrees) {
    const double k = degrees, z = 2.3263;
    const double a = 2.0 / (9.0 * k);
    return k * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

double binomial_pmf(int n, double p, int k) {
    return std::exp(std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0) + k * std::log(p) +
                    (n - k) * std::log1p(-p));
}

// Exact counts (ε = 0) of a box footprint × conic over many seeds: the histogram is Binomial(N, p)
// with p = the footprint's share of the tile × ∫_Ω D m_z.
TEST(FlakeHierarchy, CountsInAQueryAreBinomialWithTheIntegralOfD) {
    const TriangleIntegrals integrals = integrate_distribution(beckmann(0.3, 0.3));
    const int flakes = 400;
    const Vec3 omega_i = direction_from_spherical(0.3, 0.5);
    const SphericalConic conic = spherical_conic(omega_i, direction_from_spherical(0.5, 3.0), 0.25);
    const FlakeFootprint footprint = box(30.0, 70.0, 50.0);
    const double p = 0.25 * conic_integral(integrals, conic, 1e-7);
    ASSERT_GT(p * flakes, 10.0);
    const int seeds = 3000;
    std::map<int, int> histogram;
    double sum = 0.0, sum_squares = 0.0;
    for (int seed = 1; seed <= seeds; ++seed) {
        const double count = count_flakes(small_material(integrals, flakes, seed), footprint, conic, 0.0).weighted;
        ASSERT_EQ(count, std::floor(count));
        histogram[static_cast<int>(count)] += 1;
        sum += count;
        sum_squares += count * count;
    }
    const double mean = sum / seeds;
    const double variance = (sum_squares - seeds * mean * mean) / (seeds - 1);
    // Mean: within 3 standard errors; variance: Binomial's, (1 − p)/(Np) relative, within 10%.
    EXPECT_NEAR(mean, flakes * p, 3.0 * std::sqrt(flakes * p * (1 - p) / seeds));
    EXPECT_NEAR(variance / (mean * mean), (1.0 - p) / (flakes * p), 0.1 * (1.0 - p) / (flakes * p));
    // χ²: bins pooled from both tails until each expects at least 5.
    double chi_square = 0.0, expected_bin = 0.0, observed_bin = 0.0;
    int bins = 0;
    for (int k = 0; k <= flakes; ++k) {
        expected_bin += seeds * binomial_pmf(flakes, p, k);
        observed_bin += histogram.contains(k) ? histogram[k] : 0;
        if (expected_bin >= 5.0 && seeds * (1.0 - [&] {
                double below = 0.0;
                for (int j = 0; j <= k; ++j) below += binomial_pmf(flakes, p, j);
                return below;
            }()) >= 5.0) {
            chi_square += (observed_bin - expected_bin) * (observed_bin - expected_bin) / expected_bin;
            expected_bin = observed_bin = 0.0;
            ++bins;
        }
    }
    chi_square += expected_bin > 0.0 ? (observed_bin - expected_bin) * (observed_bin - expected_bin) / expected_bin : 0.0;
    ++bins;
    ASSERT_GT(bins, 8);
    EXPECT_LT(chi_square, chi_square_99(bins - 1)) << bins << " bins";
}

// With the adaptive criterion (ε = 10%) and many flakes, the mean over seeds of the weighted count
// of a Gaussian footprint equals N ∫_Ω D m_z within 2%.
TEST(FlakeHierarchy, MeanOverSeedsIsTheSmoothDistributionIntegratedOverTheQuery) {
    const TriangleIntegrals integrals = integrate_distribution(beckmann(0.1, 0.25));
    FlakeFootprint gaussian;
    gaussian.centre_x = 20.0;
    gaussian.centre_y = 50.0;
    gaussian.sigma_um = 8.0;
    const double in_footprint = 1e6;
    const double tile_flakes = in_footprint / gaussian.area_um2() * 100.0 * 100.0;
    for (const double theta_o : {0.0, 0.2, 0.35}) {
        const Vec3 omega_i = direction_from_spherical(0.1, 0.0);
        const SphericalConic conic = spherical_conic(omega_i, direction_from_spherical(theta_o, 2.0), 0.01);
        const double expected = std::round(tile_flakes) / 1e4 * gaussian.area_um2() * conic_integral(integrals, conic, 1e-8);
        double sum = 0.0;
        const int seeds = 40;
        for (int seed = 1; seed <= seeds; ++seed) {
            FlakeMaterial material = small_material(integrals, std::round(tile_flakes), seed);
            material.query_area_um2 = gaussian.area_um2();
            material.query_solid_angle = 2e-5;
            sum += count_flakes(material, gaussian, conic, 0.1).weighted;
        }
        ASSERT_GT(expected, 20.0);
        EXPECT_NEAR(sum / seeds, expected, 0.02 * expected) << "theta_o " << theta_o;
    }
}

}  // namespace
}  // namespace glintscope
