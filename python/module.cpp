// The module `glintscope`: the library's Error as glintscope.Error, the version, the thread count,
// the tables behind the keyword arguments, and each concept's bindings (heightfield.cpp,
// lobe.cpp, bsdf.cpp, colour.cpp).
#include "bindings.hpp"

#include <optional>

#include "glintscope/core/error.hpp"
#include "glintscope/core/parallel.hpp"
#include "glintscope/core/version.hpp"
#include "glintscope/pipeline/pipeline.hpp"

namespace glintscope::python {

py::array_t<float> float_view(const float* data, std::vector<py::ssize_t> shape, py::handle owner) {
    py::array_t<float> view(shape, data, owner);
    py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return view;
}

py::dict string_dict(const std::map<std::string, std::string>& entries) {
    py::dict dict;
    for (const auto& [key, value] : entries) dict[py::str(key)] = value;
    return dict;
}

namespace {

py::list query_key_table() {
    py::list keys;
    for (const QueryKey& key : query_keys())
        keys.append(py::dict(py::arg("name") = key.name, py::arg("value_name") = key.value_name,
                             py::arg("help") = key.help, py::arg("implicit") = key.implicit));
    return keys;
}

py::list method_table() {
    py::list methods;
    for (const MethodInfo& info : lobe_methods()) {
        py::list quantities, options;
        for (Quantity quantity : info.quantities) quantities.append(to_string(quantity));
        for (const MethodOption& option : info.options)
            options.append(py::dict(py::arg("key") = option.key, py::arg("help") = option.help));
        methods.append(py::dict(py::arg("name") = info.name, py::arg("description") = info.description,
                                py::arg("reference") = info.reference, py::arg("quantities") = quantities,
                                py::arg("options") = options, py::arg("wave_optics") = info.wave_optics));
    }
    return methods;
}

}  // namespace

// `with glintscope.using_threads(n):` the library calls that this Python thread makes inside the
// block run on n threads (0: the default). The library keeps no process-wide count, so other
// Python threads keep theirs.
class ThreadBlock {
public:
    explicit ThreadBlock(int threads) : threads_(threads) {}
    void enter() { scope_.emplace(threads_); }
    void exit() { scope_.reset(); }

private:
    int threads_;
    std::optional<ThreadScope> scope_;
};

}  // namespace glintscope::python

PYBIND11_MODULE(glintscope, module) {
    using namespace glintscope;
    using namespace glintscope::python;
    module.doc() =
        "glintscope: how a surface's microgeometry reflects light (wave-optics lobes, NDFs, BSDFs) from NumPy "
        "heightfields, through the same library pipeline as the command line. docs/python.md has the guide.";
    module.attr("__version__") = version();
    py::register_exception<Error>(module, "Error", PyExc_ValueError).doc() =
        "A problem with the input, with the command line's one-line message.";
    module.def("threads", &thread_count,
               "Threads the heavy loops of this thread's calls use (using_threads, else GLINTSCOPE_THREADS or the cores).");
    py::class_<ThreadBlock>(module, "using_threads",
                            "with using_threads(n): the library calls this thread makes in the block run on n threads "
                            "(0: the default). Results do not depend on it.")
        .def(py::init<int>(), py::arg("threads"))
        .def("__enter__", [](ThreadBlock& block) { block.enter(); })
        .def("__exit__", [](ThreadBlock& block, py::args) { block.exit(); });
    module.def("query_keys", &query_key_table,
               "The query keys (keyword arguments of lobe, ndf and bsdf): name, value_name, help, implicit.");
    module.def("methods", &method_table,
               "The methods: name, description, reference, quantities (brdf, ndf), options, wave_optics.");
    bind_heightfield(module);
    bind_lobe(module);
    bind_bsdf(module);
    bind_colour(module);
}
