// Transform-feedback entry of the evaluation kernels (kernels.glsl) for the
// dialects without compute shaders, GLSL 3.30 and GLSL ES 3.00
// (sg::gl::runTransformFeedback): one vertex per record, its SG_EVAL_IN
// floats in and SG_EVAL_OUT results out through sg/eval/feedback.vert.glsl.
// SG_EVAL_KERNEL (a define set by the host) selects the function, as in
// eval.comp.glsl.
// glslang-validate: SG_EVAL_KERNEL 0
// glsl-targets: glsl330 es300 (this entry exists for them; Vulkan and GL 4.5
// run eval.comp.glsl)
#include "sg/eval/kernels.glsl"
#include "sg/eval/feedback.vert.glsl"

#if SG_EVAL_IN > SG_FEEDBACK_MAX_IN || SG_EVAL_OUT > SG_FEEDBACK_MAX_OUT
#error "eval.vert.glsl: the record does not fit sg/eval/feedback.vert.glsl"
#endif

void main() {
    sgFeedbackLoad();
    SgEvalIn x;
    for (int k = 0; k < SG_EVAL_IN; ++k) x.v[k] = sgFeedbackRead(k);
    SgEvalOut y = sgEvalKernel(SG_EVAL_KERNEL, x);
    for (int k = 0; k < SG_EVAL_OUT; ++k) sgFeedbackWrite(k, y.v[k]);
    sgFeedbackStore();
}
