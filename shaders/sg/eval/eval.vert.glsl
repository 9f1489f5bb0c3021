// Transform-feedback entry of the evaluation kernels (kernels.glsl) for the
// dialects without compute shaders, GLSL 3.30 and GLSL ES 3.00
// (sg::gl::runTransformFeedback): one vertex per record, the record's
// SG_EVAL_IN floats in seven vec4 attributes, its SG_EVAL_OUT results in
// three captured vec4 outputs. SG_EVAL_KERNEL (a define set by the host)
// selects the function, as in eval.comp.glsl.
// glslang-validate: SG_EVAL_KERNEL 0
// glsl-targets: glsl330 es300 (this entry exists for them; Vulkan and GL 4.5
// run eval.comp.glsl)
#include "sg/eval/kernels.glsl"

#if SG_EVAL_IN > 28 || SG_EVAL_OUT > 12
#error "eval.vert.glsl: widen the attribute and output lists to the record sizes"
#endif

layout(location = 0) in vec4 aIn0;
layout(location = 1) in vec4 aIn1;
layout(location = 2) in vec4 aIn2;
layout(location = 3) in vec4 aIn3;
layout(location = 4) in vec4 aIn4;
layout(location = 5) in vec4 aIn5;
layout(location = 6) in vec4 aIn6;
out vec4 vOut0;
out vec4 vOut1;
out vec4 vOut2;

void main() {
    vec4 a[7] = vec4[7](aIn0, aIn1, aIn2, aIn3, aIn4, aIn5, aIn6);
    SgEvalIn x;
    for (int k = 0; k < SG_EVAL_IN; ++k) x.v[k] = a[k / 4][k % 4];
    SgEvalOut y = sgEvalKernel(SG_EVAL_KERNEL, x);
    vec4 o[3] = vec4[3](vec4(0.0f), vec4(0.0f), vec4(0.0f));
    for (int k = 0; k < SG_EVAL_OUT; ++k) o[k / 4][k % 4] = y.v[k];
    vOut0 = o[0];
    vOut1 = o[1];
    vOut2 = o[2];
    gl_Position = vec4(0.0f, 0.0f, 0.0f, 1.0f);
}
