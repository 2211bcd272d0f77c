// Lobes and NDFs through the one library pipeline (run_lobe): the image as an (L, N, N) float32
// array with the metadata an EXR of the same query carries, comparison, validation and batch.
#include "bindings.hpp"

#include "glintscope/batch/batch.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/fit/ndf_fit.hpp"
#include "glintscope/lobe/compare.hpp"
#include "glintscope/output/lobe_output.hpp"
#include "glintscope/pipeline/pipeline.hpp"
#include "glintscope/validate/validate.hpp"

namespace glintscope::python {

namespace {

py::array_t<float> lobe_values(py::object self) {
    const LobeImage& image = self.cast<const Lobe&>().image;
    const py::ssize_t n = image.resolution;
    return float_view(image.values.data(), {py::ssize_t(image.layers()), n, n}, self);
}

std::shared_ptr<Lobe> run(py::handle heightfield, const std::string& method, const py::kwargs& keys, Quantity quantity) {
    const LobeQuery query = python_query(heightfield, keys, quantity);
    LobeRun result;
    {
        py::gil_scoped_release release;
        result = run_lobe(method, query);
    }
    const py::object warn = py::module_::import("warnings").attr("warn");
    for (const std::string& warning : result.warnings) warn(warning, py::handle(PyExc_RuntimeWarning), 2);
    return std::make_shared<Lobe>(Lobe{std::move(result.image), std::move(result.notes), std::move(result.warnings)});
}

py::dict comparison_dict(const LayerComparison& c) {
    return py::dict(py::arg("wavelength_um") = c.wavelength_um, py::arg("relative_l2") = c.relative_l2,
                    py::arg("max_abs_difference") = c.max_abs_difference, py::arg("max_row") = c.max_row,
                    py::arg("max_col") = c.max_col, py::arg("test_sum") = c.test_sum,
                    py::arg("reference_sum") = c.reference_sum, py::arg("energy_ratio") = c.energy_ratio(),
                    py::arg("peak_offset_pixels") = c.peak_offset_pixels,
                    py::arg("peak_relative_error") = c.peak_relative_error, py::arg("log_rms_error") = c.log_rms_error);
}

py::list compare(const Lobe& test, const Lobe& reference) {
    py::list layers;
    for (const LayerComparison& layer : compare_lobes(test.image, reference.image)) layers.append(comparison_dict(layer));
    return layers;
}

py::list validate_methods(py::handle heightfield, const std::string& test, const std::string& reference,
                          const std::vector<std::string>& models, const std::vector<int>& kernels_per_texel,
                          const std::vector<int>& orders, const py::kwargs& keys) {
    ValidationPlan plan;
    plan.base = python_query(heightfield, keys, Quantity::brdf);
    plan.test_method = test;
    plan.reference_method = reference;
    for (const std::string& model : models) plan.models.push_back(parse_diffraction_model(model));
    plan.kernels_per_texel = kernels_per_texel;
    plan.orders = orders;
    std::vector<ValidationRow> rows;
    {
        py::gil_scoped_release release;
        rows = run_validation(plan);
    }
    py::list list;
    for (const ValidationRow& row : rows) {
        py::dict entry = comparison_dict(row.comparison);
        entry["centre_um"] = py::make_tuple(row.centre_um.x, row.centre_um.y);
        entry["model"] = to_string(row.model);
        entry["kernels_per_texel"] = row.kernels_per_texel;
        entry["order"] = row.order;
        entry["test_seconds"] = row.test_seconds;
        entry["reference_seconds"] = row.reference_seconds;
        list.append(entry);
    }
    return list;
}

py::dict batch(const std::string& manifest_path, bool force, int jobs) {
    BatchResult result;
    {
        py::gil_scoped_release release;
        const Manifest manifest = load_manifest(manifest_path);
        BatchOptions options;
        options.force = force;
        options.jobs = jobs;
        result = run_batch(manifest, options, LobeOutputOptions{});
    }
    py::list panels;
    for (const PanelReport& panel : result.panels)
        panels.append(py::dict(py::arg("panel") = panel.panel, py::arg("notes") = panel.notes,
                               py::arg("warnings") = panel.warnings));
    return py::dict(py::arg("computed") = result.computed, py::arg("up_to_date") = result.up_to_date,
                    py::arg("figure") = result.figure_path, py::arg("record") = result.record_path,
                    py::arg("panels") = panels);
}

py::list summary(const Lobe& lobe) {
    py::list list;
    for (const WavelengthSummary& s : summarize_lobe(lobe.image))
        list.append(py::dict(py::arg("wavelength_um") = s.wavelength_um, py::arg("peak_value") = s.peak_value,
                             py::arg("peak_row") = s.peak_row, py::arg("peak_col") = s.peak_col,
                             py::arg("peak_direction") = py::make_tuple(s.peak_direction.x, s.peak_direction.y,
                                                                        s.peak_direction.z),
                             py::arg("disk_sum") = s.disk_sum));
    return list;
}

py::dict fit(const Lobe& ndf, const std::string& model) {
    NdfFit result;
    {
        py::gil_scoped_release release;
        result = fit_ndf(ndf.image, parse_ndf_model_kind(model));
    }
    const EllipsoidNdf& p = result.model.parameters;
    return py::dict(py::arg("model") = to_string(result.model.kind), py::arg("alpha_x") = p.alpha_x,
                    py::arg("alpha_y") = p.alpha_y, py::arg("theta_x") = p.theta_x, py::arg("theta_y") = p.theta_y,
                    py::arg("theta_z") = p.theta_z, py::arg("relative_error") = result.relative_error,
                    py::arg("image") = std::make_shared<Lobe>(Lobe{model_ndf_image(result.model, ndf.image.resolution), {}, {}}));
}

}  // namespace

void bind_lobe(py::module_& module) {
    py::class_<Lobe, std::shared_ptr<Lobe>>(
        module, "Lobe",
        "An N x N projected-disk image per wavelength (row 0 at the top, largest y; conventions.md): f_r in 1/sr "
        "(brdf) or D (ndf). Unpacks as (values, metadata).")
        .def_property_readonly("values", &lobe_values, "The (L, N, N) float32 image, a read-only view (no copy).")
        .def_property_readonly("metadata", [](const Lobe& l) { return string_dict(l.image.metadata); },
                               "The query and the method's choices: the glintscope:* attributes of the same query's EXR.")
        .def_property_readonly("wavelengths_um", [](const Lobe& l) { return l.image.wavelengths_um; })
        .def_property_readonly("quantity", [](const Lobe& l) { return to_string(l.image.quantity); })
        .def_property_readonly("resolution", [](const Lobe& l) { return l.image.resolution; })
        .def_readonly("notes", &Lobe::notes, "The choices the pipeline made (e.g. the supersampling), one line each.")
        .def_readonly("warnings", &Lobe::warnings, "Physics warnings (also issued as RuntimeWarning).")
        .def(
            "disk_sum", [](const Lobe& l, std::size_t layer) { return disk_sum(l.image, layer); }, py::arg("layer") = 0,
            "Sum of value (2/N)^2 over the disk: the albedo (brdf) or the normalisation (ndf).")
        .def("summary", &summary, "Per wavelength: the peak value, its pixel and direction, and the disk sum.")
        .def(
            "save",
            [](const Lobe& l, const std::string& path, const std::string& colour_space, bool spectral_channels) {
                LobeOutputOptions options;
                options.colour.output_space = colour_space;
                options.spectral_channels = spectral_channels;
                py::gil_scoped_release release;
                write_lobe(l.image, path, options);
            },
            py::arg("path"), py::kw_only(), py::arg("colour_space") = "lin_rec709", py::arg("spectral_channels") = false,
            "Writes .exr, .png or .json as the CLI does (atomically).")
        .def("__iter__", [](py::object self) { return py::iter(py::make_tuple(self.attr("values"), self.attr("metadata"))); })
        .def(
            "__array__",
            [](py::object self, py::object dtype) {
                py::object values = self.attr("values");
                return dtype.is_none() ? values : values.attr("astype")(dtype);
            },
            py::arg("dtype") = py::none())
        .def("__repr__", [](const Lobe& l) {
            return "<glintscope.Lobe " + to_string(l.image.quantity) + " " + std::to_string(l.image.layers()) + "x" +
                   std::to_string(l.image.resolution) + "x" + std::to_string(l.image.resolution) + ">";
        });

    static const std::string lobe_doc =
        "lobe(heightfield, method=\"fft\", **keys) -> Lobe\n\nThe reflection lobe f_r(omega_i, omega_o) [1/sr] of one "
        "footprint (or the mean over footprints=...), by the library pipeline the CLI's `lobe` runs. heightfield: a "
        "Heightfield, or a file path / builtin:KIND read as the CLI reads it. Raises glintscope.Error with the CLI's "
        "one-line message.\n\n" + query_keys_doc(true) + "\n" + methods_doc(Quantity::brdf);
    module.def(
        "lobe", [](py::handle field, const std::string& method, py::kwargs keys) { return run(field, method, keys, Quantity::brdf); },
        py::arg("heightfield"), py::arg("method") = "fft", lobe_doc.c_str());
    static const std::string ndf_doc =
        "ndf(heightfield, method=\"pndf\", **keys) -> Lobe\n\nThe normal distribution D(h) of one footprint (or the "
        "mean over footprints=...), as the CLI's `ndf`.\n\n" + query_keys_doc(true) + "\n" + methods_doc(Quantity::ndf);
    module.def(
        "ndf", [](py::handle field, const std::string& method, py::kwargs keys) { return run(field, method, keys, Quantity::ndf); },
        py::arg("heightfield"), py::arg("method") = "pndf", ndf_doc.c_str());
    module.def(
        "load_lobe", [](const std::string& path) {
            py::gil_scoped_release release;
            return std::make_shared<Lobe>(Lobe{load_lobe_exr(path), {}, {}});
        },
        py::arg("path"), "Reads an EXR written by the CLI or Lobe.save: values and metadata exactly.");
    module.def("compare", &compare, py::arg("test"), py::arg("reference"),
               "Per wavelength: relative L2, largest difference, energies and their ratio, peak offset and error, log "
               "rms error (lobe/compare.hpp).");
    module.def(
        "difference", [](const Lobe& test, const Lobe& reference) {
            return std::make_shared<Lobe>(Lobe{difference_image(test.image, reference.image), {}, {}});
        },
        py::arg("test"), py::arg("reference"), "test - reference, pixel by pixel (a signed image).");
    static const std::string validate_doc =
        "validate(heightfield, test=\"gabor\", reference=\"fft\", models=[], kernels_per_texel=[], orders=[], **keys) "
        "-> list of dict\n\nThe CLI's `validate`: the test method against the reference on the same queries, a row per "
        "footprint (footprints=...) x model x kernel density x order x wavelength.\n\n" + query_keys_doc(true);
    module.def("validate", &validate_methods, py::arg("heightfield"), py::arg("test") = "gabor",
               py::arg("reference") = "fft", py::arg("models") = std::vector<std::string>{},
               py::arg("kernels_per_texel") = std::vector<int>{}, py::arg("orders") = std::vector<int>{},
               validate_doc.c_str());
    module.def("fit_ndf", &fit, py::arg("ndf"), py::arg("model") = "ggx",
               "The CLI's fit: a beckmann, ggx or ellipsoid NDF fitted to layer 0 of an NDF image (L2 over the projected "
               "disk, Dong 2015 §8): its parameters (alpha_x, alpha_y; angles in radians), relative error and the model "
               "drawn as an NDF image of the same resolution.");
    module.def("batch", &batch, py::arg("manifest"), py::kw_only(), py::arg("force") = false, py::arg("jobs") = 1,
               "The CLI's `batch`: computes a TOML manifest's panels (those out of date) and writes its figure.");
}

}  // namespace glintscope::python
