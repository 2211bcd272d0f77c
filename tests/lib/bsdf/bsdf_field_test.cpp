// Per-footprint BSDFs (BsdfField, for renderers): gabor's point query for any footprint equals
// its closed-form image at pixel centres, a field's BSDF of a footprint is make_bsdf's (to rounding),
// the answers do not depend on the calling threads, and methods without a point field are refused.
#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "method_cases.hpp"
#include "single_precision.hpp"

namespace glintscope {
namespace {

constexpr int kResolution = 24;

LobeQuery gabor_query() {
    LobeQuery query = testing::isotropic_builtin_query(Quantity::brdf);  // 0.45 and 0.6 µm
    query.resolution = kResolution;
    query.supersample = 1;
    return query;
}

// A few footprints away from the query's, one of them a box.
std::vector<Footprint> other_footprints(const LobeQuery& query) {
    std::vector<Footprint> footprints;
    for (int k = 0; k < 3; ++k) {
        Footprint f = query.footprint;
        f.centre_um = {f.centre_um.x + 37.5 * k - 20.0, f.centre_um.y - 11.0 * k};
        f.sigma_um = 6.0 + 4.0 * k;
        footprints.push_back(f);
    }
    Footprint box = query.footprint;
    set_box(box, "30x20um");
    footprints.push_back(box);
    return footprints;
}

Vec3 pixel_direction(int row, int col) {
    const DiskPoint p = disk_pixel_point(row, col, kResolution);
    return direction_from_disk(p.x, p.y);
}

// The products evaluation is the closed-form sum of the kernels' transforms at every sample, as
// the point query (second order: in double precision, stored as float).
TEST(BsdfField, GaborEvalEqualsItsClosedFormImageAtPixelCentres) {
    LobeQuery query = gabor_query();
    const Bsdf bsdf = make_bsdf("gabor", query);
    ASSERT_TRUE(bsdf.evaluates_directly());
    query.method_options["evaluation"] = "products";
    for (double degrees : {0.0, 35.0}) {
        query.omega_i = direction_from_spherical(degrees * pi / 180.0, 0.7);
        const LobeImage image = compute_lobe("gabor", query);
        for (int row = 0; row < kResolution; ++row)
            for (int col = 0; col < kResolution; ++col) {
                if (!inside_unit_disk(disk_pixel_point(row, col, kResolution))) continue;
                const std::vector<double> f = bsdf.eval(query.omega_i, pixel_direction(row, col));
                for (std::size_t layer = 0; layer < image.layers(); ++layer)
                    ASSERT_NEAR(f[layer], image.at(layer, row, col), 1e-4 * image.at(layer, row, col) + 1e-12)
                        << degrees << " degrees, pixel " << row << "," << col << ", layer " << layer;
            }
    }
}

// Wavelengths chosen per call: gabor's point query answers any λ, as a BSDF made with those
// wavelengths does (to rounding: that one prepares its second-order factors per wavelength); a BSDF answering from its images takes its own wavelengths only and names
// the one it cannot answer.
TEST(BsdfField, EvalAtChosenWavelengthsEqualsABsdfMadeWithThem) {
    const LobeQuery query = gabor_query();  // 0.45 and 0.6 µm
    const Bsdf bsdf = make_bsdf("gabor", query);
    ASSERT_TRUE(bsdf.any_wavelength());
    LobeQuery other = query;
    other.wavelengths_um = {0.5, 0.7};
    const Bsdf made_with_them = make_bsdf("gabor", other);
    const Vec3 omega_i = direction_from_spherical(0.3, 0.2);
    for (const Vec3 omega_o : {direction_from_spherical(0.25, 3.3), direction_from_spherical(0.45, 3.0)}) {
        const std::vector<double> chosen = bsdf.eval(omega_i, omega_o, {0.5, 0.7});
        const std::vector<double> expected = made_with_them.eval(omega_i, omega_o);
        ASSERT_EQ(chosen.size(), 2u);
        EXPECT_GT(expected[0], 0.0);
        EXPECT_NEAR(chosen[0], expected[0], 1e-9 * expected[0]);
        EXPECT_NEAR(chosen[1], expected[1], 1e-9 * expected[1]);
        // One wavelength or two: the same sum.
        const double both = bsdf.eval(omega_i, omega_o).at(1);
        EXPECT_NEAR(bsdf.eval(omega_i, omega_o, {0.6}).at(0), both, 1e-9 * both);
    }
    EXPECT_THROW(bsdf.eval(omega_i, omega_i, {0.0}), Error);

    const Bsdf from_images = make_bsdf("fft", query);
    ASSERT_FALSE(from_images.any_wavelength());
    const Vec3 omega_o = direction_from_spherical(0.25, 3.3);
    EXPECT_EQ(from_images.eval(omega_i, omega_o, {0.6}).at(0), from_images.eval(omega_i, omega_o).at(1));
    try {
        from_images.eval(omega_i, omega_o, {0.5});
        ADD_FAILURE() << "a wavelength the tables do not hold was answered";
    } catch (const Error& error) {
        EXPECT_NE(std::string(error.what()).find("not 0.5 um"), std::string::npos) << error.what();
    }
}

TEST(BsdfField, AtAFootprintIsMakeBsdfOfThatFootprint) {
    const LobeQuery query = gabor_query();
    const BsdfField field = make_bsdf_field("gabor", query);
    EXPECT_EQ(field.wavelengths_um(), query.wavelengths_um);
    const Vec3 omega_i = direction_from_spherical(0.5, 2.0);
    int nonzero = 0;
    for (const Footprint& footprint : other_footprints(query)) {
        LobeQuery at_footprint = query;
        at_footprint.footprint = footprint;
        const Bsdf own = make_bsdf("gabor", at_footprint);
        const Bsdf from_field = field.at(footprint);
        std::vector<std::vector<double>> expected_values, got_values;  // per direction, per wavelength
        for (int row = 0; row < kResolution; row += 3)
            for (int col = 0; col < kResolution; col += 3) {
                if (!inside_unit_disk(disk_pixel_point(row, col, kResolution))) continue;
                const Vec3 omega_o = pixel_direction(row, col);
                // The same kernels summed in another order: the field walks its hierarchy, a
                // footprint's own Bsdf its kernels sorted by slope.
                const std::vector<double> expected = own.eval(omega_i, omega_o);
                got_values.push_back(from_field.eval(omega_i, omega_o));
                expected_values.push_back(expected);
                nonzero += expected[0] > 0.0;
            }
        // The field's spectral sums are single precision, the footprint's own Bsdf's double.
        for (std::size_t w = 0; w < query.wavelengths_um.size(); ++w) {
            double brightest = 0.0;
            for (const std::vector<double>& values : expected_values) brightest = std::max(brightest, values[w]);
            for (std::size_t d = 0; d < expected_values.size(); ++d)
                EXPECT_NEAR(got_values[d][w], expected_values[d][w], single_precision_tolerance(expected_values[d][w], brightest));
        }
    }
    EXPECT_GT(nonzero, 20);  // the comparisons are of lobes, not of zeros
    // Footprints differ: the same direction gets another value elsewhere on the surface.
    const Vec3 omega_o = direction_from_spherical(0.45, 2.0 + pi);
    EXPECT_NE(field.at(other_footprints(query)[0]).eval(omega_i, omega_o),
              field.at(other_footprints(query)[1]).eval(omega_i, omega_o));
}

// Several ω_i at one ω_o (a renderer's lights): eval_incident equals eval direction by direction
// bit for bit, for gabor's field (one walk for all directions, two wavelengths) and for a method
// whose BSDF evaluates them one by one (stam), with unnormalised directions and one below the
// horizon.
TEST(BsdfField, EvalIncidentEqualsEvalDirectionByDirection) {
    const LobeQuery query = gabor_query();
    const BsdfField field = make_bsdf_field("gabor", query);
    std::vector<Vec3> omegas_i;
    for (int k = 0; k < 20; ++k) omegas_i.push_back((1.0 + 0.1 * k) * direction_from_spherical(0.1 + 0.04 * k, 0.5 + 0.02 * k));
    omegas_i.push_back({0.2, 0.1, -0.5});
    int nonzero = 0;
    for (const Bsdf& bsdf : {field.at(other_footprints(query)[1]), field.at(other_footprints(query)[3]),
                             make_bsdf("stam", query)})
        for (const Vec3 omega_o : {pixel_direction(12, 3), 2.0 * pixel_direction(5, 9)}) {
            const std::vector<double> together = bsdf.eval_incident(omegas_i, omega_o);
            const std::size_t layers = bsdf.wavelengths_um().size();
            ASSERT_EQ(together.size(), omegas_i.size() * layers);
            for (std::size_t d = 0; d < omegas_i.size(); ++d) {
                const std::vector<double> alone = bsdf.eval(omegas_i[d], omega_o);
                for (std::size_t w = 0; w < layers; ++w) {
                    EXPECT_EQ(together[d * layers + w], alone[w]) << bsdf.method() << " direction " << d;
                    nonzero += alone[w] > 0.0;
                }
            }
        }
    EXPECT_GT(nonzero, 50);
}

TEST(BsdfField, AnswersDoNotDependOnTheCallingThreads) {
    const LobeQuery query = gabor_query();
    const BsdfField field = make_bsdf_field("gabor", query);
    constexpr int kQueries = 400;
    auto answers = [&](int threads) {
        std::vector<std::vector<double>> out(kQueries);
        auto work = [&](int first) {
            for (int k = first; k < kQueries; k += threads) {
                Footprint footprint = query.footprint;
                footprint.centre_um = {footprint.centre_um.x + 3.7 * k, footprint.centre_um.y - 1.3 * k};
                out[k] = field.at(footprint).eval(direction_from_spherical(0.4, 0.1), direction_from_spherical(0.4, 0.1 + pi + 0.002 * k));
            }
        };
        std::vector<std::thread> pool;
        for (int t = 0; t < threads; ++t) pool.emplace_back(work, t);
        for (std::thread& thread : pool) thread.join();
        return out;
    };
    EXPECT_EQ(answers(1), answers(4));
}

TEST(BsdfField, MethodsWithoutAPointFieldAndBadFootprintsAreRefused) {
    const LobeQuery query = gabor_query();
    try {
        make_bsdf_field("stam", query);
        FAIL() << "stam has no point field";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("gabor"), std::string::npos) << e.what();
    }
    Footprint bad = query.footprint;
    bad.sigma_um = -1.0;
    EXPECT_THROW(make_bsdf_field("gabor", query).at(bad), Error);
    // An ellipse: only a point field that takes one (geometric without shadowing); a lobe query
    // (make_bsdf, images) would weigh by σ_c alone, so it refuses one naming it.
    LobeQuery elliptical = query;
    elliptical.footprint.sigma_minor_um = 0.5 * elliptical.footprint.sigma_um;
    try {
        make_bsdf("geometric", elliptical);
        FAIL() << "a lobe query took an ellipse";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("elliptical footprint"), std::string::npos) << e.what();
    }
}

// A rotated box: images hold axis-aligned boxes only, so a lobe query (an image method such as
// fft, or make_bsdf) refuses one in one line naming it, and so does a field whose point query
// does not take one (gabor; geometric with shadowing, answered from images); geometric's field
// without shadowing answers it.
TEST(BsdfField, RotatedBoxesAreRefusedWhereImagesWouldAnswerThem) {
    LobeQuery rotated = gabor_query();
    set_box(rotated.footprint, "12x8um");
    rotated.footprint.axis_radians = 0.4;
    const auto refusal = [](const auto& attempt) {
        try {
            attempt();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    for (const std::string& message : {refusal([&] { compute_lobe("fft", rotated); }), refusal([&] { make_bsdf("geometric", rotated); })}) {
        EXPECT_NE(message.find("rotated box"), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
    const LobeQuery query = gabor_query();
    const BsdfField gabor = make_bsdf_field("gabor", query);
    EXPECT_FALSE(gabor.answers_rotated_boxes());
    EXPECT_NE(refusal([&] { gabor.at(rotated.footprint); }).find("not a box rotated"), std::string::npos);
    LobeQuery shadowed = query;
    shadowed.method_options["shadowing"] = "smith";
    EXPECT_FALSE(make_bsdf_field("geometric", shadowed).answers_rotated_boxes());
    EXPECT_NE(refusal([&] { make_bsdf_field("geometric", shadowed).at(rotated.footprint); }).find("not a box rotated"),
              std::string::npos);
    const BsdfField geometric = make_bsdf_field("geometric", query);
    EXPECT_TRUE(geometric.answers_rotated_boxes());
    EXPECT_TRUE(geometric.at(rotated.footprint).evaluates_directly());
}

}  // namespace
}  // namespace glintscope
