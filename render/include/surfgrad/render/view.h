// Views: the camera of one frame as both renderers (and the plan's record
// packing) take it. Shading happens in world space RELATIVE TO THE CAMERA
// (Mikkelsen 2019, listing 16): viewProjRel maps camera-relative world
// positions to clip space.
//
// Contract: a view that is rendered has width and height >= 1 (makeView()
// takes the scene's validated output size when given 0).
#pragma once

#include <glm/glm.hpp>

#include "surfgrad/render/assets.h"
#include "surfgrad/render/image.h"
#include "surfgrad/render/scene.h"

namespace sg::render {

struct View {
    int width = 0, height = 0;
    glm::dvec3 cameraPos{0.0};   // world, binary64 (scene positions are)
    glm::mat4 viewProjRel{1.0f}; // camera-relative world -> clip
    glm::mat4 view{1.0f}, proj{1.0f};
    Aov aov = Aov::Color;
};
// The view of the scene's camera (automatic framing uses the assets' bounds)
// at the given output size (0: the scene's).
View makeView(const Scene& scene, const SceneAssets& assets, int width = 0, int height = 0,
              Aov aov = Aov::Color);
// The object -> camera-relative world transform of a draw (Mikkelsen 2019,
// listing 16 carried into the vertex stage): model's linear part unchanged,
// its translation minus the camera position, subtracted in binary64 and
// rounded once. The vertex stage applies it to object positions, so a vertex
// is rounded at its distance from the camera, not from the world origin:
// an object 1e6 units out keeps the position (and dPdx) precision it has at
// the origin. Error bound of the relative position of a vertex p: about
// |linear part| |p| 2^-23 + |translation - camera| 2^-24 (binary32 products
// and sums of small values), against |model translation| 2^-24 + |camera|
// 2^-24 for world position minus camera in binary32 (4 units at 1e8, 0.03
// at 1e6).
// `model` is affine (last row 0, 0, 0, 1). Both are binary64, as the scene
// keeps them: the camera 1e6 from the origin is placed to 1e-10, not to the
// 0.06 of a binary32 coordinate there.
glm::mat4 modelToCameraRelative(const glm::dmat4& model, const glm::dvec3& cameraPos);

// World-space bounds of every mesh instance of the scene (the positions of
// assets.meshes[i] through scene.meshes[i].transform, rounded to binary32).
// A scene without vertices gives lo = hi = (0, 0, 0).
void sceneBounds(const Scene& scene, const SceneAssets& assets, glm::vec3& lo, glm::vec3& hi);

// An orbit view around `target` (viewer).
View makeOrbitView(glm::dvec3 target, float distance, float azimuthDeg, float elevationDeg,
                   float fovDeg, float nearPlane, float farPlane, int width, int height, Aov aov);

} // namespace sg::render
