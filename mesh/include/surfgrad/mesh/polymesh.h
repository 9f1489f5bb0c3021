// OpenMesh view of a PolygonMesh: an OpenMesh::PolyMesh with custom
// properties for everything OpenSubdiv needs (any number of UV sets per
// halfedge, edge crease sharpness, vertex corner sharpness, hole faces).
// For users who already hold their meshes in OpenMesh, and for the OpenMesh
// baselines in bench/. Include only where OpenMesh is wanted: this header
// pulls in OpenMesh's templates (the rest of mesh/ does not).
//
// Halfedge UV convention (OpenMesh's own, as its OBJ reader uses it): the UV
// of the corner of face(h) at to_vertex(h) is stored on halfedge h.
#pragma once

#include <string>
#include <vector>

#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include "surfgrad/mesh/polygon_mesh.h"

namespace sg::mesh {

struct PolyMeshTraits : OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3f;
    using Normal = OpenMesh::Vec3f;
};
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<PolyMeshTraits>;

// Property handles of the attributes toPolyMesh adds.
struct PolyMeshProperties {
    std::vector<OpenMesh::HPropHandleT<OpenMesh::Vec2f>> uvSets; // per halfedge, see above
    OpenMesh::EPropHandleT<float> edgeSharpness;                 // 0 = smooth
    OpenMesh::VPropHandleT<float> cornerSharpness;               // 0 = smooth
    OpenMesh::FPropHandleT<bool> hole;
};

// Builds the OpenMesh mesh with its properties (UV set names become
// property names "uv:<name>"). OpenMesh refuses faces at complex edges or
// vertices (its add_face returns an invalid handle and would drop the face
// silently): this throws InputError naming the first refused face and why,
// so pass a validated mesh. Morph targets and face-varying normals are not
// carried.
PolyMesh toPolyMesh(const PolygonMesh& mesh, PolyMeshProperties& props,
                    const std::string& file = {});

// The reverse: vertex order and face order are kept; UVs are deduplicated
// per vertex (corners of one vertex with equal UVs share a value).
PolygonMesh fromPolyMesh(const PolyMesh& mesh, const PolyMeshProperties& props);

} // namespace sg::mesh
