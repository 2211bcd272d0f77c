// The ellipsoid NDF (Dong 2015 eq. 10–12) and its shadowing-masking (eq. 13–14): GGX as the
// special case, normalisation on the projected disk, and Smith's G1 in the GGX case.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "glintscope/fit/ndf_fit.hpp"
#include "glintscope/fit/ndf_models.hpp"

namespace glintscope {
namespace {

const EllipsoidNdf skewed{0.3, 0.15, 0.2, -0.15, 0.6};

// Walter 2007's GGX written in θ_m: α² / (π cos⁴θ (α² + tan²θ)²), independent of our code.
double walter_ggx(double alpha, Vec3 m) {
    const double c2 = m.z * m.z, tan2 = (1.0 - c2) / c2;
    return alpha * alpha / (pi * c2 * c2 * (alpha * alpha + tan2) * (alpha * alpha + tan2));
}

TEST(EllipsoidNdf, IsGgxWhenUnrotatedAndIsotropic) {
    for (double alpha : {0.05, 0.3, 1.2})
        for (double theta : {0.0, 0.3, 0.9, 1.4})
            for (double phi : {0.0, 1.0, 2.5}) {
                const Vec3 m = direction_from_spherical(theta, phi);
                const double expected = walter_ggx(alpha, m);
                EXPECT_NEAR(ellipsoid_ndf({alpha, alpha, 0, 0, 0}, m), expected, 1e-12 * expected);
                EXPECT_NEAR(ggx_ndf(alpha, alpha, m), expected, 1e-12 * expected);
            }
    // R = I, α_x ≠ α_y: GTR2aniso (Dong 2015 §8).
    const Vec3 m = direction_from_spherical(0.4, 0.7);
    EXPECT_NEAR(ellipsoid_ndf({0.1, 0.4, 0, 0, 0}, m), ggx_ndf(0.1, 0.4, m), 1e-12 * ggx_ndf(0.1, 0.4, m));
}

// Σ D (2/N)² at N = 512 (pixel centres, values stored as float).
double normalisation(const NdfModel& model) { return disk_sum(model_ndf_image(model, 512)); }

TEST(EllipsoidNdf, IntegratesToOneOnTheProjectedDisk) {
    // Measured |Σ − 1| (the midpoint rule's error at the peak and at the rim, where GGX's tail
    // is cut): ellipsoids 1.1e-6 and 1.5e-6, Beckmann 4e-10, GGX 2.4e-6.
    EXPECT_NEAR(normalisation({NdfModelKind::ellipsoid, skewed}), 1.0, 1e-5);
    EXPECT_NEAR(normalisation({NdfModelKind::ellipsoid, {0.1, 0.25, -0.3, 0.1, -1.1}}), 1.0, 1e-5);
    EXPECT_NEAR(normalisation({NdfModelKind::beckmann, {0.2, 0.1, 0, 0, 0}}), 1.0, 1e-5);
    EXPECT_NEAR(normalisation({NdfModelKind::ggx, {0.2, 0.1, 0, 0, 0}}), 1.0, 1e-5);
}

TEST(EllipsoidNdf, SameDistributionUnderAHalfTurnOfTheFrame) {
    // A → R_z(π) A leaves eq. 10 unchanged: (θ_x, θ_y, θ_z) ≡ (−θ_x, −θ_y, θ_z + π).
    const EllipsoidNdf turned{skewed.alpha_x, skewed.alpha_y, -skewed.theta_x, -skewed.theta_y, skewed.theta_z + pi};
    for (double theta : {0.0, 0.2, 0.7})
        for (double phi : {0.3, 2.0, 4.0}) {
            const Vec3 m = direction_from_spherical(theta, phi);
            EXPECT_NEAR(ellipsoid_ndf(turned, m), ellipsoid_ndf(skewed, m), 1e-12 * ellipsoid_ndf(skewed, m));
        }
}

// A quarter turn of the frame with α_x and α_y swapped is the same distribution: the canonical
// form (|θ_z| ≤ π/4) gives the same D at every normal, from θ_z in every quadrant.
TEST(EllipsoidNdf, CanonicalFormIsTheSameDistributionWithThetaZWithinAQuarter) {
    for (const double theta_z : {-3.0, -2.0, -1.0, 0.5, 0.9, 1.6, 2.5, 3.1}) {
        const EllipsoidNdf original{0.3, 0.08, 0.15, -0.1, theta_z};
        const EllipsoidNdf canonical = canonical_ellipsoid(original);
        EXPECT_LE(std::abs(canonical.theta_z), 0.25 * pi + 1e-12) << theta_z;
        for (int k = 0; k < 200; ++k) {
            const double phi = 0.731 * k, radius = std::sqrt((k + 0.5) / 200.0) * 0.95;
            const Vec3 m = direction_from_disk(radius * std::cos(phi), radius * std::sin(phi));
            const double d = ellipsoid_ndf(original, m);
            EXPECT_NEAR(ellipsoid_ndf(canonical, m), d, 1e-10 * (1.0 + d)) << theta_z << " at " << k;
        }
    }
}

TEST(EllipsoidShadowing, IsAtMostOneAndOneAtNormalIncidence) {
    double smallest = 1.0;
    for (int i = 0; i <= 40; ++i)
        for (int j = 0; j < 16; ++j) {
            const Vec3 u = direction_from_spherical(i * 0.5 * pi / 41, j * 2 * pi / 16);
            const double g1 = ellipsoid_g1(skewed, u);
            EXPECT_GE(g1, 0.0);
            EXPECT_LE(g1, 1.0);
            smallest = std::min(smallest, g1);
        }
    EXPECT_LT(smallest, 0.5);  // grazing directions are shadowed
    EXPECT_DOUBLE_EQ(ellipsoid_g1(skewed, {0, 0, 1}), 1.0);
    // A smooth NDF shadows little near the normal: GGX α = 0.05 at 10° gives 1 − 2e-5.
    EXPECT_GT(ellipsoid_g1({0.05, 0.05, 0, 0, 0}, direction_from_spherical(10 * pi / 180, 0.4)), 0.9999);
}

TEST(EllipsoidShadowing, IsSmithG1OfGgxInTheSpecialCase) {
    for (double theta : {0.1, 0.6, 1.2, 1.5})
        for (double phi : {0.0, 0.8, 2.1}) {
            const Vec3 u = direction_from_spherical(theta, phi);
            const double ax = 0.3, ay = 0.12;
            // Smith G1 of GTR2aniso: 2 / (1 + √(1 + α(φ)² tan²θ)), α(φ)² = α_x² cos²φ + α_y² sin²φ.
            const double alpha2 = ax * ax * std::cos(phi) * std::cos(phi) + ay * ay * std::sin(phi) * std::sin(phi);
            const double smith = 2.0 / (1.0 + std::sqrt(1.0 + alpha2 * std::tan(theta) * std::tan(theta)));
            EXPECT_NEAR(ellipsoid_g1({ax, ay, 0, 0, 0}, u), smith, 1e-12);
        }
}

TEST(EllipsoidShadowing, IsTheProductOfBothDirectionsAndZeroFromBehind) {
    const Vec3 wi = direction_from_spherical(1.1, 0.2), wo = direction_from_spherical(1.3, 2.9);
    const Vec3 h = normalize(wi + wo);
    EXPECT_NEAR(ellipsoid_shadowing_masking(skewed, wi, wo, h), ellipsoid_g1(skewed, wi) * ellipsoid_g1(skewed, wo),
                1e-15);
    EXPECT_EQ(ellipsoid_shadowing_masking(skewed, wi, wo, -1.0 * h), 0.0);
}

}  // namespace
}  // namespace glintscope
