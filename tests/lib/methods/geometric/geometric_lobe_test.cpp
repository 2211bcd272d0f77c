// The geometric lobe against closed forms (a mirror's albedo is F, a tilted plane reflects into
// its mirror direction), reciprocity, energy on a smooth rough surface, Smith shadowing taking
// energy away, thread independence, and the geometric limit of the FFT Kirchhoff lobe.
#include "glintscope/lobe/query.hpp"
#include "glintscope/pipeline/pipeline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "glintscope/generate/generate.hpp"
#include "glintscope/lobe/compare.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"

#include "sampled_field.hpp"
#include "lobe_queries.hpp"

namespace glintscope {
namespace {

Heightfield plane(double a, double b) {
    return testing::sampled_field(64, 64, 1.0, [=](double x, double y) { return a * x + b * y; });
}

// A Gaussian random field (Stam's smooth C1) with rms slope 0.1 per axis and T = 10 µm.
Heightfield smooth_rough(int size) {
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {size, size, 1.0};
    recipe.gaussian.correlation = CorrelationFunction::c1;
    recipe.gaussian.correlation_length_x_um = recipe.gaussian.correlation_length_y_um = 10.0;
    recipe.gaussian.sigma_h_um = 0.1 * 10.0 / std::numbers::sqrt2;
    return generate(recipe);
}

LobeQuery query_for(Heightfield field, int resolution) {
    LobeQuery query;
    query.footprint.centre_um = field.centre_um();
    query.resolution = resolution;
    set_heightfield(query, std::move(field));
    return query;
}

// A plane's NDF is one normal m: by Dong 2015 eq. 1 with G = 1 its albedo is
// F(ω_i·m)·(ω_i·m)/(cosθ_i m_z) (F at normal incidence, for any flat mirror), however narrow the
// lobe is against a pixel: the pixels integrate the lobe exactly, at default settings.
TEST(GeometricLobe, FlatAndTiltedPlanesReflectTheirClosedFormAlbedoAtEveryResolution) {
    for (const auto& [a, b] : {std::pair{0.0, 0.0}, std::pair{0.2, 0.1}})
        for (const int resolution : {64, 128, 256, 512})
            for (const double theta_deg : {0.0, 20.0, 45.0, 70.0, 80.0}) {
                LobeQuery query = query_for(plane(a, b), resolution);
                query.footprint.sigma_um = 4.0;  // inside the tile, away from the plane's wrap-around step
                query.omega_i = direction_from_spherical(theta_deg * pi / 180.0, 0.3);
                query.material.name = "Au";
                query.wavelengths_um = {0.45, 0.65};
                const Vec3 m = normalize({-a, -b, 1.0});
                const double cos_im = dot(query.omega_i, m);
                if (2.0 * cos_im * m.z - query.omega_i.z <= 0.0) continue;  // reflected below the horizon
                const LobeImage image = compute_lobe("geometric", query);
                for (std::size_t l = 0; l < 2; ++l) {
                    const double expected = fresnel_reflectance("Au", query.wavelengths_um[l], cos_im) * cos_im /
                                            (query.omega_i.z * m.z);
                    EXPECT_NEAR(disk_sum(image, l) / expected, 1.0, 0.01)
                        << "slope " << a << "," << b << ", res " << resolution << ", theta " << theta_deg << ", layer " << l;
                }
            }
}

TEST(GeometricLobe, TiltedPlanePeaksAtTheMirrorDirectionOfItsNormal) {
    const double a = 0.2, b = 0.1;
    LobeQuery query = query_for(plane(a, b), 128);
    query.footprint.sigma_um = 4.0;  // inside the tile, away from the plane's wrap-around step
    const LobeImage image = compute_lobe("geometric", query);
    int best = 0;
    for (int k = 1; k < 128 * 128; ++k)
        if (image.values[k] > image.values[best]) best = k;
    const Vec3 m = normalize({-a, -b, 1.0});
    const Vec3 mirror = 2.0 * dot(query.omega_i, m) * m - query.omega_i;
    const DiskPoint peak = disk_pixel_point(best / 128, best % 128, 128);
    EXPECT_LT(std::abs(peak.x - mirror.x), 2.0 / 128);
    EXPECT_LT(std::abs(peak.y - mirror.y), 2.0 / 128);
}

TEST(GeometricLobe, IsReciprocalWithoutShadowing) {
    LobeQuery query = query_for(smooth_rough(128), 64);
    const Vec3 a = [] { const DiskPoint p = disk_pixel_point(20, 40, 64); return direction_from_disk(p.x, p.y); }();
    const Vec3 b = [] { const DiskPoint p = disk_pixel_point(35, 22, 64); return direction_from_disk(p.x, p.y); }();
    const auto ratio = [&](int supersample) {
        query.supersample = supersample;
        query.omega_i = a;
        const float forward = compute_lobe("geometric", query).at(0, 35, 22);
        query.omega_i = b;
        const float backward = compute_lobe("geometric", query).at(0, 20, 40);
        EXPECT_GT(forward, 0.0f);
        return forward / backward;
    };
    // Point samples of f_r at pixel centres: exactly reciprocal.
    EXPECT_NEAR(ratio(1), 1.0, 1e-6);
    // Pixels integrated exactly (the default) hold f_r(a, ·) over b's pixel and f_r(b, ·) over a's:
    // reciprocal to the lobe's variation across a pixel (0.19%).
    EXPECT_NEAR(ratio(kExactPixels), 1.0, 5e-3);
}

TEST(GeometricLobe, SmoothRoughSurfaceReflectsAlmostAllLightAtNormalIncidence) {
    // With G = 1 and F = 1, ∫ f_r cosθ_o dω_o = ∫ D(h)(ω_i·h) dω_h / cosθ_i over the h whose ω_o is
    // above the horizon: 1 at normal incidence for normals within 45° (rms slope 0.1 here).
    LobeQuery query = query_for(smooth_rough(128), 128);
    query.footprint.shape = FootprintShape::whole;
    query.supersample = 2;
    const double plain = disk_sum(compute_lobe("geometric", query));
    EXPECT_NEAR(plain, 1.0, 0.01);
    query.method_options["shadowing"] = "smith";
    const double shadowed = disk_sum(compute_lobe("geometric", query));
    RecordProperty("albedo", std::to_string(plain));
    RecordProperty("albedo_smith", std::to_string(shadowed));
    EXPECT_LE(shadowed, plain);
    EXPECT_GT(shadowed, 0.999 * plain);  // at normal incidence G1(ω_i) = 1 and G1(ω_o) ≈ 1 where D lives
    // At grazing incidence Smith's G1 < 1 takes energy away: at least G1(ω_i), which for a
    // Beckmann NDF of rms slope σ per axis is 1/(1 + Λ), Λ = (erf(a) − 1)/2 + e^{−a²}/(2a√π),
    // a = 1/(√2 σ tanθ), and more through the G1(ω_o) of outgoing directions nearer the horizon.
    query.omega_i = direction_from_spherical(75.0 * std::numbers::pi / 180.0, 0.0);
    query.method_options.clear();
    const double grazing = disk_sum(compute_lobe("geometric", query));
    query.method_options["shadowing"] = "smith";
    const double grazing_shadowed = disk_sum(compute_lobe("geometric", query));
    const double a = 1.0 / (std::numbers::sqrt2 * 0.1 * std::tan(75.0 * std::numbers::pi / 180.0));
    const double beckmann_g1 = 1.0 / (1.0 + 0.5 * (std::erf(a) - 1.0) + std::exp(-a * a) / (2.0 * a * std::sqrt(std::numbers::pi)));
    RecordProperty("albedo_75deg", std::to_string(grazing));
    RecordProperty("albedo_smith_75deg", std::to_string(grazing_shadowed));
    RecordProperty("beckmann_g1_75deg", std::to_string(beckmann_g1));
    EXPECT_LT(grazing_shadowed, grazing * beckmann_g1);
    EXPECT_GT(grazing_shadowed, 0.9 * grazing);
}

// Smith's G1 of an anisotropic GGX NDF of (α_x, α_y): 2/(1 + √(1 + α² tan²θ)), α² = α_x² cos²φ
// + α_y² sin²φ: what Dong 2015 eq. 14 reduces to when the ellipsoid is axis-aligned.
double ggx_smith_g1(double alpha_x, double alpha_y, Vec3 omega) {
    const double sin2 = 1.0 - omega.z * omega.z;
    if (sin2 <= 0.0) return 1.0;
    const double alpha2 = (alpha_x * alpha_x * omega.x * omega.x + alpha_y * alpha_y * omega.y * omega.y) / sin2;
    return 2.0 / (1.0 + std::sqrt(1.0 + alpha2 * sin2 / (omega.z * omega.z)));
}

TEST(GeometricLobe, EllipsoidShadowingIsDongsTermOfTheFittedEllipsoid) {
    // shadowing=ellipsoid fits Dong 2015's ellipsoid NDF to the P-NDF and multiplies by its
    // G1(ω_i) G1(ω_o) (eq. 13-14). On this Gaussian field the fit is nearly axis-aligned, so at the
    // mirror pixel the ratio to the unshadowed lobe is the GGX Smith product of the fitted α; no
    // pixel gains. (It takes more light than Smith of the measured NDF at 75°: the ellipsoid is
    // GGX-like, with longer tails than this surface's Gaussian slopes; docs/geometric.md.)
    LobeQuery query = query_for(smooth_rough(128), 64);
    query.footprint.shape = FootprintShape::whole;
    query.omega_i = direction_from_spherical(60.0 * std::numbers::pi / 180.0, 0.0);
    const LobeImage plain = compute_lobe("geometric", query);
    query.method_options.emplace("shadowing", "ellipsoid");
    const LobeImage shadowed = compute_lobe("geometric", query);
    const std::vector<double> fitted = parse_number_list(shadowed.metadata.at("geometric.ellipsoid"));
    ASSERT_EQ(fitted.size(), 5u);
    EXPECT_LT(std::abs(fitted[2]) + std::abs(fitted[3]), 0.05);  // θ_x, θ_y: the mean normal is n
    const int row = 32, col = 10;  // ω_o near the mirror direction (−sin 60°, 0)
    const DiskPoint p = disk_pixel_point(row, col, 64);
    const Vec3 omega_o = direction_from_disk(p.x, p.y);
    const double expected =
        ggx_smith_g1(fitted[0], fitted[1], query.omega_i) * ggx_smith_g1(fitted[0], fitted[1], omega_o);
    RecordProperty("g_at_mirror", std::to_string(shadowed.at(0, row, col) / plain.at(0, row, col)));
    RecordProperty("ggx_smith_product", std::to_string(expected));
    RecordProperty("fit_relative_error", shadowed.metadata.at("geometric.ellipsoid_relative_error"));
    EXPECT_NEAR(shadowed.at(0, row, col) / plain.at(0, row, col), expected, 0.02 * expected);
    for (std::size_t k = 0; k < plain.values.size(); ++k) ASSERT_LE(shadowed.values[k], plain.values[k] * (1.0f + 1e-6f));
}

TEST(GeometricLobe, SameBitsForOneAndFourThreads) {
    LobeQuery query = query_for(smooth_rough(128), 64);
    query.omega_i = direction_from_spherical(0.4, 1.0);
    query.supersample = 2;
    query.method_options["shadowing"] = "smith";
    EXPECT_EQ(testing::compute_with_threads("geometric", query, 1).values,
              testing::compute_with_threads("geometric", query, 4).values);
}

TEST(GeometricLobe, KirchhoffFftLobeApproachesItAsTheWavelengthShrinks) {
    LobeQuery query = query_for(smooth_rough(256), 128);
    query.model = DiffractionModel::kirchhoff;
    query.supersample = 4;
    const LobeImage geometric = compute_lobe("geometric", query);
    double previous = 1e9;
    for (double lambda : {0.5, 0.25, 0.1}) {
        query.wavelengths_um = {lambda};
        // Speckle-free: both blurred by one pixel (compare.hpp), the wave lobe against the geometric one.
        const double error =
            compare_layer(layer_values(compute_lobe("fft", query), 0), layer_values(geometric, 0), 128).smoothed_relative_l2;
        RecordProperty("smoothed_relative_l2_at_" + std::to_string(lambda), std::to_string(error));
        EXPECT_LT(error, previous) << "lambda " << lambda;
        previous = error;
    }
    EXPECT_LT(previous, 0.05);
}

}  // namespace
}  // namespace glintscope
