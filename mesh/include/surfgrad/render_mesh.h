// RenderMesh: the indexed triangle mesh that leaves mesh/ for the renderer,
// the tangent generators and the writers (glTF/OBJ/PLY). Plain data, no
// behaviour; producers (loaders, subdivision, morphing) live in the other
// mesh/ headers.
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
    std::vector<glm::vec3> normals;              // empty or positions.size()
    std::vector<std::vector<glm::vec2>> uvSets;  // each positions.size()
    std::vector<glm::vec4> tangents;             // empty or positions.size()
    int tangentUvSet = -1;                       // UV set the tangents belong to
    std::vector<uint32_t> indices;               // 3 per triangle
    std::vector<MorphTarget> morphTargets;
    std::vector<float> morphWeights;             // default weights, one per target

    size_t vertexCount() const { return positions.size(); }
    size_t triangleCount() const { return indices.size() / 3; }
};

} // namespace sg::mesh
