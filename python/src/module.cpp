// The Python module surfgrad._surfgrad (imported by surfgrad/__init__.py):
// the C++ library on numpy arrays. docs/python.md is the guide,
// surfgrad/*.pyi the typed API.
#include <string>

#include <pybind11/pybind11.h>

#include "bindings.h"
#include "surfgrad/base/io.h"

namespace sg::python {

void bindErrors(py::module_& m) {
    // InputError(ValueError): malformed untrusted input, with the C++
    // error's file, element and reason as attributes.
    static py::exception<sg::io::InputError> inputError(m, "InputError", PyExc_ValueError);
    inputError.doc() = "Malformed untrusted input (a file, scene or curve text): "
                       "str(e) is '<file>: <element>: <reason>'; the attributes file, "
                       "element and reason hold the parts.";
    // Class-level defaults; every raised instance sets its own.
    for (const char* part : {"file", "element", "reason"}) inputError.attr(part) = py::str("");
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const sg::io::InputError& e) {
            py::object instance = py::handle(inputError.ptr())(py::str(e.what()));
            instance.attr("file") = py::str(e.file());
            instance.attr("element") = py::str(e.element());
            instance.attr("reason") = py::str(e.reason());
            PyErr_SetObject(inputError.ptr(), instance.ptr());
        }
    });
}

} // namespace sg::python

PYBIND11_MODULE(_surfgrad, m) {
    using namespace sg::python;
    m.doc() = "surfgrad: surface-gradient bump mapping on subdivision meshes (C++ library "
              "bindings). See docs/python.md.";
    m.attr("__version__") = SURFGRAD_VERSION;
    bindErrors(m);
    bindMesh(m);
    bindTangents(m);
    bindSubdivision(m);
    bindRender(m);
    bindBake(m);
    auto normalmap = m.def_submodule(
        "normalmap", "Height-field-correct normal-map operations (Loviscach 2008) on numpy grids.");
    bindNormalmap(normalmap);
    auto features = m.def_submodule(
        "features", "Feature-curve maps (Parilov-Rosenberg-Zorin 2005, Parilov-Zorin 2008).");
    bindFeatures(features);
}
