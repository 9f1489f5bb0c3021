// RenderMesh: the indexed triangle mesh that leaves mesh/ for the renderer,
// the tangent generators and the writers (glTF/OBJ/PLY). Plain data, no
// behaviour; producers (loaders, subdivision, morphing) live in the other
// mesh/ headers (surfgrad/mesh/mesh_io.h, surfgrad/mesh/subdivision.h,
// surfgrad/mesh/morph.h).
//
// Conventions:
//  - positions/normals in object space, right-handed, units of the source;
//  - vertices are split wherever any attribute differs (UV seams, hard
//    edges), as in glTF: every per-vertex array has positions.size() entries;
//  - triangles are counter-clockwise seen from the front (outside);
//  - texture coordinates: (0,0) is the LOWER-left corner of the image, t up
//    (OpenGL convention). glTF's upper-left TEXCOORD_n are flipped on load
//    (t = 1 - v) and back on save;
//  - tangents (optional) are MikkTSpace-style: xyz unit tangent along +s,
//    w = +-1 handedness with bitangent = w * cross(normal, tangent).
//  - normals, when present, are unit length and finite (producers guarantee
//    it; a degenerate neighbourhood gets a fallback, never NaN).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace sg::mesh {

struct MorphTarget {
    std::string name;
    std::vector<glm::vec3> positionDeltas; // empty or positions.size()
    std::vector<glm::vec3> normalDeltas;   // empty or positions.size()
    std::vector<glm::vec3> tangentDeltas;  // empty or positions.size()
};

struct RenderMesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;             // empty or positions.size()
    std::vector<std::vector<glm::vec2>> uvSets; // each positions.size()
    std::vector<glm::vec4> tangents;            // empty or positions.size()
    int tangentUvSet = -1;                      // UV set the tangents belong to
    std::vector<uint32_t> indices;              // 3 per triangle
    std::vector<MorphTarget> morphTargets;
    std::vector<float> morphWeights; // default weights, one per target

    size_t vertexCount() const { return positions.size(); }
    size_t triangleCount() const { return indices.size() / 3; }
};

// Limit-surface derivatives of a RenderMesh produced by
// sg::mesh::Subdivider with limit evaluation on (surfgrad/mesh/subdivision.h).
// Every array is aligned with the RenderMesh's vertices (RenderMesh
// positions, normals and uvSets then hold the limit position, the limit
// normal and the limit UVs).
//
// Each vertex has ONE home location on the limit surface: a ptex face
// (OpenSubdiv Far::PtexIndices: one per base quad/triangle, one per corner
// of other base polygons) and (u,v) in [0,1]^2 on it. Every derivative of
// that vertex is taken with respect to that (u,v), so positions and all UV
// sets share one parameterization and the 2x2 Jacobian d(s,t)/d(u,v) turns
// dPdu/dPdv into dP/ds, dP/dt (the chain rule behind Mikkelsen 2019,
// sec. 2.3; the "limit" tangent frames of surfgrad/mesh/tangents.h). Consequences:
//  - derivatives of two vertices are in different parameterizations unless
//    they share a ptex face: compare directions, not magnitudes;
//  - vertices split at a UV seam or a sharp crease have their own home in a
//    face on their side, so their UV derivatives belong to that side;
//  - units: dPdu in object units per unit ptex parameter, dUVdu in UV units
//    (t up) per unit ptex parameter;
//  - the cross product dPdu x dPdv points to the front (same side as the
//    normal); it may vanish at a degenerate point (a collapsed cage edge),
//    then RenderMesh::normals holds the fallback normal and dPdu/dPdv stay
//    finite (possibly zero): tangent builders must guard the division.
struct LimitFrame {
    std::vector<glm::vec3> dPdu, dPdv;
    std::vector<std::vector<glm::vec2>> dUVdu, dUVdv; // [uvSet][vertex]
    std::vector<uint32_t> ptexFace;                   // home location per vertex
    std::vector<glm::vec2> ptexUV;
    // Limit derivatives of each morph target's position deltas
    // ([target][vertex]); derivatives are linear in positions, so the frame of
    // a morphed mesh is dPdu + sum_i w_i * morphDPdu[i] (sg::mesh::Morpher).
    std::vector<std::vector<glm::vec3>> morphDPdu, morphDPdv;

    bool empty() const { return dPdu.empty(); }
};

} // namespace sg::mesh
