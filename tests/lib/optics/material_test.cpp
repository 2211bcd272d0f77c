// Metal optical constants and the conductor Fresnel reflectance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "glintscope/core/error.hpp"
#include "glintscope/optics/material.hpp"

namespace glintscope {
namespace {

// Textbook real-valued form of the unpolarised conductor reflectance (Born & Wolf §14.4; the
// a², b² substitution as in Heavens 1955), independent of the complex-arithmetic implementation.
double textbook_reflectance(double n, double k, double theta) {
    const double s = std::sin(theta), c = std::cos(theta), t = std::tan(theta);
    const double d = n * n - k * k - s * s;
    const double root = std::sqrt(d * d + 4.0 * n * n * k * k);
    const double a = std::sqrt(0.5 * (root + d));
    const double b2 = 0.5 * (root - d);
    const double r_s = ((a - c) * (a - c) + b2) / ((a + c) * (a + c) + b2);
    const double r_p = r_s * ((a - s * t) * (a - s * t) + b2) / ((a + s * t) * (a + s * t) + b2);
    return 0.5 * (r_s + r_p);
}

TEST(Material, ShipsTheMetals) {
    const std::vector<std::string> names = material_names();
    for (const char* metal : {"Ag", "Al", "Au", "Cr", "Cu", "Fe"})
        EXPECT_NE(std::find(names.begin(), names.end(), metal), names.end()) << metal;
    EXPECT_NE(material_source("Fe").find("Johnson"), std::string::npos);
    EXPECT_NE(material_source("Al").find("Rakic"), std::string::npos);
}

TEST(Material, NormalIncidenceMatchesTheClosedForm) {
    for (const std::string& metal : material_names())
        for (double lambda : {0.36, 0.45, 0.55, 0.65, 0.83}) {
            const ComplexIndex eta = complex_refractive_index(metal, lambda);
            const double expected = ((eta.n - 1) * (eta.n - 1) + eta.k * eta.k) /
                                    ((eta.n + 1) * (eta.n + 1) + eta.k * eta.k);
            EXPECT_NEAR(fresnel_reflectance(metal, lambda, 1.0), expected, 1e-14) << metal << " " << lambda;
        }
}

TEST(Material, AgreesWithTheTextbookFormulaAtEveryAngle) {
    for (const ComplexIndex eta : {ComplexIndex{0.8125, 6.048}, ComplexIndex{2.9, 3.0}, ComplexIndex{0.05, 3.5}})
        for (double degrees = 0.0; degrees < 90.0; degrees += 7.5) {
            const double theta = degrees * std::numbers::pi / 180.0;
            EXPECT_NEAR(fresnel_conductor(eta, std::cos(theta)), textbook_reflectance(eta.n, eta.k, theta), 1e-12)
                << eta.n << "+" << eta.k << "i at " << degrees;
        }
}

TEST(Material, ReflectanceGoesToOneAtGrazingIncidence) {
    for (const std::string& metal : material_names()) {
        EXPECT_EQ(fresnel_reflectance(metal, 0.55, 0.0), 1.0) << metal;
        EXPECT_GT(fresnel_reflectance(metal, 0.55, 1e-4), 0.999) << metal;
        EXPECT_LT(fresnel_reflectance(metal, 0.55, 1.0), 1.0) << metal;
    }
}

TEST(Material, MeasuredReflectancesLookLikeTheMetals) {
    // Rakić's aluminium at 0.5 µm: n ≈ 0.81, k ≈ 6.05, normal reflectance ≈ 0.92.
    EXPECT_NEAR(fresnel_reflectance("Al", 0.5, 1.0), 0.92, 0.005);
    EXPECT_GT(fresnel_reflectance("Ag", 0.55, 1.0), 0.95);
    // Gold and copper reflect red far better than blue: they look yellow and orange.
    EXPECT_GT(fresnel_reflectance("Au", 0.65, 1.0), fresnel_reflectance("Au", 0.45, 1.0) + 0.4);
    EXPECT_GT(fresnel_reflectance("Cu", 0.70, 1.0), fresnel_reflectance("Cu", 0.45, 1.0) + 0.3);
    // Iron and chromium are grey and darker.
    for (const char* metal : {"Fe", "Cr"}) {
        EXPECT_GT(fresnel_reflectance(metal, 0.55, 1.0), 0.5) << metal;
        EXPECT_LT(fresnel_reflectance(metal, 0.55, 1.0), 0.7) << metal;
    }
}

TEST(Material, InterpolatesLinearlyBetweenTableRows) {
    const ComplexIndex node = complex_refractive_index("Al", 0.44280);
    EXPECT_DOUBLE_EQ(node.n, 0.60790);
    EXPECT_DOUBLE_EQ(node.k, 5.3676);
    const ComplexIndex mid = complex_refractive_index("al", 0.5 * (0.47687 + 0.51660));  // any case
    EXPECT_NEAR(mid.n, 0.5 * (0.72780 + 0.87340), 1e-12);
    EXPECT_NEAR(mid.k, 0.5 * (5.7781 + 6.2418), 1e-12);
}

TEST(Material, EmptyNameMeansNoMaterial) { EXPECT_EQ(fresnel_reflectance("", 0.5, 0.3), 1.0); }

TEST(Material, RejectsUnknownMaterialsAndWavelengthsOutsideTheTable) {
    try {
        fresnel_reflectance("unobtainium", 0.5, 1.0);
        FAIL() << "unknown material accepted";
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("unobtainium"), std::string::npos) << message;
        EXPECT_NE(message.find("Ag, Al, Au, Cr, Cu, Fe"), std::string::npos) << message;
    }
    EXPECT_THROW(fresnel_reflectance("Au", 3.0, 1.0), Error);
    EXPECT_THROW(fresnel_reflectance("Au", 0.5, std::nan("")), Error);
}

}  // namespace
}  // namespace glintscope
