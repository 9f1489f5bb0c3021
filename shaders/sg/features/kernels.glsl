// Evaluation kernels of the feature-curve functions: one entry point per
// shared function, reading its arguments from a flat float record and
// writing its results to another (the pattern of shaders/sg/eval/
// kernels.glsl). The SAME kernels run on the CPU (sg::features::evalKernelCpu
// in surfgrad/feature_maps.h) and in a compute shader (kernels.comp.glsl via
// sg::gl::runCompute), which the CPU/GPU parity tests compare. Record layouts
// are listed with each kernel id below.
#ifndef SG_FEATURES_KERNELS_GLSL
#define SG_FEATURES_KERNELS_GLSL

#include "sg/features/evaluate.glsl"
#include "sg/features/profile.glsl"

#define SG_FEAT_EVAL_IN 32
#define SG_FEAT_EVAL_OUT 8

struct SgFeatEvalIn {
    float v[SG_FEAT_EVAL_IN];
};
struct SgFeatEvalOut {
    float v[SG_FEAT_EVAL_OUT];
};

// sgFeatEval on one texel.
//  in:  0-3 corner distances SW, SE, NE, NW; 4-11 corner gradients
//       (SW.x, SW.y, SE.x, ..., NW.y); 12 configuration word (an exact
//       integer); 13-20 edge words S, E, N, W split into 16-bit halves
//       (low, high), each an exact integer 0..65535; 21-22 local point.
//  out: 0 distance, 1-2 unit gradient, 3 side.
#define SG_FEAT_K_EVAL 0
// Profile composition (profile.glsl).
//  in:  0 distance, 1-2 unit gradient, 3 side, 4 profile kind, 5 depth,
//       6 w0, 7 w, 8 table count, 9-24 table, 25-26 base derivative,
//       27-29 base tangent-space normal.
//  out: 0-1 sgFeatDeriv (surfgrad mode), 2-4 sgFeatNormalPaper (paper
//       mode), 5 height h(d), 6 slope h'(d), 7 blend b(d).
#define SG_FEAT_K_PROFILE 1
#define SG_FEAT_K_COUNT 2

SG_FN uint sgFeatInWord(SgFeatEvalIn x, int i) {
    return uint(max(x.v[i], 0.0f)) | (uint(max(x.v[i + 1], 0.0f)) << 16u);
}

SG_FN SgFeatEvalOut sgFeatEvalKernel(int kernel, SgFeatEvalIn x) {
    SgFeatEvalOut y;
    for (int i = 0; i < SG_FEAT_EVAL_OUT; ++i) y.v[i] = 0.0f;
    if (kernel == SG_FEAT_K_EVAL) {
        SgFeatTexel tx;
        tx.dist = vec4(x.v[0], x.v[1], x.v[2], x.v[3]);
        tx.grad0 = vec2(x.v[4], x.v[5]);
        tx.grad1 = vec2(x.v[6], x.v[7]);
        tx.grad2 = vec2(x.v[8], x.v[9]);
        tx.grad3 = vec2(x.v[10], x.v[11]);
        tx.cfg = uint(max(x.v[12], 0.0f));
        tx.edges = uvec4(sgFeatInWord(x, 13), sgFeatInWord(x, 15), sgFeatInWord(x, 17), sgFeatInWord(x, 19));
        SgFeatResult r = sgFeatEval(tx, vec2(x.v[21], x.v[22]));
        y.v[0] = r.dist;
        y.v[1] = r.grad.x;
        y.v[2] = r.grad.y;
        y.v[3] = r.side;
    } else if (kernel == SG_FEAT_K_PROFILE) {
        SgFeatResult r;
        r.dist = x.v[0];
        r.grad = vec2(x.v[1], x.v[2]);
        r.side = x.v[3];
        SgFeatProfile pr;
        pr.kind = int(x.v[4]);
        pr.depth = x.v[5];
        pr.w0 = x.v[6];
        pr.w = x.v[7];
        pr.tableCount = int(x.v[8]);
        for (int i = 0; i < SG_FEAT_TABLE_MAX; ++i) pr.table[i] = x.v[9 + i];
        vec2 deriv = sgFeatDeriv(r, pr, vec2(x.v[25], x.v[26]));
        vec3 n = sgFeatNormalPaper(r, pr, vec3(x.v[27], x.v[28], x.v[29]));
        vec2 hs = sgFeatProfileHeightSlope(pr, r.dist, r.side);
        y.v[0] = deriv.x;
        y.v[1] = deriv.y;
        y.v[2] = n.x;
        y.v[3] = n.y;
        y.v[4] = n.z;
        y.v[5] = hs.x;
        y.v[6] = hs.y;
        y.v[7] = sgFeatBlend(pr, r.dist);
    }
    return y;
}

#endif
