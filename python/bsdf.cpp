// BSDFs over NumPy arrays of directions: eval, sample, pdf and albedo broadcast over (..., 3)
// arrays and run on the library's threads (core/parallel.hpp) with the GIL released, so other
// Python threads run meanwhile.
#include "bindings.hpp"

#include <optional>
#include <vector>

#include "glintscope/bsdf/bsdf.hpp"
#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"

namespace glintscope::python {

namespace {

// Arrays whose last axes hold one item each (3 for a direction, 2 for two uniforms), broadcast
// over their leading axes and made C-contiguous float64.
struct Broadcast {
    std::vector<py::ssize_t> shape;  // the leading axes
    std::size_t count = 1;
    std::vector<py::array_t<double, py::array::c_style>> arrays;
};

Broadcast broadcast(const std::vector<std::pair<py::handle, int>>& inputs, const std::vector<std::string>& names) {
    const py::module_ numpy = py::module_::import("numpy");
    std::vector<py::array> arrays;
    py::list prefixes;
    for (std::size_t k = 0; k < inputs.size(); ++k) {
        py::array array = numpy.attr("asarray")(inputs[k].first, py::arg("dtype") = "float64");
        if (array.ndim() < 1 || array.shape(array.ndim() - 1) != inputs[k].second)
            throw Error(names[k] + " must have shape (..., " + std::to_string(inputs[k].second) + "), got " +
                        py::str(py::object(array.attr("shape"))).cast<std::string>());
        prefixes.append(array.attr("shape")[py::slice(0, array.ndim() - 1, 1)]);
        arrays.push_back(array);
    }
    Broadcast result;
    py::tuple prefix;
    try {
        prefix = numpy.attr("broadcast_shapes")(*prefixes);
    } catch (const py::error_already_set&) {
        std::string shapes;
        for (py::handle p : prefixes) shapes += (shapes.empty() ? "" : " and ") + py::str(p).cast<std::string>();
        throw Error("the leading axes " + shapes + " do not broadcast");
    }
    for (py::handle axis : prefix) {
        result.shape.push_back(axis.cast<py::ssize_t>());
        result.count *= axis.cast<std::size_t>();
    }
    for (std::size_t k = 0; k < arrays.size(); ++k) {
        py::tuple full = py::reinterpret_steal<py::tuple>(PySequence_Tuple((prefix + py::make_tuple(inputs[k].second)).ptr()));
        result.arrays.push_back(numpy.attr("ascontiguousarray")(numpy.attr("broadcast_to")(arrays[k], full))
                                    .cast<py::array_t<double, py::array::c_style>>());
    }
    return result;
}

Vec3 direction(const py::array_t<double, py::array::c_style>& array, std::size_t i) {
    const double* p = array.data() + 3 * i;
    return {p[0], p[1], p[2]};
}

std::vector<py::ssize_t> with_axis(std::vector<py::ssize_t> shape, py::ssize_t last) {
    shape.push_back(last);
    return shape;
}

// body(i) for every item, on the library's threads, without the GIL.
template <class Body>
void for_each_item(std::size_t count, Body body) {
    py::gil_scoped_release release;
    parallel_for(count, 1024, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) body(i);
    });
}

// wavelengths: None (the BSDF's own) or a sequence of wavelengths in µm, one output layer each.
py::array_t<double> eval(const Bsdf& bsdf, py::handle wi, py::handle wo, std::optional<std::vector<double>> wavelengths) {
    const Broadcast in = broadcast({{wi, 3}, {wo, 3}}, {"wi", "wo"});
    const std::size_t layers = wavelengths ? wavelengths->size() : bsdf.wavelengths_um().size();
    if (wavelengths) bsdf.eval({0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}, *wavelengths);  // refuses bad ones before the loop
    std::vector<double> out(in.count * layers);
    for_each_item(in.count, [&](std::size_t i) {
        const Vec3 omega_i = direction(in.arrays[0], i), omega_o = direction(in.arrays[1], i);
        const std::vector<double> f = wavelengths ? bsdf.eval(omega_i, omega_o, *wavelengths) : bsdf.eval(omega_i, omega_o);
        std::copy(f.begin(), f.end(), out.begin() + i * layers);
    });
    return owned_array(std::move(out), with_axis(in.shape, py::ssize_t(layers)));
}

py::array_t<double> pdf(const Bsdf& bsdf, py::handle wi, py::handle wo) {
    const Broadcast in = broadcast({{wi, 3}, {wo, 3}}, {"wi", "wo"});
    std::vector<double> out(in.count);
    for_each_item(in.count, [&](std::size_t i) { out[i] = bsdf.pdf(direction(in.arrays[0], i), direction(in.arrays[1], i)); });
    return owned_array(std::move(out), in.shape);
}

py::tuple sample(const Bsdf& bsdf, py::handle wi, py::handle u) {
    const Broadcast in = broadcast({{wi, 3}, {u, 2}}, {"wi", "u"});
    const std::size_t layers = bsdf.wavelengths_um().size();
    std::vector<double> directions(in.count * 3), pdfs(in.count), weights(in.count * layers);
    for_each_item(in.count, [&](std::size_t i) {
        const double* uniforms = in.arrays[1].data() + 2 * i;
        const BsdfSample s = bsdf.sample(direction(in.arrays[0], i), uniforms[0], uniforms[1]);
        directions[3 * i] = s.omega_o.x;
        directions[3 * i + 1] = s.omega_o.y;
        directions[3 * i + 2] = s.omega_o.z;
        pdfs[i] = s.pdf;
        std::copy(s.weight.begin(), s.weight.end(), weights.begin() + i * layers);
    });
    return py::make_tuple(owned_array(std::move(directions), with_axis(in.shape, 3)), owned_array(std::move(pdfs), in.shape),
                          owned_array(std::move(weights), with_axis(in.shape, py::ssize_t(layers))));
}

py::array_t<double> albedo(const Bsdf& bsdf, py::handle wi) {
    const Broadcast in = broadcast({{wi, 3}}, {"wi"});
    const std::size_t layers = bsdf.wavelengths_um().size();
    std::vector<double> out(in.count * layers);
    // Each albedo may build a table that itself runs on the library's threads: one at a time.
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < in.count; ++i) {
        const std::vector<double> a = bsdf.albedo(direction(in.arrays[0], i));
        std::copy(a.begin(), a.end(), out.begin() + i * layers);
    }
    py::gil_scoped_acquire acquire;
    return owned_array(std::move(out), with_axis(in.shape, py::ssize_t(layers)));
}

}  // namespace

void bind_bsdf(py::module_& module) {
    py::class_<Bsdf>(module, "Bsdf",
                     "A method's BSDF for one footprint (docs/renderer.md): immutable, safe to query from many threads. "
                     "Directions are (..., 3) arrays in the heightfield's frame (+z the mean normal), broadcast against "
                     "each other; wi points toward the light, wo toward the viewer.")
        .def("eval", &eval, py::arg("wi"), py::arg("wo"), py::arg("wavelengths") = py::none(),
             "f_r(wi, wo) in 1/sr without the cosine: shape (..., L), L the BSDF's wavelengths or, given "
             "`wavelengths` (um), one layer each (any wavelength where `any_wavelength`, else the BSDF's own).")
        .def_property_readonly("any_wavelength", &Bsdf::any_wavelength,
                               "Whether eval answers wavelengths other than the ones the BSDF was made with.")
        .def("sample", &sample, py::arg("wi"), py::arg("u"),
             "wo from two uniforms u (..., 2) in [0, 1): (wo (..., 3), pdf (...) per solid angle, weight (..., L) = "
             "f_r cos(theta_o) / pdf); pdf 0 where no direction was found.")
        .def("pdf", &pdf, py::arg("wi"), py::arg("wo"), "The density per solid angle with which sample returns wo: (...).")
        .def("albedo", &albedo, py::arg("wi"), "The integral of f_r cos(theta_o) over wo: (..., L).")
        .def_property_readonly("method", &Bsdf::method)
        .def_property_readonly("wavelengths_um", &Bsdf::wavelengths_um)
        .def_property_readonly("evaluates_directly", &Bsdf::evaluates_directly,
                               "Whether eval is the method's own point query (else its lobe images' pixels).")
        .def_property_readonly("samples_directly", &Bsdf::samples_directly,
                               "Whether sample and pdf are the method's own sampler (else a pixel of its images).")
        .def_property_readonly("warnings", &Bsdf::warnings,
                               "Physics warnings that hold for every direction (also issued as RuntimeWarning by bsdf()).");

    static const std::string bsdf_doc =
        "bsdf(heightfield, method=\"fft\", **keys) -> Bsdf\n\nThe BSDF of a method for the query's footprint, "
        "wavelengths, model, material and method options (res sets its tables; incident and supersample are not "
        "used).\n\n" + query_keys_doc(true) + "\n" + methods_doc(Quantity::brdf);
    module.def(
        "bsdf",
        [](py::handle field, const std::string& method, py::kwargs keys) {
            const LobeQuery query = python_query(field, keys, Quantity::brdf);
            std::optional<Bsdf> bsdf;
            {
                py::gil_scoped_release release;
                bsdf.emplace(make_bsdf(method, query));
            }
            const py::object warn = py::module_::import("warnings").attr("warn");
            for (const std::string& warning : bsdf->warnings()) warn(warning, py::handle(PyExc_RuntimeWarning), 2);
            return std::move(*bsdf);
        },
        py::arg("heightfield"), py::arg("method") = "fft", bsdf_doc.c_str());
}

}  // namespace glintscope::python
