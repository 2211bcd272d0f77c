// Stam's expected lobes against closed forms (series limits and sums) and against the mean of
// exact FFT lobes over many footprints of generated surfaces with the same statistics.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <thread>
#include <string>
#include <utility>
#include <vector>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "methods/fft/fft_lobe.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/core/parallel.hpp"
#include "methods/stam/stam_lobe.hpp"

namespace glintscope {
namespace {

constexpr double kPi = std::numbers::pi;

Recipe gaussian_recipe(double sigma_h, double correlation_length, int size, double texel) {
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {size, size, texel};
    recipe.gaussian.sigma_h_um = sigma_h;
    recipe.gaussian.correlation_length_x_um = correlation_length;
    recipe.gaussian.correlation_length_y_um = correlation_length;
    return recipe;
}

LobeQuery query_for(Heightfield field, DiffractionModel model, double sigma_c, double lambda, int resolution,
                    int supersample) {
    LobeQuery query;
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = sigma_c;
    query.model = model;
    query.wavelengths_um = {lambda};
    query.resolution = resolution;
    query.supersample = supersample;
    set_heightfield(query, std::move(field));
    return query;
}

double image_sum(const std::vector<double>& values) {
    double sum = 0.0;
    for (double v : values) sum += v;
    return sum;
}

std::vector<double> as_doubles(const LobeImage& image) { return {image.values.begin(), image.values.end()}; }

// sqrt(Σ (a − b)² / Σ b²) over the pixels where `use` is set.
double relative_l2(const std::vector<double>& a, const std::vector<double>& b, const std::vector<bool>& use) {
    double difference = 0.0, norm = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (use[i]) {
            difference += (a[i] - b[i]) * (a[i] - b[i]);
            norm += b[i] * b[i];
        }
    return std::sqrt(difference / norm);
}

// ---- The series (Stam 1999 eq. 14–17) ------------------------------------------------------

// ∫ S_p dv = e^{−g} Σ_{m≥1} g^m/m! C(0)^m = 1 − e^{−g}: the diffuse part takes exactly the energy
// the coherent part e^{−g} loses. Midpoint rule over v on a grid covering the C1 lobe.
TEST(StamSeries, DiffuseEnergyIsOneMinusCoherentShare) {
    GaussianFieldParameters surface;
    surface.correlation_length_x_um = 2.0;
    surface.correlation_length_y_um = 3.0;
    surface.orientation_rad = 0.4;
    for (double g : {0.01, 1.6, 25.0, 400.0}) {
        const double reach = 1.5 * std::sqrt(std::max(g, 1.0)) * 10.0 / (kPi * 2.0);
        const int n = 400;
        const double dv = 2.0 * reach / n;
        const PoissonSeries series = poisson_series(surface, g);  // the weights once, not per v
        double sum = 0.0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                sum += stam_spectral_density(surface, series, -reach + (i + 0.5) * dv, -reach + (j + 0.5) * dv);
        EXPECT_NEAR(sum * dv * dv / (1.0 - std::exp(-g)), 1.0, 1e-6) << "g = " << g;
    }
}

// The C1 series sums its terms four at a time with its own e^x: the same terms summed one by one
// with std::exp agree to rounding (1e-13 relative), from the lobe's peak (v = 0) to far tails where
// the e^{−U²/4m} factors underflow for the low orders, at g of 1.6, 25 and 900 (the builtin
// isotropic surface at 0.5 µm, R-OHS: ~620 terms).
TEST(StamSeries, SimdC1SeriesEqualsTheTermByTermSum) {
    GaussianFieldParameters surface;
    surface.correlation_length_x_um = 10.0;
    surface.correlation_length_y_um = 10.0;
    for (double g : {1.6, 25.0, 900.0}) {
        const PoissonSeries series = poisson_series(surface, g);
        for (double v : {0.0, 0.05, 0.3, 1.0, 3.0}) {
            const double u2 = std::pow(2.0 * kPi * 10.0 * v, 2);
            double expected = 0.0;
            for (std::size_t k = 0; k < series.weights.size(); ++k) {
                const double m = series.first + static_cast<double>(k);
                expected += series.weights[k] * kPi * 100.0 / m * std::exp(-u2 / (4.0 * m));  // Stam 1999 eq. 15, D_1,m
            }
            const double simd = stam_spectral_density(surface, series, v, 0.0);
            EXPECT_NEAR(simd, expected, 1e-13 * expected) << "g = " << g << ", v = " << v;
            EXPECT_EQ(simd, stam_spectral_density(surface, g, v, 0.0));
        }
    }
}

// g ≪ 1: the series is its first term, the Born approximation (Stam 1999 §4.2):
// S_p → e^{−g} g D_1, the next term adding (g/4) e^{U²/8} of it (C1, v along x, U = 2πTv).
TEST(StamSeries, SmallRoughnessIsBornApproximation) {
    GaussianFieldParameters surface;
    surface.correlation_length_x_um = 2.0;
    surface.correlation_length_y_um = 2.0;
    const double g = 1e-3;
    for (double v : {0.0, 0.1, 0.3}) {
        const double u2 = std::pow(2.0 * kPi * 2.0 * v, 2);
        const double born = std::exp(-g) * g * kPi * 4.0 * std::exp(-u2 / 4.0);  // Stam 1999 eq. 15, m = 1
        const double second = 0.25 * g * std::exp(u2 / 8.0);
        EXPECT_NEAR(stam_spectral_density(surface, g, v, 0.0) / born, 1.0 + second, 0.1 * second) << "v = " << v;
    }
}

// g ≫ 1, C1: Stam's eq. 17 is the Beckmann microfacet lobe with α = 2σ_h/T, and with the
// Kirchhoff model (Stam's own factor) f_r → D(h)/(4 cos θ_i cos θ_o) exactly in the limit.
// Checked at g = (4πσ_h/λ)² ≈ 630 and at an oblique incidence.
TEST(StamLobe, LargeRoughnessIsBeckmann) {
    const double sigma_h = 1.0, t = 20.0, lambda = 0.5;
    LobeQuery query = query_for(generate(gaussian_recipe(sigma_h, t, 256, 1.0)), DiffractionModel::kirchhoff, 100.0,
                                lambda, 64, 1);
    query.omega_i = direction_from_spherical(0.3, 0.5);
    const LobeImage image = stam_lobe(query);
    const double alpha = 2.0 * sigma_h / t;
    std::vector<double> beckmann(image.values.size());
    std::vector<bool> all(image.values.size(), true);
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 64; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, 64);
            if (p.x * p.x + p.y * p.y >= 1.0) continue;
            const Vec3 omega_o = direction_from_disk(p.x, p.y);
            const Vec3 h = normalize(query.omega_i + omega_o);
            const double tan2 = (h.x * h.x + h.y * h.y) / (h.z * h.z);
            const double d = std::exp(-tan2 / (alpha * alpha)) / (kPi * alpha * alpha * std::pow(h.z, 4));
            beckmann[r * 64 + c] = d / (4.0 * query.omega_i.z * omega_o.z);
        }
    const double error = relative_l2(as_doubles(image), beckmann, all);
    std::printf("Beckmann limit: relative L2 %.4f\n", error);
    EXPECT_LT(error, 0.01);
}

// ---- Mean of FFT lobes over footprints of one generated Gaussian field ---------------------

// The mean of the FFT lobes of grid_side² footprints centred on a regular grid over the tile.
std::vector<double> mean_fft_lobe(const LobeQuery& query, int grid_side, double tile_um) {
    const int resolution = query.resolution;
    const double spacing = tile_um / grid_side;
    const int count = grid_side * grid_side;
    // Two footprint workers with single-threaded FFTs: at 48² one FFT lobe does not fill the cores.
    constexpr int kWorkers = 2;
    std::vector<std::vector<double>> sums(kWorkers, std::vector<double>(resolution * resolution));
    {
        std::vector<std::thread> workers;
        for (int t = 0; t < kWorkers; ++t)
            workers.emplace_back([&, t] {
                const ThreadScope single(1);
                LobeQuery own = query;
                for (int index = t; index < count; index += kWorkers) {
                    own.footprint.centre_um = {(index % grid_side + 0.5) * spacing, (index / grid_side + 0.5) * spacing};
                    const LobeImage lobe = compute_lobe("fft", own);
                    for (std::size_t k = 0; k < lobe.values.size(); ++k) sums[t][k] += lobe.values[k];
                }
            });
        for (std::thread& worker : workers) worker.join();
    }
    std::vector<double> mean(static_cast<std::size_t>(resolution) * resolution);
    for (std::size_t k = 0; k < mean.size(); ++k) mean[k] = (sums[0][k] + sums[1][k]) / count;
    return mean;
}

constexpr double kLambda = 0.5, kSigmaC = 12.0, kT = 2.0;
constexpr int kSize = 2048;
constexpr double kTexel = 0.25;

// An OHS query at normal incidence on a generated C1 field (T = 2 µm, 512 µm square), with FFT
// sampling fine enough for the widest lobe (g = 25: α = 0.2) not to alias into the disk, and the
// window out to 3σ_c, which holds all but e^{−9} of the footprint's |w|².
LobeQuery convergence_query(double sigma_h, int resolution, int supersample) {
    LobeQuery query = query_for(generate(gaussian_recipe(sigma_h, kT, kSize, kTexel)), DiffractionModel::ohs, kSigmaC,
                                kLambda, resolution, supersample);
    query.method_options = {{"step", "0.2"}, {"window", "3"}};
    return query;
}

// Each method's coherent part, e^{−g} times its flat-mirror lobe: for Stam ξ1 |w̃|²/A_c on the
// same sub-pixels, for the FFT its lobe of a flat field with the same sampling and window (the
// peak is narrower than a pixel, so both sample its flanks, where the FFT's truncated window shows).
struct Specular {
    std::vector<double> stam;
    std::vector<double> fft;
};

Specular specular_parts(const LobeQuery& query, double g) {
    const int n = query.resolution, k = query.supersample;
    LobeQuery flat = query_for(make_heightfield(512, 512, kTexel), DiffractionModel::ohs, kSigmaC, kLambda, n, k);
    flat.method_options = query.method_options;
    const LobeImage mirror = compute_lobe("fft", flat);
    Specular parts{std::vector<double>(mirror.values.size()), std::vector<double>(mirror.values.size())};
    for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
            double sum = 0.0;
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a) {
                    const DiskPoint p = disk_pixel_point(r, c, n, (a + 0.5) / k - 0.5, (b + 0.5) / k - 0.5);
                    const double cos_o2 = 1.0 - p.x * p.x - p.y * p.y;
                    if (cos_o2 <= 0.0) continue;
                    const double xi1 = std::sqrt(cos_o2) / (kLambda * kLambda);  // OHS, θ_i = 0
                    sum += xi1 * window_lobe(query.footprint, p.x / kLambda, p.y / kLambda);
                }
            const std::size_t i = static_cast<std::size_t>(r) * n + c;
            parts.stam[i] = std::exp(-g) * sum / (k * k);
            parts.fft[i] = std::exp(-g) * mirror.values[i];
        }
    return parts;
}

// window_lobe is the flat mirror's lobe over ξ1, for Dong 2015's rectangular patches too: against
// the FFT method's lobe of a flat field under a 8 × 5 µm box (OHS, normal incidence).
TEST(StamLobe, WindowLobeOfARectangularBoxIsTheFlatMirrorsLobe) {
    LobeQuery flat = query_for(make_heightfield(512, 512, kTexel), DiffractionModel::ohs, kSigmaC, kLambda, 64, 1);
    flat.footprint.shape = FootprintShape::box;
    flat.footprint.size_um = 8.0;
    flat.footprint.size_y_um = 5.0;
    const LobeImage mirror = compute_lobe("fft", flat);
    double worst = 0.0, peak = 0.0;
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 64; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, 64);
            const double cos_o2 = 1.0 - p.x * p.x - p.y * p.y;
            if (cos_o2 <= 0.0) continue;
            const double xi1 = std::sqrt(cos_o2) / (kLambda * kLambda);  // OHS, θ_i = 0
            const double expected = xi1 * window_lobe(flat.footprint, p.x / kLambda, p.y / kLambda);
            worst = std::max(worst, std::fabs(mirror.at(0, r, c) - expected));
            peak = std::max(peak, expected);
        }
    EXPECT_LT(worst / peak, 1e-3);
}

struct Convergence {
    double diffuse_l2 = 0.0;            // relative L2 of the diffuse parts, away from the peak
    double energy_ratio = 0.0;          // Σ mean FFT / Σ Stam
    double diffuse_energy_ratio = 0.0;  // the same for the diffuse parts
};

// The mean FFT lobe over grid_side² footprints against Stam's lobe (C1, σ_h, T = 2 µm), at 48²
// with 2×2 supersampling.
Convergence fft_mean_against_stam(double sigma_h, int grid_side) {
    LobeQuery query = convergence_query(sigma_h, 48, 2);
    const std::vector<double> mean = mean_fft_lobe(query, grid_side, kSize * kTexel);
    const double g = std::pow(4.0 * kPi * sigma_h / kLambda, 2);  // Stam 1999 §4: (k w σ_h)², w = 2 for OHS
    const Specular specular = specular_parts(query, g);
    query.method_options.clear();
    const std::vector<double> expected = as_doubles(stam_lobe(query));
    // Diffuse parts: each method's coherent part removed. Where it is not negligible (the few
    // pixels of the peak), a footprint's own coherent amplitude beats against its speckle, so the
    // diffuse comparison leaves those pixels out.
    std::vector<double> mean_diffuse(mean.size()), stam_diffuse(mean.size());
    std::vector<bool> away(mean.size());
    for (std::size_t k = 0; k < mean.size(); ++k) {
        mean_diffuse[k] = mean[k] - specular.fft[k];
        stam_diffuse[k] = expected[k] - specular.stam[k];
        away[k] = std::max(specular.stam[k], specular.fft[k]) <= 0.01 * stam_diffuse[k];
    }
    Convergence result;
    result.diffuse_l2 = relative_l2(mean_diffuse, stam_diffuse, away);
    result.energy_ratio = image_sum(mean) / image_sum(expected);
    result.diffuse_energy_ratio = image_sum(mean_diffuse) / image_sum(stam_diffuse);
    std::printf("sigma_h %.2f (g = %.1f): %d footprints, diffuse L2 %.4f, energy %.4f, diffuse energy %.4f\n",
                sigma_h, g, grid_side * grid_side, result.diffuse_l2, result.energy_ratio,
                result.diffuse_energy_ratio);
    return result;
}

// The brief's three regimes: σ_h = 0.05, 0.1, 0.2 µm, g = 1.6, 6.3, 25, 400 footprints each.
TEST(StamLobe, FftMeanConvergesWeakRoughness) {
    const Convergence c = fft_mean_against_stam(0.05, 20);
    EXPECT_LT(c.diffuse_l2, 0.06);
    EXPECT_NEAR(c.energy_ratio, 1.0, 0.02);
    EXPECT_NEAR(c.diffuse_energy_ratio, 1.0, 0.02);
}

TEST(StamLobe, FftMeanConvergesMediumRoughness) {
    const Convergence c = fft_mean_against_stam(0.1, 20);
    EXPECT_LT(c.diffuse_l2, 0.06);
    EXPECT_NEAR(c.energy_ratio, 1.0, 0.02);
    EXPECT_NEAR(c.diffuse_energy_ratio, 1.0, 0.02);
}

TEST(StamLobe, FftMeanConvergesStrongRoughness) {
    const Convergence c = fft_mean_against_stam(0.2, 20);
    EXPECT_LT(c.diffuse_l2, 0.06);
    EXPECT_NEAR(c.energy_ratio, 1.0, 0.02);
}

// g ≪ 1 (σ_h = 0.02 µm, g = 0.25): the mirror direction, sampled exactly (odd N, K = 1), keeps
// e^{−g} = 0.78 of a flat mirror's lobe in the mean FFT lobe, and Stam's lobe agrees there.
TEST(StamLobe, SmoothSurfaceKeepsCoherentShare) {
    const double sigma_h = 0.02, g = std::pow(4.0 * kPi * sigma_h / kLambda, 2);
    LobeQuery query = convergence_query(sigma_h, 49, 1);
    const std::vector<double> mean = mean_fft_lobe(query, 8, kSize * kTexel);
    const Specular specular = specular_parts(query, g);
    query.method_options.clear();
    const LobeImage stam = stam_lobe(query);
    const std::size_t centre = 24 * 49 + 24;
    const double stam_diffuse = stam.values[centre] - specular.stam[centre];
    const double coherent_share = (mean[centre] - stam_diffuse) / (specular.fft[centre] * std::exp(g));
    std::printf("g = %.3f: coherent share %.4f (e^-g = %.4f), FFT/Stam at the peak %.4f\n", g, coherent_share,
                std::exp(-g), mean[centre] / stam.values[centre]);
    EXPECT_NEAR(coherent_share / std::exp(-g), 1.0, 0.01);
    // The whole peak agrees up to the FFT window's truncation at 3σ_c (|w̃(0)|² lower by 1.1%).
    EXPECT_NEAR(mean[centre] / stam.values[centre], 1.0, 0.02);
}

// The mean FFT lobe of `model` over 49 footprints at θ_i = 30° (σ_h = 0.1 µm, g = 4.7 at the
// mirror direction) against Stam's lobe of the same model: relative L2 and energy ratio.
std::pair<double, double> oblique_convergence(DiffractionModel model) {
    LobeQuery query = convergence_query(0.1, 48, 2);
    query.model = model;
    query.omega_i = direction_from_spherical(kPi / 6.0, 0.3);
    const std::vector<double> mean = mean_fft_lobe(query, 7, kSize * kTexel);
    query.method_options.clear();
    const std::vector<double> expected = as_doubles(stam_lobe(query));
    const double error = relative_l2(mean, expected, std::vector<bool>(mean.size(), true));
    const double energy = image_sum(mean) / image_sum(expected);
    std::printf("%s, 49 footprints: relative L2 %.4f, energy %.4f\n", to_string(model).c_str(), error, energy);
    return {error, energy};
}

// Stam's own diffraction model is Yan's Kirchhoff, the slope term integrated by parts: the mean
// of exact Kirchhoff FFT lobes (with the slope term) converges to it at oblique incidence.
TEST(StamLobe, FftMeanConvergesKirchhoffOblique) {
    const auto [error, energy] = oblique_convergence(DiffractionModel::kirchhoff);
    EXPECT_LT(error, 0.1);
    EXPECT_NEAR(energy, 1.0, 0.03);
}

// The statistics carry over to GHS, whose phase ξ3 = ψ·n varies over the lobe.
TEST(StamLobe, FftMeanConvergesGhsOblique) {
    const auto [error, energy] = oblique_convergence(DiffractionModel::ghs);
    EXPECT_LT(error, 0.1);
    EXPECT_NEAR(energy, 1.0, 0.03);
}

// ---- Periodic-like surfaces (Stam 1999 §5) -------------------------------------------------

// Jacobi–Anger: Σ_m J_m(z)² = 1, the grating only redistributes light among its orders.
TEST(StamGrating, EfficienciesSumToOne) {
    for (double z : {0.3, 2.4048, 7.0, 30.0}) {
        double sum = 0.0;
        for (int m = -100; m <= 100; ++m) sum += grating_efficiency(m, z);
        EXPECT_NEAR(sum, 1.0, 1e-12) << "z = " << z;
    }
    EXPECT_NEAR(grating_efficiency(0, 2.404825557695773), 0.0, 1e-20);  // first zero of J_0
}

// Index of the brightest pixel of `values` within `radius` pixels of (row, col).
std::size_t brightest_near(const std::vector<double>& values, int n, double row, double col, int radius) {
    std::size_t best = 0;
    double best_value = -1.0;
    for (int r = static_cast<int>(std::lround(row)) - radius; r <= std::lround(row) + radius; ++r)
        for (int c = static_cast<int>(std::lround(col)) - radius; c <= std::lround(col) + radius; ++c) {
            if (r < 0 || c < 0 || r >= n || c >= n) continue;
            const std::size_t i = static_cast<std::size_t>(r) * n + c;
            if (values[i] > best_value) {
                best_value = values[i];
                best = i;
            }
        }
    return best;
}

// A generated sinusoidal grating (Λ = 4 µm, A = 0.1 µm, at 30°): one footprint's FFT lobe is
// already the expected lobe, so Stam's order sum must reproduce it pixel by pixel, each order
// at sin θ_m = sin θ_i + mλ/Λ along the grating vector with its Bessel efficiency.
TEST(StamGrating, MatchesFftOfGeneratedGrating) {
    Recipe recipe = default_recipe("grating");
    recipe.grid = {1024, 1024, 0.25};
    recipe.grating.angle_rad = kPi / 6.0;
    for (DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::ghs}) {
        LobeQuery query = query_for(generate(recipe), model, 10.0, 0.5, 95, 1);
        query.omega_i = direction_from_spherical(0.3, 0.0);
        const std::vector<double> fft = as_doubles(compute_lobe("fft", query));
        const LobeImage stam_image = stam_lobe(query);
        const std::vector<double> stam = as_doubles(stam_image);
        const double error = relative_l2(fft, stam, std::vector<bool>(fft.size(), true));
        const double energy = image_sum(fft) / image_sum(stam);
        std::printf("grating %s: relative L2 %.4f, energy %.4f\n", to_string(model).c_str(), error, energy);
        EXPECT_LT(error, 0.02);
        EXPECT_NEAR(energy, 1.0, 0.01);
        EXPECT_EQ(stam_image.metadata.at("stam.surface"), "grating");
        // Orders m = −3..3 sit where the grating equation puts them, in both images.
        for (int m = -3; m <= 3; ++m) {
            const double x = -query.omega_i.x - m * 0.5 / 4.0 * std::cos(kPi / 6.0);
            const double y = -query.omega_i.y - m * 0.5 / 4.0 * std::sin(kPi / 6.0);
            const double col = (x + 1.0) * 95 / 2.0 - 0.5, row = (1.0 - y) * 95 / 2.0 - 0.5;
            const std::size_t expected = static_cast<std::size_t>(std::lround(row)) * 95 + std::lround(col);
            EXPECT_EQ(brightest_near(fft, 95, row, col, 3), expected) << "order " << m;
            EXPECT_EQ(brightest_near(stam, 95, row, col, 3), expected) << "order " << m;
        }
    }
}

// CD tracks from the cd generator (Δx = 2.5 µm, Poisson bumps): the track period puts orders at
// v_x = m/Δx in Stam's lobe and in one footprint's FFT lobe alike.
TEST(StamCd, OrderPositionsMatchFftOfGeneratedTracks) {
    const int n = 95;
    LobeQuery query = query_for(generate_builtin("cd"), DiffractionModel::rohs, 8.0, 0.5, n, 1);
    // The bump edges are vertical steps, so the FFT gets a fixed fine step instead of its
    // slope-based one.
    query.method_options = {{"step", "0.05"}, {"window", "3"}};
    const std::vector<double> fft = as_doubles(compute_lobe("fft", query));
    query.method_options.clear();
    const LobeImage stam_image = stam_lobe(query);
    const std::vector<double> stam = as_doubles(stam_image);
    EXPECT_EQ(stam_image.metadata.at("stam.surface"), "cd");
    // ν_y b = 0.5 bumps overlap each bump: outside Stam's first-order treatment, and said so.
    EXPECT_NE(stam_image.metadata.at("stam.warning").find("overlap"), std::string::npos);
    // The run says it too, as the CLI prints and batch reports it.
    const std::vector<std::string> warnings = run_lobe("stam", query).warnings;
    EXPECT_NE(std::find(warnings.begin(), warnings.end(), "stam: " + stam_image.metadata.at("stam.warning")),
              warnings.end());
    // And the footprint's BSDF, whose closed form per direction it holds for just as much.
    EXPECT_EQ(make_bsdf("stam", query).warnings(), std::vector<std::string>{"stam: " + stam_image.metadata.at("stam.warning")});
    for (int m = -4; m <= 4; ++m) {
        const double x = -m * 0.5 / 2.5;
        const double col = (x + 1.0) * n / 2.0 - 0.5, row = (n - 1) / 2.0;
        const std::size_t fft_peak = brightest_near(fft, n, row, col, 3);
        // Odd orders fall on a pixel boundary at this N: the peak pixel is within half a pixel.
        EXPECT_LE(std::fabs(double(fft_peak % n) - col), 0.5 + 1e-9) << "order " << m;
        EXPECT_EQ(fft_peak / n, static_cast<std::size_t>(row)) << "order " << m;
        const std::size_t stam_peak = brightest_near(stam, n, row, col, 3);
        EXPECT_LE(std::fabs(double(stam_peak % n) - col), 0.5 + 1e-9) << "order " << m;
        EXPECT_EQ(stam_peak / n, static_cast<std::size_t>(row)) << "order " << m;
        const std::size_t expected = fft_peak;
        std::printf("cd order %+d: FFT/Stam at the peak %.3f\n", m, fft[expected] / stam[expected]);
    }
}

// Weak bumps (κh0 = 0.5 rad): p ≈ 1 − iκΣb is linear in the heights, so Stam's first-order
// eq. 21 holds even where bumps overlap, and the order energies of the mean FFT lobe over 16
// footprints of generated tracks match Stam's (7×7-pixel sums around orders −3…3).
TEST(StamCd, WeakBumpOrderEnergiesMatchFftMean) {
    const int n = 95;
    Recipe recipe = default_recipe("cd");
    recipe.grid = {2000, 2000, 0.1};
    recipe.cd.bump_height_um = 0.02;
    LobeQuery query = query_for(generate(recipe), DiffractionModel::rohs, 8.0, 0.5, n, 1);
    query.method_options = {{"step", "0.05"}, {"window", "3"}};
    const std::vector<double> fft = mean_fft_lobe(query, 4, 200.0);
    query.method_options.clear();
    const std::vector<double> stam = as_doubles(stam_lobe(query));
    for (int m = -3; m <= 3; ++m) {
        const int col = static_cast<int>(std::lround((1.0 - m * 0.2) * n / 2.0 - 0.5)), row = (n - 1) / 2;
        double fft_sum = 0.0, stam_sum = 0.0;
        for (int r = row - 3; r <= row + 3; ++r)
            for (int c = col - 3; c <= col + 3; ++c) {
                fft_sum += fft[static_cast<std::size_t>(r) * n + c];
                stam_sum += stam[static_cast<std::size_t>(r) * n + c];
            }
        std::printf("weak cd order %+d: FFT/Stam energy %.4f\n", m, fft_sum / stam_sum);
        // Order 0 is 2.1% low in the FFT: 1.1% from its window truncated at 3σ_c, 1.0% beyond first
        // order (the exact Poisson mean field e^{ν_y b φ} − 1 against Stam's ν_y b φ, at fill a/Δx).
        EXPECT_NEAR(fft_sum / stam_sum, 1.0, m == 0 ? 0.03 : 0.1) << "order " << m;
    }
}

// ---- Parameters, metadata, reciprocity ------------------------------------------------------

// Options override the generator's parameters, and the lobe depends on nothing else: asking for
// σ_h = 0.2 µm on a σ_h = 0.1 µm field gives the bits of the σ_h = 0.2 µm field.
TEST(StamLobe, OptionsOverrideGeneratorParameters) {
    LobeQuery query = query_for(generate(gaussian_recipe(0.1, 2.0, 128, 0.5)), DiffractionModel::rohs, 12.0, 0.5, 32, 1);
    const LobeImage from_generator = stam_lobe(query);
    EXPECT_EQ(from_generator.metadata.at("stam.sigma_h_um"), "0.1");
    EXPECT_EQ(from_generator.metadata.at("stam.source.sigma_h"), "generator");
    EXPECT_EQ(from_generator.metadata.count("stam.warning"), 0u);
    query.method_options["sigma_h"] = "200nm";
    const LobeImage overridden = stam_lobe(query);
    EXPECT_EQ(overridden.metadata.at("stam.sigma_h_um"), "0.2");
    EXPECT_EQ(overridden.metadata.at("stam.source.sigma_h"), "options");
    LobeQuery rougher = query_for(generate(gaussian_recipe(0.2, 2.0, 128, 0.5)), DiffractionModel::rohs, 12.0, 0.5, 32, 1);
    EXPECT_EQ(overridden.values, stam_lobe(rougher).values);
}

// The reflectance enters once per direction and wavelength, at cos θ_d = |ψ|/2 as in the FFT lobe.
TEST(StamLobe, FresnelPerWavelengthAndDirection) {
    LobeQuery query = query_for(generate(gaussian_recipe(0.1, 2.0, 128, 0.5)), DiffractionModel::rghs, 12.0, 0.5, 33, 1);
    query.wavelengths_um = {0.45, 0.65};
    query.omega_i = direction_from_spherical(0.6, 1.0);
    const LobeImage plain = stam_lobe(query);
    query.material.name = "Au";
    const LobeImage gold = stam_lobe(query);
    int checked = 0;
    for (std::size_t layer = 0; layer < 2; ++layer)
        for (int r = 0; r < 33; r += 4)
            for (int c = 0; c < 33; c += 4) {
                if (plain.at(layer, r, c) < 1e-3f) continue;
                const DiskPoint p = disk_pixel_point(r, c, 33);
                const Vec3 psi = query.omega_i + direction_from_disk(p.x, p.y);
                const double fresnel = fresnel_reflectance("Au", query.wavelengths_um[layer], 0.5 * length(psi));
                EXPECT_NEAR(gold.at(layer, r, c) / plain.at(layer, r, c), fresnel, 1e-5 * fresnel);
                ++checked;
            }
    EXPECT_GT(checked, 20);
}

// Without generator provenance the field's measured Sq and 1/e correlation lengths are used.
TEST(StamLobe, MeasuredStatisticsStandInForProvenance) {
    Heightfield field = generate(gaussian_recipe(0.1, 2.0, 512, 0.25));
    field.provenance.clear();
    LobeQuery query = query_for(std::move(field), DiffractionModel::rohs, 12.0, 0.5, 32, 1);
    const LobeImage image = stam_lobe(query);
    EXPECT_EQ(image.metadata.at("stam.source.sigma_h"), "statistics");
    EXPECT_NEAR(std::stod(image.metadata.at("stam.sigma_h_um")), 0.1, 1e-6);  // the generator sets Sq exactly
    EXPECT_NEAR(std::stod(image.metadata.at("stam.correlation_length_x_um")), 2.0, 0.1);
    EXPECT_NEAR(std::stod(image.metadata.at("stam.correlation_length_y_um")), 2.0, 0.1);
}

// σ_c < 3T breaks Stam's w⋆w ≈ A_c: the image says so; bad options are refused by name.
TEST(StamLobe, WarnsAndRefuses) {
    LobeQuery query = query_for(generate(gaussian_recipe(0.1, 2.0, 128, 0.5)), DiffractionModel::rohs, 5.0, 0.5, 16, 1);
    EXPECT_NE(stam_lobe(query).metadata.at("stam.warning").find("correlation length"), std::string::npos);
    query.method_options = {{"correlation", "c4"}};
    EXPECT_THROW(compute_lobe("stam", query), Error);
    query.method_options = {{"step", "0.1"}};  // an fft option
    EXPECT_THROW(compute_lobe("stam", query), Error);
    query.method_options = {{"surface", "cd"}};  // not a cd field
    EXPECT_THROW(compute_lobe("stam", query), Error);
}

// The reciprocal models give f(ω_i, ω_o) = f(ω_o, ω_i) (anisotropic C3 field, rotated), and the
// image is the same for any thread count.
TEST(StamLobe, ReciprocalAndThreadIndependent) {
    Recipe recipe = gaussian_recipe(0.08, 2.0, 128, 0.5);
    recipe.gaussian.correlation = CorrelationFunction::c3;
    recipe.gaussian.correlation_length_y_um = 3.0;
    recipe.gaussian.orientation_rad = 0.5;
    const int n = 41;
    const Vec3 a = direction_from_disk(disk_pixel_point(10, 25, n).x, disk_pixel_point(10, 25, n).y);
    const Vec3 b = direction_from_disk(disk_pixel_point(22, 12, n).x, disk_pixel_point(22, 12, n).y);
    for (DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::rghs, DiffractionModel::kirchhoff}) {
        LobeQuery query = query_for(generate(recipe), model, 12.0, 0.5, n, 1);
        query.omega_i = a;
        const LobeImage forward = stam_lobe(query);
        query.omega_i = b;
        const LobeImage backward = stam_lobe(query);
        EXPECT_NEAR(forward.at(0, 22, 12) / backward.at(0, 10, 25), 1.0, 1e-5) << to_string(model);
        EXPECT_EQ(with_threads(1, [&] { return stam_lobe(query); }).values, backward.values);
    }
}

}  // namespace
}  // namespace glintscope
