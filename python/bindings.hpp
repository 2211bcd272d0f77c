#pragma once
// What the binding sources share: the per-concept bind functions module.cpp calls, keyword
// arguments as query text, and the query every lobe and BSDF call builds.
#include <memory>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "glintscope/lobe/query_keys.hpp"

namespace glintscope::python {

namespace py = pybind11;

void bind_heightfield(py::module_& module);
void bind_lobe(py::module_& module);
void bind_bsdf(py::module_& module);
void bind_colour(py::module_& module);

// A Python value as the text of a key: str as given, bool as yes/no, numbers in shortest form
// (µm for lengths, as bare numbers are in the CLI), sequences joined by `separator`.
std::string value_text(py::handle value, const std::string& separator = ",");

// Keyword arguments as query keys: the same names as the CLI's (lambda_ for the Python keyword
// lambda), method option keys (kernels_per_texel=2) as option.KEY. Unknown names are passed on,
// so the library refuses them with the CLI's message.
QueryText keyword_query_text(const py::kwargs& keywords);

// The query of a heightfield — a Heightfield object, or a path / builtin:KIND string, loaded as
// the CLI loads it — with the keyword arguments applied and `quantity` set.
LobeQuery python_query(py::handle heightfield, const py::kwargs& keywords, Quantity quantity);

// A read-only NumPy view of `size` floats at `data` that keeps `owner` alive.
py::array_t<float> float_view(const float* data, std::vector<py::ssize_t> shape, py::handle owner);

// A NumPy array taking ownership of `values` (no copy).
template <class T>
py::array_t<T> owned_array(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    auto* owned = new std::vector<T>(std::move(values));
    py::capsule free_when_done(owned, [](void* pointer) { delete static_cast<std::vector<T>*>(pointer); });
    return py::array_t<T>(shape, owned->data(), free_when_done);
}

// A dict of str → str from the library's string maps (metadata, provenance).
py::dict string_dict(const std::map<std::string, std::string>& entries);

}  // namespace glintscope::python

namespace glintscope::python {

// A computed (or loaded) lobe image with what the pipeline said about it: glintscope.Lobe.
struct Lobe {
    LobeImage image;
    std::vector<std::string> notes;
    std::vector<std::string> warnings;
};

// Docstring sections generated from the library's tables, so help() shows every key with its
// units and default, and every method with its reference and options.
std::string query_keys_doc(bool with_load_keys);
std::string methods_doc(Quantity quantity);

}  // namespace glintscope::python
