// The power spectral density and the autocorrelation curves against closed forms: a sinusoid's
// PSD peak at its frequency holding A²/4 on each side (A²/2 in all), Parseval (each PSD
// integrates to Sq²), a generated Gaussian-correlated field's autocorrelation exp(−τ²/T²) within
// its sampling error, f(0) = 1, and the s = 0.2 crossing of the curves at info's Sal.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/surface/spectra.hpp"

namespace glintscope {
namespace {

constexpr double kPi = std::numbers::pi;

// ∫ C_1D df over both signs of f, from the one-sided list (f = 0 and Nyquist counted once).
double two_sided_integral(const std::vector<double>& density, double step, int samples) {
    double sum = 0.0;
    for (std::size_t k = 0; k < density.size(); ++k)
        sum += (k == 0 || 2 * k == static_cast<std::size_t>(samples) ? 1.0 : 2.0) * density[k];
    return sum * step;
}

double radial_integral(const PowerSpectralDensity& psd) {
    double sum = 0.0;
    for (std::size_t b = 0; b < psd.radial_um4.size(); ++b)
        if (psd.radial_area_per_um2[b] > 0.0) sum += psd.radial_um4[b] * psd.radial_area_per_um2[b];
    return sum;
}

Heightfield gaussian_field(int size, double correlation_um, std::uint64_t seed) {
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {size, size, 1.0};
    recipe.seed = seed;
    recipe.gaussian.correlation_length_x_um = recipe.gaussian.correlation_length_y_um = correlation_um;
    recipe.gaussian.sigma_h_um = 0.2;
    return generate(recipe);
}

TEST(Spectra, SinusoidPeaksAtItsFrequencyWithItsPower) {
    // h = A sin(2π x/Λ): periods whole across a periodic 128 × 256 field of 0.5 µm texels.
    const double amplitude = 0.3, texel = 0.5;
    const int rows = 128, cols = 256, periods = 8;
    Heightfield field = make_heightfield(rows, cols, texel);
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
            field.at(r, c) = static_cast<float>(amplitude * std::sin(2.0 * kPi * periods * (c + 0.5) / cols));
    const PowerSpectralDensity psd = compute_power_spectral_density(field);
    EXPECT_FALSE(psd.hann_window);
    const double frequency = periods / (cols * texel);  // 1/Λ
    EXPECT_DOUBLE_EQ(psd.x_frequency_per_um[periods], frequency);
    // Two-sided: A²/4 at +1/Λ and A²/4 at −1/Λ; nothing elsewhere.
    EXPECT_NEAR(psd.x_um3[periods] * psd.frequency_step_x_per_um, amplitude * amplitude / 4.0, 1e-6);
    for (std::size_t k = 0; k < psd.x_um3.size(); ++k)
        if (k != static_cast<std::size_t>(periods)) {
            EXPECT_LT(psd.x_um3[k] * psd.frequency_step_x_per_um, 1e-9);
        }
    // Along y the heights do not vary: all the power sits at f_y = 0.
    EXPECT_NEAR(psd.y_um3[0] * psd.frequency_step_y_per_um, amplitude * amplitude / 2.0, 1e-6);
    // Radially: the annulus through ±1/Λ holds both peaks, A²/2.
    const double step = std::max(psd.frequency_step_x_per_um, psd.frequency_step_y_per_um);
    const auto annulus = static_cast<std::size_t>(std::lround(frequency / step));
    EXPECT_NEAR(psd.radial_um4[annulus] * psd.radial_area_per_um2[annulus], amplitude * amplitude / 2.0, 1e-6);
}

TEST(Spectra, EveryPowerSpectralDensityIntegratesToSqSquared) {  // Parseval
    const Heightfield field = gaussian_field(256, 6.0, 4);
    const PowerSpectralDensity psd = compute_power_spectral_density(field);
    const double sq2 = 0.2 * 0.2;  // the generator rescales each tile to Sq = σ_h exactly
    EXPECT_NEAR(psd.mean_square_um2, sq2, 1e-6 * sq2);
    EXPECT_NEAR(two_sided_integral(psd.x_um3, psd.frequency_step_x_per_um, field.cols), sq2, 1e-5 * sq2);
    EXPECT_NEAR(two_sided_integral(psd.y_um3, psd.frequency_step_y_per_um, field.rows), sq2, 1e-5 * sq2);
    EXPECT_NEAR(radial_integral(psd), sq2, 1e-5 * sq2);
    // The continuous form ∫ 2πf C(f) df of the radial PSD, out to the Nyquist circle where the
    // Gaussian spectrum has long vanished, agrees within the annuli's discretisation.
    double continuum = 0.0;
    const double step = psd.radial_frequency_per_um[1];
    for (std::size_t b = 1; 2.0 * psd.radial_frequency_per_um[b] <= 1.0; ++b)
        continuum += 2.0 * kPi * psd.radial_frequency_per_um[b] * psd.radial_um4[b] * step;
    EXPECT_NEAR(continuum, sq2, 0.02 * sq2);
}

TEST(Spectra, MeasuredScanIsWindowedAndStillIntegratesToItsMeanSquare) {
    Heightfield field = gaussian_field(128, 4.0, 9);
    field.periodic = false;
    field.at(10, 20) = std::nanf("");  // a drop-out leaves the sums
    const PowerSpectralDensity psd = compute_power_spectral_density(field);
    EXPECT_TRUE(psd.hann_window);
    const double m = psd.mean_square_um2;
    EXPECT_NEAR(two_sided_integral(psd.x_um3, psd.frequency_step_x_per_um, field.cols), m, 1e-5 * m);
    EXPECT_NEAR(radial_integral(psd), m, 1e-5 * m);
    // The Hann-weighted mean square is a sample of Sq² (0.04): within its sampling error.
    EXPECT_NEAR(m, 0.04, 0.2 * 0.04);
}

TEST(Spectra, GaussianFieldAutocorrelationIsItsClosedForm) {
    // Stam's C1: f(τ) = exp(−τ²/T²). 512² texels hold ~(512/T)² = 4096 correlation areas, so the
    // sampled autocorrelation scatters by about 1/√4096 · a few ≈ 0.05 around it.
    const double correlation = 8.0;
    const Heightfield field = gaussian_field(512, correlation, 2);
    const AutocorrelationCurves curves = compute_autocorrelation_curves(field);
    EXPECT_DOUBLE_EQ(curves.x[0], 1.0);
    EXPECT_DOUBLE_EQ(curves.y[0], 1.0);
    EXPECT_DOUBLE_EQ(curves.radial[0], 1.0);
    for (double lag : {2.0, 4.0, 8.0, 12.0, 16.0}) {
        const double expected = std::exp(-lag * lag / (correlation * correlation));
        const auto k = static_cast<std::size_t>(lag);
        EXPECT_NEAR(curves.x[k], expected, 0.06) << "x lag " << lag;
        EXPECT_NEAR(curves.y[k], expected, 0.06) << "y lag " << lag;
        // The radial mean averages all directions: a quarter of the axial scatter is ample.
        EXPECT_NEAR(curves.radial[k], expected, 0.03) << "radial lag " << lag;
    }
    // Sal: where the fastest direction falls to s = 0.2, T √ln 5 ≈ 10.2 µm; the radial mean,
    // which averages the directions, crosses s near it.
    const double sal = correlation * std::sqrt(std::log(5.0));
    EXPECT_NEAR(curves.parameters.sal_um, sal, 0.1 * sal);
    EXPECT_EQ(curves.parameters.sal_um, compute_areal_parameters(field).sal_um);  // info's Sal, exactly
    const auto below = static_cast<std::size_t>(std::ceil(1.1 * curves.parameters.sal_um));
    EXPECT_LT(curves.radial[below], curves.parameters.threshold);
    const auto above = static_cast<std::size_t>(std::floor(0.9 * curves.parameters.sal_um));
    EXPECT_GT(curves.radial[above], curves.parameters.threshold);
}

TEST(Spectra, FlatFieldsAndBadThresholdsAreRefused) {
    const Heightfield flat = make_heightfield(16, 16, 1.0, 0.5f);
    EXPECT_THROW(compute_autocorrelation_curves(flat), Error);
    EXPECT_THROW(compute_autocorrelation_curves(gaussian_field(64, 4.0, 1), 1.0), Error);
    Heightfield missing = make_heightfield(4, 4, 1.0, std::nanf(""));
    missing.at(0, 0) = 1.0f;
    EXPECT_THROW(compute_power_spectral_density(missing), Error);  // one valid height
}

}  // namespace
}  // namespace glintscope
