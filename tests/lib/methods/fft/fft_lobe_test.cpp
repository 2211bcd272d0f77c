// The FFT ground truth against closed forms: a flat mirror's lobe is the transform of the
// coherence window, a tilted plane reflects into its mirror direction, a sinusoidal grating
// diffracts into Bessel-weighted orders; the sampling converges, the reciprocal models are
// reciprocal and the result does not depend on the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/compare.hpp"
#include "methods/fft/fft_lobe.hpp"
#include "numerics/chirp_z.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/text_format.hpp"

#include "lobe_queries.hpp"

namespace glintscope {
namespace {

constexpr double kPi = std::numbers::pi;
const DiffractionModel kAllModels[] = {DiffractionModel::ohs, DiffractionModel::ghs, DiffractionModel::rohs,
                                       DiffractionModel::rghs, DiffractionModel::kirchhoff};

LobeQuery query_for(Heightfield field, double sigma_um, double lambda_um, int resolution) {
    LobeQuery query;
    query.footprint.centre_um = field.centre_um();
    query.footprint.sigma_um = sigma_um;
    query.wavelengths_um = {lambda_um};
    query.resolution = resolution;
    query.supersample = 1;  // pixel centres: where the closed forms below are evaluated
    set_heightfield(query, std::move(field));
    return query;
}

Vec3 pixel_direction(int row, int col, int resolution) {
    const DiskPoint p = disk_pixel_point(row, col, resolution);
    return direction_from_disk(p.x, p.y);
}

// ξ1 of Yan 2018 Fig. 6 with its F/λ².
double xi1(const LobeQuery& query, Vec3 omega_o) {
    const double lambda = query.wavelengths_um[0];
    const double fresnel =
        fresnel_reflectance(query.material.name, lambda, 0.5 * length(query.omega_i + omega_o));
    return xi1_geometric(query.model, query.omega_i, omega_o) * fresnel / (lambda * lambda);
}

// The Gaussian window's transform: |w̃(v)| = 2πσ² e^{−2π²σ²|v|²}, v = ψ̄/λ.
double gaussian_window_lobe(const LobeQuery& query, Vec3 omega_o) {
    const double sigma = query.footprint.sigma_um;
    const double lambda = query.wavelengths_um[0];
    const Vec3 psi = query.omega_i + omega_o;
    const double v2 = (psi.x * psi.x + psi.y * psi.y) / (lambda * lambda);
    const double amplitude = 2.0 * kPi * sigma * sigma * std::exp(-2.0 * kPi * kPi * sigma * sigma * v2);
    return xi1(query, omega_o) / (kPi * sigma * sigma) * amplitude * amplitude;
}

// The window lobe at a pixel centre; 0 outside the disk.
double gaussian_window_lobe_at_pixel(const LobeQuery& query, int row, int col) {
    const DiskPoint p = disk_pixel_point(row, col, query.resolution);
    return inside_unit_disk(p) ? gaussian_window_lobe(query, direction_from_disk(p.x, p.y)) : 0.0;
}

// The number `validate` reports: relative L2 over the disk (single-wavelength images).
double relative_l2_difference(const LobeImage& a, const LobeImage& b) {
    return compare_lobes(a, b).at(0).relative_l2;
}

// An isotropic Gaussian random surface of Yan 2018 Fig. 8 (rms slope 0.17 per axis), 128² µm.
Heightfield rough_surface() {
    Recipe recipe = default_recipe("isotropic");
    recipe.grid = {128, 128, 1.0};
    return generate(recipe);
}

// ---- Flat mirror -------------------------------------------------------------------------

// σ_c = 2 µm at λ = 0.5 µm blurs the specular peak by λ/(2πσ_c) ≈ 0.04 in disk units, 2.5
// pixels at N = 128, so the pixel sum resolves it.
LobeQuery flat_mirror_query(DiffractionModel model, Vec3 omega_i) {
    LobeQuery query = query_for(make_heightfield(48, 48, 1.0, 0.3f), 2.0, 0.5, 128);
    query.model = model;
    query.omega_i = omega_i;
    return query;
}

const Vec3 kNormal{0.0, 0.0, 1.0};
const Vec3 kOblique = direction_from_spherical(40.0 * kPi / 180.0, 30.0 * kPi / 180.0);

TEST(FftLobe, FlatMirrorIsTheTransformOfTheCoherenceWindow) {
    for (DiffractionModel model : kAllModels)
        for (Vec3 omega_i : {kNormal, kOblique}) {
            const LobeQuery query = flat_mirror_query(model, omega_i);
            const LobeImage image = compute_lobe("fft", query);
            const double peak = gaussian_window_lobe(query, {-omega_i.x, -omega_i.y, omega_i.z});
            double worst = 0.0;
            for (int r = 0; r < query.resolution; ++r)
                for (int c = 0; c < query.resolution; ++c)
                    worst = std::max(worst, std::fabs(image.at(0, r, c) - gaussian_window_lobe_at_pixel(query, r, c)));
            // The window is cut at ±4σ_c, which leaves e^{−8}-level ripples (~2e-4 of the peak).
            EXPECT_LT(worst / peak, 1e-3) << to_string(model) << " theta_i " << std::acos(omega_i.z);
            EXPECT_NEAR(disk_sum(image), 1.0, 0.005) << to_string(model) << " theta_i " << std::acos(omega_i.z);
        }
}

TEST(FftLobe, WideWindowMatchesTheWindowTransformToRoundoff) {
    LobeQuery query = flat_mirror_query(DiffractionModel::rohs, kOblique);
    query.method_options["window"] = "7";
    const LobeImage image = compute_lobe("fft", query);
    const double peak = gaussian_window_lobe(query, {-kOblique.x, -kOblique.y, kOblique.z});
    double worst = 0.0;
    for (int r = 0; r < query.resolution; ++r)
        for (int c = 0; c < query.resolution; ++c)
            worst = std::max(worst, std::fabs(image.at(0, r, c) - gaussian_window_lobe_at_pixel(query, r, c)));
    EXPECT_LT(worst / peak, 1e-6);
}

TEST(FftLobe, FlatMirrorAlbedoIsTheFresnelReflectance) {
    LobeQuery query = flat_mirror_query(DiffractionModel::rohs, kOblique);
    query.material.name = "Au";
    const double expected = fresnel_reflectance("Au", 0.5, kOblique.z);
    EXPECT_NEAR(disk_sum(compute_lobe("fft", query)) / expected, 1.0, 0.005);
}

TEST(FftLobe, SupersamplingAveragesExactSubpixelValues) {
    LobeQuery query = flat_mirror_query(DiffractionModel::ghs, kOblique);
    query.resolution = 24;
    query.supersample = 3;
    query.method_options["window"] = "7";
    const LobeImage image = compute_lobe("fft", query);
    double worst = 0.0, peak = 0.0;
    for (int r = 0; r < query.resolution; ++r)
        for (int c = 0; c < query.resolution; ++c) {
            double expected = 0.0;
            for (int b = 0; b < 3; ++b)
                for (int a = 0; a < 3; ++a) {
                    const double du = (a + 0.5) / 3 - 0.5, dv = (b + 0.5) / 3 - 0.5;
                    const DiskPoint p = disk_pixel_point(r, c, query.resolution, du, dv);
                    if (inside_unit_disk(p)) expected += gaussian_window_lobe(query, direction_from_disk(p.x, p.y)) / 9.0;
                }
            worst = std::max(worst, std::fabs(image.at(0, r, c) - expected));
            peak = std::max(peak, expected);
        }
    EXPECT_LT(worst / peak, 1e-6);
}

// A box of sides a along x and b along y: w̃(v) = a b sinc(a v_x) sinc(b v_y), A_c = a b; the
// largest pixel error relative to the peak.
double box_sinc_lobe_error(double a, double b) {
    LobeQuery query = flat_mirror_query(DiffractionModel::rohs, kNormal);
    query.footprint.shape = FootprintShape::box;
    query.footprint.size_um = a;
    query.footprint.size_y_um = b;
    const LobeImage image = compute_lobe("fft", query);
    const auto sinc = [](double x) { return x == 0.0 ? 1.0 : std::sin(kPi * x) / (kPi * x); };
    double worst = 0.0, peak = 0.0;
    for (int r = 0; r < query.resolution; ++r)
        for (int c = 0; c < query.resolution; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, query.resolution);
            if (!inside_unit_disk(p)) continue;
            const Vec3 omega_o = direction_from_disk(p.x, p.y);
            const double amplitude = a * b * sinc(a * p.x / 0.5) * sinc(b * p.y / 0.5);
            const double expected = xi1(query, omega_o) / (a * b) * amplitude * amplitude;
            worst = std::max(worst, std::fabs(image.at(0, r, c) - expected));
            peak = std::max(peak, expected);
        }
    return worst / peak;
}

// Square, and Dong 2015's rectangular patches.
TEST(FftLobe, BoxFootprintGivesTheSincLobeOfEachSide) {
    EXPECT_LT(box_sinc_lobe_error(8.0, 8.0), 1e-3);
    EXPECT_LT(box_sinc_lobe_error(8.0, 5.0), 1e-3);
}

// ---- Tilted plane ------------------------------------------------------------------------

// H = t (x − x_c): rising toward +x, so the normal (−t, 0, 1) leans toward −x and light from the
// zenith reflects to ω_o = (−2t, 0, 1 − t²)/(1 + t²), left of the image centre. With ξ3 = ψ·n
// the phase ξ3 t x + ψ̄_x x is stationary exactly there (ψ̄ = −ξ3 H'); with ξ3 = 2 (OHS, R-OHS)
// at ψ̄_x = −2t instead. At that pixel R̃* = ∫w = 2πσ², times ξ2 = 1 + t² for Kirchhoff.
LobeImage tilted_plane_lobe(DiffractionModel model, double slope, int resolution, LobeQuery& query) {
    Heightfield field = make_heightfield(64, 64, 1.0);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c)
            field.at(r, c) = static_cast<float>(slope * (sample_position(field, r, c).x - 32.0));
    query = query_for(std::move(field), 3.0, 0.5, resolution);
    query.model = model;
    query.method_options["phase_error"] = "1e-6";
    return compute_lobe("fft", query);
}

TEST(FftLobe, TiltedPlaneReflectsIntoTheMirrorDirectionOfItsNormal) {
    const int resolution = 65;  // odd, so that the row through the centre has y = 0
    const int row = 32, col = 20;
    const double x = disk_pixel_point(row, col, resolution).x;
    ASSERT_LT(x, 0.0);
    for (DiffractionModel model : kAllModels) {
        const bool mirror = phase_depends_on_outgoing(model);
        // Mirror direction x = −2t/(1 + t²) solved for t; paraxial x = −2t otherwise.
        const double slope = mirror ? (std::sqrt(1.0 - x * x) - 1.0) / x : -0.5 * x;
        LobeQuery query;
        const LobeImage image = tilted_plane_lobe(model, slope, resolution, query);
        int best_row = 0, best_col = 0;
        for (int r = 0; r < resolution; ++r)
            for (int c = 0; c < resolution; ++c)
                if (image.at(0, r, c) > image.at(0, best_row, best_col)) best_row = r, best_col = c;
        EXPECT_EQ(best_row, row) << to_string(model);
        EXPECT_EQ(best_col, col) << to_string(model);
        const double sigma = query.footprint.sigma_um;
        const double xi2 = model == DiffractionModel::kirchhoff ? 1.0 + slope * slope : 1.0;
        const double amplitude = 2.0 * kPi * sigma * sigma * xi2;
        const double expected = xi1(query, pixel_direction(row, col, resolution)) * amplitude * amplitude /
                                (kPi * sigma * sigma);
        EXPECT_NEAR(image.at(0, row, col) / expected, 1.0, 2e-3) << to_string(model);
    }
}

// ---- Sinusoidal grating ------------------------------------------------------------------

// H = A sin(2πx/Λ). Jacobi–Anger: e^{−iβ sin θ} = Σ_n J_n(β) e^{−inθ}, β = 2πξ3A/λ, so
// R̃*(v) = Σ_n J_n(β) w̃(v_x + n/Λ, v_y): order n sits at ψ̄_x = −nλ/Λ (order +1 on the side the
// slope faces, as for the tilted plane) with |R̃*| = 2πσ² |J_n(β)|. For Kirchhoff the ξ2 term
// adds H_x e^{−iβ sin θ} = Σ_n (nλ/(Λξ3)) J_n e^{−inθ}, i.e. the factor 1 − ψ̄_x nλ/(Λ ξ3 ψ·n).
TEST(FftLobe, SinusoidalGratingHasBesselWeightedOrders) {
    const double texel = 0.25, period = 8.0, amplitude = 0.07, lambda = 0.5;
    Heightfield field = make_heightfield(16, 512, texel);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            const double x = sample_position(field, r, c).x;
            field.at(r, c) = static_cast<float>(amplitude * std::sin(2.0 * kPi * x / period));
        }
    const int resolution = 256;
    for (DiffractionModel model : kAllModels) {
        LobeQuery query = query_for(field, 8.0, lambda, resolution);
        query.model = model;
        // −ω̄_i is the centre of pixel (128, 127); the orders are λ/Λ = 8 pixels apart.
        query.omega_i = direction_from_disk(1.0 / resolution, 1.0 / resolution);
        const LobeImage image = compute_lobe("fft", query);
        const double sigma = query.footprint.sigma_um;
        for (int n = -3; n <= 3; ++n) {
            const int row = 128, col = 127 - 8 * n;
            const Vec3 omega_o = pixel_direction(row, col, resolution);
            const Vec3 psi = query.omega_i + omega_o;
            ASSERT_NEAR(psi.x, -n * lambda / period, 1e-12);
            const double xi3_n = xi3(model, query.omega_i, omega_o);
            const double bessel = std::cyl_bessel_j(std::abs(n), 2.0 * kPi * xi3_n * amplitude / lambda);
            const double xi2 =
                model == DiffractionModel::kirchhoff ? 1.0 - psi.x * n * lambda / (period * xi3_n * psi.z) : 1.0;
            const double order_amplitude = 2.0 * kPi * sigma * sigma * bessel * xi2;
            const double expected = xi1(query, omega_o) * order_amplitude * order_amplitude / (kPi * sigma * sigma);
            EXPECT_NEAR(image.at(0, row, col) / expected, 1.0, 0.005) << to_string(model) << " order " << n;
        }
    }
}

// ---- Convergence, reciprocity, threads ---------------------------------------------------

TEST(FftLobe, HalvingTheStepOrWideningTheWindowChangesLittle) {
    for (DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::kirchhoff}) {
        LobeQuery query = query_for(rough_surface(), 5.0, 0.5, 96);
        query.model = model;
        query.omega_i = kOblique;
        const LobeImage automatic = compute_lobe("fft", query);
        const std::string steps = automatic.metadata.at("fft.step_um");
        const double step = std::min(std::stod(steps), std::stod(steps.substr(steps.find(',') + 1)));
        query.method_options["step"] = std::to_string(step / 2.0);
        const LobeImage fine = compute_lobe("fft", query);
        query.method_options.erase("step");
        query.method_options["window"] = "6";
        const LobeImage wide = compute_lobe("fft", query);
        EXPECT_LT(relative_l2_difference(automatic, fine), 1e-3) << to_string(model);
        EXPECT_LT(relative_l2_difference(automatic, wide), 1e-3) << to_string(model);
    }
}

// The ξ3 interpolation bound: |δR̃*| ≤ ε ∫|w| ds = ε·2πσ_c² at every pixel, checked on |R̃*| =
// √(f_r A_c/ξ1) against a run with a 1e5 times smaller ε.
TEST(FftLobe, Xi3InterpolationStaysWithinItsBound) {
    const double bound = 0.1;
    LobeQuery query = query_for(rough_surface(), 5.0, 0.5, 48);
    query.model = DiffractionModel::rghs;
    query.omega_i = kOblique;
    query.method_options["phase_error"] = "0.1";
    const LobeImage coarse = compute_lobe("fft", query);
    query.method_options["phase_error"] = "1e-6";
    const LobeImage fine = compute_lobe("fft", query);
    const double sigma = query.footprint.sigma_um;
    double worst = 0.0;
    for (int r = 0; r < query.resolution; ++r)
        for (int c = 0; c < query.resolution; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, query.resolution);
            if (!inside_unit_disk(p)) continue;
            const double to_amplitude2 = kPi * sigma * sigma / xi1(query, direction_from_disk(p.x, p.y));
            worst = std::max(worst, std::fabs(std::sqrt(coarse.at(0, r, c) * to_amplitude2) -
                                              std::sqrt(fine.at(0, r, c) * to_amplitude2)));
        }
    EXPECT_LT(worst, bound * 2.0 * kPi * sigma * sigma);
    EXPECT_GT(worst, 1e-3 * bound * 2.0 * kPi * sigma * sigma);  // the coarse run really is interpolating
}

TEST(FftLobe, ReciprocalModelsAreReciprocal) {
    const int resolution = 64;
    // Directions at pixel centres, so that each is an outgoing pixel of the other's lobe.
    const int first_row = 20, first_col = 41, second_row = 47, second_col = 19;
    const Vec3 first = pixel_direction(first_row, first_col, resolution);
    const Vec3 second = pixel_direction(second_row, second_col, resolution);
    for (DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::rghs, DiffractionModel::kirchhoff}) {
        LobeQuery query = query_for(rough_surface(), 5.0, 0.5, resolution);
        query.model = model;
        query.omega_i = first;
        const double forward = compute_lobe("fft", query).at(0, second_row, second_col);
        query.omega_i = second;
        const double backward = compute_lobe("fft", query).at(0, first_row, first_col);
        ASSERT_GT(forward, 0.0);
        EXPECT_NEAR(backward / forward, 1.0, 1e-4) << to_string(model);
    }
}

TEST(FftLobe, ResultDoesNotDependOnTheThreadCount) {
    LobeQuery query = query_for(rough_surface(), 5.0, 0.5, 48);
    query.model = DiffractionModel::kirchhoff;
    query.omega_i = kOblique;
    query.supersample = 2;
    EXPECT_EQ(testing::compute_with_threads("fft", query, 1).values, testing::compute_with_threads("fft", query, 2).values);
}

// The automatic step divides the image's period along each axis into an integer count of bins,
// so that the transforms fold (ChirpZ::fold_size): the lobe equals the chirp-z transforms of a
// grid 1% coarser (the option step, not commensurate) to the grids' own discretisation, and is
// the same for any thread count (the folded rows add in a fixed order).
TEST(FftLobe, CommensurateGridsFoldAndAgreeWithAnotherGrid) {
    for (int supersample : {1, 2})
        for (DiffractionModel model : {DiffractionModel::rohs, DiffractionModel::kirchhoff}) {
            LobeQuery query = query_for(rough_surface(), 5.0, 0.5, 64);
            query.model = model;
            query.omega_i = kOblique;
            query.supersample = supersample;
            const LobeImage folded = compute_lobe("fft", query);
            const std::string steps = folded.metadata.at("fft.step_um");
            const double step_x = std::stod(steps), step_y = std::stod(steps.substr(steps.find(',') + 1));
            const double period_y = query.resolution * query.wavelengths_um[0] / 2.0;  // 1/Δv, Δv = 2/(Nλ) per row
            const double bins_x = supersample * period_y / step_x, bins_y = period_y / step_y;
            EXPECT_NEAR(bins_x, std::round(bins_x), 1e-9 * bins_x) << supersample;
            EXPECT_NEAR(bins_y, std::round(bins_y), 1e-9 * bins_y) << supersample;
            EXPECT_EQ(commensurate_fold(step_x, 1.0 / (supersample * period_y)), std::lround(bins_x));
            LobeQuery other = query;
            other.method_options["step"] = std::to_string(1.01 * std::min(step_x, step_y));
            const LobeImage chirp_z = compute_lobe("fft", other);
            EXPECT_LT(relative_l2_difference(folded, chirp_z), 1e-4) << to_string(model) << " " << supersample;
            EXPECT_EQ(testing::compute_with_threads("fft", query, 1).values, folded.values) << to_string(model);
        }
}

TEST(FftLobe, RejectsBadOptions) {
    LobeQuery query = flat_mirror_query(DiffractionModel::rohs, kNormal);
    query.method_options = {{"stepp", "0.1"}};
    EXPECT_THROW(compute_lobe("fft", query), Error);
    query.method_options = {{"step", "-0.1um"}};
    EXPECT_THROW(compute_lobe("fft", query), Error);
    query.method_options = {{"step", "0"}};
    EXPECT_THROW(compute_lobe("fft", query), Error);
    query.method_options = {{"window", "0.5"}};
    EXPECT_THROW(compute_lobe("fft", query), Error);
    query.method_options = {{"phase_error", "abc"}};
    EXPECT_THROW(compute_lobe("fft", query), Error);
    query.method_options = {{"step", "1nm"}};  // 16001² samples over the footprint: refused, not attempted
    EXPECT_THROW(compute_lobe("fft", query), Error);
}

// Over the memory budget the FFT gives up its oversampling beyond the alias-free bound first, and
// says so: the lobe stays within 1% of the unconstrained one. Below even that, it refuses in one
// line naming --memory.
TEST(FftLobe, AMemoryBudgetLowersTheOversamplingThenRefuses) {
    LobeQuery query;
    set_heightfield(query, generate_builtin("isotropic"));
    query.footprint.centre_um = query.field->centre_um();
    query.resolution = 48;
    const LobeRun unconstrained = run_lobe("fft", query);
    EXPECT_EQ(unconstrained.image.metadata.at("fft.oversampling"), "3");
    query.memory_budget_gb = 0.01;  // 250 000 samples: below the 619 x 625 grid at oversampling 3
    const LobeRun budgeted = run_lobe("fft", query);
    EXPECT_LT(parse_number(budgeted.image.metadata.at("fft.oversampling")), 3.0);
    EXPECT_GE(parse_number(budgeted.image.metadata.at("fft.oversampling")), 1.0);
    const auto said = [](const LobeRun& run) {
        for (const std::string& note : run.notes)
            if (note.find("memory budget") != std::string::npos) return true;
        return false;
    };
    EXPECT_TRUE(said(budgeted));
    EXPECT_FALSE(said(unconstrained));
    EXPECT_LT(compare_lobes(budgeted.image, unconstrained.image).at(0).relative_l2, 0.01);
    query.footprint.sigma_um = 20.0;  // 709 x 761 samples even at the alias-free bound
    try {
        compute_lobe("fft", query);
        ADD_FAILURE() << "a grid over the budget was computed";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--memory"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace glintscope
