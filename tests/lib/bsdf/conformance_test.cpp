// The BSDF contract, tested for every method in the table as pbrt-v4 tests its BxDFs
// (bsdfs_test.cpp): a χ² test of each sampler against its pdf, the pdf's normalisation, eval
// against the method's image at pixel centres, the mean sampling weight against the albedo, the
// albedo against the image sum, reciprocity, and the same answers from 1 and 8 threads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <thread>

#include "numerics/disk_distribution.hpp"
#include "core/counter_rng.hpp"
#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "disk_chi_square.hpp"
#include "mean_weight.hpp"
#include "method_cases.hpp"

namespace glintscope {
namespace {

using testing::MethodCase;

std::vector<MethodCase> cases(Quantity quantity) {
    return testing::method_cases([quantity](Quantity q) { return q == quantity; });
}

std::string case_name(const ::testing::TestParamInfo<MethodCase>& info) { return info.param.method.name; }

constexpr int kResolution = 40;

// Two wavelengths, so that the spectral weights differ from one another.
LobeQuery isotropic_query(Quantity quantity) {
    LobeQuery query = testing::isotropic_builtin_query(quantity);
    query.resolution = kResolution;
    query.supersample = 1;
    return query;
}

Vec3 incidence(double degrees) { return direction_from_spherical(degrees * pi / 180.0, 0.4); }

// ---- χ² test (pbrt-v4 bsdfs_test.cpp) ------------------------------------------------------

constexpr int kCells = 2 * kResolution;  // half-pixel histogram cells over [−1, 1]²
constexpr long kSamples = 1'000'000;
constexpr int kChiSquareTestsPerCase = 3;  // the incidences: Šidák correction over them
constexpr testing::DiskChiSquare kChiSquare{kCells, kSamples};
using testing::Grid;

// ---- BSDF ----------------------------------------------------------------------------------

// Σ value × (the pixel's area inside the disk): the integral over the disk of the image read as
// a piecewise-constant function, which eval is. The plain Σ value (2/N)² also counts the rim
// pixels' corners beyond the horizon: at N = 40 that adds 0.3% (normal incidence) to 1.2% (30°)
// to the stam lobe, whose R-OHS factor grows as 1/cosθ_o toward the rim.
double disk_integral(const LobeImage& image, std::size_t layer) {
    const double side = 2.0 / image.resolution;
    double sum = 0.0;
    for (int row = 0; row < image.resolution; ++row)
        for (int col = 0; col < image.resolution; ++col) {
            if (!inside_unit_disk(disk_pixel_point(row, col, image.resolution))) continue;
            const double x0 = -1.0 + col * side, y1 = 1.0 - row * side;
            sum += image.at(layer, row, col) * area_inside_disk(x0, x0 + side, y1 - side, y1);
        }
    return sum;
}

class BsdfConformance : public ::testing::TestWithParam<MethodCase> {};

// Bsdf::sample evaluates every sample's weight, so where an eval is costly 10⁶ samples per
// incidence, or the albedo at N = 128, would take minutes; such methods test their samplers
// themselves. gabor (15–50 µs per eval, two wavelengths, second order): over its kernel mixture,
// the mean weight at N = 32 (tests/lib/methods/gabor/gabor_sampling_test.cpp). discrete (a count
// of flakes in a tree per eval): over Jakob 2014's sampler, the mean weight at N = 40
// (tests/lib/methods/discrete/flake_sampling_test.cpp). fft (its point evaluation of eq. 6, about
// a millisecond for two wavelengths here): its sampler is the images' sampler, tested here with
// every method that samples its images; the mean weight at N = 32 (tests/lib/methods/fft/fft_point_test.cpp).
bool sampler_tested_with_its_method(const std::string& method) {
    return method == "gabor" || method == "discrete" || method == "fft";
}

TEST_P(BsdfConformance, SamplesFollowThePdfWhichIntegratesToOne) {
    if (sampler_tested_with_its_method(GetParam().method.name)) GTEST_SKIP() << "tested with the method";
    const Bsdf bsdf = make_bsdf(GetParam().method.name, isotropic_query(Quantity::brdf));
    const CounterRng rng(22, 1);
    for (double degrees : {0.0, 30.0, 70.0}) {
        const Vec3 omega_i = incidence(degrees);
        const Grid grid = bsdf.samples_directly() ? Grid::half_vector : Grid::omega_o;
        std::vector<long> observed(kCells * kCells + 1, 0);
        for (long k = 0; k < kSamples; ++k) {
            const BsdfSample s = bsdf.sample(omega_i, rng.uniform(2 * k), rng.uniform(2 * k + 1));
            if (s.pdf == 0.0) {
                ++observed.back();
                continue;
            }
            ASSERT_GT(s.omega_o.z, 0.0);
            if (k % 997 == 0) {
                ASSERT_NEAR(s.pdf, bsdf.pdf(omega_i, s.omega_o), 1e-9 * s.pdf);
            }
            ++observed[kChiSquare.cell_of(grid, omega_i, s.omega_o)];
        }
        const auto expected = kChiSquare.expected_probabilities(grid, omega_i, [&](Vec3 omega) { return bsdf.pdf(omega_i, omega); });
        EXPECT_GT(kChiSquare.p_value(observed, expected), testing::sidak_significance(kChiSquareTestsPerCase))
            << "incidence " << degrees << " degrees";
    }
}

// The method's image of the test query at an incidence, and its ω_i.
// Gabor's eval is the closed-form sum of its kernels' transforms, which its images compute with
// evaluation=products (the default sums the kernels on the fft grid: docs/gabor.md "Images").
std::pair<LobeImage, Vec3> image_at(const std::string& method, double degrees) {
    LobeQuery query = isotropic_query(Quantity::brdf);
    query.omega_i = incidence(degrees);
    if (method == "gabor") query.method_options["evaluation"] = "products";
    return {compute_lobe(method, query), query.omega_i};
}

TEST_P(BsdfConformance, EvalEqualsTheImageAtPixelCentres) {
    const Bsdf bsdf = make_bsdf(GetParam().method.name, isotropic_query(Quantity::brdf));
    for (double degrees : {0.0, 30.0}) {
        const auto [image, omega_i] = image_at(GetParam().method.name, degrees);
        for (int row = 0; row < kResolution; ++row)
            for (int col = 0; col < kResolution; ++col) {
                const DiskPoint p = disk_pixel_point(row, col, kResolution);
                if (!inside_unit_disk(p)) continue;
                const std::vector<double> f = bsdf.eval(omega_i, direction_from_disk(p.x, p.y));
                for (std::size_t layer = 0; layer < image.layers(); ++layer)
                    ASSERT_NEAR(f[layer], image.at(layer, row, col), 1e-4 * image.at(layer, row, col))
                        << row << "," << col;
            }
    }
}

// albedo() is the exact integral of an eval read from the image's pixels. For a method's point
// query it is the image's own disk sum at supersample 4, a quadrature of the continuous lobe
// whose mean weight is the exact integral: at N = 128 (not the suite's 40) the quadrature's
// error stays below the 3 standard errors of 2·10⁵ weights. The dk image at supersample 4 also
// reads a D_K table that was itself supersampled (the BSDF's is point-sampled): 0.13% apart at
// N = 128, so point queries are held to 2e-3 of the image sum, images to 1e-3.
TEST_P(BsdfConformance, AlbedoIsTheImageSumAndTheMeanWeight) {
    if (sampler_tested_with_its_method(GetParam().method.name)) GTEST_SKIP() << "tested with the method";
    LobeQuery query = isotropic_query(Quantity::brdf);
    const bool direct = make_bsdf(GetParam().method.name, query).evaluates_directly();
    query.resolution = direct ? 128 : kResolution;
    const Bsdf bsdf = make_bsdf(GetParam().method.name, query);
    for (double degrees : {0.0, 30.0}) {
        query.omega_i = incidence(degrees);
        query.supersample = direct ? 4 : 1;
        const LobeImage image = compute_lobe(GetParam().method.name, query);
        const Vec3 omega_i = query.omega_i;
        const std::vector<double> albedo = bsdf.albedo(omega_i);
        const testing::MeanWeight weights = testing::mean_weight(bsdf, omega_i, 200'000, CounterRng(22, 2));
        for (std::size_t layer = 0; layer < image.layers(); ++layer) {
            const double image_sum = direct ? disk_sum(image, layer) : disk_integral(image, layer);
            EXPECT_NEAR(albedo[layer], image_sum, (direct ? 2e-3 : 1e-3) * image_sum) << degrees << " degrees, layer " << layer;
            const double mean = weights.mean[layer];
            const double error = weights.standard_error[layer];
            // Rounding alone, where the weight is constant (one pixel's f_r/p_A is the same everywhere).
            EXPECT_NEAR(mean, albedo[layer], 3.0 * error + 1e-9 * albedo[layer]) << degrees << " degrees";
        }
    }
}

TEST_P(BsdfConformance, OneAndEightThreadsGiveTheSameAnswers) {
    const LobeQuery query = isotropic_query(Quantity::brdf);
    const std::vector<Vec3> incident = {incidence(30.0), incidence(70.0)};
    // fft's point evaluation sums a grid of ~640k samples per wavelength: fewer queries.
    const int queries = GetParam().method.name == "fft" ? 400 : 4000;
    // Each answer as numbers, in query order: eval at a fixed direction, then a sample.
    auto answers = [&](const Bsdf& bsdf, int threads) {
        std::vector<std::vector<double>> out(queries);
        auto work = [&](int first) {
            const CounterRng rng(22, 3);
            for (int k = first; k < queries; k += threads) {
                const Vec3& omega_i = incident[k % incident.size()];
                const BsdfSample s = bsdf.sample(omega_i, rng.uniform(2 * k), rng.uniform(2 * k + 1));
                out[k] = bsdf.eval(omega_i, direction_from_spherical(0.3, 0.01 * k));
                out[k].insert(out[k].end(), {s.omega_o.x, s.omega_o.y, s.omega_o.z, s.pdf});
                out[k].insert(out[k].end(), s.weight.begin(), s.weight.end());
            }
        };
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t) pool.emplace_back(work, t);
        for (std::thread& thread : pool) thread.join();
        return out;
    };
    const auto one = answers(make_bsdf(GetParam().method.name, query), 1);
    const auto eight = answers(make_bsdf(GetParam().method.name, query), 8);
    EXPECT_EQ(one, eight);
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, BsdfConformance, ::testing::ValuesIn(cases(Quantity::brdf)), case_name);

// ---- Reciprocity ---------------------------------------------------------------------------

struct ReciprocityCase {
    std::string method;
    DiffractionModel model;
    std::map<std::string, std::string> options;
    bool reciprocal;
};

// f(a, b) against f(b, a) at pixel centres of the tables, over the pairs of four directions
// (two near each other's mirror directions, where the lobe is strong: every table costs an
// image); the largest difference relative to the larger of the two, where that is above 1% of
// the largest value seen.
double largest_reciprocity_error(const ReciprocityCase& c) {
    LobeQuery query = isotropic_query(Quantity::brdf);
    query.model = c.model;
    query.method_options = c.options;
    const Bsdf bsdf = make_bsdf(c.method, query);
    auto centre = [](int row, int col) {
        const DiskPoint p = disk_pixel_point(row, col, kResolution);
        return direction_from_disk(p.x, p.y);
    };
    const std::vector<Vec3> directions = {centre(14, 17), centre(27, 21), centre(24, 11), centre(14, 31)};
    std::vector<std::pair<double, double>> values;
    double peak = 0.0;
    for (std::size_t i = 0; i < directions.size(); ++i)
        for (std::size_t j = i + 1; j < directions.size(); ++j) {
            values.push_back({bsdf.eval(directions[i], directions[j])[0], bsdf.eval(directions[j], directions[i])[0]});
            peak = std::max({peak, values.back().first, values.back().second});
        }
    EXPECT_GT(peak, 0.05) << c.method << ": the pairs miss the lobe";
    double largest = 0.0;
    for (const auto& [ab, ba] : values)
        if (std::max(ab, ba) > 0.01 * peak) largest = std::max(largest, std::fabs(ab - ba) / std::max(ab, ba));
    return largest;
}

TEST(BsdfReciprocity, ReciprocalModelsAndMethodsAreSymmetricAndOhsIsNot) {
    const std::vector<ReciprocityCase> cases = {
        {"fft", DiffractionModel::rohs, {}, true},
        {"fft", DiffractionModel::rghs, {}, true},
        {"fft", DiffractionModel::kirchhoff, {}, true},
        {"gabor", DiffractionModel::rohs, {}, true},
        {"stam", DiffractionModel::rohs, {}, true},
        // A BSDF reads point samples (supersample 1), not the exact pixel integrals that are
        // geometric's automatic choice (those are 3% from reciprocal at N = 40 and 120).
        {"geometric", DiffractionModel::rohs, {{"shadowing", "none"}}, true},
        {"dk", DiffractionModel::rohs, {}, true},
        // Eq. 8's set is symmetric in ω_i and ω_o, the counts' approximations (the adaptive
        // criterion, eq. 10, and shares of partial cells) are not quite: 3.5% apart at the default
        // error 0.1, 1.1% at 0.001 (tested below).
        {"discrete", DiffractionModel::rohs, {{"error", "0.001"}}, true},
        {"fft", DiffractionModel::ohs, {}, false},  // ξ1 = cosθ_o/cosθ_i: the negative control
    };
    for (const ReciprocityCase& c : cases) {
        const double error = largest_reciprocity_error(c);
        if (c.reciprocal)
            EXPECT_LT(error, c.method == "discrete" ? 0.02 : 2e-3) << c.method << " " << to_string(c.model);
        else
            EXPECT_GT(error, 0.05) << c.method << " " << to_string(c.model);
    }
}

// ---- NDF -----------------------------------------------------------------------------------

class NdfConformance : public ::testing::TestWithParam<MethodCase> {};

// An NDF from its image reads the image's pixels (1e-4). A point query (pndf's, normal_density/
// normal_bounds_tree.hpp) is D at h itself, whose mean over a pixel is the pixel: its 24 × 24
// means are held to 7% relative L2 of the image (measured at N = 40: 0.114 at K = 8, 0.047 at
// K = 24: the caustics of the rough surface make D singular along folds, and the quadrature
// converges as 1/K).
TEST_P(NdfConformance, SamplesFollowThePdfAndDIsTheImage) {
    const LobeQuery query = isotropic_query(Quantity::ndf);
    const Ndf ndf = make_ndf(GetParam().method.name, query);
    const LobeImage image = compute_lobe(GetParam().method.name, query);
    const int k = ndf.evaluates_directly() ? 24 : 1;
    double difference = 0.0, norm = 0.0;
    for (int row = 0; row < kResolution; ++row)
        for (int col = 0; col < kResolution; ++col) {
            const DiskPoint p = disk_pixel_point(row, col, kResolution);
            if (!inside_unit_disk(p)) continue;
            double mean = 0.0;
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a) {
                    const DiskPoint q = disk_subpixel_point(row, col, b, a, kResolution, k);
                    if (inside_unit_disk(q)) mean += ndf.eval(direction_from_disk(q.x, q.y))[0] / (k * k);
                }
            const double pixel = image.at(0, row, col);
            if (k == 1) {
                ASSERT_NEAR(mean, pixel, 1e-4 * pixel) << row << "," << col;
            }
            difference += (mean - pixel) * (mean - pixel);
            norm += pixel * pixel;
        }
    RecordProperty("relative_l2", ::testing::PrintToString(std::sqrt(difference / norm)));
    EXPECT_LT(std::sqrt(difference / norm), 0.07);
    const double image_sum = disk_integral(image, 0);
    EXPECT_NEAR(ndf.normalisation()[0], image_sum, 1e-3 * image_sum);
    // A point query's own sampler (pndf's) is tested against its pdf with its method
    // (tests/lib/methods/pndf/pndf_test.cpp, on a paraboloid): here the caustics make D singular
    // along folds, beyond the cells' quadrature, and each sample's pdf is a point query.
    if (ndf.samples_directly()) return;
    const CounterRng rng(22, 4);
    std::vector<long> observed(kCells * kCells + 1, 0);
    for (long k = 0; k < kSamples; ++k) {
        const NdfSample s = ndf.sample(rng.uniform(2 * k), rng.uniform(2 * k + 1));
        ASSERT_GT(s.pdf, 0.0);
        ++observed[kChiSquare.cell_of(Grid::omega_o, {0.0, 0.0, 1.0}, s.h)];
    }
    const auto expected = kChiSquare.expected_probabilities(Grid::omega_o, {0.0, 0.0, 1.0}, [&](Vec3 h) { return ndf.pdf(h); });
    EXPECT_GT(kChiSquare.p_value(observed, expected), testing::sidak_significance(1));
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, NdfConformance, ::testing::ValuesIn(cases(Quantity::ndf)), case_name);

// ---- Bad input -----------------------------------------------------------------------------

TEST(BsdfInput, BadDirectionsAndAveragedFootprintsAreRefusedInOneLine) {
    LobeQuery query = isotropic_query(Quantity::brdf);
    const Bsdf bsdf = make_bsdf("stam", query);
    EXPECT_THROW(bsdf.eval({NAN, 0.0, 1.0}, {0.0, 0.0, 1.0}), Error);
    EXPECT_THROW(bsdf.pdf({0.0, 0.0, 1.0}, {0.0, 0.0, 0.0}), Error);
    EXPECT_EQ(bsdf.eval({0.0, 0.0, 1.0}, {0.0, 0.6, -0.8}), std::vector<double>(2, 0.0));
    EXPECT_EQ(bsdf.pdf({0.0, 0.6, -0.8}, {0.0, 0.0, 1.0}), 0.0);
    query.footprints = parse_footprint_set("grid");
    EXPECT_THROW(make_bsdf("stam", query), Error);
    EXPECT_THROW(make_bsdf("pndf", isotropic_query(Quantity::brdf)), Error);  // an NDF method
}

}  // namespace
}  // namespace glintscope
