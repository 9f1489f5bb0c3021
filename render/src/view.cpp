// Camera views (surfgrad/render/view.h): the scene's camera or an orbit
// around a target, near and far planes fitted to the scene's bounds, the
// camera-relative view-projection (Mikkelsen 2019, listing 16).
#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "render_internal.h"
#include "surfgrad/render.h"

namespace sg::render {

namespace {

View finishView(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, float fovDeg, float nearP,
                float farP, int w, int h, Aov aov) {
    View v;
    v.width = w;
    v.height = h;
    v.aov = aov;
    v.cameraPos = eye;
    // In binary64: the direction target - eye of a camera 1e6 from the
    // origin keeps its digits.
    const glm::dmat4 view = glm::lookAt(eye, target, up);
    v.view = glm::mat4(view);
    v.proj = glm::perspective(glm::radians(fovDeg), float(w) / float(h), nearP, farP);
    // Camera-relative: the view's rotation only (listing 16's relative
    // world position keeps the translation out of every derivative).
    v.viewProjRel = v.proj * glm::mat4(glm::mat3(view));
    return v;
}

} // namespace

void sceneBounds(const Scene& scene, const SceneAssets& assets, glm::vec3& lo, glm::vec3& hi) {
    lo = glm::vec3(1e30f);
    hi = glm::vec3(-1e30f);
    for (size_t i = 0; i < scene.meshes.size() && i < assets.meshes.size(); ++i) {
        const glm::dmat4& M = scene.meshes[i].transform;
        for (const auto& p : assets.meshes[i].mesh.positions) {
            glm::vec3 w = glm::vec3(M * glm::dvec4(glm::dvec3(p), 1.0));
            lo = glm::min(lo, w);
            hi = glm::max(hi, w);
        }
    }
    if (!(lo.x <= hi.x)) lo = hi = glm::vec3(0.0f);
}

View makeView(const Scene& scene, const SceneAssets& assets, int width, int height, Aov aov) {
    int w = width > 0 ? width : scene.output.width;
    int h = height > 0 ? height : scene.output.height;
    glm::vec3 lo, hi;
    sceneBounds(scene, assets, lo, hi);
    const glm::dvec3 center = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
    float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    const Camera& c = scene.camera;
    glm::dvec3 eye = c.position, target = c.target;
    float halfFov = glm::radians(c.fovDeg) * 0.5f;
    if (c.automatic) {
        float az = glm::radians(c.azimuthDeg), el = glm::radians(c.elevationDeg);
        glm::vec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
        // Fit the bounding sphere in the narrower of the two fields of view.
        float halfFovX = std::atan(std::tan(halfFov) * float(w) / float(h));
        float dist = radius / std::sin(std::min(halfFov, halfFovX)) * c.distanceScale;
        target = center;
        eye = center + glm::dvec3(dir * dist);
    }
    float dist = float(glm::length(eye - center));
    float nearP = c.nearPlane > 0 ? c.nearPlane
                                  : std::max(dist - 2.0f * radius, std::max(dist, radius) * 1e-3f);
    float farP = c.farPlane > 0 ? c.farPlane : dist + 3.0f * radius;
    return finishView(eye, target, c.up, c.fovDeg, nearP, farP, w, h, aov);
}

View makeOrbitView(glm::dvec3 target, float distance, float azimuthDeg, float elevationDeg,
                   float fovDeg, float nearPlane, float farPlane, int width, int height, Aov aov) {
    float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    glm::vec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
    return finishView(target + glm::dvec3(distance * dir), target, glm::dvec3(0, 1, 0), fovDeg,
                      nearPlane, farPlane, width, height, aov);
}

} // namespace sg::render
