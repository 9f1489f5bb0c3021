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
    glm::vec3 cameraPos{0.0f};
    glm::mat4 viewProjRel{1.0f}; // camera-relative world -> clip
    glm::mat4 view{1.0f}, proj{1.0f};
    Aov aov = Aov::Color;
};
// The view of the scene's camera (automatic framing uses the assets' bounds)
// at the given output size (0: the scene's).
View makeView(const Scene& scene, const SceneAssets& assets, int width = 0, int height = 0,
              Aov aov = Aov::Color);
// An orbit view around `target` (viewer).
View makeOrbitView(glm::vec3 target, float distance, float azimuthDeg, float elevationDeg,
                   float fovDeg, float nearPlane, float farPlane, int width, int height, Aov aov);

} // namespace sg::render
