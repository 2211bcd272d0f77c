// Heightfields from and to NumPy: Heightfield(array, texel=..., periodic=...), .heights as a view,
// load / save / generate, the preparation steps (each returns a new field, so that a view of the
// old one stays valid), and the statistics and ISO 25178-2 parameters as dicts.
#include <cmath>

#include "bindings.hpp"

#include "glintscope/core/error.hpp"
#include "glintscope/core/text_format.hpp"
#include "glintscope/core/units.hpp"
#include "glintscope/generate/generate.hpp"
#include "glintscope/io/heightfield_io.hpp"
#include "glintscope/prepare/prepare.hpp"
#include "glintscope/surface/areal_parameters.hpp"
#include "glintscope/surface/statistics.hpp"

namespace glintscope::python {

namespace {

double length_um(py::handle value, const std::string& what) {
    try {
        return parse_length_um(value_text(value));
    } catch (const Error& e) {
        throw Error(what + ": " + e.what());
    }
}

// Copies any 2-D float32/float64 array, whatever its strides (C, Fortran or a slice), into the
// field's row-major storage: the one copy, since the library's Heightfield owns its heights.
template <class T>
void copy_heights(const py::array& array, Heightfield& field) {
    const auto* base = static_cast<const char*>(array.data());
    const py::ssize_t row_stride = array.strides(0), col_stride = array.strides(1);
    for (int r = 0; r < field.rows; ++r)
        for (int c = 0; c < field.cols; ++c)
            field.at(r, c) = static_cast<float>(*reinterpret_cast<const T*>(base + r * row_stride + c * col_stride));
}

Heightfield from_array(const py::array& array, py::handle texel, bool periodic, bool allow_missing) {
    if (array.ndim() != 2)
        throw Error("a heightfield is a 2-D array of heights, got a " + std::to_string(array.ndim()) + "-D array");
    const py::dtype type = array.dtype();
    if (type.kind() != 'f' || (type.itemsize() != 4 && type.itemsize() != 8))
        throw Error("heights must be float32 or float64, got " + py::str(array.attr("dtype")).cast<std::string>());
    if (array.shape(0) < 1 || array.shape(1) < 1 || array.shape(0) > INT32_MAX || array.shape(1) > INT32_MAX)
        throw Error("a heightfield needs at least one row and one column, got " + std::to_string(array.shape(0)) + "x" +
                    std::to_string(array.shape(1)));
    Heightfield field = make_heightfield(int(array.shape(0)), int(array.shape(1)), length_um(texel, "texel"));
    if (type.itemsize() == 4)
        copy_heights<float>(array, field);
    else
        copy_heights<double>(array, field);
    field.periodic = periodic;
    validate(field, "the heightfield array", allow_missing);
    return field;
}

Tiling tiling_of(const Heightfield& field) { return field.periodic ? Tiling::periodic : Tiling::none; }

// The field after one preparation step on a copy of it, with the GIL released.
template <class Step>
Heightfield prepared(const Heightfield& field, Step step) {
    Heightfield copy = field;
    py::gil_scoped_release release;
    step(copy);
    return copy;
}

py::dict statistics_dict(const Heightfield& field) {
    SurfaceStatistics s;
    {
        py::gil_scoped_release release;
        s = compute_statistics(field);
    }
    return py::dict(py::arg("mean_um") = s.mean_um, py::arg("sq_um") = s.sq_um, py::arg("sa_um") = s.sa_um,
                    py::arg("min_um") = s.min_um, py::arg("max_um") = s.max_um, py::arg("rms_slope_x") = s.rms_slope_x,
                    py::arg("rms_slope_y") = s.rms_slope_y, py::arg("correlation_length_x_um") = s.correlation_length_x_um,
                    py::arg("correlation_length_y_um") = s.correlation_length_y_um,
                    py::arg("correlation_threshold") = s.correlation_threshold,
                    py::arg("autocorrelation_at_half_x") = s.autocorrelation_at_half_x,
                    py::arg("autocorrelation_at_half_y") = s.autocorrelation_at_half_y,
                    py::arg("missing_count") = s.missing_count, py::arg("missing_fraction") = s.missing_fraction);
}

py::dict iso_dict(const Heightfield& field, double threshold) {
    ArealParameters p;
    {
        py::gil_scoped_release release;
        p = compute_areal_parameters(field, threshold);
    }
    py::dict d(py::arg("Sq_um") = p.sq_um, py::arg("Ssk") = p.ssk, py::arg("Sku") = p.sku, py::arg("Sp_um") = p.sp_um,
               py::arg("Sv_um") = p.sv_um, py::arg("Sz_um") = p.sz_um, py::arg("Sa_um") = p.sa_um, py::arg("Sdq") = p.sdq,
               py::arg("Sdr") = p.sdr, py::arg("Sal_um") = p.sal_um, py::arg("Sal_is_lower_bound") = p.sal_is_lower_bound,
               py::arg("Sal_direction_deg") = p.sal_direction_deg, py::arg("Str") = p.str,
               py::arg("Str_is_upper_bound") = p.str_is_upper_bound, py::arg("Std_deg") = p.std_deg);
    d["threshold"] = p.threshold;
    d["longest_decay_um"] = p.longest_decay_um;
    d["longest_direction_deg"] = p.longest_direction_deg;
    d["max_lag_x_um"] = p.max_lag_x_um;
    d["max_lag_y_um"] = p.max_lag_y_um;
    return d;
}

Heightfield load(const std::string& path, const py::object& channel, const py::object& height_unit,
                 const py::object& texel, double height_scale, bool periodic) {
    LoadOptions options;
    if (!channel.is_none()) options.channel = value_text(channel);
    if (!height_unit.is_none()) options.height_unit = parse_length_unit(value_text(height_unit));
    if (py::isinstance<py::tuple>(texel) || py::isinstance<py::list>(texel)) {
        const py::sequence spacing = texel.cast<py::sequence>();
        if (spacing.size() != 2)
            throw Error("texel: one length or a pair (dx, dy), got " + std::to_string(spacing.size()) + " values");
        options.texel_um = length_um(spacing[0], "texel dx");
        options.texel_y_um = length_um(spacing[1], "texel dy");
    } else if (!texel.is_none()) {
        options.texel_um = length_um(texel, "texel");
    }
    options.height_scale = height_scale;
    options.periodic = periodic;
    py::gil_scoped_release release;
    return load_heightfield(path, options);
}

Heightfield generate_field(const py::object& kind, const py::object& recipe_path, const py::kwargs& parameters) {
    if (!kind.is_none() && !recipe_path.is_none()) throw Error("give a kind or a recipe file, not both");
    Recipe recipe = recipe_path.is_none() ? default_recipe(kind.is_none() ? "gaussian" : kind.cast<std::string>())
                                          : load_recipe(recipe_path.cast<std::string>());
    for (const auto& [key, value] : parameters) set_recipe_value(recipe, key.cast<std::string>(), value_text(value));
    if (const std::string warning = seamless_warning(recipe); !warning.empty())
        py::module_::import("warnings").attr("warn")(warning);
    py::gil_scoped_release release;
    return generate(recipe);
}

std::string recipe_keys_doc() {
    std::string doc = "Recipe keys (lengths in um or with a unit, angles in degrees):\n";
    for (const RecipeKey& key : recipe_keys()) doc += "    " + key.name + " [" + key.unit + "]: " + key.description + "\n";
    return doc;
}

}  // namespace

void bind_heightfield(py::module_& module) {
    py::class_<Heightfield, std::shared_ptr<Heightfield>>(
        module, "Heightfield", py::dynamic_attr(),
        "A grid of heights in um, row 0 at the top (largest y), sample spacing texel_um in x and y "
        "(conventions.md). NaN marks a missing point.")
        .def(py::init(&from_array), py::arg("heights"), py::kw_only(), py::arg("texel") = 1.0, py::arg("periodic") = false,
             py::arg("allow_missing") = false,
             "From a 2-D float32 or float64 array in um (C or Fortran order, any strides), copied once into the "
             "field. texel: a length (\"0.5um\" or a number in um). periodic: the array is one tile of a periodic "
             "surface. allow_missing: NaN are missing points (fill them with fill()); infinities are always refused.")
        .def_property_readonly(
            "heights",
            [](py::object self) {
                const auto& field = self.cast<const Heightfield&>();
                return float_view(field.heights_um.data(), {field.rows, field.cols}, self);
            },
            "The heights as a read-only float32 (rows, cols) view of the field's storage (no copy).")
        .def(
            "__array__",
            [](py::object self, py::object dtype) {
                py::object heights = self.attr("heights");
                return dtype.is_none() ? heights : heights.attr("astype")(dtype);
            },
            py::arg("dtype") = py::none())
        .def_readonly("rows", &Heightfield::rows)
        .def_readonly("cols", &Heightfield::cols)
        .def_readonly("texel_um", &Heightfield::texel_um, "dx, the column spacing (um).")
        .def_property_readonly("texel_y_um", &Heightfield::dy_um, "dy, the row spacing (um); texel_um when square.")
        .def_readonly("periodic", &Heightfield::periodic, "Whether the field tiles the plane (footprints may cross its border).")
        .def_readonly("units_assumed", &Heightfield::units_assumed)
        .def_property_readonly("shape", [](const Heightfield& f) { return py::make_tuple(f.rows, f.cols); })
        .def_property_readonly("width_um", &Heightfield::width_um)
        .def_property_readonly("height_um", &Heightfield::height_um)
        .def_property_readonly("missing", [](const Heightfield& f) { return count_missing(f); }, "Number of NaN points.")
        .def_property_readonly("provenance", [](const Heightfield& f) { return string_dict(f.provenance); },
                               "Where the field came from and each preparation step (prepare.N).")
        .def(
            "save", [](const Heightfield& f, const std::string& path) {
                py::gil_scoped_release release;
                save_heightfield(path, f);
            },
            py::arg("path"), "Writes .exr, .x3p or .npy atomically, with texel, units and provenance.")
        .def(
            "fill",
            [](const Heightfield& f, const std::string& method) {
                return prepared(f, [&](Heightfield& g) { fill_missing(g, parse_fill_method(method), tiling_of(g)); });
            },
            py::arg("method") = "biharmonic", "A copy with every NaN filled (harmonic or biharmonic inpainting).")
        .def(
            "remove_form",
            [](const Heightfield& f, py::handle order) {
                const int n = py::isinstance<py::str>(order) ? parse_form_order(order.cast<std::string>()) : order.cast<int>();
                return prepared(f, [&](Heightfield& g) { remove_form(g, n); });
            },
            py::arg("order") = "plane",
            "A copy less its least-squares Legendre form: \"mean\" (0), \"plane\" (1), \"poly:N\" or an order N <= 6.")
        .def(
            "crop",
            [](const Heightfield& f, py::handle x0, py::handle y0, py::handle width, py::handle height) {
                const CropRegion region{length_um(x0, "x0"), length_um(y0, "y0"), length_um(width, "width"),
                                        length_um(height, "height")};
                return prepared(f, [&](Heightfield& g) { crop(g, region); });
            },
            py::arg("x0"), py::arg("y0"), py::arg("width"), py::arg("height"),
            "A copy of the region whose lower-left corner is (x0, y0) from the field's lower-left corner (lengths).")
        .def(
            "resample",
            [](const Heightfield& f, py::handle texel) {
                const double texel_um = length_um(texel, "texel");
                return prepared(f, [&](Heightfield& g) { resample(g, texel_um, tiling_of(g)); });
            },
            py::arg("texel"), "A copy resampled to a new texel (bicubic; area-averaged first when downsampling).")
        .def(
            "orient",
            [](const Heightfield& f, bool flip_x, bool flip_y, int rotate) {
                return prepared(f, [&](Heightfield& g) { orient(g, Orientation{flip_x, flip_y, rotate}); });
            },
            py::arg("flip_x") = false, py::arg("flip_y") = false, py::arg("rotate") = 0,
            "A copy mirrored (x, then y) and turned counter-clockwise by 0, 90, 180 or 270 degrees (exact).")
        .def("statistics", &statistics_dict, "Mean, Sq, Sa, range, rms slopes, correlation lengths (1/e), missing points.")
        .def("iso_parameters", &iso_dict, py::arg("threshold") = kIsoAutocorrelationThreshold,
             "ISO 25178-2 areal parameters (Sq, Ssk, Sku, Sp, Sv, Sz, Sa, Sdq, Sdr, Sal, Str, Std) on the field as given.")
        .def("__repr__", [](const Heightfield& f) {
            return "<glintscope.Heightfield " + std::to_string(f.rows) + "x" + std::to_string(f.cols) + " texel " +
                   texel_text(f) + (f.periodic ? ", periodic" : "") + ">";
        });

    module.def("load", &load, py::arg("path"), py::kw_only(), py::arg("channel") = py::none(),
               py::arg("height_unit") = py::none(), py::arg("texel") = py::none(), py::arg("height_scale") = 1.0,
               py::arg("periodic") = false,
               "Reads a heightfield (.exr .tif .png .npy .x3p, ...) as the CLI does, with the same load options; "
               "texel: one length for square texels or a pair (dx, dy) for rectangular ones (each \"0.5um\" or a "
               "number in um), declared over what the file states.");
    static const std::string generate_doc = "A procedural heightfield: a kind (" + join(generator_kinds()) +
                                            "; default gaussian) or a recipe file, with recipe keys as keyword "
                                            "arguments.\n" + recipe_keys_doc();
    module.def("generate", &generate_field, py::arg("kind") = py::none(), py::kw_only(), py::arg("recipe") = py::none(),
               generate_doc.c_str());
    module.def("generator_kinds", &generator_kinds);
}

}  // namespace glintscope::python
