// Animated cages on the GPU (GLSL only): the control points of adaptive
// patches recomputed from the cage positions with the stencil rows of
// sg::mesh::AdaptivePatches (stencilOffsets/Indices/Weights, OpenSubdiv's
// Far::StencilTable factorised down to the cage), so that per frame only the
// cage is uploaded. One invocation per point i:
//   points[i] = sum over k in [offsets[i], offsets[i+1]) of
//               weights[k] * cage[indices[k]],
// summed from 0 in k order, each product rounded before the add (`precise`
// forbids fused multiply-adds): the same operations in the same order as
// sg::mesh::updateAdaptivePoints, so the GPU's points equal the CPU's bit
// for bit (AdaptiveAnim tests in tests/render/adaptive_test.cpp).
layout(local_size_x = 64) in;

layout(std430, binding = 0) writeonly buffer SgPatchPoints {
    float sgPoints[]; // xyz per control point, object space (patch_vs.glsl reads it)
};
layout(std430, binding = 4) readonly buffer SgCagePoints {
    float sgCage[]; // xyz per cage vertex, object space
};
layout(std430, binding = 5) readonly buffer SgStencilOffsets {
    uint sgStencilOffsets[]; // pointCount + 1 entries
};
layout(std430, binding = 6) readonly buffer SgStencilIndices {
    uint sgStencilIndices[];
};
layout(std430, binding = 7) readonly buffer SgStencilWeights {
    float sgStencilWeights[];
};

uniform uint uFirstPoint; // this dispatch's first point (large tables take several)
uniform uint uPointCount; // points in the table

void main() {
    uint i = uFirstPoint + gl_GlobalInvocationID.x;
    if (i >= uPointCount) return;
    precise vec3 p = vec3(0.0);
    uint end = sgStencilOffsets[i + 1u];
    for (uint k = sgStencilOffsets[i]; k < end; ++k) {
        uint c = 3u * sgStencilIndices[k];
        precise vec3 term = sgStencilWeights[k] * vec3(sgCage[c], sgCage[c + 1u], sgCage[c + 2u]);
        p = p + term;
    }
    sgPoints[3u * i] = p.x;
    sgPoints[3u * i + 1u] = p.y;
    sgPoints[3u * i + 2u] = p.z;
}
