// The high-resolution mesh as a ray-casting target: an Embree 3 triangle
// scene (robust traversal, high build quality) with the mesh's vertex
// normals for shading the hit. Closest hits of single rays; thread-safe
// after construction (Embree's rtcIntersect1 on a committed scene).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "surfgrad/mesh/render_mesh.h"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace sg::bake::detail {

struct RayHit {
    bool hit = false;
    float t = 0.0f;      // distance along the (unit) direction
    glm::vec3 normal{0}; // the high mesh's interpolated vertex normal, unit
};

class HighMesh {
public:
    // Copies positions and triangles into Embree's buffers and builds the
    // BVH. Normals: the mesh's own when it has them, else area-weighted
    // vertex normals (sg::mesh::computeVertexNormals). Throws io::InputError
    // naming `file` for a mesh without triangles, a non-finite position or
    // normal ("vertex N"), or an index out of range ("triangle N"); and
    // std::runtime_error when Embree fails (its message).
    HighMesh(const mesh::RenderMesh& high, const std::string& file);
    ~HighMesh();
    HighMesh(const HighMesh&) = delete;
    HighMesh& operator=(const HighMesh&) = delete;

    // Closest hit of the ray origin + t dir, t in [0, tFar] (dir unit).
    RayHit cast(glm::vec3 origin, glm::vec3 dir, float tFar) const;

private:
    RTCDeviceTy* device_ = nullptr;
    RTCSceneTy* scene_ = nullptr;
    std::vector<glm::vec3> positions_, normals_;
    std::vector<uint32_t> indices_;
};

} // namespace sg::bake::detail
