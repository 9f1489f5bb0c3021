// HLSL compute entry of the feature-curve evaluation kernels
// (sg/features/kernels.glsl, with the near field's functions), the HLSL twin
// of kernels.comp.glsl: one thread per record; SG_FEAT_EVAL_KERNEL (a define
// set by the host) selects the function. The feature-kernel tests compile it
// with glslang's HLSL front end to SPIR-V, translate that to GLSL 4.50 with
// SPIRV-Cross and run it beside the C++ build (docs/engines.md, "HLSL").
// The record count is the output buffer's length (no constant buffer: the
// harness binds the two buffers and nothing else).
// glslang-validate: SG_FEAT_EVAL_KERNEL 0
#include "sg/compat.hlsl"
#define SG_FEAT_NEAR 1
#include "sg/features/kernels.glsl"

[[vk::binding(0)]] StructuredBuffer<float> inData : register(t0);
[[vk::binding(1)]] RWStructuredBuffer<float> outData : register(u1);

[numthreads(64, 1, 1)] void main(uint3 threadId : SV_DispatchThreadID) {
    uint outFloats;
    uint strideBytes;
    outData.GetDimensions(outFloats, strideBytes);
    uint i = threadId.x;
    if (i >= outFloats / uint(SG_FEAT_EVAL_OUT)) return;
    SgFeatEvalIn x;
    for (int k = 0; k < SG_FEAT_EVAL_IN; ++k) x.v[k] = inData[i * uint(SG_FEAT_EVAL_IN) + uint(k)];
    SgFeatEvalOut y = sgFeatEvalKernel(SG_FEAT_EVAL_KERNEL, x);
    for (int k = 0; k < SG_FEAT_EVAL_OUT; ++k) outData[i * uint(SG_FEAT_EVAL_OUT) + uint(k)] = y.v[k];
}
