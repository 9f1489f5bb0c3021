// HLSL compute entry of the evaluation kernels (kernels.glsl), the HLSL
// twin of eval.comp.glsl: one thread per record; SG_EVAL_KERNEL (a define
// set by the host) selects the function. The parity suite compiles it with
// glslang's HLSL front end to SPIR-V, translates that to GLSL 4.50 with
// SPIRV-Cross and runs it beside the C++ build (docs/engines.md, "HLSL"), so
// the numbers of the HLSL spelling of the shared source are checked.
// The record count is the output buffer's length (no constant buffer: the
// harness binds the two buffers and nothing else).
// glslang-validate: SG_EVAL_KERNEL 0
#include "sg/compat.hlsl"
#include "sg/eval/kernels.glsl"

[[vk::binding(0)]] StructuredBuffer<float> inData : register(t0);
[[vk::binding(1)]] RWStructuredBuffer<float> outData : register(u1);

[numthreads(64, 1, 1)] void main(uint3 threadId : SV_DispatchThreadID) {
    uint outFloats;
    uint strideBytes;
    outData.GetDimensions(outFloats, strideBytes);
    uint i = threadId.x;
    if (i >= outFloats / uint(SG_EVAL_OUT)) return;
    SgEvalIn x;
    for (int k = 0; k < SG_EVAL_IN; ++k) x.v[k] = inData[i * uint(SG_EVAL_IN) + uint(k)];
    SgEvalOut y = sgEvalKernel(SG_EVAL_KERNEL, x);
    for (int k = 0; k < SG_EVAL_OUT; ++k) outData[i * uint(SG_EVAL_OUT) + uint(k)] = y.v[k];
}
