// Compute entry that samples bound feature maps exactly as a renderer does
// (sgFeatSample through texelFetch, fetch.glsl; with SG_FEAT_NEAR 1,
// sgFeatSampleNear with the near-field textures too): one texel-space
// position per record (2 floats) -> distance, gradient x, gradient y, side
// (4 floats). Used by the parity tests to exercise the texture path, not
// just the evaluator.
// glslang-validate: SG_FEAT_NEAR 1
#include "sg/features/fetch.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer SampleInput { float inData[]; };
layout(std430, binding = 1) writeonly buffer SampleOutput { float outData[]; };
uniform uint uCount;
uniform usampler2D uFeatCorners;
uniform usampler2D uFeatEdges;
#if SG_FEAT_NEAR
uniform usampler2D uFeatNear;
uniform usampler2D uFeatPieces;
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uCount) return;
    vec2 texelPos = vec2(inData[2u * i], inData[2u * i + 1u]);
#if SG_FEAT_NEAR
    SgFeatResult r = sgFeatSampleNear(uFeatCorners, uFeatEdges, uFeatNear, uFeatPieces, texelPos);
#else
    SgFeatResult r = sgFeatSample(uFeatCorners, uFeatEdges, texelPos);
#endif
    outData[4u * i] = r.dist;
    outData[4u * i + 1u] = r.grad.x;
    outData[4u * i + 2u] = r.grad.y;
    outData[4u * i + 3u] = r.side;
}
