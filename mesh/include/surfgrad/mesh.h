// Umbrella header of the mesh module (surfgrad_mesh, mesh/).
// Meshes from file to renderer: OBJ/OFF/PLY/STL/glTF input and output,
// validation, OpenSubdiv refinement and limit evaluation, feature-adaptive
// patches, blendshapes and tangent frames. No shader math: links base only.
//
// Includes every public header of the module:
//   surfgrad/mesh/polygon_mesh.h          PolygonMesh: a polygon cage, UV sets, subdivision tags
//   surfgrad/mesh/render_mesh.h           RenderMesh: the triangle mesh handed to the renderer
//   surfgrad/mesh/mesh_io.h               loaders, validation and repair, writers
//   surfgrad/mesh/polymesh.h              an OpenMesh view of a PolygonMesh
//   surfgrad/mesh/subdivision.h           OpenSubdiv refinement, limit evaluation, stencils
//   surfgrad/mesh/osd_primvar.h           primvar adaptors for OpenSubdiv over glm arrays
//   surfgrad/mesh/adaptive_patches.h      feature-adaptive patch tables for GPU tessellation
//   surfgrad/mesh/morph.h                 blendshapes (glTF 2.0 morph targets)
//   surfgrad/mesh/tangents.h              tangent frames: MikkTSpace and the other sources
//   surfgrad/mesh/mikktspace_reference.h  the MikkTSpace oracle; NOT included here: it is the
//                                         test-only surfgrad_mesh_oracle (mesh/oracle/include)
#pragma once

#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/morph.h"
#include "surfgrad/mesh/osd_primvar.h"
#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/polymesh.h"
#include "surfgrad/mesh/render_mesh.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"
