// Spectral lobes to colour arrays through output/colour (the CLI's EXR and PNG path): CIE XYZ,
// scene-linear RGB of an OpenColorIO space, and the 8-bit display pixels of its PNG.
#include "bindings.hpp"

#include "glintscope/core/error.hpp"
#include "glintscope/output/colour.hpp"

namespace glintscope::python {

namespace {

ColourSettings settings(const std::string& illuminant, const py::object& config) {
    ColourSettings colour;
    colour.illuminant = parse_illuminant(illuminant);
    if (!config.is_none()) colour.config_path = config.cast<std::string>();
    return colour;
}

std::vector<py::ssize_t> pixels_shape(const Lobe& lobe) { return {lobe.image.resolution, lobe.image.resolution, 3}; }

}  // namespace

void bind_colour(py::module_& module) {
    module.def(
        "to_xyz",
        [](const Lobe& lobe, const std::string& illuminant) {
            std::vector<float> xyz;
            {
                py::gil_scoped_release release;
                xyz = lobe_to_xyz(lobe.image, parse_illuminant(illuminant));
            }
            return owned_array(std::move(xyz), pixels_shape(lobe));
        },
        py::arg("lobe"), py::kw_only(), py::arg("illuminant") = "d65",
        "CIE XYZ (N, N, 3) float32 of a lobe under d65 or e, adapted to the D65 white (docs/colour.md); a "
        "single-wavelength lobe is the D65 white scaled to Y = f_r.");
    module.def(
        "to_rgb",
        [](const Lobe& lobe, const std::string& colour_space, const std::string& illuminant, const py::object& config) {
            ColourSettings colour = settings(illuminant, config);
            colour.output_space = colour_space;
            std::vector<float> rgb;
            {
                py::gil_scoped_release release;
                rgb = lobe_to_rgb(lobe.image, colour);
            }
            return owned_array(std::move(rgb), pixels_shape(lobe));
        },
        py::arg("lobe"), py::kw_only(), py::arg("colour_space") = "lin_rec709", py::arg("illuminant") = "d65",
        py::arg("config") = py::none(),
        "Scene-linear RGB (N, N, 3) float32 in an OpenColorIO space (the R, G, B of the CLI's EXR).");
    module.def(
        "to_display",
        [](const Lobe& lobe, const py::object& exposure, bool log_scale, const std::string& illuminant,
           const py::object& config) {
            ColourSettings colour = settings(illuminant, config);
            if (!exposure.is_none()) colour.exposure_ev = exposure.cast<double>();
            colour.log_scale = log_scale;
            DisplayImage display;
            {
                py::gil_scoped_release release;
                display = lobe_to_display(lobe.image, colour);
            }
            return py::make_tuple(owned_array(std::move(display.pixels), pixels_shape(lobe)), display.exposure.ev);
        },
        py::arg("lobe"), py::kw_only(), py::arg("exposure") = py::none(), py::arg("log") = false,
        py::arg("illuminant") = "d65", py::arg("config") = py::none(),
        "The sRGB 8-bit pixels (N, N, 3) of the CLI's colour PNG and the exposure in EV (auto unless given).");
    module.def("colour_spaces", [](const py::object& config) { return colour_space_names(settings("d65", config)); },
               py::arg("config") = py::none(), "The colour spaces of the OpenColorIO config (built in unless given).");
}

}  // namespace glintscope::python
