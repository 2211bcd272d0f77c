// The discrete method's images: as the number of flakes grows they converge to the smooth NDF and
// microfacet lobe (Jakob 2014: the model keeps the smooth BRDF on average), few flakes glitter,
// materials scale the lobe by Fresnel, and options are checked.
#include "methods/discrete/discrete_lobe.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <string>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/maps/glint_map.hpp"
#include "glintscope/optics/material.hpp"
#include "glintscope/fit/ndf_models.hpp"

namespace glintscope {
namespace {

LobeQuery flake_query(Quantity quantity, const std::string& flakes) {
    LobeQuery query;
    Heightfield flat;  // the method reads no heightfield
    flat.rows = flat.cols = 16;
    flat.heights_um.assign(256, 0.0f);
    set_heightfield(query, flat);
    query.quantity = quantity;
    query.resolution = 64;
    query.omega_i = direction_from_spherical(0.3, 0.4);
    query.footprint.centre_um = {4.0, 4.0};
    query.method_options["flakes"] = flakes;
    query.method_options.insert_or_assign("alpha", std::string("0.25"));
    return query;
}

// The smooth microfacet lobe of the same Beckmann distribution at each pixel centre (G = 1):
// F D/(4 cosθ_i cosθ_o) (conventions.md), or D itself for an NDF.
std::vector<double> smooth_image(const LobeQuery& query) {
    std::vector<double> values(static_cast<std::size_t>(query.resolution) * query.resolution, 0.0);
    for (int r = 0; r < query.resolution; ++r)
        for (int c = 0; c < query.resolution; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, query.resolution);
            if (!inside_unit_disk(p)) continue;
            const Vec3 omega = direction_from_disk(p.x, p.y);
            double& value = values[static_cast<std::size_t>(r) * query.resolution + c];
            if (query.quantity == Quantity::ndf) {
                value = beckmann_ndf(0.25, 0.25, omega);
            } else {
                const Vec3 h = normalize(query.omega_i + omega);
                value = beckmann_ndf(0.25, 0.25, h) / (4.0 * query.omega_i.z * omega.z);
            }
        }
    return values;
}

double relative_l2(const LobeImage& image, const std::vector<double>& reference) {
    double difference = 0.0, norm = 0.0;
    for (std::size_t k = 0; k < reference.size(); ++k) {
        difference += (image.values[k] - reference[k]) * (image.values[k] - reference[k]);
        norm += reference[k] * reference[k];
    }
    return std::sqrt(difference / norm);
}

// Relative L2 against the smooth image: the Poisson noise of the ~N·D·σ(Ω_h) flakes of a pixel
// falls as 1/√N down to a floor of about 0.5% set by Algorithm 2's 1% tolerance on the integrals of
// D that steer the multinomial draws (measured ndf 0.130, 0.0133, 0.0047; brdf 0.270, 0.029,
// 0.0057 for N = 1e4, 1e6, 1e8).
TEST(DiscreteLobe, ConvergesToTheSmoothMicrofacetModelAsFlakesIncrease) {
    for (const Quantity quantity : {Quantity::ndf, Quantity::brdf}) {
        std::vector<double> errors;
        for (const std::string flakes : {"1e4", "1e6", "1e8"}) {
            const LobeQuery query = flake_query(quantity, flakes);
            errors.push_back(relative_l2(compute_lobe("discrete", query), smooth_image(query)));
        }
        EXPECT_GT(errors[0], 0.1) << to_string(quantity);  // tens of flakes per pixel: visible glitter
        EXPECT_LT(errors[1], errors[0] / 7.0) << to_string(quantity);
        EXPECT_LT(errors[2], errors[1]) << to_string(quantity);
        EXPECT_LT(errors[2], 0.008) << to_string(quantity);
    }
}

TEST(DiscreteLobe, MaterialScalesTheLobeByFresnelAndSeedsChangeTheGlitter) {
    LobeQuery query = flake_query(Quantity::brdf, "1e5");
    query.resolution = 32;
    const LobeImage plain = compute_lobe("discrete", query);
    query.material.name = "Al";
    const LobeImage aluminium = compute_lobe("discrete", query);
    const ComplexIndex eta = complex_refractive_index("Al", query.wavelengths_um[0]);
    for (int r = 0; r < 32; ++r)
        for (int c = 0; c < 32; ++c) {
            const DiskPoint p = disk_pixel_point(r, c, 32);
            if (!inside_unit_disk(p)) continue;
            const Vec3 h = normalize(query.omega_i + direction_from_disk(p.x, p.y));
            EXPECT_NEAR(aluminium.at(0, r, c), fresnel_conductor(eta, dot(query.omega_i, h)) * plain.at(0, r, c),
                        1e-5 * plain.at(0, r, c) + 1e-12);
        }
    query.material.name.clear();
    query.method_options.insert_or_assign("seed", std::string("2"));
    EXPECT_GT(relative_l2(compute_lobe("discrete", query), std::vector<double>(plain.values.begin(), plain.values.end())), 0.05);
}

// With the heightfield's own P-NDF as the distribution, a billion flakes give back that P-NDF.
TEST(DiscreteLobe, ManyFlakesOfTheSurfacesOwnDistributionGiveItsPatchNdf) {
    Recipe recipe = default_recipe("isotropic");
    recipe.grid.rows = recipe.grid.cols = 128;
    LobeQuery query;
    set_heightfield(query, generate(recipe));
    query.quantity = Quantity::ndf;
    query.resolution = 48;
    query.footprint.centre_um = query.field->centre_um();
    const LobeImage pndf = compute_lobe("pndf", query);
    query.method_options.insert_or_assign("distribution", std::string("pndf"));
    query.method_options.insert_or_assign("flakes", std::string("1e9"));
    const LobeImage flakes = compute_lobe("discrete", query);
    const std::vector<double> reference(pndf.values.begin(), pndf.values.begin() + 48 * 48);
    // Measured 0.031: the flakes average the P-NDF over a cap of one pixel's solid angle, the pndf
    // image over the pixel's square, and this P-NDF has sharp folds.
    EXPECT_LT(relative_l2(flakes, reference), 0.05);
}

// The default flakes follow Beckmann α 0.2 whatever the heightfield: the run says so (a note,
// said once), and not when the flakes follow the heightfield's own P-NDF.
TEST(DiscreteLobe, SaysWhenItsFlakesIgnoreTheHeightfield) {
    Recipe recipe = default_recipe("isotropic");
    recipe.grid.rows = recipe.grid.cols = 64;
    LobeQuery query;
    set_heightfield(query, generate(recipe));
    query.resolution = 16;
    query.footprint.centre_um = query.field->centre_um();
    query.method_options["flakes"] = "1e4";
    const auto mentions = [](const LobeRun& run) {
        return std::count_if(run.notes.begin(), run.notes.end(),
                             [](const std::string& note) { return note.find("not the heightfield") != std::string::npos; });
    };
    EXPECT_EQ(mentions(run_lobe("discrete", query)), 1);
    query.method_options["distribution"] = "pndf";
    EXPECT_EQ(mentions(run_lobe("discrete", query)), 0);
}

// The glint map's centre is the lobe's pixel at the same ω_o, and its mean over many footprints is
// the smooth lobe there (each footprint holds ~60 flakes in the cone; 256 positions 16 µm apart).
TEST(DiscreteGlintMap, CentreIsTheLobePixelAndMeanIsTheSmoothLobe) {
    LobeQuery query = flake_query(Quantity::brdf, "3e4");
    query.resolution = 32;
    query.method_options.insert_or_assign("error", std::string("0"));
    const LobeImage lobe = compute_lobe("discrete", query);
    const DiskPoint p = disk_pixel_point(14, 12, 32);
    const Vec3 omega_o = direction_from_disk(p.x, p.y);
    const ScalarImage centred = discrete_glint_map(query, omega_o, 3, 2.0);
    EXPECT_FLOAT_EQ(centred.values[4], lobe.at(0, 14, 12));
    const ScalarImage map = discrete_glint_map(query, omega_o, 16, 16.0);
    double mean = 0.0;
    for (float value : map.values) mean += value / map.values.size();
    const Vec3 h = normalize(query.omega_i + omega_o);
    const double smooth = beckmann_ndf(0.25, 0.25, h) / (4.0 * query.omega_i.z * omega_o.z);
    EXPECT_NEAR(mean, smooth, 0.05 * smooth);  // measured 0.7% below; standard error about 1%
    EXPECT_THROW(discrete_glint_map(query, omega_o, 0, 1.0), Error);
    query.method_options.insert_or_assign("kernels_per_texel", std::string("2"));
    EXPECT_THROW(discrete_glint_map(query, omega_o, 8, 1.0), Error);
}

TEST(DiscreteLobe, OptionsAreChecked) {
    LobeQuery query = flake_query(Quantity::ndf, "1e5");
    query.method_options.insert_or_assign("flake_density", std::string("3"));
    EXPECT_THROW(compute_lobe("discrete", query), Error);
    query.method_options.erase("flake_density");
    for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
             {"alpha", "0"}, {"distribution", "phong"}, {"cone", "45"}, {"error", "-1"}, {"seed", "1.5"}, {"tile", "10"},
             {"flakes", "1e30"}, {"flakes", "nan"}}) {
        LobeQuery bad = query;
        bad.method_options[key] = value;
        EXPECT_THROW(compute_lobe("discrete", bad), Error) << key << "=" << value;
    }
}

}  // namespace
}  // namespace glintscope

namespace glintscope {
namespace {

// The point field a renderer uses (a BSDF per shading point, each with its own footprint): for
// the query's own footprint it is the image's pixel at supersample 1 (the same count at the
// pixel centre's cone; exact counts, error 0: eq. 10's estimates are draws keyed by the query's
// conic, and with them the two differed by up to 15% at 1e4 flakes, probably because the image's
// sub-pixel point and disk_pixel_point differ in the last bits), and for a footprint 100× larger in area it counts the same flakes there
// (glitter: it differs from the small footprint's) and converges to the smooth lobe of their
// distribution (≈ 8·10⁵ flakes per cone: 1%; measured below 2% at 6 directions).
TEST(DiscreteLobe, ThePointFieldIsTheImagesPixelAndCountsAnyFootprintsFlakes) {
    LobeQuery query = flake_query(Quantity::brdf, "1e4");
    query.resolution = 16;
    query.supersample = 1;
    query.wavelengths_um = {0.5};
    query.material.name = "Al";
    query.method_options["error"] = "0";
    const LobeImage image = compute_lobe("discrete", query);
    const BsdfField field = make_bsdf_field("discrete", query);
    const Bsdf own = field.at(query.footprint);
    int lit = 0;
    for (const auto& [row, col] : {std::pair{8, 8}, {6, 9}, {9, 5}, {4, 7}, {10, 10}, {7, 12}}) {
        const DiskPoint p = disk_pixel_point(row, col, 16);
        const double value = own.eval(query.omega_i, direction_from_disk(p.x, p.y))[0];
        EXPECT_NEAR(value, image.at(0, row, col), 1e-5 * image.at(0, row, col)) << row << "," << col;
        lit += value > 0.0;
    }
    EXPECT_GE(lit, 4);
    Footprint large = query.footprint;
    large.sigma_um = 10.0 * query.footprint.sigma_um;  // 1e6 flakes under it
    LobeQuery dense = query;
    dense.method_options["flakes"] = "1e6";  // the same flakes per µm² at the query's own footprint
    dense.method_options["error"] = "0.01";
    const Bsdf large_bsdf = make_bsdf_field("discrete", dense).at(large);
    const double fresnel_normal = fresnel_conductor(complex_refractive_index("Al", 0.5), 1.0);
    for (const auto& [theta, phi] : {std::pair{0.3, 3.5}, {0.2, 2.0}, {0.5, 4.0}, {0.4, 3.0}, {0.1, 0.0}, {0.6, 3.6}}) {
        const Vec3 omega_o = direction_from_spherical(theta, phi);
        const Vec3 h = normalize(query.omega_i + omega_o);
        const double fresnel = fresnel_conductor(complex_refractive_index("Al", 0.5), dot(query.omega_i, h));
        const double smooth = fresnel * beckmann_ndf(0.25, 0.25, h) / (4.0 * query.omega_i.z * omega_o.z);
        EXPECT_NEAR(large_bsdf.eval(query.omega_i, omega_o)[0], smooth, 0.02 * smooth) << theta << "," << phi;
        EXPECT_GT(fresnel, 0.8 * fresnel_normal);
    }
}

}  // namespace
}  // namespace glintscope
