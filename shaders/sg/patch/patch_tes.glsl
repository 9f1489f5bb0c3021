// Tessellation evaluation stage of the adaptive-patch draw (GLSL only):
// the limit surface at GL's domain point through the shared patch basis
// (sg/patch/basis.glsl, the same source the CPU evaluates), with the
// outputs of the surface vertex stage (sg/render/surface_vs.glsl: positions
// camera-relative through uModelRel, Mikkelsen 2019 listing 16), so the
// fragment stage is unchanged. Integer (equal) spacing: the CPU knows the
// levels exactly (sgPatchEdgeTessLevel returns integers).
// Defines set by the host program:
//   SG_PATCH_CAPTURE (0/1)  also append (patch, u, v, object position) of
//                           every evaluated point to the capture buffer
//                           (binding 2; tests of parity and crack-freedom).
// glslang-validate: SG_PATCH_CAPTURE 1
#include "sg/patch/basis.glsl"

#ifndef SG_PATCH_CAPTURE
#define SG_PATCH_CAPTURE 0
#endif

layout(quads, equal_spacing, ccw) in;

in vec3 tcCtrlObj[];
patch in uint tcPatchIndex;

layout(std430, binding = 1) readonly buffer SgPatchData {
    uint sgPatchData[];
};
#if SG_PATCH_CAPTURE
// count, then 6 words per point: patch, u, v (float bits), x, y, z.
layout(std430, binding = 2) buffer SgPatchCapture {
    uint sgCaptureCount;
    uint sgCaptureCapacity;
    uint sgCapture[];
};
#endif

uniform int uPatchType; // SG_PATCH_REGULAR or SG_PATCH_GREGORY_BASIS
uniform mat4 uModel;
uniform mat4 uModelRel;
uniform mat3 uNormalMat;
uniform mat4 uViewProjRel;

out vec3 vRelPos;
out vec3 vWorldPos;
out vec3 vObjPos;
out vec3 vNormal;

void main() {
    uint patchIndex = tcPatchIndex;
    uint field1 = sgPatchData[5u * patchIndex];
    vec2 faceUv = sgPatchUnnormalizeUv(field1, gl_TessCoord.xy);
    SgPatchBasis b = sgPatchBasis(uPatchType, field1, faceUv);
    vec3 pos = vec3(0.0), du = vec3(0.0), dv = vec3(0.0);
    for (int i = 0; i < b.count; ++i) {
        pos += b.point.v[i] * tcCtrlObj[i];
        du += b.du.v[i] * tcCtrlObj[i];
        dv += b.dv.v[i] * tcCtrlObj[i];
    }
    vec3 nObj = sgSafeNormalize(cross(du, dv), vec3(0.0, 0.0, 1.0));
    vObjPos = pos;
    vWorldPos = (uModel * vec4(pos, 1.0)).xyz;
    vRelPos = (uModelRel * vec4(pos, 1.0)).xyz;
    vNormal = uNormalMat * nObj;
    gl_Position = uViewProjRel * vec4(vRelPos, 1.0);
#if SG_PATCH_CAPTURE
    uint slot = atomicAdd(sgCaptureCount, 1u);
    if (slot < sgCaptureCapacity) {
        uint o = 6u * slot;
        sgCapture[o] = patchIndex;
        sgCapture[o + 1u] = floatBitsToUint(gl_TessCoord.x);
        sgCapture[o + 2u] = floatBitsToUint(gl_TessCoord.y);
        sgCapture[o + 3u] = floatBitsToUint(pos.x);
        sgCapture[o + 4u] = floatBitsToUint(pos.y);
        sgCapture[o + 5u] = floatBitsToUint(pos.z);
    }
#endif
}
