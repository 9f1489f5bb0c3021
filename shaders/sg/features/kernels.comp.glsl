// Compute entry of the feature-curve evaluation kernels (kernels.glsl): one
// invocation per record; SG_FEAT_EVAL_KERNEL (a define set by the host)
// selects the function.
// glslang-validate: SG_FEAT_EVAL_KERNEL 0
// The kernels include the near field's functions.
#define SG_FEAT_NEAR 1
#include "sg/features/kernels.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer EvalInput { float inData[]; };
layout(std430, binding = 1) writeonly buffer EvalOutput { float outData[]; };
uniform uint uCount;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= uCount) return;
    SgFeatEvalIn x;
    for (int k = 0; k < SG_FEAT_EVAL_IN; ++k) x.v[k] = inData[i * uint(SG_FEAT_EVAL_IN) + uint(k)];
    SgFeatEvalOut y = sgFeatEvalKernel(SG_FEAT_EVAL_KERNEL, x);
    for (int k = 0; k < SG_FEAT_EVAL_OUT; ++k) outData[i * uint(SG_FEAT_EVAL_OUT) + uint(k)] = y.v[k];
}
