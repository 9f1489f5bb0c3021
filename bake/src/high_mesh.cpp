// Ray casting against the high-resolution mesh with Embree 3 (Wald et al.,
// "Embree: a kernel framework for efficient CPU ray tracing", ACM TOG
// 33(4), 2014). See high_mesh.h.
#include "high_mesh.h"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include "surfgrad/base/io.h"
#include "surfgrad/mesh/subdivision.h"

namespace sg::bake::detail {

namespace {

bool finite3(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string embreeError(RTCDevice device, const char* what) {
    const RTCError e = rtcGetDeviceError(device);
    return std::string("Embree: ") + what + " failed (error " + std::to_string(int(e)) + ")";
}

void checkHigh(const mesh::RenderMesh& high, const std::string& file) {
    if (high.triangleCount() == 0) throw io::InputError(file, "", "the high mesh has no triangles");
    for (size_t v = 0; v < high.positions.size(); ++v)
        if (!finite3(high.positions[v]))
            throw io::InputError(file, "vertex " + std::to_string(v), "position is not finite");
    for (size_t v = 0; v < high.normals.size(); ++v)
        if (!finite3(high.normals[v]))
            throw io::InputError(file, "vertex " + std::to_string(v), "normal is not finite");
    for (size_t k = 0; k < high.indices.size(); ++k)
        if (high.indices[k] >= high.positions.size())
            throw io::InputError(file, "triangle " + std::to_string(k / 3),
                                 "vertex index " + std::to_string(high.indices[k]) +
                                     " is out of range");
}

} // namespace

HighMesh::HighMesh(const mesh::RenderMesh& high, const std::string& file) {
    checkHigh(high, file);
    if (high.normals.size() == high.positions.size()) {
        normals_ = high.normals;
    } else {
        mesh::RenderMesh copy;
        copy.positions = high.positions;
        copy.indices = high.indices;
        mesh::computeVertexNormals(copy);
        normals_ = std::move(copy.normals);
    }
    indices_ = high.indices;
    positions_ = high.positions;
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("Embree: rtcNewDevice failed");
    scene_ = rtcNewScene(device_);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                           RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                           high.positions.size()));
    auto* ib = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(uint32_t), high.triangleCount()));
    if (!vb || !ib) {
        rtcReleaseGeometry(geom);
        const std::string msg = embreeError(device_, "allocating the high mesh's buffers");
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
        throw std::runtime_error(msg);
    }
    std::memcpy(vb, high.positions.data(), high.positions.size() * sizeof(glm::vec3));
    std::memcpy(ib, high.indices.data(), high.indices.size() * sizeof(uint32_t));
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) {
        const std::string msg = embreeError(device_, "building the BVH");
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
        throw std::runtime_error(msg);
    }
}

HighMesh::~HighMesh() {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

RayHit HighMesh::cast(glm::vec3 origin, glm::vec3 dir, float tFar) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray.org_x = origin.x;
    rh.ray.org_y = origin.y;
    rh.ray.org_z = origin.z;
    rh.ray.dir_x = dir.x;
    rh.ray.dir_y = dir.y;
    rh.ray.dir_z = dir.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = tFar;
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    RayHit out;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
    out.hit = true;
    out.t = rh.ray.tfar;
    const uint32_t* tri = &indices_[size_t(rh.hit.primID) * 3];
    const float u = rh.hit.u, v = rh.hit.v;
    const glm::vec3 n =
        (1.0f - u - v) * normals_[tri[0]] + u * normals_[tri[1]] + v * normals_[tri[2]];
    const float len = glm::length(n);
    // Opposite vertex normals can cancel: the triangle's own normal then
    // (counter-clockwise front; a hit triangle has a non-zero area).
    const glm::vec3 p0 = positions_[tri[0]];
    out.normal = len > 1e-6f
                     ? n / len
                     : glm::normalize(glm::cross(positions_[tri[1]] - p0, positions_[tri[2]] - p0));
    return out;
}

} // namespace sg::bake::detail
