// Vertex program of the renderer (GLSL only; assembled by render with the
// options of sg/render/program_options.glsl).
// glsl-targets: glsl330 es300 (and 4.50; Vulkan GLSL forbids default-block
// uniforms: `surfgrad shader --target spirv|hlsl|msl` gathers them into one
// block, surfgrad/translate/shader_target.h)
// Positions reach the fragment program relative to the camera (Mikkelsen
// 2019, listing 16: "NO TRANSLATION" in the derivatives, so dFdx of the
// position keeps its precision far from the origin). The relative position
// comes from uModelRel, composed on the CPU with the camera subtracted in
// binary64 (sg::render::modelToCameraRelative, render/view.h): it is never
// the difference of two large binary32 world positions. No stage passes
// the absolute world position (rounded at its distance from the origin):
// world-space volume layers take vRelPos and the camera's part packed per
// layer in binary64 (SgVolumeSpace, sg/render/common.glsl).
#include "sg/render/program_options.glsl"

layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
#if SG_UV_COUNT > 0
layout(location = 2) in vec2 aUv0;
out vec2 vUv0;
#endif
#if SG_UV_COUNT > 1
layout(location = 3) in vec2 aUv1;
out vec2 vUv1;
#endif
#if SG_UV_COUNT > 2
layout(location = 4) in vec2 aUv2;
out vec2 vUv2;
#endif
#if SG_UV_COUNT > 3
layout(location = 5) in vec2 aUv3;
out vec2 vUv3;
#endif
#if SG_VTX_TANGENT_0
layout(location = 6) in vec4 aTangent0;
out vec4 vTangent0;
#endif
#if SG_VTX_TANGENT_1
layout(location = 7) in vec4 aTangent1;
out vec4 vTangent1;
#endif
#if SG_VTX_TANGENT_2
layout(location = 8) in vec4 aTangent2;
out vec4 vTangent2;
#endif
#if SG_VTX_TANGENT_3
layout(location = 9) in vec4 aTangent3;
out vec4 vTangent3;
#endif

uniform mat4 uModel;       // object -> world
uniform mat4 uModelRel;    // object -> camera-relative world (translation minus camera, binary64)
uniform mat3 uNormalMat;   // inverse transpose of uModel's 3x3 part
uniform float uDetSign;    // sign of det(uModel's 3x3): mirrors flip tangent handedness
uniform mat4 uViewProjRel; // camera-relative world -> clip (view rotation and projection)

out vec3 vRelPos;   // world position minus camera position
out vec3 vObjPos;   // object position (volume layers in object space)
out vec3 vNormal;   // world normal, unnormalized (normalized per pixel, listing 16)

void main() {
    vRelPos = (uModelRel * vec4(aPosition, 1.0)).xyz;
    vObjPos = aPosition;
    vNormal = uNormalMat * aNormal;
#if SG_UV_COUNT > 0
    vUv0 = aUv0;
#endif
#if SG_UV_COUNT > 1
    vUv1 = aUv1;
#endif
#if SG_UV_COUNT > 2
    vUv2 = aUv2;
#endif
#if SG_UV_COUNT > 3
    vUv3 = aUv3;
#endif
#if SG_VTX_TANGENT_0
    vTangent0 = vec4(mat3(uModel) * aTangent0.xyz, aTangent0.w * uDetSign);
#endif
#if SG_VTX_TANGENT_1
    vTangent1 = vec4(mat3(uModel) * aTangent1.xyz, aTangent1.w * uDetSign);
#endif
#if SG_VTX_TANGENT_2
    vTangent2 = vec4(mat3(uModel) * aTangent2.xyz, aTangent2.w * uDetSign);
#endif
#if SG_VTX_TANGENT_3
    vTangent3 = vec4(mat3(uModel) * aTangent3.xyz, aTangent3.w * uDetSign);
#endif
    gl_Position = uViewProjRel * vec4(vRelPos, 1.0);
}
