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

// Where samples are counted: half-pixel cells of the projected disk of ω_o, on which a sampler
// over the images has a constant density, or of the half vector h = (ω_i + ω_o)/|ω_i + ω_o| for
// a method's own sampler, which draws h from a table of the NDF (Walter 2007): its density is
// constant over the table's pixels, whose sides (2/(2N), 2/(4N)) the cells' sides divide, so the
// expected counts are exact in either case. h ↦ ω_o is one to one, so either is a test of the
// whole distribution.
enum class Grid { omega_o, half_vector };

int cell_of(Grid grid, Vec3 omega_i, Vec3 omega_o) {
    const Vec3 w = grid == Grid::omega_o ? omega_o : normalize(omega_i + omega_o);
    const int col = std::clamp(static_cast<int>((w.x + 1.0) * 0.5 * kCells), 0, kCells - 1);
    const int row = std::clamp(static_cast<int>((1.0 - w.y) * 0.5 * kCells), 0, kCells - 1);
    return row * kCells + col;
}

// The probability of each disk cell: the density per disk area (pdf / cosθ) averaged over
// points × points points of the cell that lie inside the disk, times the cell's area inside the disk. Near
// grazing a lobe may put much of its mass in the rim's slivers (G = 1 and 1/cosθ_o), so a sliver
// that holds none of the points is read at its point nearest the disk's centre.
template <typename Pdf>
void disk_probabilities(const Pdf& pdf, int points, std::vector<double>& expected) {
    const double side = 2.0 / kCells;
    for (int row = 0; row < kCells; ++row)
        for (int col = 0; col < kCells; ++col) {
            const double x0 = -1.0 + col * side, y1 = 1.0 - row * side;
            const double area = area_inside_disk(x0, x0 + side, y1 - side, y1);
            if (area <= 0.0) continue;
            double sum = 0.0;
            int inside = 0;
            for (int a = 0; a < points; ++a)
                for (int b = 0; b < points; ++b) {
                    const DiskPoint p{x0 + (a + 0.5) * side / points, y1 - (b + 0.5) * side / points};
                    if (!inside_unit_disk(p)) continue;
                    const Vec3 omega = direction_from_disk(p.x, p.y);
                    sum += pdf(omega) / omega.z;
                    ++inside;
                }
            if (inside == 0) {
                const double x = std::clamp(0.0, x0, x0 + side), y = std::clamp(0.0, y1 - side, y1);
                const double shrink = (1.0 - 1e-9) / std::hypot(x, y);
                const Vec3 omega = direction_from_disk(x * shrink, y * shrink);
                sum = pdf(omega) / omega.z;
                inside = 1;
            }
            expected[row * kCells + col] = sum / inside * area;
        }
}

// The probability of every cell, and a last entry for samples that find no direction. Over h,
// the density per solid angle of h is pdf(ω_o) · 4 ω_o·h (Walter 2007 eq. 14).
template <typename Pdf>
std::vector<double> expected_probabilities(Grid grid, Vec3 omega_i, const Pdf& pdf) {
    std::vector<double> expected(kCells * kCells + 1, 0.0);
    if (grid == Grid::omega_o) {
        disk_probabilities(pdf, 4, expected);
        return expected;
    }
    disk_probabilities(
        [&](Vec3 h) {
            const double cos_ih = dot(omega_i, h);
            const Vec3 omega_o = 2.0 * cos_ih * h - omega_i;
            return cos_ih > 0.0 && omega_o.z > 0.0 ? pdf(omega_o) * 4.0 * cos_ih : 0.0;
        },
        16, expected);  // the horizon of ω_o cuts the cells of h along a curve: 16 × 16 points
    return expected;
}

// Upper tail of χ² with k degrees of freedom (Wilson–Hilferty: k is in the hundreds here).
double chi_square_tail(double statistic, double dof) {
    const double c = 2.0 / (9.0 * dof);
    const double z = (std::cbrt(statistic / dof) - (1.0 - c)) / std::sqrt(c);
    return 0.5 * std::erfc(z / std::sqrt(2.0));
}

// Pearson's statistic of the observed counts against the expected probabilities, cells with
// an expected count below 5 pooled into one; returns the p-value. The last cell counts the
// samples that found no direction (a microfacet sampler's h that reflects ω_i below the
// horizon): the pdf over the disk must integrate to 1 less their share, to 1e-3 beyond the
// share's own 3σ (a sampler over the images never fails: the pdf integrates to 1).
double chi_square_p_value(std::vector<long> observed, std::vector<double> expected) {
    double total = 0.0;
    for (double e : expected) total += e;
    const double failed = double(observed.back()) / kSamples;
    EXPECT_NEAR(total, 1.0 - failed, 1e-3 + 3.0 * std::sqrt(failed * (1.0 - failed) / kSamples))
        << "the pdf does not integrate to 1 less the failed samples' share";
    expected.back() = std::max(0.0, 1.0 - total);
    double statistic = 0.0, pooled_expected = 0.0;
    long pooled_observed = 0;
    int cells = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        const double e = expected[i] * kSamples;
        if (e < 5.0) {
            pooled_expected += e;
            pooled_observed += observed[i];
            continue;
        }
        statistic += (observed[i] - e) * (observed[i] - e) / e;
        ++cells;
    }
    if (pooled_expected > 0.0) {
        // A pool that expects nothing must receive nothing.
        if (pooled_expected < 5.0) {
            EXPECT_LE(pooled_observed, 5 + 5 * pooled_expected) << "samples where the pdf is ~0";
        } else {
            statistic += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
            ++cells;
        }
    }
    return cells > 1 ? chi_square_tail(statistic, cells - 1) : 1.0;
}

double sidak_significance(int tests) { return 1.0 - std::pow(1.0 - 0.01, 1.0 / tests); }

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

TEST_P(BsdfConformance, SamplesFollowThePdfWhichIntegratesToOne) {
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
            ++observed[cell_of(grid, omega_i, s.omega_o)];
        }
        const auto expected = expected_probabilities(grid, omega_i, [&](Vec3 omega) { return bsdf.pdf(omega_i, omega); });
        EXPECT_GT(chi_square_p_value(observed, expected), sidak_significance(kChiSquareTestsPerCase))
            << "incidence " << degrees << " degrees";
    }
}

// The method's image of the test query at an incidence, and its ω_i.
// gabor's point query is the closed-form sum of its kernels' transforms, which its images compute
// with evaluation=products (their default sums the kernels on the fft grid instead).
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
        const CounterRng rng(22, 2);
        constexpr long kWeights = 200'000;
        std::vector<double> sum(image.layers(), 0.0), sum_squares(image.layers(), 0.0);
        for (long k = 0; k < kWeights; ++k) {
            const BsdfSample s = bsdf.sample(omega_i, rng.uniform(2 * k), rng.uniform(2 * k + 1));
            for (std::size_t layer = 0; layer < image.layers(); ++layer) {
                sum[layer] += s.weight[layer];
                sum_squares[layer] += s.weight[layer] * s.weight[layer];
            }
        }
        for (std::size_t layer = 0; layer < image.layers(); ++layer) {
            const double image_sum = direct ? disk_sum(image, layer) : disk_integral(image, layer);
            EXPECT_NEAR(albedo[layer], image_sum, (direct ? 2e-3 : 1e-3) * image_sum) << degrees << " degrees, layer " << layer;
            const double mean = sum[layer] / kWeights;
            const double error = std::sqrt(std::max(0.0, sum_squares[layer] / kWeights - mean * mean) / kWeights);
            // Rounding alone, where the weight is constant (one pixel's f_r/p_A is the same everywhere).
            EXPECT_NEAR(mean, albedo[layer], 3.0 * error + 1e-9 * albedo[layer]) << degrees << " degrees";
        }
    }
}

TEST_P(BsdfConformance, OneAndEightThreadsGiveTheSameAnswers) {
    const LobeQuery query = isotropic_query(Quantity::brdf);
    const std::vector<Vec3> incident = {incidence(30.0), incidence(70.0)};
    constexpr int kQueries = 4000;
    // Each answer as numbers, in query order: eval at a fixed direction, then a sample.
    auto answers = [&](const Bsdf& bsdf, int threads) {
        std::vector<std::vector<double>> out(kQueries);
        auto work = [&](int first) {
            const CounterRng rng(22, 3);
            for (int k = first; k < kQueries; k += threads) {
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

TEST_P(NdfConformance, SamplesFollowThePdfAndDIsTheImage) {
    const LobeQuery query = isotropic_query(Quantity::ndf);
    const Ndf ndf = make_ndf(GetParam().method.name, query);
    const LobeImage image = compute_lobe(GetParam().method.name, query);
    for (int row = 0; row < kResolution; ++row)
        for (int col = 0; col < kResolution; ++col) {
            const DiskPoint p = disk_pixel_point(row, col, kResolution);
            if (!inside_unit_disk(p)) continue;
            ASSERT_NEAR(ndf.eval(direction_from_disk(p.x, p.y))[0], image.at(0, row, col),
                        1e-4 * image.at(0, row, col));
        }
    const double image_sum = disk_integral(image, 0);
    EXPECT_NEAR(ndf.normalisation()[0], image_sum, 1e-3 * image_sum);
    const CounterRng rng(22, 4);
    std::vector<long> observed(kCells * kCells + 1, 0);
    for (long k = 0; k < kSamples; ++k) {
        const NdfSample s = ndf.sample(rng.uniform(2 * k), rng.uniform(2 * k + 1));
        ASSERT_GT(s.pdf, 0.0);
        ++observed[cell_of(Grid::omega_o, {0.0, 0.0, 1.0}, s.h)];
    }
    const auto expected = expected_probabilities(Grid::omega_o, {0.0, 0.0, 1.0}, [&](Vec3 h) { return ndf.pdf(h); });
    EXPECT_GT(chi_square_p_value(observed, expected), sidak_significance(1));
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
