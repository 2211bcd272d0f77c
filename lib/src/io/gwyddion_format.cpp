// Heightfields in the formats glintscope does not read natively (Gwyddion's .gwy, Digital
// Surf .sur, Sensofar, Keyence, Zygo and some 150 more), through the file modules of
// Gwyddion's library (libgwyddion20-dev and the gwyddion package's modules; GPL-2+, so a binary
// built with them is bound by the GPL when distributed: docs/dependencies.md). Built only with
// -DGLINTSCOPE_GWYDDION=ON; without it such files get a line saying how to read them.
//
// The library runs headless: file modules are loaded non-interactively and need no display.
// One channel is read (LoadOptions::channel by index or title, else the first). Gwyddion's row 0
// is the top of its image, as ours is, so the heightfield looks as Gwyddion shows it. Lateral
// spacings and heights come in metres when the file gives SI units; other height units (V, A,
// none) are left as stored numbers and reported as assumed.
#include "formats.hpp"
#include "glintscope/core/atomic_output.hpp"

#ifdef GLINTSCOPE_HAVE_GWYDDION

#include <charconv>
#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include <app/gwyapp.h>
#include <libgwyddion/gwyddion.h>
#include <libgwydgets/gwydgets.h>
#include <libgwymodule/gwymodule.h>
#include <libprocess/gwyprocess.h>

#include "glintscope/core/text_format.hpp"

namespace glintscope {
namespace {

void ignore_log(const gchar*, GLogLevelFlags, const gchar*, gpointer) {}

// Registers the file modules once; the library's own log lines (a missing ~/.gwyddion) are
// dropped, so a failure is our one line.
void start_gwyddion() {
    static std::once_flag once;
    std::call_once(once, [] {
        g_log_set_default_handler(ignore_log, nullptr);
        gwy_widgets_type_init();
        gchar** directories = gwy_app_settings_get_module_dirs();
        gwy_module_register_modules(const_cast<const gchar**>(directories));
        g_strfreev(directories);
    });
}

struct ContainerHandle {
    GwyContainer* container = nullptr;
    ~ContainerHandle() {
        if (container) g_object_unref(container);
    }
};

std::string unit_text(GwySIUnit* unit) {
    gchar* text = gwy_si_unit_get_string(unit, GWY_SI_UNIT_FORMAT_PLAIN);
    std::string result = text ? text : "";
    g_free(text);
    return result;
}

std::string channel_title(GwyContainer* container, int id) {
    const gchar* title = nullptr;
    gwy_container_gis_string(container, gwy_app_get_data_title_key_for_id(id), reinterpret_cast<const guchar**>(&title));
    return title ? title : "";
}

// The requested channel's id: by index into the file's channels, or by title.
int choose_channel(GwyContainer* container, const std::string& requested, const std::string& path) {
    gint* ids = gwy_app_data_browser_get_data_ids(container);
    std::vector<int> channels;
    for (gint* id = ids; *id != -1; ++id) channels.push_back(*id);
    g_free(ids);
    if (channels.empty()) throw read_error(path, "Gwyddion finds no image channel in it");
    if (requested.empty()) return channels.front();
    std::string available;
    for (std::size_t i = 0; i < channels.size(); ++i) {
        const std::string title = channel_title(container, channels[i]);
        if (title == requested) return channels[i];
        available += (i ? ", " : "") + std::to_string(i) + ":" + title;
    }
    std::size_t index = 0;
    const auto [end, ec] = std::from_chars(requested.data(), requested.data() + requested.size(), index);
    if (ec == std::errc() && end == requested.data() + requested.size() && index < channels.size())
        return channels[index];
    throw read_error(path, "no channel '" + requested + "' (available: " + available + ")");
}

}  // namespace

bool reads_other_formats_through_gwyddion() { return true; }

Heightfield read_gwyddion(const std::string& path, const LoadOptions& options) {
    start_gwyddion();
    GError* error = nullptr;
    ContainerHandle data{gwy_file_load(path.c_str(), GWY_RUN_NONINTERACTIVE, &error)};
    if (!data.container) {
        const std::string message = error && error->message ? error->message : "unknown error";
        if (error) g_error_free(error);
        throw read_error(path, "Gwyddion's library cannot read it (" + message + ")");
    }
    const int id = choose_channel(data.container, options.channel, path);
    GwyDataField* source = GWY_DATA_FIELD(gwy_container_get_object(data.container, gwy_app_get_data_key_for_id(id)));
    const int cols = gwy_data_field_get_xres(source), rows = gwy_data_field_get_yres(source);
    check_grid_size(cols, rows, path);
    const std::string xy_unit = unit_text(gwy_data_field_get_si_unit_xy(source));
    const std::string z_unit = unit_text(gwy_data_field_get_si_unit_z(source));
    const double dx_um = gwy_data_field_get_dx(source) * 1e6, dy_um = gwy_data_field_get_dy(source) * 1e6;

    StoredUnits stored;
    if (xy_unit == "m") stored.texel_um = dx_um;
    if (z_unit == "m") stored.height_unit = LengthUnit::m;
    const HeightConversion conversion = resolve_units(stored, options, path);

    Heightfield field = make_heightfield(rows, cols, conversion.texel_um);
    field.units_assumed = conversion.units_assumed;
    const gdouble* values = gwy_data_field_get_data_const(source);
    for (std::size_t i = 0; i < field.size(); ++i) field.heights_um[i] = conversion.to_um(values[i]);
    gchar* module = nullptr;
    if (const gchar* name = gwy_file_detect(path.c_str(), FALSE, GWY_FILE_OPERATION_LOAD)) module = g_strdup(name);
    field.provenance["gwyddion:module"] = module ? module : "unknown";
    g_free(module);
    field.provenance["gwyddion:channel"] = channel_title(data.container, id);
    field.provenance["gwyddion:units"] = "lateral '" + xy_unit + "', heights '" + z_unit + "'";
    apply_spacing(field, options, conversion.texel_um, {dx_um, dy_um, 1e-6, xy_unit == "m"}, path);
    return field;
}

}  // namespace glintscope

#else

namespace glintscope {

bool reads_other_formats_through_gwyddion() { return false; }

Heightfield read_gwyddion(const std::string& path, const LoadOptions&) {
    throw read_error(path, "'." + file_extension(path) +
                               "' files are read through Gwyddion's library, which this build lacks "
                               "(install libgwyddion20-dev and gwyddion, and build with -DGLINTSCOPE_GWYDDION=ON)");
}

}  // namespace glintscope

#endif
