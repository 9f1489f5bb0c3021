// Record input and output of the transform-feedback entries
// (sg/eval/eval.vert.glsl, sg/features/kernels.vert.glsl) for the dialects
// without compute shaders, GLSL 3.30 and GLSL ES 3.00, as
// sg::gl::runTransformFeedback feeds and captures them: record float k is
// component k % 4 of attribute k / 4 (up to 32 floats, eight vec4s), result
// float k is component k % 4 of output vOut<k / 4> (up to 12 floats, three
// vec4s; the host captures as many of them as its record needs).
// glsl-targets: glsl330 es300 (the entries exist for them)
#ifndef SG_EVAL_FEEDBACK_VERT_GLSL
#define SG_EVAL_FEEDBACK_VERT_GLSL

#define SG_FEEDBACK_MAX_IN 32
#define SG_FEEDBACK_MAX_OUT 12

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
out vec4 vOut2;

// The record's attributes as one array, and the results being written.
vec4 sgFeedbackIn[8];
vec4 sgFeedbackOut[3];

void sgFeedbackLoad() {
    sgFeedbackIn = vec4[8](aIn0, aIn1, aIn2, aIn3, aIn4, aIn5, aIn6, aIn7);
    sgFeedbackOut = vec4[3](vec4(0.0f), vec4(0.0f), vec4(0.0f));
}
float sgFeedbackRead(int k) { return sgFeedbackIn[k / 4][k % 4]; }
void sgFeedbackWrite(int k, float v) { sgFeedbackOut[k / 4][k % 4] = v; }
void sgFeedbackStore() {
    vOut0 = sgFeedbackOut[0];
    vOut1 = sgFeedbackOut[1];
    vOut2 = sgFeedbackOut[2];
    gl_Position = vec4(0.0f, 0.0f, 0.0f, 1.0f);
}

#endif
