// The geometric method's point field (one normal-bounds tree per field, any footprint): the
// microfacet lobe of pndf's point query, exactly reciprocal, conserving the energy that the
// footprint's NDF image predicts, sampled with its own pdf (χ²) and a mean weight equal to that
// albedo, and answered from the images where a tree cannot answer (shadowing).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "glintscope/generate/generate.hpp"
#include "glintscope/optics/material.hpp"
#include "methods/geometric/geometric_lobe.hpp"
#include "methods/pndf/pndf.hpp"
#include "normal_density/normal_density.hpp"
#include "core/counter_rng.hpp"
#include "disk_chi_square.hpp"
#include "sampled_field.hpp"

namespace glintscope {
namespace {

LobeQuery small_isotropic_query(Quantity quantity) {
    LobeQuery query;
    set_heightfield(query, testing::isotropic_field(128));
    query.footprint.centre_um = {40.0, 90.0};
    query.footprint.sigma_um = 10.0;
    query.resolution = 32;
    query.quantity = quantity;
    query.wavelengths_um = {0.45, 0.65};
    return query;
}

Footprint gaussian_at(Point2 centre, double sigma) {
    Footprint footprint;
    footprint.centre_um = centre;
    footprint.sigma_um = sigma;
    return footprint;
}

TEST(GeometricPointField, IsTheMicrofacetLobeOfThePndfPointQuery) {
    // At ndf_oversampling 1 the geometric tree has pndf's triangles, so f_r·4 cosθ_i cosθ_o = D(h)
    // without a material, for footprints other than the query's own: Gaussians and a rotated box.
    LobeQuery query = small_isotropic_query(Quantity::brdf);
    query.method_options = {{"ndf_oversampling", "1"}};
    const PointAnswersAt geometric = geometric_method().point_field(query);
    const PointAnswersAt pndf = pndf_method().point_field(small_isotropic_query(Quantity::ndf));
    int nonzero = 0;
    Footprint rotated_box = gaussian_at({60.0, 30.0}, 10.0);
    set_box(rotated_box, "30x14um");
    rotated_box.axis_radians = 2.2;
    for (const Footprint& footprint : {gaussian_at({5.0, 7.0}, 6.0), gaussian_at({100.0, 60.0}, 15.0), rotated_box}) {
        const PointAnswers f = geometric(footprint), d = pndf(footprint);
        ASSERT_TRUE(f.eval && d.eval);
        for (int k = 0; k < 60; ++k) {
            const Vec3 omega_i = direction_from_spherical(0.01 * k, 0.3 * k);
            const Vec3 omega_o = direction_from_spherical(0.2 + 0.005 * k, 0.3 * k + 3.0 + 0.02 * k);
            const Vec3 h = normalize(omega_i + omega_o);
            const double expected = d.eval({0.0, 0.0, 1.0}, h)[0];
            const std::vector<double> values = f.eval(omega_i, omega_o);
            ASSERT_EQ(values.size(), 2u);
            for (double value : values) EXPECT_NEAR(value * 4.0 * omega_i.z * omega_o.z, expected, 1e-12 * expected);
            nonzero += expected > 0.0;
        }
    }
    EXPECT_GT(nonzero, 30) << "the directions miss the lobe";
}

TEST(GeometricPointField, IsReciprocalWithAMaterial) {
    // h and F(ω_i·h) = F(ω_o·h) are symmetric in the two directions.
    LobeQuery query = small_isotropic_query(Quantity::brdf);
    query.material.name = "Au";
    const PointAnswers f = geometric_method().point_field(query)(gaussian_at({64.0, 64.0}, 10.0));
    double largest = 0.0;
    for (int k = 0; k < 100; ++k) {
        const Vec3 a = direction_from_spherical(0.02 * (k % 30), 0.7 * k);
        const Vec3 b = direction_from_spherical(0.03 * (k % 20), 0.7 * k + 3.1);
        const std::vector<double> ab = f.eval(a, b), ba = f.eval(b, a);
        for (std::size_t l = 0; l < ab.size(); ++l) {
            EXPECT_NEAR(ab[l], ba[l], 1e-12 * std::max(ab[l], ba[l]));
            largest = std::max(largest, ab[l]);
        }
    }
    EXPECT_GT(largest, 0.1) << "the pairs miss the lobe";
}

TEST(GeometricPointField, ReflectsTheEnergyOfTheFootprintsNdf) {
    // ∫ f_r cosθ_o dω_o over the disk of ω_o (an 80² midpoint quadrature of the point answers)
    // against the NDF image of the same footprint: each h pixel of D carries
    // D (ω_i·h)/(cosθ_i h_z) of albedo where it reflects above the horizon (Dong 2015 eq. 1 with
    // dω_o = 4 (ω_i·h) dω_h). An intrinsic roughness of 0.05 rad smooths the caustics, whose
    // singular D a quadrature of 160² directions missed by 7% (σ_c = 8 µm, no roughness).
    // Measured with it: −1.8e-4 at 0°, −3.7e-4 at 30°.
    LobeQuery query = small_isotropic_query(Quantity::brdf);
    query.method_options = {{"intrinsic_roughness", "0.05"}};
    const Footprint footprint = gaussian_at({70.0, 30.0}, 4.0);
    const PointAnswers f = geometric_method().point_field(query)(footprint);
    const int ndf_resolution = 256;
    const std::vector<double> density = normal_density(*query.surface, footprint, ndf_resolution, {1, 0.02, 0.05});
    for (double degrees : {0.0, 30.0}) {
        const Vec3 omega_i = direction_from_spherical(degrees * pi / 180.0, 0.4);
        double expected = 0.0;
        for (int row = 0; row < ndf_resolution; ++row)
            for (int col = 0; col < ndf_resolution; ++col) {
                const DiskPoint p = disk_pixel_point(row, col, ndf_resolution);
                const double d = density[static_cast<std::size_t>(row) * ndf_resolution + col];
                if (d == 0.0) continue;
                const Vec3 h = direction_from_disk(p.x, p.y);
                const Vec3 omega_o = 2.0 * dot(omega_i, h) * h - omega_i;
                if (omega_o.z > 0.0) expected += d * dot(omega_i, h) / (omega_i.z * h.z) * disk_pixel_area(ndf_resolution);
            }
        const int m = 80;
        double albedo = 0.0;
        for (int row = 0; row < m; ++row)
            for (int col = 0; col < m; ++col) {
                const DiskPoint p = disk_pixel_point(row, col, m);
                if (!inside_unit_disk(p)) continue;
                albedo += f.eval(omega_i, direction_from_disk(p.x, p.y))[0] * disk_pixel_area(m);  // dA = cosθ_o dω_o
            }
        RecordProperty("relative_difference_" + std::to_string(int(degrees)), ::testing::PrintToString(albedo / expected - 1.0));
        EXPECT_NEAR(albedo, expected, 3e-3 * expected) << degrees << " degrees";
    }
}

// The expected ∫ f_r cosθ_o dω_o from an NDF image of the footprint: each h pixel of D carries
// D (ω_i·h)/(cosθ_i h_z) of albedo where it reflects above the horizon (Dong 2015 eq. 1 with
// dω_o = 4 (ω_i·h) dω_h).
double albedo_from_ndf_image(const std::vector<double>& density, int resolution, Vec3 omega_i) {
    double expected = 0.0;
    for (int row = 0; row < resolution; ++row)
        for (int col = 0; col < resolution; ++col) {
            const double d = density[static_cast<std::size_t>(row) * resolution + col];
            if (d == 0.0) continue;
            const DiskPoint p = disk_pixel_point(row, col, resolution);
            const Vec3 h = direction_from_disk(p.x, p.y);
            const Vec3 omega_o = 2.0 * dot(omega_i, h) * h - omega_i;
            if (omega_o.z > 0.0) expected += d * dot(omega_i, h) / (omega_i.z * h.z) * disk_pixel_area(resolution);
        }
    return expected;
}

TEST(GeometricPointField, SamplesFollowItsPdfAndTheMeanWeightIsTheAlbedo) {
    // The sampler of the point field (h with the point query's own density, ω_o = reflect(ω_i, h))
    // against its pdf: χ² over cells of h (pbrt-v4's test, DiskChiSquare) on a paraboloid, whose D
    // is smooth enough for the cells' 16 × 16-point quadrature of the pdf (a rough surface's
    // caustics are not: tests/lib/normal_density/normal_bounds_tree_test.cpp tests the draws of
    // h there against the image's exact pixel masses); and on the rough field the mean weight
    // f_r cosθ_o / pdf against the albedo the footprint's NDF image predicts, at 0° and 40°.
    const double a = 0.008, b = 0.006, c = 0.002;
    LobeQuery smooth = small_isotropic_query(Quantity::brdf);
    set_heightfield(smooth, testing::sampled_field(128, 128, 1.0, [&](double x, double y) {
        const double u = x - 64.0, v = y - 64.0;
        return 0.5 * a * u * u + 0.5 * b * v * v + c * u * v;
    }));
    smooth.method_options = {{"tolerance", "0"}};  // the field's seam would be divided 64-fold
    const PointAnswers paraboloid = geometric_method().point_field(smooth)(gaussian_at({64.0, 64.0}, 12.0));
    ASSERT_TRUE(paraboloid.sample && paraboloid.pdf);
    const testing::DiskChiSquare chi_square{20, 200'000};
    for (double degrees : {0.0, 30.0}) {
        const CounterRng rng(27, static_cast<std::uint64_t>(degrees));
        const Vec3 omega_i = direction_from_spherical(degrees * pi / 180.0, 0.4);
        const std::vector<long> observed = chi_square.histogram(testing::Grid::half_vector, omega_i, [&](long k) -> std::optional<Vec3> {
            const DirectionSample s = paraboloid.sample(omega_i, rng.uniform(2 * k), rng.uniform(2 * k + 1));
            if (!(s.pdf > 0.0)) return std::nullopt;
            if (k % 1000 == 0) {
                EXPECT_NEAR(s.pdf, paraboloid.pdf(omega_i, s.direction), 1e-9 * s.pdf);
            }
            return s.direction;
        });
        const auto expected = chi_square.expected_probabilities(testing::Grid::half_vector, omega_i,
                                                                [&](Vec3 omega_o) { return paraboloid.pdf(omega_i, omega_o); });
        const double p = chi_square.p_value(observed, expected);
        RecordProperty("p_value_" + std::to_string(int(degrees)), ::testing::PrintToString(p));
        EXPECT_GT(p, testing::sidak_significance(2)) << degrees << " degrees";
    }
    const LobeQuery rough = small_isotropic_query(Quantity::brdf);
    const Footprint footprint = gaussian_at({70.0, 30.0}, 6.0);
    const PointAnswers f = geometric_method().point_field(rough)(footprint);
    // The triangles of the point field's tree: N × ndf_oversampling 4, the tolerance in lobe pixels.
    const int ndf_resolution = 4 * rough.resolution;
    const std::vector<double> density = normal_density(*rough.surface, footprint, ndf_resolution, {1, 0.08, 0.0});
    for (double degrees : {0.0, 40.0}) {
        const CounterRng rng(25, static_cast<std::uint64_t>(degrees));
        const Vec3 omega_i = direction_from_spherical(degrees * pi / 180.0, 0.4);
        const long count = 40'000;
        double sum = 0.0, squares = 0.0;
        for (long k = 0; k < count; ++k) {
            const DirectionSample s = f.sample(omega_i, rng.uniform(2 * k), rng.uniform(2 * k + 1));
            if (!(s.pdf > 0.0)) continue;
            const double weight = f.eval(omega_i, s.direction)[0] * s.direction.z / s.pdf;
            sum += weight, squares += weight * weight;
        }
        const double mean = sum / count, error = std::sqrt(std::max(0.0, squares / count - mean * mean) / count);
        const double expected = albedo_from_ndf_image(density, ndf_resolution, omega_i);
        RecordProperty("relative_difference_" + std::to_string(int(degrees)), ::testing::PrintToString(mean / expected - 1.0));
        EXPECT_NEAR(mean, expected, 3.0 * error + 5e-4 * expected) << degrees << " degrees";
    }
}

TEST(GeometricPointField, ShadowingIsAnsweredFromTheImages) {
    const LobeQuery query = small_isotropic_query(Quantity::brdf);
    LobeQuery smith = query;
    smith.method_options = {{"shadowing", "smith"}};
    EXPECT_FALSE(geometric_method().point_field(smith)(query.footprint).eval);
}

}  // namespace
}  // namespace glintscope
