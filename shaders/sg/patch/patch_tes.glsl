// Tessellation evaluation stage of the adaptive-patch draw (GLSL only):
// the limit surface at GL's domain point through the shared patch basis
// (sg/patch/basis.glsl, the same source the CPU evaluates), with the
// outputs of the surface vertex stage (sg/render/surface_vs.glsl: positions
// camera-relative through uModelRel, Mikkelsen 2019 listing 16), so the
// fragment stage is unchanged. Integer (equal) spacing: the CPU knows the
// levels exactly (sgPatchEdgeTessLevel returns integers).
//
// Crack-freedom between patches of the same depth (they share an edge's two
// corner vertices, hence its level): a point on a patch edge is evaluated
// from the edge's owner patch (AdaptivePatches::edgeOwners), at the
// parameter i / n of the owner's edge, with i recovered from GL's domain
// coordinate as an integer (round(t n), flipped as n - i when the owner runs
// the edge the other way) and n the edge's integer level. Both sides then
// run the same instructions on the same inputs (`precise`: no
// reassociation or fusing that could differ between the two programs), so
// the two positions are equal bit for bit. Corners likewise from their
// owner (cornerOwners). Interior points use this patch's own control points.
// Defines set by the host program:
//   SG_PATCH_CAPTURE (0/1)  also append (patch, u, v, object position) of
//                           every evaluated point to the capture buffer
//                           (binding 2; tests of parity and crack-freedom).
// glslang-validate: SG_PATCH_CAPTURE 1
#include "sg/patch/basis.glsl"
#include "sg/patch/watertight.glsl"

#ifndef SG_PATCH_CAPTURE
#define SG_PATCH_CAPTURE 0
#endif

layout(quads, equal_spacing, ccw) in;

in vec3 tcCtrlObj[];
patch in uint tcPatchIndex;

layout(std430, binding = 0) readonly buffer SgPatchPoints {
    float sgPoints[]; // xyz per control point, object space
};
// Per patch, 16 words: field1, four corner vertices, type, first entry of
// its control points in sgPatchIndices, unused, four edge owners, four
// corner owners (AdaptivePatches).
layout(std430, binding = 1) readonly buffer SgPatchData {
    uint sgPatchData[];
};
layout(std430, binding = 3) readonly buffer SgPatchIndices {
    uint sgPatchIndices[];
};
#if SG_PATCH_CAPTURE
// count, then 6 words per point: patch, u, v (float bits), x, y, z.
layout(std430, binding = 2) buffer SgPatchCapture {
    uint sgCaptureCount;
    uint sgCaptureCapacity;
    uint sgCapture[];
};
#endif

uniform mat4 uModel;
uniform mat4 uModelRel;
uniform mat3 uNormalMat;
uniform mat4 uViewProjRel;

out vec3 vRelPos;
out vec3 vWorldPos;
out vec3 vObjPos;
out vec3 vNormal;
// The patch AOV (Aov::Patch): 1 + patch index, tessellation level (the
// largest outer level), Far patch type, depth.
flat out vec4 vPatchAov;

#define SG_PATCH_DATA_STRIDE 16u

vec3 controlPoint(uint first, int i) {
    uint v = sgPatchIndices[first + uint(i)];
    return vec3(sgPoints[3u * v], sgPoints[3u * v + 1u], sgPoints[3u * v + 2u]);
}

// Position and derivatives of patch p at (u,v) of its own square, control
// points from the buffers (the owner of a shared edge or corner).
void evalFromBuffers(uint p, vec2 uv, out vec3 pos, out vec3 du, out vec3 dv) {
    uint base = SG_PATCH_DATA_STRIDE * p;
    uint field1 = sgPatchData[base];
    SgPatchBasis b = sgPatchBasis(int(sgPatchData[base + 5u]), field1,
                                  sgPatchUnnormalizeUv(field1, uv));
    uint first = sgPatchData[base + 6u];
    precise vec3 sp = vec3(0.0), su = vec3(0.0), sv = vec3(0.0);
    for (int i = 0; i < b.count; ++i) {
        vec3 c = controlPoint(first, i);
        sp += b.point.v[i] * c;
        su += b.du.v[i] * c;
        sv += b.dv.v[i] * c;
    }
    pos = sp;
    du = su;
    dv = sv;
}

void main() {
    uint patchIndex = tcPatchIndex;
    uint base = SG_PATCH_DATA_STRIDE * patchIndex;
    vec2 uv = gl_TessCoord.xy;
    uvec4 edgeOwners = uvec4(sgPatchData[base + 8u], sgPatchData[base + 9u],
                             sgPatchData[base + 10u], sgPatchData[base + 11u]);
    uvec4 cornerOwners = uvec4(sgPatchData[base + 12u], sgPatchData[base + 13u],
                               sgPatchData[base + 14u], sgPatchData[base + 15u]);
    vec4 outer = vec4(gl_TessLevelOuter[0], gl_TessLevelOuter[1], gl_TessLevelOuter[2],
                      gl_TessLevelOuter[3]);
    SgPatchSite site = sgPatchEvalSite(patchIndex, edgeOwners, cornerOwners, outer, uv);
    vec3 pos, du, dv;
    // Every boundary point takes the buffers' path (also when this patch is
    // the owner): the same instructions as on the other side.
    if (uv.x == 0.0 || uv.x == 1.0 || uv.y == 0.0 || uv.y == 1.0) {
        evalFromBuffers(site.patchIndex, site.uv, pos, du, dv);
    } else {
        uint field1 = sgPatchData[base];
        SgPatchBasis b = sgPatchBasis(int(sgPatchData[base + 5u]), field1,
                                      sgPatchUnnormalizeUv(field1, uv));
        pos = vec3(0.0);
        du = vec3(0.0);
        dv = vec3(0.0);
        for (int i = 0; i < b.count; ++i) {
            pos += b.point.v[i] * tcCtrlObj[i];
            du += b.du.v[i] * tcCtrlObj[i];
            dv += b.dv.v[i] * tcCtrlObj[i];
        }
    }
    vec3 nObj = sgSafeNormalize(cross(du, dv), vec3(0.0, 0.0, 1.0));
    vObjPos = pos;
    vWorldPos = (uModel * vec4(pos, 1.0)).xyz;
    vRelPos = (uModelRel * vec4(pos, 1.0)).xyz;
    vNormal = uNormalMat * nObj;
    gl_Position = uViewProjRel * vec4(vRelPos, 1.0);
    uint field1 = sgPatchData[base];
    vPatchAov = vec4(float(patchIndex + 1u), max(max(outer.x, outer.y), max(outer.z, outer.w)),
                     float(sgPatchData[base + 5u]), float(sgPatchDepth(field1)));
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
