// Animated cages on the GPU (GLSL only): the control points of adaptive
// patches recomputed from the cage positions with the stencil passes of
// sg::mesh::AdaptivePatches (stencilOffsets/Indices/Weights/Passes: one
// pass per refinement level, each level's points from the level above as
// OpenSubdiv's Far::StencilTable with factorizeIntermediateLevels = false
// gives them, then the Gregory end caps' local points), so that per frame
// only the cage is uploaded (into the points buffer's first cage points).
// One dispatch per pass (a memory barrier between passes: a pass reads
// points earlier passes wrote), one invocation per point i of the pass,
// row r = i - cagePointCount:
//   points[i] = sum over k in [offsets[r], offsets[r+1]) of
//               weights[k] * points[indices[k]],
// summed from 0 in k order, each product rounded before the add (`precise`
// forbids fused multiply-adds): the same operations in the same order as
// sg::mesh::updateAdaptivePoints, so the GPU's points equal the CPU's bit
// for bit (AdaptiveAnim tests in tests/render/adaptive_test.cpp).
layout(local_size_x = 64) in;

layout(std430, binding = 0) buffer SgPatchPoints {
    float sgPoints[]; // xyz per control point, object space (patch_vs.glsl reads it)
};
layout(std430, binding = 5) readonly buffer SgStencilOffsets {
    uint sgStencilOffsets[]; // one per point past the cage, + 1
};
layout(std430, binding = 6) readonly buffer SgStencilIndices {
    uint sgStencilIndices[]; // point indices, all before the pass's first point
};
layout(std430, binding = 7) readonly buffer SgStencilWeights {
    float sgStencilWeights[];
};

uniform uint uFirstPoint;     // this dispatch's first point (a large pass takes several)
uniform uint uEndPoint;       // one past the pass's last point
uniform uint uCagePointCount; // points before the first row

void main() {
    uint i = uFirstPoint + gl_GlobalInvocationID.x;
    if (i >= uEndPoint) return;
    uint r = i - uCagePointCount;
    precise vec3 p = vec3(0.0);
    uint end = sgStencilOffsets[r + 1u];
    for (uint k = sgStencilOffsets[r]; k < end; ++k) {
        uint c = 3u * sgStencilIndices[k];
        precise vec3 term =
            sgStencilWeights[k] * vec3(sgPoints[c], sgPoints[c + 1u], sgPoints[c + 2u]);
        p = p + term;
    }
    sgPoints[3u * i] = p.x;
    sgPoints[3u * i + 1u] = p.y;
    sgPoints[3u * i + 2u] = p.z;
}
