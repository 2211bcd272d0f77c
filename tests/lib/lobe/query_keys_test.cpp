// Query keys: text → query → text is a fixed point, and an output's metadata re-runs the query
// bit for bit.
#include <gtest/gtest.h>

#include "glintscope/core/error.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/output/lobe_output.hpp"
#include "glintscope/lobe/query_keys.hpp"
#include "cli_runner.hpp"

namespace glintscope {
namespace {

std::string value_of(const QueryText& text, const std::string& key) {
    for (const auto& [name, value] : text)
        if (name == key) return value;
    return "(absent)";
}

std::string error_of(const QueryText& text) {
    try {
        make_query(text);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(QueryKeys, TextToQueryToTextIsAFixedPoint) {
    const QueryText given = {{"heightfield", "builtin:grating"}, {"centre", "20um,30um"}, {"sigma_c", "5um"},
                             {"incident", "30,45"},             {"spectral", "4"},       {"model", "kirchhoff"},
                             {"material", "Au"},                {"res", "64"},           {"supersample", "2"},
                             {"option.step", "0.05um"}};
    const LobeQuery query = make_query(given);
    EXPECT_DOUBLE_EQ(query.footprint.centre_um.x, 20.0);
    EXPECT_DOUBLE_EQ(query.footprint.sigma_um, 5.0);
    EXPECT_NEAR(query.omega_i.z, std::cos(30.0 * pi / 180.0), 1e-15);
    EXPECT_EQ(query.wavelengths_um.size(), 4u);
    EXPECT_EQ(query.method_options.at("step"), "0.05um");
    const QueryText written = query_text(query);
    EXPECT_EQ(value_of(written, "centre"), "20,30");
    EXPECT_EQ(value_of(written, "incident"), "(absent)");  // written as the exact omega_i
    const QueryText rewritten = query_text(make_query(written));
    EXPECT_EQ(rewritten, written);
}

TEST(QueryKeys, ABoxTakesOneSideOrTwoWithTheUnitWrittenOnce) {
    const LobeQuery rectangle = make_query({{"heightfield", "builtin:grating"}, {"box", "0.07x0.053mm"}});
    EXPECT_EQ(rectangle.footprint.shape, FootprintShape::box);
    EXPECT_DOUBLE_EQ(box_width_um(rectangle.footprint), 70.0);
    EXPECT_DOUBLE_EQ(box_height_um(rectangle.footprint), 53.0);
    EXPECT_EQ(value_of(query_text(rectangle), "box"), "70x53");
    const LobeQuery mixed = make_query({{"heightfield", "builtin:grating"}, {"box", "70um x 0.053mm"}});
    EXPECT_DOUBLE_EQ(box_height_um(mixed.footprint), 53.0);
    const LobeQuery square = make_query({{"heightfield", "builtin:grating"}, {"box", "20um"}});
    EXPECT_DOUBLE_EQ(box_height_um(square.footprint), 20.0);
    EXPECT_EQ(value_of(query_text(square), "box"), "20");
    EXPECT_NE(error_of({{"heightfield", "builtin:grating"}, {"box", "70x53x2um"}}).find("WIDTHxHEIGHT"), std::string::npos);
    EXPECT_NE(error_of({{"heightfield", "builtin:grating"}, {"box", "70x"}}).find("query key box:"), std::string::npos);
    EXPECT_NE(error_of({{"heightfield", "builtin:grating"}, {"box", "70x0um"}}).find("box footprint sides"),
              std::string::npos);
}

TEST(QueryKeys, TheFootprintDefaultsToTheHeightfieldCentre) {
    const LobeQuery query = make_query({{"heightfield", "builtin:grating"}});
    EXPECT_DOUBLE_EQ(query.footprint.centre_um.x, query.field->centre_um().x);
    EXPECT_DOUBLE_EQ(query.footprint.centre_um.y, query.field->centre_um().y);
}

TEST(QueryKeys, ErrorsNameTheKey) {
    EXPECT_NE(error_of({{"heightfield", "builtin:grating"}, {"sigma_c", "ten"}}).find("query key sigma_c:"),
              std::string::npos);
    EXPECT_NE(error_of({{"heightfield", "builtin:grating"}, {"colour", "red"}}).find("unknown query key 'colour'"),
              std::string::npos);
    EXPECT_NE(error_of({{"heightfield", "builtin:grating"}, {"lambda", "0.5"}, {"spectral", "8"}})
                  .find("'lambda' and 'spectral' exclude each other"),
              std::string::npos);
    EXPECT_NE(error_of({{"heightfield", "builtin:grating"}, {"res", "8"}, {"res", "9"}}).find("given twice"),
              std::string::npos);
    EXPECT_NE(error_of({{"heightfield", "builtin:grating"}, {"incident", "95,0"}}).find("theta must be in [0, 90)"),
              std::string::npos);
    EXPECT_NE(error_of({{"sigma_c", "5"}}).find("names no heightfield"), std::string::npos);
}

TEST(QueryKeys, OverridesReplaceTheKeysTheyExclude) {
    const QueryText base = {{"heightfield", "a.exr"}, {"omega_i", "0,0,1"}, {"lambda", "0.5"}, {"res", "64"}};
    const QueryText merged = merge_query_text(base, {{"incident", "20,0"}, {"res", "128"}});
    EXPECT_EQ(value_of(merged, "omega_i"), "(absent)");
    EXPECT_EQ(value_of(merged, "incident"), "20,0");
    EXPECT_EQ(value_of(merged, "res"), "128");
    EXPECT_EQ(value_of(merged, "lambda"), "0.5");
}

// Any EXR or JSON the tool wrote holds its query; re-running it gives the same image, bit for bit.
TEST(QueryKeys, AnOutputsMetadataRerunsTheQueryBitForBit) {
    testing::TemporaryDirectory directory;
    const std::string field = directory.file("field.exr");
    {
        Heightfield rough = make_heightfield(48, 48, 0.5);
        for (int r = 0; r < 48; ++r)
            for (int c = 0; c < 48; ++c) rough.at(r, c) = float(0.3 * std::sin(0.7 * c + 0.2 * r) * std::cos(0.3 * r));
        save_heightfield(field, rough);
    }
    const QueryText given = {{"heightfield", field}, {"sigma_c", "3um"}, {"incident", "25,10"},
                             {"lambda", "0.45um"},  {"model", "rghs"},  {"res", "32"},
                             {"option.kernels_per_texel", "1"}};
    for (const std::string method : {"fft", "gabor"}) {
        QueryText text = given;
        if (method == "fft") text.pop_back();
        const LobeImage first = compute_lobe(method, make_query(text));
        const std::string exr = directory.file(method + ".exr");
        const std::string json = directory.file(method + ".json");
        write_lobe_exr(first, exr, {});
        write_lobe_json(first, json, {});
        for (const std::string& path : {exr, json}) {
            const Provenance metadata = read_output_metadata(path);
            EXPECT_EQ(metadata.at("method"), method);
            const LobeImage again = compute_lobe(metadata.at("method"), make_query(query_text_from_metadata(metadata)));
            EXPECT_EQ(again.values, first.values) << path;
        }
    }
}

}  // namespace
}  // namespace glintscope
