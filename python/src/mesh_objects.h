// Checks shared by the binding parts that take meshes from Python
// (bind_mesh.cpp defines them).
#pragma once

#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/render_mesh.h"

namespace sg::python {

// Throws ValueError when a RenderMesh's arrays disagree (an index out of
// range, a per-vertex array of another length, a tangent_uv_set that is
// not a set). Meshes built by the module always pass; this guards the C++
// preconditions of the functions that take one.
void checkRenderMeshArrays(const sg::mesh::RenderMesh& mesh);
// Throws ValueError when a cage's positions (the one array Python can write
// through a view) hold NaN or Inf.
void checkCageArrays(const sg::mesh::PolygonMesh& cage);

} // namespace sg::python
