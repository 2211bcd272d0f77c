// A declared sample spacing (LoadOptions::texel_um, texel_y_um; the CLI's --texel 1x2um): files
// that store none (NPY) get it, files that store one are overridden, and the field records both.
#include <gtest/gtest.h>

#include "cli_runner.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/surface/areal_parameters.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

LoadOptions declared(double dx_um, double dy_um) {
    LoadOptions options;
    options.texel_um = dx_um;
    if (dy_um != dx_um) options.texel_y_um = dy_um;
    return options;
}

// An anisotropic C1 field at 1 × 2 µm, 96 × 128 µm... small enough to be quick.
Heightfield rectangular_field() {
    Recipe recipe = default_recipe("gaussian");
    recipe.grid = {64, 96, 1.0, 2.0};
    recipe.gaussian = {CorrelationFunction::c1, 0.1, 4.0, 8.0, 0.0};
    return generate(recipe);
}

TEST(DeclaredSpacing, NpyWithADeclaredSpacingIsTheExrWrittenAtIt) {
    TemporaryDirectory directory;
    const Heightfield field = rectangular_field();
    save_heightfield(directory.file("f.exr"), field);
    save_heightfield(directory.file("f.npy"), field);
    const Heightfield exr = load_heightfield(directory.file("f.exr"));
    const Heightfield npy = load_heightfield(directory.file("f.npy"), declared(1.0, 2.0));
    ASSERT_DOUBLE_EQ(exr.dy_um(), 2.0);
    EXPECT_DOUBLE_EQ(npy.dx_um(), 1.0);
    EXPECT_DOUBLE_EQ(npy.dy_um(), 2.0);
    EXPECT_EQ(npy.heights_um, exr.heights_um);
    EXPECT_EQ(npy.provenance.at("spacing.declared"), "1 um x 2 um (x by y)");
    EXPECT_EQ(npy.provenance.count("spacing.file"), 0u);  // NPY states none
    // Every statistic uses the spacing: the same numbers from both files.
    const SurfaceStatistics a = compute_statistics(exr);
    const SurfaceStatistics b = compute_statistics(npy);
    EXPECT_EQ(a.rms_slope_y, b.rms_slope_y);
    EXPECT_EQ(a.correlation_length_y_um, b.correlation_length_y_um);
    const ArealParameters pa = compute_areal_parameters(exr);
    const ArealParameters pb = compute_areal_parameters(npy);
    EXPECT_EQ(pa.sdq, pb.sdq);
    EXPECT_EQ(pa.sal_um, pb.sal_um);
    EXPECT_EQ(pa.str, pb.str);
    // Undeclared, the NPY reads as 1 µm squares: a different surface.
    EXPECT_NE(compute_statistics(load_heightfield(directory.file("f.npy"))).rms_slope_y, b.rms_slope_y);
}

TEST(DeclaredSpacing, OverridingAStoredSpacingRecordsTheFilesOwn) {
    TemporaryDirectory directory;
    save_heightfield(directory.file("f.x3p"), rectangular_field());
    const Heightfield field = load_heightfield(directory.file("f.x3p"), declared(0.5, 0.25));
    EXPECT_DOUBLE_EQ(field.dx_um(), 0.5);
    EXPECT_DOUBLE_EQ(field.dy_um(), 0.25);
    EXPECT_EQ(field.provenance.at("spacing.declared"), "500 nm x 250 nm (x by y)");
    EXPECT_EQ(field.provenance.at("spacing.file"), "1 um x 2 um (x by y)");
    // Spacings further apart than a resampling could bridge are refused as in a file.
    try {
        load_heightfield(directory.file("f.x3p"), declared(1.0, 20.0));
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("differ by more than 16 times"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace glintscope
