// Gabor importance sampling (Yan 2018 §5 with the exact mixture pdf, gabor_sampling.hpp): the χ²
// test of the BSDF conformance suite over the footprint's kernel mixture itself (a Gabor eval costs
// 15–50 µs, too much for 10⁶ samples per incidence through Bsdf::sample), the pdf's integral, and
// through the BSDF the mean weight f_r cosθ_o / pdf against the albedo.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/counter_rng.hpp"
#include "disk_chi_square.hpp"
#include "glintscope/bsdf/bsdf.hpp"
#include "mean_weight.hpp"
#include "method_cases.hpp"
#include "methods/gabor/gabor_kernels.hpp"
#include "methods/gabor/gabor_math.hpp"
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
    return gabor::KernelMixture(
        std::make_shared<const gabor::SlopeIndex>(
            gabor::gather_kernels(*query.surface, grid, window, query.footprint.centre_um).arrays, grid),
        model, query.wavelengths_um);
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

// The mixture's density written out plainly over every kernel of the footprint (docs/gabor.md
// "Sampling"): (1/L) Σ_λ Σ_k (w_k/Σw) N(d; μ_k, S_k,λ) cut at e^{−cut} of its peak and renormalised,
// times cosθ_o, with the sum's own exp (gabor_math::exp_neg), so that only the order of the terms
// differs from pdf().
double pdf_over_every_kernel(const gabor::KernelArrays& k, const gabor::KernelGrid& grid, DiffractionModel model,
                             double cut, const std::vector<double>& wavelengths, Vec3 omega_i, Vec3 omega_o) {
    const double xi = xi3(model, omega_i, {-omega_i.x, -omega_i.y, omega_i.z});
    const double sigma = grid.sigma_um;
    const double curvature = grid.order == 2 ? sigma * sigma * xi * xi : 0.0;
    double total_weight = 0.0;
    for (std::size_t i = 0; i < k.size(); ++i) total_weight += k.weight[i];
    double density = 0.0;
    for (const double lambda : wavelengths) {
        const double diffraction = lambda * lambda / (4.0 * pi * pi * sigma * sigma);
        for (std::size_t i = 0; i < k.size(); ++i) {
            const double a = grid.order == 2 ? k.curvature_xx[i] : 0.0;
            const double b = grid.order == 2 ? k.curvature_xy[i] : 0.0;
            const double c = grid.order == 2 ? k.curvature_yy[i] : 0.0;
            // S = diffraction I + curvature (H'')².
            const double sxx = diffraction + curvature * (a * a + b * b);
            const double sxy = curvature * b * (a + c);
            const double syy = diffraction + curvature * (c * c + b * b);
            const double det = sxx * syy - sxy * sxy;
            // e = d − μ_k with d = ω_o,xy and μ_k = −ω_i,xy − ξ3 H'_k.
            const double ex = omega_o.x + omega_i.x + xi * k.slope_x[i];
            const double ey = omega_o.y + omega_i.y + xi * k.slope_y[i];
            const double half_q = (syy * ex * ex - 2.0 * sxy * ex * ey + sxx * ey * ey) / (2.0 * det);
            if (half_q < cut)
                density += k.weight[i] / total_weight * gabor_math::exp_neg(half_q) /
                           (2.0 * pi * std::sqrt(det) * -std::expm1(-cut));
        }
    }
    return density / wavelengths.size() * omega_o.z;
}

// The pdf sums only the kernels of the slope index's cells that can reach d; every other kernel's
// cut Gaussian is 0 there, so it equals the sum over every kernel (to rounding), at both orders,
// for a model with fixed covariances (R-OHS) and two whose chirped covariances are made per call,
// on two footprints, near the mirror direction and over the whole disk (where one dropped kernel
// may be most of the density: a reach shrunk by 10% fails this).
TEST(GaborSampling, PdfOfTheReachingCellsIsThePdfOfEveryKernel) {
    const std::shared_ptr<const BicubicInterpolant> surface = testing::isotropic_builtin_query(Quantity::brdf).surface;
    const std::vector<double> wavelengths = {0.45, 0.6};
    const CounterRng rng(22, 7);
    long uniform_index = 0;
    int compared = 0, tails = 0;
    for (const Point2 centre : {Point2{512.0, 512.0}, Point2{311.0, 702.5}})
        for (const int order : {1, 2})
            for (const DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::ghs, DiffractionModel::kirchhoff}) {
                GaborSettings settings;
                settings.order = order;
                const gabor::KernelGrid grid = gabor::kernel_grid(surface->texel_um(), settings);
                Footprint footprint;
                footprint.centre_um = centre;
                footprint.sigma_um = centre.x == 512.0 ? 10.0 : 7.0;
                const gabor::CoherenceWindow window(footprint, settings.footprint_sigmas);
                const gabor::KernelArrays all = gabor::gather_kernels(*surface, grid, window, centre).arrays;
                const auto index = std::make_shared<const gabor::SlopeIndex>(all, grid);
                const gabor::KernelMixture m(index, model, wavelengths);
                // The cut holds each kernel's box where the Gaussians are the transforms' magnitudes.
                const double cut =
                    phase_depends_on_outgoing(model) ? 25.0 : settings.kernel_sigmas * settings.kernel_sigmas;
                for (const double degrees : {20.0, 70.0}) {
                    const Vec3 omega_i = incidence(degrees);
                    for (int j = 0; j < 150; ++j) {
                        // Every other direction near the mirror direction, the rest uniform over the disk.
                        const double u1 = rng.uniform(uniform_index++), u2 = rng.uniform(uniform_index++);
                        const double radius = j % 2 == 0 ? 0.2 * std::sqrt(u1) : std::sqrt(u1);
                        double x = radius * std::cos(2.0 * pi * u2), y = radius * std::sin(2.0 * pi * u2);
                        if (j % 2 == 0) x -= omega_i.x, y -= omega_i.y;
                        if (!(x * x + y * y < 1.0)) continue;
                        const Vec3 omega_o = direction_from_disk(x, y);
                        const double every = pdf_over_every_kernel(index->kernels(), grid, model, cut, wavelengths, omega_i, omega_o);
                        const double indexed = m.pdf(omega_i, omega_o);
                        EXPECT_NEAR(indexed, every, 1e-12 * every)
                            << "order " << order << ", model " << static_cast<int>(model) << ", " << degrees << " degrees";
                        ++compared;
                        tails += every > 0.0 && every < 1e-3;
                    }
                }
            }
    EXPECT_GT(compared, 3000);
    EXPECT_GT(tails, 100) << "directions in the tails, where a missed kernel would show";
}

// Bsdf::sample of a footprint's BSDF gets f_r and the pdf from one pass over the kernels eval
// sums where the mixture's Gaussians share their exponents with the transforms (R-OHS, OHS at
// second order), then the pdf's other kernels: its weight is eval's f_r cosθ_o / pdf and its pdf
// is pdf()'s, as on the paths that share nothing (first order, GHS).
TEST(GaborSampling, SampleSharingItsSumsAgreesWithEvalAndPdf) {
    LobeQuery query = testing::isotropic_builtin_query(Quantity::brdf);
    const CounterRng rng(22, 8);
    long index = 0;
    for (const int order : {2, 1})
        for (const DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::ohs, DiffractionModel::ghs}) {
            query.method_options["order"] = std::to_string(order);
            query.model = model;
            const Bsdf bsdf = make_bsdf("gabor", query);
            int sampled = 0;
            for (const double degrees : {20.0, 60.0})
                for (int k = 0; k < 60; ++k) {
                    const Vec3 omega_i = incidence(degrees);
                    const BsdfSample s = bsdf.sample(omega_i, rng.uniform(index), rng.uniform(index + 1));
                    index += 2;
                    if (!(s.pdf > 0.0)) continue;
                    ++sampled;
                    EXPECT_NEAR(s.pdf, bsdf.pdf(omega_i, s.omega_o), 1e-12 * s.pdf) << "order " << order;
                    const std::vector<double> f = bsdf.eval(omega_i, s.omega_o);
                    for (std::size_t layer = 0; layer < f.size(); ++layer) {
                        const double weight = f[layer] * s.omega_o.z / s.pdf;
                        EXPECT_NEAR(s.weight[layer], weight, 1e-12 * weight + 1e-300) << "order " << order;
                    }
                }
            EXPECT_GT(sampled, 80);
        }
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
