// Declarations shared by every assembled fragment program of the renderer
// (GLSL only; render generates main() from the scene's layers and
// includes only the layer files the material uses). Defines as in
// sg/render/surface_vs.glsl, plus SG_LIGHT_COUNT (>= 1) and
// SG_LAYER_RECORDS (>= 1, vec4 records of packed layer parameters).
// glslang-validate: SG_LIGHT_COUNT 1, SG_LAYER_RECORDS 1
// glsl-targets: glsl450 (the renderer's desktop program: dFdxFine,
// default-block uniforms)
#ifndef SG_RENDER_SURFACE_FS_GLSL
#define SG_RENDER_SURFACE_FS_GLSL

#include "sg/render/common.glsl"
#include "sg/render/shading.glsl"

#ifndef SG_UV_COUNT
#define SG_UV_COUNT 0
#endif

in vec3 vRelPos;
in vec3 vObjPos;
in vec3 vNormal;
#if SG_UV_COUNT > 0
in vec2 vUv0;
#endif
#if SG_UV_COUNT > 1
in vec2 vUv1;
#endif
#if SG_UV_COUNT > 2
in vec2 vUv2;
#endif
#if SG_UV_COUNT > 3
in vec2 vUv3;
#endif
#if SG_VTX_TANGENT_0
in vec4 vTangent0;
#endif
#if SG_VTX_TANGENT_1
in vec4 vTangent1;
#endif
#if SG_VTX_TANGENT_2
in vec4 vTangent2;
#endif
#if SG_VTX_TANGENT_3
in vec4 vTangent3;
#endif

uniform int uBfaceMode;   // SG_BFACE_* (section 2.10)
uniform int uAov;         // SG_AOV_*
uniform float uPrimBase;  // added to gl_PrimitiveID + 1 for SG_AOV_PRIM_ID
uniform vec3 uBaseColor;  // linear albedo
uniform float uRoughness; // GGX roughness in [0, 1]
uniform vec3 uAmbient;    // hemispherical ambient radiance
uniform mat3 uModel3;     // object -> world, 3x3 part
uniform mat3 uModelInv3;  // world -> object, 3x3 part
uniform mat3 uNormalMat;  // object normal -> world normal
uniform vec4 uLights[2 * SG_LIGHT_COUNT];
uniform vec4 uLayerData[SG_LAYER_RECORDS];

layout(location = 0) out vec4 outValue;

#endif
