// ISO 25178-2 areal parameters against closed forms: a sinusoid (Sq = A/√2, Ssk = 0, Sku = 1.5,
// Sdq = √2 πA/Λ, Sal from cos(2πt/Λ) = s, Std along the ridges), a tilted plane
// (Sdr = 1/cos θ − 1), a Gaussian field with an exactly Gaussian autocorrelation of lengths
// Tx, Ty (Sal = √ln(1/s)·min T, Str = min T / max T, Ssk → 0, Sku → 3), missing points that must
// not bias them, and a correlation longer than the field reported as a bound.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <fftw3.h>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/surface/areal_parameters.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {
namespace {

constexpr double kPi = std::numbers::pi;

// h = A sin(2π (nx·x/W + ny·y/H)): whole periods across a periodic field.
Heightfield sinusoid(int rows, int cols, double texel, double amplitude, int nx, int ny, bool periodic = true) {
    Heightfield field = make_heightfield(rows, cols, texel);
    field.periodic = periodic;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            field.at(r, c) = static_cast<float>(
                amplitude * std::sin(2.0 * kPi * (nx * s.x / field.width_um() + ny * s.y / field.height_um())));
        }
    return field;
}

TEST(ArealParameters, SinusoidMatchesItsClosedForms) {
    const double amplitude = 0.4, texel = 0.5;
    const int cols = 256, periods = 4;  // Λ = 64 texels = 32 µm
    const double wavelength = cols * texel / periods;
    const ArealParameters p = compute_areal_parameters(sinusoid(128, cols, texel, amplitude, periods, 0));
    EXPECT_NEAR(p.sq_um, amplitude / std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(p.ssk, 0.0, 1e-4);
    EXPECT_NEAR(p.sku, 1.5, 1e-4);
    EXPECT_NEAR(p.sa_um, 2.0 * amplitude / kPi, 2e-3 * amplitude);  // mean |sin| = 2/π
    // The samples (at texel centres) straddle the crests by half a texel.
    EXPECT_NEAR(p.sp_um, amplitude * std::cos(kPi / 64.0), 1e-6);
    EXPECT_NEAR(p.sz_um, 2.0 * amplitude * std::cos(kPi / 64.0), 2e-6);
    // Central differences see sin(kΔ)/Δ instead of k: exact below, the continuum within 0.2%.
    const double k = 2.0 * kPi / wavelength;
    EXPECT_NEAR(p.sdq, amplitude * std::sin(k * texel) / texel / std::sqrt(2.0), 1e-5);
    EXPECT_NEAR(p.sdq, std::sqrt(2.0) * kPi * amplitude / wavelength, 2e-3 * p.sdq);
    // Sal: cos(2π t/Λ) = 0.2 along x, the fastest direction; along y it never decays.
    EXPECT_NEAR(p.sal_um, wavelength * std::acos(0.2) / (2.0 * kPi), 5e-3 * p.sal_um);
    EXPECT_FALSE(p.sal_is_lower_bound);
    EXPECT_NEAR(p.sal_direction_deg, 0.0, 0.01);
    EXPECT_TRUE(p.longest_is_lower_bound);
    EXPECT_TRUE(p.str_is_upper_bound);
    EXPECT_NEAR(p.longest_direction_deg, 90.0, 1.0);
    EXPECT_NEAR(p.longest_autocorrelation_at_edge, 1.0, 1e-3);
    // The ridges run along y.
    EXPECT_NEAR(p.std_deg, 90.0, 0.5);
}

TEST(ArealParameters, DiagonalRidgesGiveTheirDirection) {
    // Wave vector along (1, 1): ridges along (1, −1), at −45°.
    EXPECT_NEAR(compute_areal_parameters(sinusoid(128, 128, 1.0, 1.0, 3, 3)).std_deg, -45.0, 0.5);
    // Wave vector along (1, −1): ridges at +45°.
    EXPECT_NEAR(compute_areal_parameters(sinusoid(128, 128, 1.0, 1.0, 3, -3)).std_deg, 45.0, 0.5);
}

TEST(ArealParameters, TiltedPlaneHasSdrOfItsSecant) {
    Heightfield plane = make_heightfield(40, 60, 0.25);
    plane.periodic = false;
    const double a = 0.3, b = -0.4;  // |∇h| = 0.5, θ = atan 0.5
    for (int r = 0; r < plane.rows; ++r)
        for (int c = 0; c < plane.cols; ++c) {
            const Point2 s = sample_position(plane, r, c);
            plane.at(r, c) = static_cast<float>(a * s.x + b * s.y);
        }
    const ArealParameters p = compute_areal_parameters(plane);
    const double theta = std::atan(0.5);
    EXPECT_NEAR(p.sdq, 0.5, 1e-5);
    EXPECT_NEAR(p.sdr, 1.0 / std::cos(theta) - 1.0, 1e-5);
    EXPECT_NEAR(p.ssk, 0.0, 1e-3);
}

// A periodic field whose power spectrum is exactly that of the Gaussian autocorrelation
// exp(−(tx/Tx)² − (ty/Ty)²), with random phases: its circular autocorrelation is that Gaussian
// (summed over periods) whatever the phases.
Heightfield gaussian_field(int n, double tx, double ty, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> phase(0.0, 2.0 * kPi);
    const int bins = n / 2 + 1;
    std::vector<std::complex<double>> spectrum(static_cast<std::size_t>(n) * bins);
    for (int j = 0; j < n; ++j)
        for (int k = 0; k < bins; ++k) {
            const double fy = (j <= n / 2 ? j : j - n) / double(n), fx = k / double(n);
            const double power = std::exp(-kPi * kPi * (tx * tx * fx * fx + ty * ty * fy * fy));
            spectrum[j * bins + k] = std::polar(std::sqrt(power), phase(random));
        }
    // Columns kx = 0 and kx = n/2 hold both ±ky: Hermitian there, so the power is exactly as set.
    for (const int k : {0, n / 2})
        for (int j = 0; j <= n / 2; ++j) {
            std::complex<double>& value = spectrum[j * bins + k];
            if (j == 0 || j == n / 2)
                value = std::abs(value) * (value.real() < 0.0 ? -1.0 : 1.0);
            else
                spectrum[(n - j) * bins + k] = std::conj(value);
        }
    spectrum[0] = 0.0;
    std::vector<double> heights(static_cast<std::size_t>(n) * n);
    fftw_plan plan = fftw_plan_dft_c2r_2d(n, n, reinterpret_cast<fftw_complex*>(spectrum.data()), heights.data(),
                                          FFTW_ESTIMATE);
    fftw_execute(plan);
    fftw_destroy_plan(plan);
    Heightfield field = make_heightfield(n, n, 1.0);
    for (std::size_t i = 0; i < heights.size(); ++i) field.heights_um[i] = static_cast<float>(heights[i]);
    return field;
}

TEST(ArealParameters, AnisotropicGaussianFieldHasStrOfItsCorrelationLengths) {
    const double tx = 12.0, ty = 4.0;
    const ArealParameters p = compute_areal_parameters(gaussian_field(512, tx, ty, 7));
    const double root = std::sqrt(std::log(5.0));  // exp(−(t/T)²) = 0.2
    EXPECT_NEAR(p.sal_um, root * ty, 0.02 * root * ty);
    EXPECT_NEAR(p.sal_direction_deg, 90.0, 1.0);
    EXPECT_FALSE(p.longest_is_lower_bound);
    EXPECT_NEAR(p.longest_decay_um, root * tx, 0.02 * root * tx);
    EXPECT_NEAR(p.str, ty / tx, 0.03 * ty / tx);
    EXPECT_NEAR(p.std_deg, 0.0, 1.0);  // features elongated along x
    // Gaussian heights, within the sampling error of ~512²/(π Tx Ty) independent patches.
    EXPECT_NEAR(p.ssk, 0.0, 0.1);
    EXPECT_NEAR(p.sku, 3.0, 0.2);
}

TEST(ArealParameters, MissingPointsDoNotBiasTheAutocorrelation) {
    Heightfield field = gaussian_field(256, 6.0, 6.0, 3);
    const ArealParameters whole = compute_areal_parameters(field);
    for (std::size_t i = 0; i < field.size(); i += 37) field.heights_um[i] = std::numeric_limits<float>::quiet_NaN();
    const ArealParameters holed = compute_areal_parameters(field);
    EXPECT_NEAR(holed.sal_um, whole.sal_um, 0.01 * whole.sal_um);
    EXPECT_NEAR(holed.str, whole.str, 0.02);
    EXPECT_NEAR(holed.sq_um, whole.sq_um, 0.01 * whole.sq_um);
}

TEST(ArealParameters, NonPeriodicFieldUsesPairsInsideTheField) {
    // The same Gaussian field read as a measured scan: zero padding instead of wrapping, each lag
    // averaged over the pairs inside the field. Its estimate differs from the circular one only
    // by the missing wrap-around pairs, a few per cent at these lags.
    Heightfield field = gaussian_field(256, 12.0, 3.0, 5);
    const ArealParameters tile = compute_areal_parameters(field);
    field.periodic = false;
    const ArealParameters scan = compute_areal_parameters(field);
    EXPECT_NEAR(scan.sal_um, tile.sal_um, 0.05 * tile.sal_um);
    EXPECT_NEAR(scan.str, tile.str, 0.05 * tile.str);
    EXPECT_NEAR(scan.std_deg, tile.std_deg, 2.0);
    EXPECT_NE(scan.sal_um, tile.sal_um);  // the two estimators do differ
}

TEST(ArealParameters, ADirectionThatNeverDecaysGivesABoundNotNaN) {
    // A grating constant along y: its autocorrelation stays 1 along y to the field's edge.
    const ArealParameters p = compute_areal_parameters(sinusoid(64, 64, 1.0, 1.0, 2, 0, false));
    EXPECT_TRUE(p.longest_is_lower_bound);
    EXPECT_TRUE(p.str_is_upper_bound);
    EXPECT_NEAR(p.longest_decay_um, 32.0, 0.25);  // the ray ends at half the field
    EXPECT_NEAR(p.longest_autocorrelation_at_edge, 1.0, 1e-3);
    EXPECT_TRUE(std::isfinite(p.str));
    EXPECT_NEAR(p.str, p.sal_um / 32.0, 0.01 * p.str);
}

TEST(ArealParameters, SameForAnyThreadCount) {
    const Heightfield field = gaussian_field(128, 5.0, 3.0, 11);
    const ArealParameters one = with_threads(1, [&] { return compute_areal_parameters(field); });
    const ArealParameters four = with_threads(4, [&] { return compute_areal_parameters(field); });
    EXPECT_EQ(one.sq_um, four.sq_um);
    EXPECT_EQ(one.sdr, four.sdr);
    EXPECT_EQ(one.sal_um, four.sal_um);
    EXPECT_EQ(one.str, four.str);
    EXPECT_EQ(one.std_deg, four.std_deg);
}

TEST(ArealParameters, SurfaceReportAgreesWithTheSeparateCalls) {
    // info's report reads the statistics' 1/e lengths off the areal autocorrelation; the
    // statistics' own line spectra use the same estimator, so the two agree to float rounding, on
    // a tile, on a scan (pairs inside the field) and with missing points.
    for (const bool periodic : {true, false})
        for (const bool holes : {false, true}) {
            Heightfield field = gaussian_field(128, 9.0, 4.0, 13);
            field.periodic = periodic;
            if (holes)
                for (std::size_t i = 0; i < field.size(); i += 29) field.heights_um[i] = std::numeric_limits<float>::quiet_NaN();
            const SurfaceReport report = compute_surface_report(field);
            const SurfaceStatistics alone = compute_statistics(field);
            const ArealParameters iso = compute_areal_parameters(field);
            ASSERT_TRUE(report.iso.has_value());
            const SurfaceStatistics& s = report.statistics;
            EXPECT_NEAR(s.correlation_length_x_um, alone.correlation_length_x_um, 1e-5 * alone.correlation_length_x_um);
            EXPECT_NEAR(s.correlation_length_y_um, alone.correlation_length_y_um, 1e-5 * alone.correlation_length_y_um);
            EXPECT_NEAR(s.correlation_length_x_um, 9.0, 0.1 * 9.0);  // exp(−(t/T)²) = 1/e at t = T
            EXPECT_NEAR(s.correlation_length_y_um, 4.0, 0.1 * 4.0);
            EXPECT_EQ(s.sq_um, alone.sq_um);
            EXPECT_EQ(s.rms_slope_x, alone.rms_slope_x);
            EXPECT_EQ(s.rms_slope_y, alone.rms_slope_y);
            EXPECT_EQ(s.missing_count, alone.missing_count);
            EXPECT_EQ(report.iso->sq_um, iso.sq_um);
            EXPECT_EQ(report.iso->sdr, iso.sdr);
            EXPECT_EQ(report.iso->sal_um, iso.sal_um);
            EXPECT_EQ(report.iso->str, iso.str);
            EXPECT_EQ(report.iso->std_deg, iso.std_deg);
        }
    // Where the ISO parameters are not defined the statistics are still whole, with the reason.
    const SurfaceReport flat = compute_surface_report(make_heightfield(8, 8, 1.0, 2.0f));
    EXPECT_FALSE(flat.iso.has_value());
    EXPECT_EQ(flat.iso_undefined, "the heights do not vary");
    Heightfield strip = sinusoid(2, 64, 1.0, 1.0, 4, 0, false);
    const SurfaceReport narrow = compute_surface_report(strip);
    EXPECT_EQ(narrow.iso_undefined, "fewer than 3 x 3 samples");
    EXPECT_EQ(narrow.statistics.correlation_length_x_um, compute_statistics(strip).correlation_length_x_um);
    EXPECT_THROW(compute_surface_report(strip, 1.5), Error);
}

TEST(ArealParameters, FlatFieldsAndBadThresholdsAreRefused) {
    EXPECT_THROW(compute_areal_parameters(make_heightfield(8, 8, 1.0, 2.0f)), Error);
    EXPECT_THROW(compute_areal_parameters(sinusoid(16, 16, 1.0, 1.0, 1, 0), 1.5), Error);
}

}  // namespace
}  // namespace glintscope
