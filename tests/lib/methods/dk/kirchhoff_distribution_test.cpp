// The Kirchhoff distribution (Dong 2015 eq. 6-8) against closed forms: a flat patch's D_K is the
// window's transform at h = n; a Gaussian random field shows the coherent spike of weight e^{-g}
// when σ_h ≪ λ_q and approaches Beckmann when σ_h ≫ λ_q; its BRDF with per-pixel λ_q is the
// Kirchhoff-model lobe; its width matches the filtered NDF's on a rough surface (Dong's finding).
#include "methods/dk/kirchhoff_distribution.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "glintscope/lobe/compare.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "mean_lobe.hpp"
#include "glintscope/generate/generate.hpp"
#include "disk_sums.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/fit/ndf_models.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {
namespace {

using testing::second_moment;

LobeQuery query_for(Heightfield field, Quantity quantity, int resolution) {
    LobeQuery query;
    query.quantity = quantity;
    query.resolution = resolution;
    query.footprint.centre_um = field.centre_um();
    set_heightfield(query, std::move(field));
    return query;
}

// Stam's C1 (Gaussian-correlated) random field.
Heightfield gaussian_field(int size, double sigma_h_um, double correlation_um, double texel_um) {
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {size, size, texel_um};
    recipe.gaussian.correlation = CorrelationFunction::c1;
    recipe.gaussian.correlation_length_x_um = recipe.gaussian.correlation_length_y_um = correlation_um;
    recipe.gaussian.sigma_h_um = sigma_h_um;
    return generate(recipe);
}

// D_K of the flat patch at a half vector h.
double flat_distribution(Vec3 h, double sigma, double lambda) {
    const double q2 = std::pow(4.0 * pi / lambda, 2) * (h.x * h.x + h.y * h.y);
    return 16.0 * pi * sigma * sigma * h.z * h.z * std::exp(-sigma * sigma * q2) / (lambda * lambda);
}

TEST(KirchhoffDistribution, FlatPatchIsTheWindowTransformAtTheNormal) {
    // w = exp(−|s|²/(2σ²)): ∫ w e^{−i q·s} = 2πσ² e^{−σ²|q_xy|²/2}, so with A_c = πσ²
    // D_K(h) = q_z² |W|²/(4π² A_c) = 16π σ² h_z² e^{−σ² |q_xy|²}/λ_q², q = 4πh/λ_q.
    LobeQuery query = query_for(make_heightfield(64, 64, 1.0), Quantity::ndf, 128);
    query.footprint.sigma_um = 1.0;
    const LobeImage image = compute_lobe("dk", query);
    const double lambda = 0.555, sigma = 1.0;
    double difference = 0.0, norm = 0.0, expected_sum = 0.0;
    for (int r = 0; r < 128; ++r)
        for (int c = 0; c < 128; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, 128);
            if (!inside_unit_disk(p)) continue;
            const double expected = flat_distribution(direction_from_disk(p.x, p.y), sigma, lambda);
            difference += std::pow(image.at(0, r, c) - expected, 2);
            norm += expected * expected;
            expected_sum += expected;
        }
    EXPECT_LT(std::sqrt(difference / norm), 1e-4);
    // Σ D_K (2/N)² = ⟨h_z²⟩ ≈ 1 − ⟨|h_xy|²⟩ = 1 − (λ_q/(4πσ))² for the flat patch.
    EXPECT_NEAR(disk_sum(image), 1.0 - std::pow(lambda / (4.0 * pi * sigma), 2), 2e-3);
    EXPECT_NEAR(disk_sum(image), expected_sum * disk_pixel_area(128), 1e-4);
}

TEST(KirchhoffDistribution, RoughSurfaceSumsToOneWithinTheLeakage) {
    LobeQuery query = query_for(generate_builtin("isotropic"), Quantity::ndf, 96);
    query.supersample = 2;
    const double sum = disk_sum(compute_lobe("dk", query));
    RecordProperty("disk_sum", std::to_string(sum));
    // What h_z² < 1 and the part beyond the disk take: about ⟨|h_xy|²⟩ ≈ 0.5 rms slope² (0.17).
    EXPECT_GT(sum, 0.97);
    EXPECT_LE(sum, 1.0);
}

TEST(KirchhoffDistribution, PerPixelLambdaQLobeIsTheKirchhoffLobe) {
    LobeQuery query = query_for(generate_builtin("isotropic"), Quantity::brdf, 64);
    query.omega_i = direction_from_spherical(0.5, 0.7);
    query.material.name = "Au";
    query.wavelengths_um = {0.45, 0.65};
    query.supersample = 2;
    query.method_options["lambda_q"] = "per-pixel";
    const LobeImage dk = compute_lobe("dk", query);
    query.method_options.clear();
    query.model = DiffractionModel::kirchhoff;
    const LobeImage fft = compute_lobe("fft", query);
    for (const LayerComparison& layer : compare_lobes(dk, fft)) EXPECT_LT(layer.relative_l2, 1e-3);
}

TEST(KirchhoffDistribution, FixedLambdaQLobeIsEquationEightOfTheDistribution) {
    // Dong 2015 eq. 8 with G = F = 1: f_r = D_K(h)/(4 cos θ_i cos θ_o), D_K read from its table;
    // against the closed form at every sub-pixel's h.
    LobeQuery query = query_for(make_heightfield(64, 64, 1.0), Quantity::brdf, 64);
    query.footprint.sigma_um = 1.0;
    query.omega_i = direction_from_spherical(0.3, 0.0);
    query.supersample = 2;
    query.method_options.emplace("ndf_oversampling", "4");
    const LobeImage lobe = compute_lobe("dk", query);
    double difference = 0.0, norm = 0.0;
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 64; ++c) {
            if (!inside_unit_disk(disk_pixel_point(r, c, 64))) continue;
            double expected = 0.0;
            for (int b = 0; b < 2; ++b)
                for (int a = 0; a < 2; ++a) {
                    const DiskPoint p = disk_subpixel_point(r, c, b, a, 64, 2);
                    if (!inside_unit_disk(p)) continue;
                    const Vec3 omega_o = direction_from_disk(p.x, p.y);
                    const Vec3 h = normalize(query.omega_i + omega_o);
                    expected += flat_distribution(h, 1.0, 0.555) / (4.0 * query.omega_i.z * omega_o.z) / 4.0;
                }
            difference += std::pow(lobe.at(0, r, c) - expected, 2);
            norm += expected * expected;
        }
    RecordProperty("relative_l2", std::to_string(std::sqrt(difference / norm)));
    EXPECT_LT(std::sqrt(difference / norm), 0.02);
}

TEST(KirchhoffDistribution, SmoothRandomSurfaceShowsTheCoherentSpikeOfWeightExpMinusG) {
    // σ_h = 0.02 µm ≪ λ_q: g = (4πσ_h/λ_q)² = 0.205 at normal incidence. The coherent part of
    // |∫ w e^{−iq·s}|² keeps e^{−g} of the energy in the window's transform around n (standard
    // deviation λ_q/(4π√2 σ_c) ≈ 0.0062 in h, resolved by the sub-pixels); the diffuse rest
    // spreads ten times wider (standard deviation λ_q√2/(4πT) ≈ 0.062 per axis). The spike's
    // weight: the mass within 0.035 of n minus the diffuse level there, from the ring
    // 0.05-0.07 (that ring sits lower on the diffuse Gaussian: +0.009 left over, in the margin).
    // T = 4 texels, so that the interpolated surface keeps the samples' σ_h between them.
    const double lambda = 0.555;
    Heightfield field = gaussian_field(256, 0.02, 1.0, 0.25);
    const double sigma_h = compute_statistics(field).sq_um;
    LobeQuery query = query_for(std::move(field), Quantity::ndf, 128);
    query.footprint.sigma_um = 5.0;
    query.supersample = 4;
    const LobeImage mean = testing::mean_of_single_lobes("dk", query, {{16, 16}, {48, 16}, {16, 48}, {48, 48}});
    double central = 0.0, ring = 0.0, ring_area = 0.0;
    const double area = disk_pixel_area(128);
    for (int r = 0; r < 128; ++r)
        for (int c = 0; c < 128; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, 128);
            const double radius = std::hypot(p.x, p.y);
            if (radius < 0.035) central += mean.at(0, r, c) * area;
            if (radius > 0.05 && radius < 0.07) {
                ring += mean.at(0, r, c) * area;
                ring_area += area;
            }
        }
    const double spike = central - ring / ring_area * pi * 0.035 * 0.035;
    const double g = std::pow(4.0 * pi * sigma_h / lambda, 2);
    RecordProperty("spike_weight", std::to_string(spike));
    RecordProperty("exp_minus_g", std::to_string(std::exp(-g)));
    EXPECT_NEAR(spike, std::exp(-g), 0.025);
}

// A paraboloid H = −|s|²/(2R) has slopes −s/R: under the Gaussian weight |w|²/A_c (std σ_c/√2 per
// axis) they are Gaussian with std σ_c/(√2 R), so its geometric NDF is exactly Beckmann with
// α = σ_c/R (its P-NDF matches to 0.07%), and D_K's stationary-phase limit is that NDF. The heights
// under the weight spread by σ_h = σ_c²/(2R) = 0.5 µm. Pixel means of 8×8 sub-samples, as the
// reference: relative L2 0.34% at λ_q = 1 µm (σ_h/λ_q = 0.5), 0.040% at 0.25 µm (2), the rest the
// window's diffraction blur, ∝ λ_q. (A random field approaches its Beckmann NDF only through its
// finite patch statistics as well, and needs ~10⁷ samples per footprint at λ_q ≪ σ_h.)
TEST(KirchhoffDistribution, ApproachesBeckmannWhenHeightsFarExceedTheWavelength) {
    const double radius = 100.0, sigma_c = 10.0, alpha = sigma_c / radius;
    Heightfield field = make_heightfield(256, 256, 0.5);
    for (int r = 0; r < 256; ++r)
        for (int c = 0; c < 256; ++c) {
            const double x = (c + 0.5) * 0.5 - 64.0, y = 64.0 - (r + 0.5) * 0.5;
            field.at(r, c) = static_cast<float>(-(x * x + y * y) / (2.0 * radius));
        }
    const int resolution = 16;
    std::vector<double> beckmann(resolution * resolution, 0.0);
    for (int r = 0; r < resolution; ++r)
        for (int c = 0; c < resolution; ++c) {
            if (!inside_unit_disk(disk_pixel_point(r, c, resolution))) continue;
            for (int a = 0; a < 8; ++a)
                for (int b = 0; b < 8; ++b) {
                    const DiskPoint p = disk_subpixel_point(r, c, a, b, resolution, 8);
                    if (inside_unit_disk(p)) beckmann[r * resolution + c] += beckmann_ndf(alpha, alpha, direction_from_disk(p.x, p.y)) / 64.0;
                }
        }
    std::vector<double> errors;
    for (const std::string lambda_q : {"1um", "0.25um"}) {
        LobeQuery query = query_for(field, Quantity::ndf, resolution);
        query.footprint.sigma_um = sigma_c;
        query.method_options.insert_or_assign("lambda_q", lambda_q);
        query.supersample = 8;  // the Beckmann reference's sub-samples
        query.method_options.insert_or_assign("window", std::string("3"));
        query.method_options.insert_or_assign("oversampling", std::string("1"));
        const LobeImage image = compute_lobe("dk", query);
        double difference = 0.0, norm = 0.0;
        for (std::size_t k = 0; k < beckmann.size(); ++k) {
            difference += (image.values[k] - beckmann[k]) * (image.values[k] - beckmann[k]);
            norm += beckmann[k] * beckmann[k];
        }
        errors.push_back(std::sqrt(difference / norm));
    }
    EXPECT_LT(errors[1], errors[0] / 4.0);
    EXPECT_LT(errors[1], 0.002);
}

TEST(KirchhoffDistribution, WidthMatchesTheFilteredNdfOnARoughSurface) {
    LobeQuery query = query_for(generate_builtin("isotropic"), Quantity::ndf, 96);
    query.supersample = 2;
    const double dk = second_moment(compute_lobe("dk", query));
    query.supersample = 1;
    const double filtered = second_moment(compute_lobe("filtered", query));
    RecordProperty("dk_rms_width", std::to_string(std::sqrt(dk)));
    RecordProperty("filtered_rms_width", std::to_string(std::sqrt(filtered)));
    EXPECT_NEAR(std::sqrt(dk) / std::sqrt(filtered), 1.0, 0.2);
}

TEST(KirchhoffDistribution, RoughRandomSurfaceApproachesTheGeometricNdf) {
    // Dong 2015 §6: when σ_h ≫ λ_q the Kirchhoff distribution tends to the geometric NDF of the
    // same footprint, the P-NDF (the exact geometric limit, itself tested against Beckmann on a
    // whole field in tests/lib/methods/pndf). The oracle is the P-NDF of the same footprints and
    // not Beckmann itself: four footprints hold only ~10 correlation cells each, so their NDF
    // departs from Beckmann by far more than D_K departs from it. C1 field, σ_h = 3 µm = 5.4 λ_q,
    // T = 16 µm (per-axis rms slope σ_h√2/T ≈ 0.27), texel 0.5 µm, smooth at the λ_q scale.
    // What is left between the two: the diffraction blur (λ_q/(4πσ_c) ≈ 0.006 in h) and the
    // speckle of D_K. The speckle is what the pixels' L2 sees (measured 0.35 at 48², σ_c = 8 µm,
    // four footprints; a coherent spike or a lobe of the wrong width gives ≳ 1); the rms width
    // averages it out (measured ratio 1.007). oversampling=1 keeps the FFT grid small (~3 s).
    Heightfield field = gaussian_field(256, 3.0, 16.0, 0.5);
    LobeQuery query = query_for(std::move(field), Quantity::ndf, 48);
    query.footprint.sigma_um = 8.0;
    query.supersample = 1;
    query.method_options = {{"oversampling", "1"}};
    const std::vector<Point2> centres{{32, 32}, {96, 32}, {32, 96}, {96, 96}};
    const LobeImage dk = testing::mean_of_single_lobes("dk", query, centres);
    query.method_options = {};
    const LobeImage pndf = testing::mean_of_single_lobes("pndf", query, centres);
    double difference = 0.0, norm = 0.0;
    for (int r = 0; r < 48; ++r)
        for (int c = 0; c < 48; ++c) {
            difference += std::pow(dk.at(0, r, c) - pndf.at(0, r, c), 2);
            norm += pndf.at(0, r, c) * pndf.at(0, r, c);
        }
    const double width_ratio = std::sqrt(second_moment(dk) / second_moment(pndf));
    RecordProperty("relative_l2", std::to_string(std::sqrt(difference / norm)));
    RecordProperty("width_ratio", std::to_string(width_ratio));
    EXPECT_NEAR(width_ratio, 1.0, 0.03);
    EXPECT_LT(std::sqrt(difference / norm), 0.45);
}

}  // namespace
}  // namespace glintscope
