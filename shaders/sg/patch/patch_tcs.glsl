// Tessellation control stage of the adaptive-patch draw (GLSL only).
// Defines set by the host program:
//   SG_PATCH_POINTS  control points per patch: 16 (regular) or 20 (Gregory).
// glslang-validate: SG_PATCH_POINTS 16
//
// Levels: each outer level from the two refined vertices at the ends of the
// patch edge (AdaptivePatches::cornerVertices, read from the points buffer,
// never from this patch's own control points), through the shared
// sgPatchEdgeTessLevel (sg/patch/tess_level.glsl). Two patches of the same
// depth that share an edge read the same two vertices and compute the same
// level bit for bit (the function is symmetric in its end points), so GL
// places the same domain points on the edge from both sides. Inner levels:
// the larger of the two opposite outer levels.
//
// Transition edges (AdaptivePatches::transitionMask bit k): the outer level
// is the sum of the two halves' levels, each from the corner vertices of
// the half's fine owner in the owner's order (what the fine patch computes
// for its own edge), both capped at sgPatchHalfMaxLevel; the lower half's
// level goes to the evaluation stage (tcTransLoLevel), which maps the edge's
// points onto the halves (sg/patch/watertight.glsl). An edge that is a half
// (bit 4 + k) is capped the same way.
#include "sg/patch/tess_level.glsl"

layout(vertices = SG_PATCH_POINTS) out;

in vec3 vCtrlObj[];
flat in uint vPatchIndex[];
out vec3 tcCtrlObj[];
patch out uint tcPatchIndex;
patch out vec4 tcTransLoLevel; // per edge: the lower half's level, 0 if not a transition

// Every control point's object position, xyz (AdaptivePatches::points).
layout(std430, binding = 0) readonly buffer SgPatchPoints {
    float sgPoints[];
};
// Per patch, SG_PATCH_DATA_STRIDE words (layout in patch_tes.glsl):
// PatchParam field1, the four corner vertices, ...
layout(std430, binding = 1) readonly buffer SgPatchData {
    uint sgPatchData[];
};

uniform mat4 uModelRel;     // object -> camera-relative world (as surface_vs.glsl)
uniform float uFocalPx;     // sgPatchFocalPx of the projection and viewport
uniform float uPixelsPerEdge;
uniform float uMaxTessLevel;

vec3 cornerRel(uint vertex) {
    vec3 p = vec3(sgPoints[3u * vertex], sgPoints[3u * vertex + 1u], sgPoints[3u * vertex + 2u]);
    return (uModelRel * vec4(p, 1.0)).xyz;
}

#define SG_PATCH_DATA_STRIDE 28u

float edgeLevel(vec3 a, vec3 b, float maxLevel) {
    return sgPatchEdgeTessLevel(a, b, uFocalPx, uPixelsPerEdge, maxLevel);
}

// Level of the half owned by `owner` ((patch << 3) | (edge << 1) | flip):
// that patch's own edge, from its corner vertices in its order.
float halfLevel(uint owner) {
    uint base = SG_PATCH_DATA_STRIDE * (owner >> 3u);
    uint e = (owner >> 1u) & 3u;
    uint from = e == 2u ? 1u : e == 3u ? 3u : 0u;
    uint to = e == 0u ? 3u : e == 1u ? 1u : 2u;
    return edgeLevel(cornerRel(sgPatchData[base + 1u + from]),
                     cornerRel(sgPatchData[base + 1u + to]), sgPatchHalfMaxLevel(uMaxTessLevel));
}

// Outer level of edge k from its ends a, b, or (transition) the halves'.
float outerLevel(uint base, uint mask, uint k, vec3 a, vec3 b, inout vec4 loLevel) {
    if ((mask & (1u << k)) != 0u) {
        float lo = halfLevel(sgPatchData[base + 16u + k]);
        loLevel[k] = lo;
        return lo + halfLevel(sgPatchData[base + 20u + k]);
    }
    bool isHalf = (mask & (16u << k)) != 0u;
    return edgeLevel(a, b, isHalf ? sgPatchHalfMaxLevel(uMaxTessLevel) : uMaxTessLevel);
}

void main() {
    tcCtrlObj[gl_InvocationID] = vCtrlObj[gl_InvocationID];
    if (gl_InvocationID == 0) {
        tcPatchIndex = vPatchIndex[0];
        uint base = SG_PATCH_DATA_STRIDE * vPatchIndex[0];
        uint mask = sgPatchData[base + 7u];
        vec3 c00 = cornerRel(sgPatchData[base + 1u]);
        vec3 c10 = cornerRel(sgPatchData[base + 2u]);
        vec3 c11 = cornerRel(sgPatchData[base + 3u]);
        vec3 c01 = cornerRel(sgPatchData[base + 4u]);
        // GL's quad domain: outer 0 is the edge u = 0, 1 is v = 0, 2 is
        // u = 1, 3 is v = 1.
        vec4 loLevel = vec4(0.0);
        float o0 = outerLevel(base, mask, 0u, c00, c01, loLevel);
        float o1 = outerLevel(base, mask, 1u, c00, c10, loLevel);
        float o2 = outerLevel(base, mask, 2u, c10, c11, loLevel);
        float o3 = outerLevel(base, mask, 3u, c01, c11, loLevel);
        tcTransLoLevel = loLevel;
        gl_TessLevelOuter[0] = o0;
        gl_TessLevelOuter[1] = o1;
        gl_TessLevelOuter[2] = o2;
        gl_TessLevelOuter[3] = o3;
        gl_TessLevelInner[0] = max(o1, o3);
        gl_TessLevelInner[1] = max(o0, o2);
    }
}
