// Table 11's error measure: adaptive_error.h.
#include "adaptive_error.h"

#include <chrono>
#include <cstdio>

#include "render_internal.h"
#include "surfgrad/bump/patch_basis.h"

#include <algorithm>
#include <cmath>

#include "common.h"

namespace study {

SurfaceReference::SurfaceReference(const sg::mesh::RenderMesh& m)
    : pos_(m.positions), nrm_(m.normals) {
    double edge = 0.0;
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3)
        edge += glm::length(pos_[m.indices[t]] - pos_[m.indices[t + 1]]);
    cell_ = float(2.0 * edge / double(std::max<size_t>(m.indices.size() / 3, 1)));
    grid_.reserve(pos_.size());
    for (uint32_t v = 0; v < pos_.size(); ++v) grid_.push_back({key(cellOf(pos_[v])), v});
    std::sort(grid_.begin(), grid_.end());
}

uint64_t SurfaceReference::key(glm::ivec3 c) {
    return (uint64_t(uint32_t(c.x) & 0x1FFFFFu) << 42) |
           (uint64_t(uint32_t(c.y) & 0x1FFFFFu) << 21) | uint64_t(uint32_t(c.z) & 0x1FFFFFu);
}

float SurfaceReference::distance(glm::vec3 p) const {
    const glm::ivec3 c = cellOf(p);
    float best = INFINITY;
    uint32_t bestV = 0;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const uint64_t k = key(c + glm::ivec3(dx, dy, dz));
                auto it = std::lower_bound(grid_.begin(), grid_.end(),
                                           std::pair<uint64_t, uint32_t>(k, 0));
                for (; it != grid_.end() && it->first == k; ++it) {
                    const glm::vec3 d = p - pos_[it->second];
                    const float d2 = glm::dot(d, d);
                    if (d2 < best) {
                        best = d2;
                        bestV = it->second;
                    }
                }
            }
    if (!std::isfinite(best)) return -1.0f;
    return std::fabs(glm::dot(p - pos_[bestV], nrm_[bestV]));
}

ScreenError screenError(const SurfaceReference& ref, const sg::mesh::RenderMesh& m,
                        const sg::render::View& v, float focalPx, size_t maxTriangles) {
    std::vector<double> px;
    const size_t tris = m.indices.size() / 3;
    const size_t stride = std::max<size_t>(1, tris / std::max<size_t>(maxTriangles, 1));
    ScreenError e;
    const glm::mat4 vp = v.proj * v.view;
    for (size_t t = 0; t < tris; t += stride) {
        const glm::vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                        c = m.positions[m.indices[3 * t + 2]];
        for (const glm::vec3 p :
             {(a + b + c) / 3.0f, 0.5f * (a + b), 0.5f * (b + c), 0.5f * (c + a)}) {
            const glm::vec4 clip = vp * glm::vec4(p, 1.0f);
            if (!(clip.w > 0.0f) || std::fabs(clip.x) > clip.w || std::fabs(clip.y) > clip.w)
                continue;
            const float d = ref.distance(p);
            if (d < 0.0f) {
                ++e.missed;
                continue;
            }
            const float depth = -(v.view * glm::vec4(p, 1.0f)).z;
            px.push_back(double(d) * double(focalPx) / double(depth));
        }
    }
    e.samples = px.size();
    if (px.empty()) return e;
    std::sort(px.begin(), px.end());
    e.max = px.back();
    e.p99 = px[std::min(px.size() - 1, size_t(0.99 * double(px.size())))];
    return e;
}

DirectionDiff compareDirections(const sg::render::Image& a, const sg::render::Image& b,
                                const sg::render::Image& baseA, const sg::render::Image& baseB) {
    DirectionDiff d;
    for (size_t i = 0; i < a.texelCount(); ++i) {
        const glm::dvec3 x(a.rgba(i)), y(b.rgba(i));
        const glm::dvec3 nx(baseA.rgba(i)), ny(baseB.rgba(i));
        if (!std::isfinite(x.x + x.y + x.z) || !std::isfinite(y.x + y.y + y.z)) {
            ++d.nonFinite;
            continue;
        }
        const bool ca = glm::length(nx) > 0.5, cb = glm::length(ny) > 0.5;
        if (!ca && !cb) continue; // background in both
        if (!ca || !cb || angleDeg(nx, ny) > kSameSheetDeg) {
            ++d.otherSheet;
            continue;
        }
        d.deg.push_back(angleDeg(x, y));
    }
    std::sort(d.deg.begin(), d.deg.end());
    return d;
}

// ---- The tessellated-asset view ------------------------------------------

// A scene of one mesh `file` (absolute path or data:) on the tessellated-
// asset example's camera at `distanceScale`, 960x540, one plain material;
// `extra`: more fields of the mesh (e.g. its displacement).
std::string meshScene(const std::string& file, float distanceScale, const std::string& subdivision,
                      const std::string& extra) {
    char cam[160];
    std::snprintf(
        cam, sizeof cam,
        R"("camera": {"azimuth_deg": 105, "elevation_deg": 14, "distance_scale": %g, "fov_deg": 32})",
        double(distanceScale));
    return R"({"output": {"width": 960, "height": 540}, )" + std::string(cam) +
           R"(, "materials": [{"name": "m"}], "meshes": [{"file": ")" + file +
           R"(", "subdivision": )" + subdivision + extra + "}]}";
}

sg::render::Scene sceneOf(const std::string& json) {
    return sg::render::parseScene(json, "table_adaptive.json", ".");
}

std::string adaptiveJson(int isolation, float pixelsPerEdge) {
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  R"({"mode": "adaptive", "isolation": %d, "pixels_per_edge": %g})", isolation,
                  double(pixelsPerEdge));
    return buf;
}

// The displaced surface as the CPU tessellator makes it for `view`
// (sg::render::detail::tessellatePatches with the scene's displacement, the evaluation
// stage's math), with area-weighted vertex normals of its triangles (the
// displaced surface's, for SurfaceReference's tangent planes).
sg::mesh::RenderMesh displacedMesh(const sg::render::Scene& s, const sg::render::SceneAssets& a,
                                   const sg::render::View& view, float pixelsPerEdge,
                                   double* cpuMs) {
    const sg::render::MeshInstance& inst = s.meshes[0];
    sg::render::detail::PatchDisplacement disp;
    sg::render::detail::PatchDisplacement* dp = nullptr;
    if (inst.displacement) {
        disp.map.image = a.textures.at(inst.displacement->map.key()).get();
        disp.scale = inst.displacement->scale;
        disp.offset = inst.displacement->offset;
        disp.uvSet = inst.displacement->uvSet;
        dp = &disp;
    }
    const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
    const auto t0 = std::chrono::steady_clock::now();
    sg::mesh::RenderMesh m =
        sg::render::detail::tessellatePatches(
            *a.meshes[0].patches, sg::render::modelToCameraRelative(inst.transform, view.cameraPos),
            focalPx, pixelsPerEdge, dp)
            .mesh;
    if (cpuMs)
        *cpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                     .count();
    std::vector<glm::dvec3> n(m.positions.size(), glm::dvec3(0.0));
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        const glm::dvec3 a0(m.positions[m.indices[t]]), a1(m.positions[m.indices[t + 1]]),
            a2(m.positions[m.indices[t + 2]]);
        const glm::dvec3 fn = glm::cross(a1 - a0, a2 - a0); // twice the area, along the normal
        for (int k = 0; k < 3; ++k) n[m.indices[t + size_t(k)]] += fn;
    }
    for (size_t v = 0; v < n.size(); ++v) {
        const double len = glm::length(n[v]);
        m.normals[v] = len > 0.0 ? glm::vec3(n[v] / len) : m.normals[v];
    }
    return m;
}

} // namespace study
