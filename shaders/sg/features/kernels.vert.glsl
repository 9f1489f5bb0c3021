// Transform-feedback entry of the feature-curve evaluation kernels
// (kernels.glsl) for the dialects without compute shaders, GLSL 3.30 and
// GLSL ES 3.00 (sg::gl::runTransformFeedback): one vertex per record, the
// record's SG_FEAT_EVAL_IN floats in eight vec4 attributes, its
// SG_FEAT_EVAL_OUT results in two captured vec4 outputs. SG_FEAT_EVAL_KERNEL
// (a define set by the host) selects the function, as in kernels.comp.glsl.
// glslang-validate: SG_FEAT_EVAL_KERNEL 0
// glsl-targets: glsl330 es300 (this entry exists for them; GL 4.5 runs
// kernels.comp.glsl)
// The kernels include the near field's functions.
#define SG_FEAT_NEAR 1
#include "sg/features/kernels.glsl"

#if SG_FEAT_EVAL_IN > 32 || SG_FEAT_EVAL_OUT > 8
#error "kernels.vert.glsl: widen the attribute and output lists to the record sizes"
#endif

layout(location = 0) in vec4 aIn0;
layout(location = 1) in vec4 aIn1;
layout(location = 2) in vec4 aIn2;
layout(location = 3) in vec4 aIn3;
layout(location = 4) in vec4 aIn4;
layout(location = 5) in vec4 aIn5;
layout(location = 6) in vec4 aIn6;
layout(location = 7) in vec4 aIn7;
out vec4 vOut0;
out vec4 vOut1;

void main() {
    vec4 a[8] = vec4[8](aIn0, aIn1, aIn2, aIn3, aIn4, aIn5, aIn6, aIn7);
    SgFeatEvalIn x;
    for (int k = 0; k < SG_FEAT_EVAL_IN; ++k) x.v[k] = a[k / 4][k % 4];
    SgFeatEvalOut y = sgFeatEvalKernel(SG_FEAT_EVAL_KERNEL, x);
    vec4 o[2] = vec4[2](vec4(0.0f), vec4(0.0f));
    for (int k = 0; k < SG_FEAT_EVAL_OUT; ++k) o[k / 4][k % 4] = y.v[k];
    vOut0 = o[0];
    vOut1 = o[1];
    gl_Position = vec4(0.0f, 0.0f, 0.0f, 1.0f);
}
