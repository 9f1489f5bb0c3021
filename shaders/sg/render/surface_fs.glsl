// Declarations shared by every assembled fragment program of the renderer
// (GLSL only; render generates main() from the scene's layers and
// includes only the layer files the material uses). Defines as in
// sg/render/surface_vs.glsl, plus SG_LIGHT_COUNT (>= 1) and
// SG_LAYER_RECORDS (>= 1, vec4 records of packed layer parameters).
// glslang-validate: SG_LIGHT_COUNT 1, SG_LAYER_RECORDS 1
// glsl-targets: glsl330 es300 (and 4.50; Vulkan GLSL forbids default-block
// uniforms: `surfgrad shader --target spirv|hlsl|msl` gathers them into one
// block, surfgrad/translate/shader_target.h)
#ifndef SG_RENDER_SURFACE_FS_GLSL
#define SG_RENDER_SURFACE_FS_GLSL

#include "sg/render/common.glsl"
#include "sg/render/shading.glsl"

#include "sg/render/program_options.glsl"

// Screen derivatives as the generated main() takes them: dFdxFine/dFdyFine
// (differences inside the pixel's own row and column of its 2x2 quad) where
// the dialect has them (GLSL 4.00 and later); GLSL 3.30 and ES 3.00 have
// only dFdx/dFdy, which a driver may evaluate once per quad (coarse), so a
// pixel's frame may use its neighbour's differences there (docs/engines.md,
// "Scene programs per target", says what that costs).
#ifdef SG_GLSL_LEGACY
#define SG_DFDX(v) dFdx(v)
#define SG_DFDY(v) dFdy(v)
#else
#define SG_DFDX(v) dFdxFine(v)
#define SG_DFDY(v) dFdyFine(v)
#endif
// The primitive index of the primid AOV. GLSL ES 3.00 has no
// gl_PrimitiveID (ES 3.2 adds it): there every triangle reads 0.
#ifdef GL_ES
#define SG_PRIMITIVE_ID 0
#else
#define SG_PRIMITIVE_ID gl_PrimitiveID
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
