// compute_lobe: dispatch, validation, quantities, option keys, error prefixes and metadata.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/lobe/image.hpp"
#include "glintscope/lobe/query.hpp"
#include "lobe_queries.hpp"

namespace glintscope {
namespace {

using testing::compute_error;
using testing::flat_query;

// A footprint below the wavelength sends most of a flat mirror's light beyond the hemisphere (the
// fft lobe's albedo 0.8 at σ_c = 0.1 µm, λ = 0.5 µm, against 1 at 3 µm), and the run says why;
// a geometric method, which has no wavelength scale, is not warned.
TEST(ComputeLobe, WarnsOfWaveFootprintsBelowTheWavelength) {
    const auto below_wavelength = [](const LobeRun& run) {
        for (const std::string& warning : run.warnings)
            if (warning.find("is below the wavelength") != std::string::npos) return true;
        return false;
    };
    LobeQuery query = flat_query();
    query.resolution = 64;
    query.supersample = 2;
    const LobeRun wide = run_lobe("fft", query);
    EXPECT_FALSE(below_wavelength(wide));
    EXPECT_NEAR(disk_sum(wide.image), 1.0, 0.02);
    query.footprint.sigma_um = 0.1;
    const LobeRun narrow = run_lobe("fft", query);
    EXPECT_TRUE(below_wavelength(narrow));
    EXPECT_LT(disk_sum(narrow.image), 0.9);
    // The footprint's BSDF says it too (it holds for every direction), and only it.
    EXPECT_EQ(make_bsdf("fft", query).warnings(), footprint_warnings("fft", query.footprint, query.wavelengths_um));
    ASSERT_EQ(footprint_warnings("fft", query.footprint, query.wavelengths_um).size(), 1u);
    EXPECT_NE(footprint_warnings("fft", query.footprint, query.wavelengths_um)[0].find("is below the wavelength"),
              std::string::npos);
    EXPECT_FALSE(below_wavelength(run_lobe("geometric", query)));
}

TEST(ComputeLobe, UnknownMethodListsTheAvailableOnes) {
    const std::string message = compute_error("raytrace", flat_query());
    EXPECT_NE(message.find("unknown method 'raytrace'"), std::string::npos) << message;
    for (const MethodInfo& method : lobe_methods()) EXPECT_NE(message.find(method.name), std::string::npos) << message;
}

TEST(ComputeLobe, InvalidQueriesFailBeforeTheMethodRuns) {
    LobeQuery query = flat_query();
    query.resolution = 2;
    EXPECT_NE(compute_error("fft", query).find("resolution must be between 4 and 8192"), std::string::npos);
    query = flat_query();
    query.omega_i = {0.0, 0.0, 2.0};
    EXPECT_NE(compute_error("gabor", query).find("unit vector"), std::string::npos);
}

TEST(ComputeLobe, UnknownOptionsAndBadValuesNameTheMethodOnce) {
    LobeQuery query = flat_query();
    query.method_options["colour"] = "blue";
    const std::string unknown = compute_error("gabor", query);
    EXPECT_EQ(unknown.rfind("gabor: method 'gabor' has no option 'colour' (options: ", 0), 0u) << unknown;
    query.method_options = {{"kernels_per_texel", "2.5"}};
    const std::string bad = compute_error("gabor", query);
    EXPECT_EQ(bad.rfind("gabor: ", 0), 0u) << bad;
    EXPECT_EQ(bad.find("gabor: ", 1), std::string::npos) << bad;  // prefixed once
    EXPECT_NE(bad.find("kernels_per_texel"), std::string::npos) << bad;
}

TEST(ComputeLobe, AMethodRefusesAQuantityItDoesNotAnswer) {
    LobeQuery query = flat_query();
    query.quantity = Quantity::ndf;
    const std::string message = compute_error("fft", query);
    EXPECT_NE(message.find("method 'fft' does not compute ndf"), std::string::npos) << message;
}

TEST(ComputeLobe, MetadataNamesTheMethodItsReferenceAndTheQuery) {
    LobeQuery query = flat_query();
    query.method_options["kernels_per_texel"] = "1";
    const LobeImage image = compute_lobe("gabor", query);
    EXPECT_EQ(image.metadata.at("method"), "gabor");
    EXPECT_EQ(image.metadata.at("method.reference"), lobe_method("gabor").reference);
    EXPECT_EQ(image.metadata.at("quantity"), "brdf");
    EXPECT_EQ(image.metadata.at("query.sigma_c"), "3");
    EXPECT_EQ(image.metadata.at("query.centre"), "16,16");
    EXPECT_EQ(image.metadata.at("query.option.kernels_per_texel"), "1");
    EXPECT_EQ(image.metadata.at("query.omega_i"), "0,0,1");
    EXPECT_EQ(image.metadata.at("heightfield.size"), "32x32");
    EXPECT_EQ(image.quantity, Quantity::brdf);
}

TEST(ComputeLobe, EveryMethodHasAReferenceInTheCitationForm) {
    for (const MethodInfo& method : lobe_methods()) {
        EXPECT_FALSE(method.description.empty()) << method.name;
        // "<Author> <Year> eq. N" (or § / Fig.): a bare "eq. 6" would be ambiguous.
        EXPECT_TRUE(std::regex_search(method.reference, std::regex("^[A-Z][a-z]+ (19|20)[0-9]{2} (eq\\.|§|sec\\.|Fig\\.)")))
            << method.reference;
        EXPECT_FALSE(method.quantities.empty()) << method.name;
    }
}

}  // namespace
}  // namespace glintscope
