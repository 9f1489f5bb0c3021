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
#include "sg/patch/tess_level.glsl"

layout(vertices = SG_PATCH_POINTS) out;

in vec3 vCtrlObj[];
flat in uint vPatchIndex[];
out vec3 tcCtrlObj[];
patch out uint tcPatchIndex;

// Every control point's object position, xyz (AdaptivePatches::points).
layout(std430, binding = 0) readonly buffer SgPatchPoints {
    float sgPoints[];
};
// Per patch, 16 words (layout in patch_tes.glsl): PatchParam field1, the
// four corner vertices, ...
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

float edgeLevel(vec3 a, vec3 b) {
    return sgPatchEdgeTessLevel(a, b, uFocalPx, uPixelsPerEdge, uMaxTessLevel);
}

void main() {
    tcCtrlObj[gl_InvocationID] = vCtrlObj[gl_InvocationID];
    if (gl_InvocationID == 0) {
        tcPatchIndex = vPatchIndex[0];
        uint base = 16u * vPatchIndex[0];
        vec3 c00 = cornerRel(sgPatchData[base + 1u]);
        vec3 c10 = cornerRel(sgPatchData[base + 2u]);
        vec3 c11 = cornerRel(sgPatchData[base + 3u]);
        vec3 c01 = cornerRel(sgPatchData[base + 4u]);
        // GL's quad domain: outer 0 is the edge u = 0, 1 is v = 0, 2 is
        // u = 1, 3 is v = 1.
        float o0 = edgeLevel(c00, c01), o1 = edgeLevel(c00, c10);
        float o2 = edgeLevel(c10, c11), o3 = edgeLevel(c01, c11);
        gl_TessLevelOuter[0] = o0;
        gl_TessLevelOuter[1] = o1;
        gl_TessLevelOuter[2] = o2;
        gl_TessLevelOuter[3] = o3;
        gl_TessLevelInner[0] = max(o1, o3);
        gl_TessLevelInner[1] = max(o0, o2);
    }
}
