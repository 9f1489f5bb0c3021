// The Python module's parts (python/src/bind_*.cpp), each adding its
// classes and functions to the module or a submodule; module.cpp calls them
// in this order (later parts use the classes of earlier ones).
#pragma once

#include <pybind11/pybind11.h>

namespace sg::python {

namespace py = pybind11;

void bindErrors(py::module_& m);      // InputError and the translation of C++ errors
void bindMesh(py::module_& m);        // RenderMesh, PolygonMesh, loading, writing, validation
void bindTangents(py::module_& m);    // MikkTSpace and limit tangents
void bindSubdivision(py::module_& m); // Subdivider, LimitFrame, blendshapes
void bindRender(py::module_& m);      // render() and eval() of the shared functions
void bindNormalmap(py::module_& m);   // surfgrad.normalmap
void bindFeatures(py::module_& m);    // surfgrad.features
void bindBake(py::module_& m);        // bake(): a high mesh onto a cage's limit surface

} // namespace sg::python
