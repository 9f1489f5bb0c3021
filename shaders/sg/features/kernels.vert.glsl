// Transform-feedback entry of the feature-curve evaluation kernels
// (kernels.glsl) for the dialects without compute shaders, GLSL 3.30 and
// GLSL ES 3.00 (sg::gl::runTransformFeedback): one vertex per record, its
// SG_FEAT_EVAL_IN floats in and SG_FEAT_EVAL_OUT results out through
// sg/eval/feedback.vert.glsl. SG_FEAT_EVAL_KERNEL (a define set by the host)
// selects the function, as in kernels.comp.glsl.
// glslang-validate: SG_FEAT_EVAL_KERNEL 0
// glsl-targets: glsl330 es300 (this entry exists for them; GL 4.5 runs
// kernels.comp.glsl)
// The kernels include the near field's functions.
#define SG_FEAT_NEAR 1
#include "sg/features/kernels.glsl"
#include "sg/eval/feedback.vert.glsl"

#if SG_FEAT_EVAL_IN > SG_FEEDBACK_MAX_IN || SG_FEAT_EVAL_OUT > SG_FEEDBACK_MAX_OUT
#error "kernels.vert.glsl: the record does not fit sg/eval/feedback.vert.glsl"
#endif

void main() {
    sgFeedbackLoad();
    SgFeatEvalIn x;
    for (int k = 0; k < SG_FEAT_EVAL_IN; ++k) x.v[k] = sgFeedbackRead(k);
    SgFeatEvalOut y = sgFeatEvalKernel(SG_FEAT_EVAL_KERNEL, x);
    for (int k = 0; k < SG_FEAT_EVAL_OUT; ++k) sgFeedbackWrite(k, y.v[k]);
    sgFeedbackStore();
}
