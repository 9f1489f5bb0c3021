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
// owner (cornerOwners). Transition edges (a coarse patch against two finer
// ones): each point from the fine owner of its half at the fine side's own
// parameter (sgPatchEvalSite with the halves' levels from the control
// stage). Interior points use this patch's own control points.
//
// UV sets (sg::mesh::AdaptiveUvSet): each set's face-varying patch is
// evaluated with the same shared basis at this patch's own domain point
// (not the owner's: across a UV seam the two sides have different UVs, as
// the uniform path's split vertices do), and passed to the fragment stage
// as surface_vs.glsl passes its UV sets (vUv0..3).
// Defines set by the host program:
//   SG_PATCH_CAPTURE (0/1)  also append (patch, u, v, object position) of
//                           every evaluated point to the capture buffer
//                           (binding 2; tests of parity and crack-freedom).
//   SG_UV_COUNT (0..4)      UV sets written (as surface_vs.glsl).
//   SG_DISPLACEMENT (0/1)   displace along the limit normal by uDispScale
//                           times the red channel of uDispMap plus
//                           uDispOffset, the map read at UV set
//   SG_DISP_UV_SET (0..3)   SG_DISP_UV_SET (sg/patch/displace.glsl): vRelPos
//                           stays undisplaced (the fragment stage's frame,
//                           Mikkelsen 2019 section 2.5), vRelPosLit and
//                           gl_Position are displaced. Boundary points take
//                           everything from their owner's site (UV, normal,
//                           level of the map), so displaced shared edges stay
//                           crack-free.
//   SG_VTX_TANGENT_k (0/1)  write vTangentk, the "limit" tangent of UV set k
//                           (sg/patch/limit_tangent.glsl), world space as
//                           surface_vs.glsl writes its vertex tangents: the
//                           position patch's and the set's derivatives at
//                           this patch's own domain point (the chart of the
//                           UVs this point carries: across a UV seam each
//                           side keeps its own tangent, as the uniform
//                           path's split vertices do), made orthogonal to
//                           the output normal (the owner's on shared edges
//                           and corners). Undisplaced surface (Mikkelsen
//                           2019, section 2.5). Only the sets the plan asks
//                           for (an enabled layer reads their basis).
// glslang-validate: SG_PATCH_CAPTURE 1
// glslang-validate: SG_UV_COUNT 2, SG_DISPLACEMENT 1, SG_DISP_UV_SET 1
// glslang-validate: SG_UV_COUNT 2, SG_VTX_TANGENT_0 1, SG_VTX_TANGENT_1 1
#include "sg/patch/basis.glsl"
#include "sg/patch/watertight.glsl"

#ifndef SG_PATCH_CAPTURE
#define SG_PATCH_CAPTURE 0
#endif
#include "sg/render/program_options.glsl"
#ifndef SG_DISPLACEMENT
#define SG_DISPLACEMENT 0
#endif
#if SG_DISPLACEMENT
#include "sg/patch/displace.glsl"
#endif
#define SG_PATCH_TANGENTS (SG_VTX_TANGENT_0 || SG_VTX_TANGENT_1 || SG_VTX_TANGENT_2 || SG_VTX_TANGENT_3)
#if SG_PATCH_TANGENTS
#include "sg/patch/limit_tangent.glsl"
#endif

layout(quads, equal_spacing, ccw) in;

in vec3 tcCtrlObj[];
patch in uint tcPatchIndex;
patch in vec4 tcTransLoLevel;

layout(std430, binding = 0) readonly buffer SgPatchPoints {
    float sgPoints[]; // xyz per control point, object space
};
// Per patch, SG_PATCH_DATA_STRIDE (28) words: field1, four corner
// vertices, type, first entry of its control points in sgPatchIndices,
// transition mask, four edge owners, four corner owners, then per edge the
// transition's lower-half owner, upper-half owner and midpoint owner (four
// words each; AdaptivePatches).
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

#if SG_UV_COUNT > 0
// Every UV set's face-varying values, xy, the sets one after the other
// (binding 4); per patch and set (patch-major), SG_PATCH_UV_STRIDE words:
// the face-varying PatchParam field1, the patch type, then 20 indices into
// sgUvValues (binding 5). Layout written by gl_renderer.cpp.
layout(std430, binding = 4) readonly buffer SgPatchUvValues {
    float sgUvValues[];
};
layout(std430, binding = 5) readonly buffer SgPatchUvPatches {
    uint sgUvPatches[];
};
#define SG_PATCH_UV_STRIDE 22u

// UV set `set` of patch p at (u,v) of the ptex face.
vec2 patchUv(uint p, uint set, vec2 faceUv) {
    uint base = SG_PATCH_UV_STRIDE * (p * uint(SG_UV_COUNT) + set);
    uint field1 = sgUvPatches[base];
    SgPatchBasis b = sgPatchBasis(int(sgUvPatches[base + 1u]), field1, faceUv);
    vec2 st = vec2(0.0);
    for (int i = 0; i < b.count; ++i) {
        uint v = sgUvPatches[base + 2u + uint(i)];
        st += b.pos.v[i] * vec2(sgUvValues[2u * v], sgUvValues[2u * v + 1u]);
    }
    return st;
}
out vec2 vUv0;
#endif
#if SG_DISPLACEMENT || SG_PATCH_TANGENTS
// UV set `set` of patch p at (u,v) of the ptex face, and its derivatives
// with respect to that (u,v) (as the positions' from sgPatchBasis).
void patchUvDeriv(uint p, uint set, vec2 faceUv, out vec2 st, out vec2 du, out vec2 dv) {
    uint base = SG_PATCH_UV_STRIDE * (p * uint(SG_UV_COUNT) + set);
    uint field1 = sgUvPatches[base];
    SgPatchBasis b = sgPatchBasis(int(sgUvPatches[base + 1u]), field1, faceUv);
    precise vec2 s0 = vec2(0.0), s1 = vec2(0.0), s2 = vec2(0.0);
    for (int i = 0; i < b.count; ++i) {
        uint v = sgUvPatches[base + 2u + uint(i)];
        vec2 x = vec2(sgUvValues[2u * v], sgUvValues[2u * v + 1u]);
        s0 += b.pos.v[i] * x;
        s1 += b.du.v[i] * x;
        s2 += b.dv.v[i] * x;
    }
    st = s0;
    du = s1;
    dv = s2;
}
#endif
#if SG_DISPLACEMENT
uniform sampler2D uDispMap;
uniform float uDispScale;
uniform float uDispOffset;
uniform float uFocalPx;
uniform float uPixelsPerEdge;
out vec3 vRelPosLit; // displaced, camera-relative (lighting)
#endif
#if SG_UV_COUNT > 1
out vec2 vUv1;
#endif
#if SG_UV_COUNT > 2
out vec2 vUv2;
#endif
#if SG_UV_COUNT > 3
out vec2 vUv3;
#endif
#if SG_VTX_TANGENT_0
out vec4 vTangent0;
#endif
#if SG_VTX_TANGENT_1
out vec4 vTangent1;
#endif
#if SG_VTX_TANGENT_2
out vec4 vTangent2;
#endif
#if SG_VTX_TANGENT_3
out vec4 vTangent3;
#endif
#if SG_PATCH_TANGENTS
uniform float uDetSign; // sign of det(uModel's 3x3): mirrors flip tangent handedness
#endif

uniform mat4 uModel;
uniform mat4 uModelRel;
uniform mat3 uNormalMat;
uniform mat4 uViewProjRel;

out vec3 vRelPos;
out vec3 vObjPos;
out vec3 vNormal;
// The patch AOV (Aov::Patch): 1 + patch index, tessellation level (the
// largest outer level), Far patch type, depth.
flat out vec4 vPatchAov;

#define SG_PATCH_DATA_STRIDE 28u

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
        sp += b.pos.v[i] * c;
        su += b.du.v[i] * c;
        sv += b.dv.v[i] * c;
    }
    pos = sp;
    du = su;
    dv = sv;
}

#if SG_PATCH_TANGENTS
// The limit tangent of UV set `set` of patch p at (u,v) of its ptex face
// (dPdu, dPdv: that patch's derivatives there; nObj: the output normal),
// world space. Only sets below SG_UV_COUNT (the plan's vertex tangents).
vec4 patchTangent(uint p, uint set, vec2 faceUv, vec3 dPdu, vec3 dPdv, vec3 nObj) {
    vec2 st, sdu, sdv;
    patchUvDeriv(p, set, faceUv, st, sdu, sdv);
    int resolved;
    vec4 t = sgPatchLimitTangent(dPdu, dPdv, sdu, sdv, nObj, resolved);
    return vec4(mat3(uModel) * t.xyz, t.w * uDetSign);
}
#endif

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
    SgPatchTransitions trans;
    trans.lo = uvec4(sgPatchData[base + 16u], sgPatchData[base + 17u], sgPatchData[base + 18u],
                     sgPatchData[base + 19u]);
    trans.hi = uvec4(sgPatchData[base + 20u], sgPatchData[base + 21u], sgPatchData[base + 22u],
                     sgPatchData[base + 23u]);
    trans.mid = uvec4(sgPatchData[base + 24u], sgPatchData[base + 25u], sgPatchData[base + 26u],
                      sgPatchData[base + 27u]);
    trans.loLevel = tcTransLoLevel;
    SgPatchSite site = sgPatchEvalSite(patchIndex, edgeOwners, cornerOwners, trans, outer, uv);
    vec3 pos, du, dv;
    // Every boundary point takes the buffers' path (also when this patch is
    // the owner): the same instructions as on the other side.
    bool onBoundary = uv.x == 0.0 || uv.x == 1.0 || uv.y == 0.0 || uv.y == 1.0;
    if (onBoundary) {
        evalFromBuffers(site.patchIndex, site.uv, pos, du, dv);
    } else {
        uint field1 = sgPatchData[base];
        SgPatchBasis b = sgPatchBasis(int(sgPatchData[base + 5u]), field1,
                                      sgPatchUnnormalizeUv(field1, uv));
        pos = vec3(0.0);
        du = vec3(0.0);
        dv = vec3(0.0);
        for (int i = 0; i < b.count; ++i) {
            pos += b.pos.v[i] * tcCtrlObj[i];
            du += b.du.v[i] * tcCtrlObj[i];
            dv += b.dv.v[i] * tcCtrlObj[i];
        }
    }
    vec3 nObj = sgSafeNormalize(cross(du, dv), vec3(0.0, 0.0, 1.0));
    vObjPos = pos;
    vRelPos = (uModelRel * vec4(pos, 1.0)).xyz;
    vNormal = uNormalMat * nObj;
#if SG_DISPLACEMENT
    // Everything from the site (the owner's patch and parameter on shared
    // edges and corners; this patch's inside): the same bits on both sides.
    vec2 dispSt, dispDu, dispDv;
    patchUvDeriv(site.patchIndex, uint(SG_DISP_UV_SET),
                 sgPatchUnnormalizeUv(sgPatchData[SG_PATCH_DATA_STRIDE * site.patchIndex], site.uv),
                 dispSt, dispDu, dispDv);
    precise vec3 relDu = mat3(uModelRel) * du, relDv = mat3(uModelRel) * dv;
    precise vec3 relBase = (uModelRel * vec4(pos, 1.0)).xyz;
    ivec2 dispSize = textureSize(uDispMap, 0);
    precise float dispLod = sgDisplaceLod(relDu, relDv, dispDu, dispDv, length(relBase), uFocalPx,
                                          uPixelsPerEdge, float(max(dispSize.x, dispSize.y)));
    float height = textureLod(uDispMap, dispSt, dispLod).r;
    precise vec3 dispN = sgSafeNormalize(cross(du, dv), vec3(0.0, 0.0, 1.0));
    precise vec3 posLit = sgDisplacePoint(pos, dispN, height, uDispScale, uDispOffset);
    vRelPosLit = (uModelRel * vec4(posLit, 1.0)).xyz;
    gl_Position = uViewProjRel * vec4(vRelPosLit, 1.0);
#else
    vec3 posLit = pos;
    gl_Position = uViewProjRel * vec4(vRelPos, 1.0);
#endif
    uint field1 = sgPatchData[base];
#if SG_UV_COUNT > 0
    vec2 faceUv = sgPatchUnnormalizeUv(field1, uv);
    vUv0 = patchUv(patchIndex, 0u, faceUv);
#endif
#if SG_UV_COUNT > 1
    vUv1 = patchUv(patchIndex, 1u, faceUv);
#endif
#if SG_UV_COUNT > 2
    vUv2 = patchUv(patchIndex, 2u, faceUv);
#endif
#if SG_UV_COUNT > 3
    vUv3 = patchUv(patchIndex, 3u, faceUv);
#endif
#if SG_PATCH_TANGENTS
    // The tangents' chart: this patch's own derivatives (the site's on the
    // inside; evaluated again here on the boundary, where the site may be
    // another patch with another (u,v)).
    vec3 ownDu = du, ownDv = dv;
    if (onBoundary) {
        vec3 ownPos;
        evalFromBuffers(patchIndex, uv, ownPos, ownDu, ownDv);
    }
#endif
#if SG_VTX_TANGENT_0
    vTangent0 = patchTangent(patchIndex, 0u, faceUv, ownDu, ownDv, nObj);
#endif
#if SG_VTX_TANGENT_1
    vTangent1 = patchTangent(patchIndex, 1u, faceUv, ownDu, ownDv, nObj);
#endif
#if SG_VTX_TANGENT_2
    vTangent2 = patchTangent(patchIndex, 2u, faceUv, ownDu, ownDv, nObj);
#endif
#if SG_VTX_TANGENT_3
    vTangent3 = patchTangent(patchIndex, 3u, faceUv, ownDu, ownDv, nObj);
#endif
    vPatchAov = vec4(float(patchIndex + 1u), max(max(outer.x, outer.y), max(outer.z, outer.w)),
                     float(sgPatchData[base + 5u]), float(sgPatchDepth(field1)));
#if SG_PATCH_CAPTURE
    uint slot = atomicAdd(sgCaptureCount, 1u);
    if (slot < sgCaptureCapacity) {
        uint o = 6u * slot;
        sgCapture[o] = patchIndex;
        sgCapture[o + 1u] = floatBitsToUint(gl_TessCoord.x);
        sgCapture[o + 2u] = floatBitsToUint(gl_TessCoord.y);
        sgCapture[o + 3u] = floatBitsToUint(posLit.x);
        sgCapture[o + 4u] = floatBitsToUint(posLit.y);
        sgCapture[o + 5u] = floatBitsToUint(posLit.z);
    }
#endif
}
