// Jakob 2014 §3.4's importance sampling of the discrete BRDF (flake_sampling.hpp): the χ² test of
// the BSDF conformance suite over the sampler itself (a discrete eval counts flakes in a tree,
// tens of µs, too much for 10⁶ samples per incidence through Bsdf::sample, which computes the
// weight), the pdf's integral, its quadrature of the cone against a fine rule, and through the
// BSDF the mean weight f_r cosθ_o / pdf against the albedo.
#include "methods/discrete/flake_sampling.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/counter_rng.hpp"
#include "disk_chi_square.hpp"
#include "glintscope/bsdf/bsdf.hpp"
#include "mean_weight.hpp"
#include "method_cases.hpp"
#include "methods/discrete/discrete_lobe.hpp"

namespace glintscope {
namespace {

Vec3 incidence(double degrees) { return direction_from_spherical(degrees * pi / 180.0, 0.4); }

// The conformance suite's query (isotropic builtin, σ_c = 10 µm, 0.45 and 0.6 µm, N = 40) with the
// discrete defaults: Beckmann α = 0.2, 10⁶ flakes, the cone of one pixel (1.6°).
LobeQuery discrete_query() {
    LobeQuery query = testing::isotropic_builtin_query(Quantity::brdf);
    query.resolution = 40;
    return query;
}

FlakeSampler sampler_of(const LobeQuery& query) {
    DiscreteSetup setup;
    setup_discrete(query, setup);
    return FlakeSampler(setup.sampler, setup.cone);
}

// 10⁶ draws counted on 40 × 40 cells of the disk of the half vector against the pdf integrated
// over them (its integral checked against the share of draws that found a direction), Šidák-
// corrected over the incidences; sample()'s pdf is pdf()'s on every 997th draw. The cells are of
// h, as for dk's sampler: the density per area of the disk of ω_o grows as 1/cosθ_o toward the
// rim, where the grazing half of a microfacet lobe lies, and 4 × 4 points per cell overestimate its
// integral there (measured: Σ = 1.017 for 0.998 at normal incidence, 1.35 for 0.71 at 70°); over
// h it is bounded (Σ = 0.9979 and 0.7129).

void expect_draws_follow_the_pdf(const FlakeSampler& sampler, const std::vector<double>& degrees_list) {
    constexpr testing::DiskChiSquare chi_square{40, 1'000'000};
    constexpr auto grid = testing::Grid::half_vector;
    const CounterRng rng(22, 7);
    for (double degrees : degrees_list) {
        const Vec3 omega_i = incidence(degrees);
        const std::vector<long> observed = chi_square.histogram(grid, omega_i, [&](long k) {
            const double u1 = rng.uniform(2 * k), u2 = rng.uniform(2 * k + 1);
            const std::optional<Vec3> omega_o = sampler.draw(omega_i, u1, u2);
            if (omega_o && k % 997 == 0) {
                const DirectionSample s = sampler.sample(omega_i, u1, u2);
                EXPECT_EQ(s.direction.x, omega_o->x);
                EXPECT_EQ(s.pdf, sampler.pdf(omega_i, *omega_o));
                EXPECT_GT(s.pdf, 0.0);
            }
            return omega_o;
        });
        const auto expected =
            chi_square.expected_probabilities(grid, omega_i, [&](Vec3 omega) { return sampler.pdf(omega_i, omega); });
        EXPECT_GT(chi_square.p_value(observed, expected), testing::sidak_significance(int(degrees_list.size())))
            << "incidence " << degrees << " degrees";
    }
}

TEST(FlakeSampling, DrawsFollowThePdfWhichIntegratesToOne) {
    expect_draws_follow_the_pdf(sampler_of(discrete_query()), {0.0, 30.0, 70.0});
}

// GGX's slope radius and a wide cone (Jakob 2014's ornaments: γ = 5°), anisotropic.
TEST(FlakeSampling, GgxWithAWideConeFollowsThePdf) {
    LobeQuery query = discrete_query();
    query.method_options = {{"distribution", "ggx"}, {"alpha_x", "0.1"}, {"alpha_y", "0.3"}, {"cone", "5"}};
    expect_draws_follow_the_pdf(sampler_of(query), {45.0});
}

// The pdf's quadrature of the cone (4 × 8 nodes) against a 64 × 256 midpoint rule of the same
// convolution, at directions of the lobe away from the horizon: exact to 1e-9 for the default cone,
// to 1e-4 for a 5° cone.
TEST(FlakeSampling, PdfIsTheConvolutionOfTheSmoothDensityWithTheCone) {
    for (double cone_deg : {1.6, 5.0}) {
        const double cone = cone_deg * pi / 180.0;
        const FlakeSampler sampler({SmoothSampler::Shape::beckmann, 0.4, 0.25}, cone);
        const Vec3 omega_i = incidence(30.0);
        for (const Vec3 omega_o : {direction_from_spherical(0.5, pi + 0.4), direction_from_spherical(0.2, 1.0),
                                   direction_from_spherical(0.9, pi + 0.1)}) {
            // (1/Ω_γ) ∫ p(ω') dω' over the cone about ω_o, midpoints in cosθ and φ.
            const double one_minus_cos_cone = 1.0 - std::cos(cone);
            const Vec3 t = normalize(cross(omega_o, {0.0, 1.0, 0.0})), s = cross(omega_o, t);
            constexpr int kRings = 64, kAzimuths = 256;
            double sum = 0.0;
            for (int a = 0; a < kRings; ++a) {
                const double c = 1.0 - one_minus_cos_cone * (a + 0.5) / kRings, sine = std::sqrt(1.0 - c * c);
                for (int b = 0; b < kAzimuths; ++b) {
                    const double phi = 2.0 * pi * (b + 0.5) / kAzimuths;
                    sum += sampler.reflected_pdf(omega_i, normalize((sine * std::cos(phi)) * t + (sine * std::sin(phi)) * s + c * omega_o));
                }
            }
            const double fine = sum / (kRings * kAzimuths);
            EXPECT_NEAR(sampler.pdf(omega_i, omega_o), fine, (cone_deg < 2.0 ? 1e-9 : 1e-4) * fine) << cone_deg << " degrees";
        }
    }
}

// The weight is honest: its mean over samples is ∫ f_r cosθ_o dω_o, which albedo() computes by
// quadrature of eval (the image's disk sum at supersample 4), within 3 standard errors of 3000
// weights. A discrete eval walks the flake tree from its root (tens of µs), so the BSDF is made
// at N = 16 (3.2k evals per albedo) with N = 40's default cone of 1.6° (N = 16's, 4°, costs ten
// times as much per count): the test catches a wrong Jacobian, normalisation or cone, not a
// bias of 1%.
TEST(FlakeSampling, MeanWeightIsTheAlbedo) {
    LobeQuery query = discrete_query();
    query.resolution = 16;
    query.method_options["cone"] = "1.6";
    const Bsdf bsdf = make_bsdf("discrete", query);
    ASSERT_TRUE(bsdf.samples_directly());
    ASSERT_TRUE(bsdf.evaluates_directly());
    for (double degrees : {0.0, 30.0}) {
        const Vec3 omega_i = incidence(degrees);
        const std::vector<double> albedo = bsdf.albedo(omega_i);
        const testing::MeanWeight weights = testing::mean_weight(bsdf, omega_i, 3000, CounterRng(22, 8));
        for (std::size_t layer = 0; layer < albedo.size(); ++layer) {
            const double mean = weights.mean[layer];
            const double error = weights.standard_error[layer];
            EXPECT_NEAR(mean, albedo[layer], 3.0 * error) << "albedo " << albedo[layer] << " mean " << mean << ", "
                                                          << degrees << " degrees, layer " << layer << ": s.e. " << error;
        }
    }
}

// With the surface's own P-NDF as the flakes' distribution the sampler is the Beckmann
// distribution of its mean square slopes, doubled (here α_sample = 0.50 and 0.55), which matches
// the flakes only roughly: the weight stays honest. Measured at N = 16, cone 1.6°: albedo 1.000
// and 1.024 at 0° and 30°, mean weights 0.995 and 1.013 with a standard error of 0.031.
TEST(FlakeSampling, PndfFlakesMeanWeightIsTheAlbedo) {
    LobeQuery query = discrete_query();
    query.resolution = 16;
    query.method_options = {{"distribution", "pndf"}, {"cone", "1.6"}};
    const Bsdf bsdf = make_bsdf("discrete", query);
    for (double degrees : {0.0, 30.0}) {
        const Vec3 omega_i = incidence(degrees);
        const std::vector<double> albedo = bsdf.albedo(omega_i);
        const testing::MeanWeight weights = testing::mean_weight(bsdf, omega_i, 3000, CounterRng(22, 10));
        EXPECT_NEAR(weights.mean[0], albedo[0], 3.0 * weights.standard_error[0]) << degrees << " degrees";
    }
}

}  // namespace
}  // namespace glintscope
