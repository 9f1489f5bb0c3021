// Compute entry that samples bound feature maps exactly as a renderer does
// (sgFeatSample through texelFetch, fetch.glsl): one texel-space position per
// record (2 floats) -> distance, gradient x, gradient y, side (4 floats).
// Used by the parity tests to exercise the texture path, not just the
// evaluator.
#include "sg/features/fetch.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer SampleInput { float inData[]; };
layout(std430, binding = 1) writeonly buffer SampleOutput { float outData[]; };
uniform uint uCount;
uniform usampler2D uFeatCorners;
uniform usampler2D uFeatEdges;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uCount) return;
    SgFeatResult r = sgFeatSample(uFeatCorners, uFeatEdges, vec2(inData[2u * i], inData[2u * i + 1u]));
    outData[4u * i] = r.dist;
    outData[4u * i + 1u] = r.grad.x;
    outData[4u * i + 2u] = r.grad.y;
    outData[4u * i + 3u] = r.side;
}
