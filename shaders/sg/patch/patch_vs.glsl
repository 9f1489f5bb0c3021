// Vertex stage of the adaptive-patch draw (GLSL only): one vertex per
// control point of each patch (a non-indexed draw of pointsPerPatch
// vertices per patch), fetched from the points buffer through the patch
// arrays' indices. The patch index travels with the vertex: it is not taken
// from gl_PrimitiveID, which Mesa's llvmpipe restarts within large patch
// draws.
// glsl-targets: glsl450 (the points and indices are std430 buffers)
layout(std430, binding = 0) readonly buffer SgPatchPoints {
    float sgPoints[]; // xyz per control point, object space
};
layout(std430, binding = 3) readonly buffer SgPatchIndices {
    uint sgPatchIndices[]; // AdaptivePatches::indices
};

uniform uint uFirstIndex;     // this draw's first entry of sgPatchIndices
uniform uint uFirstPatch;     // this draw's first patch
uniform int uPointsPerPatch;  // 16 or 20

out vec3 vCtrlObj;
flat out uint vPatchIndex;

void main() {
    uint k = uint(gl_VertexID);
    uint v = sgPatchIndices[uFirstIndex + k];
    vCtrlObj = vec3(sgPoints[3u * v], sgPoints[3u * v + 1u], sgPoints[3u * v + 2u]);
    vPatchIndex = uFirstPatch + k / uint(uPointsPerPatch);
}
