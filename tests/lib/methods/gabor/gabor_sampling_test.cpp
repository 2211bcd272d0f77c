// Gabor importance sampling (Yan 2018 §5 with the exact mixture pdf, gabor_sampling.hpp): the χ²
// test of the BSDF conformance suite over the footprint's kernel mixture itself (a Gabor eval costs
// 15–50 µs, too much for 10⁶ samples per incidence through Bsdf::sample), the pdf's integral, and
// through the BSDF the mean weight f_r cosθ_o / pdf against the albedo.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/counter_rng.hpp"
#include "disk_chi_square.hpp"
#include "glintscope/bsdf/bsdf.hpp"
#include "mean_weight.hpp"
#include "method_cases.hpp"
#include "methods/gabor/gabor_kernels.hpp"
#include "methods/gabor/gabor_sampling.hpp"

namespace glintscope {
namespace {

Vec3 incidence(double degrees) { return direction_from_spherical(degrees * pi / 180.0, 0.4); }

// The kernel mixture of the conformance suite's footprint (isotropic builtin, σ_c = 10 µm,
// 0.45 and 0.6 µm) at a given order and model.
gabor::KernelMixture mixture(int order, DiffractionModel model) {
    const LobeQuery query = testing::isotropic_builtin_query(Quantity::brdf);
    GaborSettings settings;
    settings.order = order;
    const gabor::KernelGrid grid = gabor::kernel_grid(query.surface->texel_um(), settings);
    const gabor::CoherenceWindow window(query.footprint, settings.footprint_sigmas);
    return gabor::KernelMixture(gabor::gather_kernels(*query.surface, grid, window, query.footprint.centre_um).arrays,
                                grid, model, query.wavelengths_um);
}

// 10⁶ draws counted on 40 × 40 cells of the disk of ω_o against the pdf integrated over them
// (its integral is checked against the share of draws that found a direction), at the given
// incidences, Šidák-corrected over `tests`; sample()'s pdf is pdf()'s on every 997th draw.
void expect_draws_follow_the_pdf(const gabor::KernelMixture& m, const std::vector<double>& degrees_list, int tests) {
    constexpr testing::DiskChiSquare chi_square{40, 1'000'000};
    const CounterRng rng(22, 5);
    for (double degrees : degrees_list) {
        const Vec3 omega_i = incidence(degrees);
        std::vector<long> observed(chi_square.cells * chi_square.cells + 1, 0);
        for (long k = 0; k < chi_square.samples; ++k) {
            const double u1 = rng.uniform(2 * k), u2 = rng.uniform(2 * k + 1);
            const std::optional<Vec3> omega_o = m.draw(omega_i, u1, u2);
            if (!omega_o) {
                ++observed.back();
                continue;
            }
            if (k % 997 == 0) {
                const DirectionSample s = m.sample(omega_i, u1, u2);
                ASSERT_EQ(s.direction.x, omega_o->x);
                ASSERT_NEAR(s.pdf, m.pdf(omega_i, *omega_o), 1e-12 * s.pdf);
                ASSERT_GT(s.pdf, 0.0);
            }
            ++observed[chi_square.cell_of(testing::Grid::omega_o, omega_i, *omega_o)];
        }
        const auto expected = chi_square.expected_probabilities(testing::Grid::omega_o, omega_i,
                                                                [&](Vec3 omega) { return m.pdf(omega_i, omega); });
        EXPECT_GT(chi_square.p_value(observed, expected), testing::sidak_significance(tests))
            << "incidence " << degrees << " degrees";
    }
}

TEST(GaborSampling, ChirpedKernelDrawsFollowTheMixturePdfWhichIntegratesToOne) {
    expect_draws_follow_the_pdf(mixture(2, DiffractionModel::rohs), {0.0, 30.0, 70.0}, 4);
}

// R-GHS places the Gaussians with ξ3 = ψ·n at ω_i's mirror direction, and its chirped
// covariances are made per call: the other code path of pdf().
TEST(GaborSampling, RghsDrawsFollowTheMixturePdf) {
    expect_draws_follow_the_pdf(mixture(2, DiffractionModel::rghs), {70.0}, 4);
}

TEST(GaborSampling, FirstOrderDrawsFollowTheMixturePdf) {
    expect_draws_follow_the_pdf(mixture(1, DiffractionModel::rohs), {30.0}, 4);
}

// The weight is honest: its mean over samples is ∫ f_r cosθ_o dω_o, which albedo() computes by
// quadrature of eval (the image's disk sum at supersample 4, N = 32), within 3 standard errors
// of 10,000 weights (1.2–1.5%: the coherent sum's speckle makes f_r/pdf vary) plus 0.2%. This
// catches a wrong Jacobian or normalisation, not a bias of 1%: the quadrature itself moves by
// 1.3% at 30° between N = 24 and 32 (R-OHS grows as 1/cosθ_o toward the rim). Measured at N = 32:
// 0.987 against 0.973 and 0.966 against 0.975 at normal incidence, 1.047 against 1.029 and 1.027
// against 1.022 at 30°.
TEST(GaborSampling, MeanWeightIsTheAlbedo) {
    LobeQuery query = testing::isotropic_builtin_query(Quantity::brdf);
    query.resolution = 32;
    const Bsdf bsdf = make_bsdf("gabor", query);
    ASSERT_TRUE(bsdf.samples_directly());
    for (double degrees : {0.0, 30.0}) {
        const Vec3 omega_i = incidence(degrees);
        const std::vector<double> albedo = bsdf.albedo(omega_i);
        const testing::MeanWeight weights = testing::mean_weight(bsdf, omega_i, 10'000, CounterRng(22, 6));
        for (std::size_t layer = 0; layer < albedo.size(); ++layer) {
            const double mean = weights.mean[layer];
            const double error = weights.standard_error[layer];
            EXPECT_NEAR(mean, albedo[layer], 3.0 * error + 2e-3 * albedo[layer]) << "albedo " << albedo[layer] << " mean " << mean
                << degrees << " degrees, layer " << layer << ": s.e. " << error;
        }
    }
}

}  // namespace
}  // namespace glintscope
