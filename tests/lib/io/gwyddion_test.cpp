// Gwyddion's library as the independent implementation, where it is installed: it reads the X3P
// files glintscope writes with the same heights, spacing and orientation, its statistics of the
// same data agree with our ISO 25178-2 parameters, and (when the build reads through it,
// -DGLINTSCOPE_GWYDDION=ON) a .gwy file that Gwyddion wrote loads here with its heights and
// spacing. Without the reader, instrument formats get one line saying how to read them.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "cli_runner.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/surface/areal_parameters.hpp"

#ifdef GLINTSCOPE_TEST_GWYDDION
#include <app/gwyapp.h>
#include <libgwyddion/gwyddion.h>
#include <libgwydgets/gwydgets.h>
#include <libgwymodule/gwymodule.h>
#include <libprocess/gwyprocess.h>
#endif

namespace glintscope {
namespace {

using testing::TemporaryDirectory;

// A smooth, anisotropic non-periodic test surface: two sinusoids and a bump, 0.4 µm texels.
Heightfield test_surface() {
    Heightfield field = make_heightfield(48, 64, 0.4);
    field.periodic = false;
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) {
            const Point2 s = sample_position(field, r, c);
            field.at(r, c) = static_cast<float>(0.3 * std::sin(s.x / 1.7) + 0.1 * std::cos(s.y / 0.9 + 0.3 * s.x) +
                                                0.5 * std::exp(-((s.x - 9) * (s.x - 9) + (s.y - 7) * (s.y - 7)) / 6.0));
        }
    return field;
}

#ifdef GLINTSCOPE_TEST_GWYDDION

void ignore_log(const gchar*, GLogLevelFlags, const gchar*, gpointer) {}

void start_gwyddion() {
    static bool started = false;
    if (started) return;
    started = true;
    g_log_set_default_handler(ignore_log, nullptr);
    gwy_widgets_type_init();
    gchar** directories = gwy_app_settings_get_module_dirs();
    gwy_module_register_modules(const_cast<const gchar**>(directories));
    g_strfreev(directories);
}

// The first channel of `path` as Gwyddion's library reads it (the container owns it).
GwyDataField* gwyddion_channel(GwyContainer* container) {
    gint* ids = gwy_app_data_browser_get_data_ids(container);
    const gint id = ids[0];
    g_free(ids);
    return GWY_DATA_FIELD(gwy_container_get_object(container, gwy_app_get_data_key_for_id(id)));
}

TEST(Gwyddion, ReadsOurX3pWithTheSameHeightsSpacingAndOrientation) {
    start_gwyddion();
    const TemporaryDirectory directory;
    const std::string path = directory.file("ours.x3p");
    const Heightfield field = test_surface();
    save_heightfield(path, field);
    GwyContainer* container = gwy_file_load(path.c_str(), GWY_RUN_NONINTERACTIVE, nullptr);
    ASSERT_NE(container, nullptr);
    GwyDataField* read = gwyddion_channel(container);
    ASSERT_EQ(gwy_data_field_get_xres(read), field.cols);
    ASSERT_EQ(gwy_data_field_get_yres(read), field.rows);
    EXPECT_NEAR(gwy_data_field_get_dx(read), field.texel_um * 1e-6, 1e-15);
    EXPECT_NEAR(gwy_data_field_get_dy(read), field.texel_um * 1e-6, 1e-15);
    // Gwyddion draws the X3P's first row (y = 0, our bottom row) at its top.
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c)
            EXPECT_NEAR(gwy_data_field_get_val(read, c, field.rows - 1 - r) * 1e6, field.at(r, c), 1e-6) << r << "," << c;
    g_object_unref(container);
}

TEST(Gwyddion, ItsStatisticsAgreeWithOurIsoParameters) {
    start_gwyddion();
    const Heightfield field = test_surface();
    GwyDataField* same = gwy_data_field_new(field.cols, field.rows, field.cols * field.texel_um * 1e-6,
                                            field.rows * field.texel_um * 1e-6, FALSE);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) gwy_data_field_set_val(same, c, r, field.at(r, c) * 1e-6);
    gdouble mean = 0, ra = 0, rms = 0, skew = 0, kurtosis = 0;
    gwy_data_field_get_stats(same, &mean, &ra, &rms, &skew, &kurtosis);
    const ArealParameters p = compute_areal_parameters(field);
    EXPECT_NEAR(p.sq_um, rms * 1e6, 1e-6 * p.sq_um);
    EXPECT_NEAR(p.sa_um, ra * 1e6, 1e-6 * p.sa_um);
    EXPECT_NEAR(p.ssk, skew, 1e-5);
    EXPECT_NEAR(p.sku, kurtosis + 3.0, 1e-5);  // Gwyddion reports the excess kurtosis
    // Sdr: Gwyddion triangulates each texel, we use central differences; on this smooth field the
    // two discretisations of ∫√(1 + |∇z|²) agree to a few per cent of Sdr.
    const double projected = field.cols * field.rows * field.texel_um * field.texel_um * 1e-12;
    const double gwyddion_sdr = gwy_data_field_get_surface_area(same) / projected - 1.0;
    EXPECT_NEAR(p.sdr, gwyddion_sdr, 0.05 * gwyddion_sdr);
    g_object_unref(same);
}

TEST(Gwyddion, AGwyFileThatGwyddionWroteLoadsWithItsHeightsAndSpacing) {
    if (!reads_other_formats_through_gwyddion()) GTEST_SKIP() << "this build does not read through Gwyddion";
    start_gwyddion();
    const TemporaryDirectory directory;
    const std::string path = directory.file("written-by-gwyddion.gwy");
    const Heightfield field = test_surface();
    GwyDataField* written = gwy_data_field_new(field.cols, field.rows, field.cols * field.texel_um * 1e-6,
                                               field.rows * field.texel_um * 1e-6, FALSE);
    gwy_si_unit_set_from_string(gwy_data_field_get_si_unit_xy(written), "m");
    gwy_si_unit_set_from_string(gwy_data_field_get_si_unit_z(written), "m");
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c) gwy_data_field_set_val(written, c, r, field.at(r, c) * 1e-6);
    GwyContainer* container = gwy_container_new();
    gwy_container_set_object(container, gwy_app_get_data_key_for_id(0), written);
    gwy_container_set_const_string(container, gwy_app_get_data_title_key_for_id(0),
                                   reinterpret_cast<const guchar*>("Height"));
    ASSERT_EQ(gwy_file_save(container, path.c_str(), GWY_RUN_NONINTERACTIVE, nullptr), GWY_FILE_OPERATION_SAVE);
    g_object_unref(written);
    g_object_unref(container);

    LoadOptions options;
    options.channel = "Height";
    const Heightfield loaded = load_heightfield(path, options);
    ASSERT_EQ(loaded.rows, field.rows);
    ASSERT_EQ(loaded.cols, field.cols);
    EXPECT_NEAR(loaded.texel_um, field.texel_um, 1e-12);
    EXPECT_FALSE(loaded.units_assumed);
    for (std::size_t i = 0; i < field.size(); ++i) EXPECT_NEAR(loaded.heights_um[i], field.heights_um[i], 1e-6) << i;
    EXPECT_EQ(loaded.provenance.at("gwyddion:channel"), "Height");
    EXPECT_NE(loaded.provenance.at("gwyddion:module").find("gwy"), std::string::npos)
        << loaded.provenance.at("gwyddion:module");
}

#endif

TEST(Gwyddion, InstrumentFormatsSayHowToReadThemWithoutTheLibrary) {
    if (reads_other_formats_through_gwyddion()) GTEST_SKIP() << "this build reads them through Gwyddion";
    const TemporaryDirectory directory;
    const std::string path = directory.file("scan.sur");
    std::ofstream(path) << "DIGITAL SURF";
    try {
        load_heightfield(path);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'.sur' files are read through Gwyddion's library, which this build lacks"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace glintscope
