// What every method in the table gets tested for, for every quantity it answers: a new method
// is covered by adding its table line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "glintscope/core/text_format.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/lobe/query.hpp"
#include "glintscope/output/lobe_output.hpp"
#include "glintscope/core/parallel.hpp"
#include "method_cases.hpp"

#include "lobe_queries.hpp"

namespace glintscope {
namespace {

using testing::MethodCase;

std::string case_name(const ::testing::TestParamInfo<MethodCase>& info) {
    return info.param.method.name + "_" + to_string(info.param.quantity);
}

LobeQuery isotropic_query(Quantity quantity) {
    LobeQuery query = testing::isotropic_builtin_query(quantity);
    query.omega_i = direction_from_spherical(0.2, 0.3);
    query.resolution = 48;
    query.supersample = 2;
    return query;
}

class MethodConformance : public ::testing::TestWithParam<MethodCase> {};

TEST_P(MethodConformance, ImageShapeDiskAndValues) {
    const LobeQuery query = isotropic_query(GetParam().quantity);
    const LobeImage image = compute_lobe(GetParam().method.name, query);
    ASSERT_EQ(image.resolution, query.resolution);
    ASSERT_EQ(image.wavelengths_um, query.wavelengths_um);
    ASSERT_EQ(image.values.size(), image.layers() * 48 * 48);
    EXPECT_EQ(image.quantity, query.quantity);
    for (std::size_t layer = 0; layer < image.layers(); ++layer)
        for (int row = 0; row < 48; ++row)
            for (int col = 0; col < 48; ++col) {
                const float value = image.at(layer, row, col);
                ASSERT_TRUE(std::isfinite(value));
                ASSERT_GE(value, 0.0f);
                if (!inside_unit_disk(disk_pixel_point(row, col, 48))) {
                    ASSERT_EQ(value, 0.0f) << row << "," << col;
                }
            }
}

// NDFs integrate to 1 on the projected disk; BRDF albedos of this rough, mostly non-grazing
// surface at 11.5° incidence lie just below 1 (F = 1; a little light leaves below the horizon).
TEST_P(MethodConformance, NormalisationOnTheIsotropicBuiltin) {
    const LobeImage image = compute_lobe(GetParam().method.name, isotropic_query(GetParam().quantity));
    for (const WavelengthSummary& summary : summarize_lobe(image)) {
        if (GetParam().quantity == Quantity::ndf)
            EXPECT_NEAR(summary.disk_sum, 1.0, 0.02) << summary.wavelength_um;
        else
            EXPECT_TRUE(summary.disk_sum > 0.9 && summary.disk_sum < 1.02) << summary.disk_sum;
    }
}

TEST_P(MethodConformance, MetadataRecordsMethodReferenceAndWhatDoesNotApply) {
    const MethodInfo& method = GetParam().method;
    const LobeImage image = compute_lobe(method.name, isotropic_query(GetParam().quantity));
    EXPECT_EQ(image.metadata.at("method"), method.name);
    EXPECT_EQ(image.metadata.at("method.reference"), method.reference);
    EXPECT_EQ(image.metadata.at("quantity"), to_string(GetParam().quantity));
    EXPECT_EQ(image.metadata.at("query.res"), "48");
    // Without a material a geometric method's λ changes nothing: listed, so captions omit it.
    EXPECT_EQ(image.metadata.count("not_applicable"), method.ignored.empty() && method.wave_optics ? 0u : 1u);
    if (!method.wave_optics) {
        const std::vector<std::string> listed = split(image.metadata.at("not_applicable"), ',');
        EXPECT_NE(std::find(listed.begin(), listed.end(), "lambda"), listed.end()) << method.name;
    }
}

TEST_P(MethodConformance, UnknownOptionIsRejectedWithTheMethodsName) {
    LobeQuery query = isotropic_query(GetParam().quantity);
    query.method_options["no_such_option"] = "1";
    try {
        compute_lobe(GetParam().method.name, query);
        FAIL() << "accepted an unknown option";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(GetParam().method.name + ": ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find("no_such_option"), std::string::npos) << e.what();
    }
}

TEST_P(MethodConformance, ResultsDoNotDependOnTheThreadCount) {
    const LobeQuery query = isotropic_query(GetParam().quantity);
    EXPECT_EQ(testing::compute_with_threads(GetParam().method.name, query, 1).values,
              testing::compute_with_threads(GetParam().method.name, query, 4).values);
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, MethodConformance,
                         ::testing::ValuesIn(testing::method_cases([](Quantity) { return true; })), case_name);

}  // namespace
}  // namespace glintscope
