// The pndf method: one identical, normalised NDF layer per wavelength, equal to the exact
// normal density of the query's footprint; its options are checked and recorded. Its Ndf samples
// h with the point query's own density, and samples its image where the query has no sampler.
#include "methods/pndf/pndf.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <thread>
#include <vector>

#include "core/counter_rng.hpp"
#include "disk_chi_square.hpp"
#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/surface/statistics.hpp"
#include "glintscope/generate/generate.hpp"
#include "sampled_field.hpp"

namespace glintscope {
namespace {

LobeQuery isotropic_query(int resolution) {
    Recipe recipe = default_recipe("isotropic");
    recipe.grid.rows = recipe.grid.cols = 128;
    LobeQuery query;
    query.resolution = resolution;
    query.quantity = Quantity::ndf;
    set_heightfield(query, generate(recipe));
    query.footprint.centre_um = query.field->centre_um();
    return query;
}

TEST(Pndf, EveryWavelengthLayerIsTheNormalisedNormalDensity) {
    LobeQuery query = isotropic_query(64);
    query.wavelengths_um = {0.4, 0.7};
    query.method_options["intrinsic_roughness"] = "0.02";
    const LobeImage image = compute_lobe("pndf", query);
    NormalDensitySettings settings;
    settings.intrinsic_roughness = 0.02;
    const std::vector<double> density = normal_density(*query.surface, query.footprint, 64, settings);
    for (std::size_t k = 0; k < density.size(); ++k) {
        EXPECT_EQ(image.values[k], static_cast<float>(density[k]));
        EXPECT_EQ(image.values[density.size() + k], image.values[k]);
    }
    EXPECT_NEAR(disk_sum(image), 1.0, 1e-5);
    EXPECT_EQ(image.metadata.at("pndf.intrinsic_roughness_rad"), "0.02");
}

TEST(Pndf, RejectsUnknownAndOutOfRangeOptions) {
    LobeQuery query = isotropic_query(32);
    query.method_options = {{"refinement", "0"}};
    EXPECT_THROW(compute_lobe("pndf", query), Error);
    query.method_options = {{"step", "1"}};
    EXPECT_THROW(compute_lobe("pndf", query), Error);
}

TEST(Pndf, WholeGaussianRandomFieldApproachesBeckmann) {
    // A C1 (Gaussian-correlated) field has Gaussian slopes: its large-area NDF is Beckmann's,
    // D(h) = exp(−tan²θ/α²)/(π α² cos⁴θ) with α = √2·σ_slope (per-axis rms slope 0.1 here).
    // 1024² samples, T = 8 texels: ~16,000 correlation cells.
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {1024, 1024, 1.0};
    recipe.gaussian.correlation = CorrelationFunction::c1;
    recipe.gaussian.correlation_length_x_um = recipe.gaussian.correlation_length_y_um = 8.0;
    recipe.gaussian.sigma_h_um = 0.1 * 8.0 / std::sqrt(2.0);
    const Heightfield field = generate(recipe);
    const SurfaceStatistics statistics = compute_statistics(field);
    const double alpha = std::sqrt(2.0) * std::sqrt(0.5 * (statistics.rms_slope_x * statistics.rms_slope_x +
                                                           statistics.rms_slope_y * statistics.rms_slope_y));
    LobeQuery query;
    query.quantity = Quantity::ndf;
    query.resolution = 64;
    query.footprint.shape = FootprintShape::whole;
    set_heightfield(query, field);
    const LobeImage image = compute_lobe("pndf", query);
    double difference = 0.0, norm = 0.0;
    for (int r = 0; r < 64; ++r)
        for (int c = 0; c < 64; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, 64);
            if (!inside_unit_disk(p)) continue;
            const double cos2 = 1.0 - p.x * p.x - p.y * p.y;
            const double tan2 = (p.x * p.x + p.y * p.y) / cos2;
            const double beckmann = std::exp(-tan2 / (alpha * alpha)) / (pi * alpha * alpha * cos2 * cos2);
            difference += std::pow(image.at(0, r, c) - beckmann, 2);
            norm += beckmann * beckmann;
        }
    RecordProperty("alpha", std::to_string(alpha));
    RecordProperty("relative_l2", std::to_string(std::sqrt(difference / norm)));
    EXPECT_LT(std::sqrt(difference / norm), 0.05);
}

// The pndf Ndf of a paraboloid under a 12 µm Gaussian footprint: no folds, so D is smooth
// enough for the χ² cells' quadrature (a rough field's caustics are not; the draws are tested
// there against the image's exact pixel masses in tests/lib/normal_density/normal_bounds_tree_test.cpp).
LobeQuery paraboloid_query() {
    const double a = 0.008, b = 0.006, c = 0.002;
    LobeQuery query;
    set_heightfield(query, testing::sampled_field(128, 128, 1.0, [&](double x, double y) {
        const double u = x - 64.0, v = y - 64.0;
        return 0.5 * a * u * u + 0.5 * b * v * v + c * u * v;
    }));
    query.quantity = Quantity::ndf;
    query.resolution = 32;
    query.wavelengths_um = {0.5};
    query.footprint.centre_um = {64.0, 64.0};
    query.footprint.sigma_um = 12.0;
    query.method_options = {{"tolerance", "0"}};  // the field's seam would be divided 64-fold
    return query;
}

TEST(PndfNdf, SamplesPdfAndEvalAreOneDensity) {
    // χ² of Ndf::sample against Ndf::pdf integrated over 20 × 20 cells of the disk (16 × 16
    // points each, pbrt-v4's test, DiskChiSquare), 2·10⁵ draws; each draw's pdf is pdf(h) (1e-12);
    // pdf(h)/h_z over eval(h) is one constant (1e-9), the sampler's normalisation (truncated
    // weight / the triangles' weight, 1 ± 1e-5); and the pdf integrates to 1 over the hemisphere.
    const Ndf ndf = make_ndf("pndf", paraboloid_query());
    ASSERT_TRUE(ndf.evaluates_directly() && ndf.samples_directly());
    const testing::DiskChiSquare chi_square{20, 200'000};
    const CounterRng rng(22, 5);
    const Vec3 normal{0.0, 0.0, 1.0};
    std::optional<double> normalisation;
    const std::vector<long> observed = chi_square.histogram(testing::Grid::omega_o, normal, [&](long k) -> std::optional<Vec3> {
        const NdfSample s = ndf.sample(rng.uniform(2 * k), rng.uniform(2 * k + 1));
        if (!(s.pdf > 0.0)) return std::nullopt;
        if (k % 100 == 0) {
            EXPECT_NEAR(ndf.pdf(s.h), s.pdf, 1e-12 * s.pdf);
            const double ratio = s.pdf / (s.h.z * ndf.eval(s.h)[0]);
            if (!normalisation) normalisation = ratio;
            EXPECT_NEAR(ratio, *normalisation, 1e-9 * *normalisation);
        }
        return s.h;
    });
    ASSERT_TRUE(normalisation.has_value());
    RecordProperty("normalisation_minus_1", ::testing::PrintToString(*normalisation - 1.0));
    EXPECT_NEAR(*normalisation, 1.0, 1e-4);
    std::vector<double> expected(20 * 20 + 1, 0.0);
    chi_square.disk_probabilities([&](Vec3 h) { return ndf.pdf(h); }, 16, expected);
    double integral = 0.0;  // ∫ pdf dω = Σ over the cells of (pdf / h_z) dA
    for (double e : expected) integral += e;
    RecordProperty("pdf_integral_minus_1", ::testing::PrintToString(integral - 1.0));
    EXPECT_NEAR(integral, 1.0, 1e-3);
    const double p = chi_square.p_value(observed, expected);
    RecordProperty("p_value", ::testing::PrintToString(p));
    EXPECT_GT(p, 0.01);
}

TEST(PndfNdf, OneAndEightThreadsGiveTheSameDraws) {
    // The first draws from eight threads race to make the footprint's cumulative weights (made
    // once, on first use): every draw and pdf must be those of one thread.
    const auto draws = [](int threads) {
        const Ndf ndf = make_ndf("pndf", paraboloid_query());
        const int count = 4000;
        std::vector<std::array<double, 5>> out(count);
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t)
            pool.emplace_back([&, t] {
                const CounterRng rng(22, 7);
                for (int k = t; k < count; k += threads) {
                    const NdfSample s = ndf.sample(rng.uniform(2 * k), rng.uniform(2 * k + 1));
                    out[k] = {s.h.x, s.h.y, s.h.z, s.pdf, ndf.pdf(direction_from_spherical(0.0001 * k, 0.1 * k))};
                }
            });
        for (std::thread& thread : pool) thread.join();
        return out;
    };
    const auto one = draws(1);
    EXPECT_GT(std::count_if(one.begin(), one.end(), [](const auto& d) { return d[4] > 0.0; }), 100) << "the pdfs miss the NDF";
    EXPECT_EQ(one, draws(8));
}

TEST(PndfNdf, BoxFootprintsAndIntrinsicRoughnessSampleTheImage) {
    // Where the point query has no sampler (a box's lattice is not the texels'; intrinsic
    // roughness blurs each triangle), h is drawn from the image: pdf/h_z is the pixel holding h
    // over the image's integral, for every draw (1e-9), though with roughness eval is the query.
    LobeQuery box = isotropic_query(32);
    box.footprint.shape = FootprintShape::box;
    box.footprint.size_um = 20.0;
    LobeQuery rough = isotropic_query(32);
    rough.method_options = {{"intrinsic_roughness", "0.05"}};
    for (const LobeQuery& query : {box, rough}) {
        const Ndf ndf = make_ndf("pndf", query);
        EXPECT_FALSE(ndf.samples_directly());
        EXPECT_EQ(ndf.evaluates_directly(), query.footprint.shape != FootprintShape::box);
        const LobeImage image = compute_lobe("pndf", query);
        const double integral = ndf.normalisation()[0];
        const CounterRng rng(22, 6);
        for (long k = 0; k < 2000; ++k) {
            const NdfSample s = ndf.sample(rng.uniform(2 * k), rng.uniform(2 * k + 1));
            ASSERT_GT(s.pdf, 0.0);
            const int col = std::clamp(static_cast<int>((s.h.x + 1.0) * 0.5 * 32), 0, 31);
            const int row = std::clamp(static_cast<int>((1.0 - s.h.y) * 0.5 * 32), 0, 31);
            const double expected = image.at(0, row, col) / integral;
            ASSERT_NEAR(s.pdf / s.h.z, expected, 1e-9 * expected) << (query.footprint.shape == FootprintShape::box ? "box" : "roughness");
            ASSERT_NEAR(ndf.pdf(s.h), s.pdf, 1e-12 * s.pdf);
        }
    }
}

}  // namespace
}  // namespace glintscope
