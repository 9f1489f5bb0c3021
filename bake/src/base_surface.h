// The surface a bake measures from, per texel: the point whose UV is the
// texel's centre, its unit normal (the ray direction) and the tangent frame
// the normal map is written in. Two kinds:
//  - LimitBase: the cage's Catmull-Clark limit surface (adaptive patches,
//    limit_patches.h), the exact limit normal and the limit tangent
//    (sg/patch/limit_tangent.glsl): what the renderer draws for adaptive
//    meshes and for "limit": true;
//  - TriangleBase: the cage refined uniformly to a level and triangulated
//    (surfgrad/mesh/subdivision.h, no limit evaluation), positions, vertex
//    normals and MikkTSpace tangents interpolated linearly over each
//    triangle: what triangle-mesh bakers (Blender, xNormal, Substance)
//    measure from, and what a renderer drawing that refined mesh with
//    vertex tangents ("tangents": "mikktspace") reads.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "limit_patches.h"
#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/render_mesh.h"
#include "uv_cover.h"

namespace sg::bake::detail {

struct BaseSample {
    glm::vec3 pos{0.0f};                       // object space
    glm::vec3 normal{0.0f, 0.0f, 1.0f};        // unit
    glm::vec4 tangent{1.0f, 0.0f, 0.0f, 1.0f}; // xyz and sign w (bitangent w cross(N, T))
    // Surface length of one texel here (sqrt of the chart's area ratio
    // over the map's larger side); 0 where the UV chart is degenerate.
    float texelLength = 0.0f;
    float residualTexels = 0.0f; // |st - texel centre| left (limit: Newton)
};

class BaseSurface {
public:
    virtual ~BaseSurface() = default;
    // The texels each primitive (patch, triangle) covers.
    virtual UvCover cover(int width, int height) const = 0;
    // The point of primitive `prim` whose UV is `target` (the claim's
    // estimate `estimate` is its start or, for triangles, its barycentrics).
    virtual BaseSample at(uint32_t prim, glm::vec2 estimate, glm::vec2 target) const = 0;
    virtual size_t primitiveCount() const = 0;
};

// texelsPerUv: the map's (width, height).
std::unique_ptr<BaseSurface> limitBase(const mesh::PolygonMesh& cage, int isolation, int uvSet,
                                       const std::string& file, int threads, glm::vec2 texelsPerUv);
std::unique_ptr<BaseSurface> triangleBase(const mesh::PolygonMesh& cage, int level, int uvSet,
                                          const std::string& file, int threads,
                                          glm::vec2 texelsPerUv);

} // namespace sg::bake::detail
