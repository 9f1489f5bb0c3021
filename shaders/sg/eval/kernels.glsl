// Evaluation kernels: one entry point per shared function, reading its
// arguments from a flat float record and writing its results to another.
// The SAME kernels run on the CPU (bump/include/surfgrad/eval_kernels.h)
// and in a compute shader (gl/ compute harness), which is what the CPU/GPU
// parity suite, `surfgrad selftest` and `surfgrad eval [--gpu]` compare.
// Record layouts (which slot holds which argument) are listed in
// bump/src/eval_table.cpp next to the JSON keys; keep them in step.
#ifndef SG_EVAL_KERNELS_GLSL
#define SG_EVAL_KERNELS_GLSL

#include "sg/surfgrad.glsl"
#include "sg/deriv_edit.glsl"

#define SG_EVAL_IN 28
#define SG_EVAL_OUT 12

struct SgEvalIn {
    float v[SG_EVAL_IN];
};
struct SgEvalOut {
    float v[SG_EVAL_OUT];
};

SG_FN vec2 sgIn2(SgEvalIn x, int i) { return vec2(x.v[i], x.v[i + 1]); }
SG_FN vec3 sgIn3(SgEvalIn x, int i) { return vec3(x.v[i], x.v[i + 1], x.v[i + 2]); }
SG_FN vec4 sgIn4(SgEvalIn x, int i) { return vec4(x.v[i], x.v[i + 1], x.v[i + 2], x.v[i + 3]); }
SG_FN bool sgInBool(SgEvalIn x, int i) { return x.v[i] != 0.0f; }
SG_FN void sgOut1(SG_INOUT(SgEvalOut) y, int i, float a) { y.v[i] = a; }
SG_FN void sgOut2(SG_INOUT(SgEvalOut) y, int i, vec2 a) {
    y.v[i] = a.x;
    y.v[i + 1] = a.y;
}
SG_FN void sgOut3(SG_INOUT(SgEvalOut) y, int i, vec3 a) {
    y.v[i] = a.x;
    y.v[i + 1] = a.y;
    y.v[i + 2] = a.z;
}

// A frame for kernels that take {n, dpdx, dpdy}: front-facing, mode NONE,
// so nrmBase = normalize(n) and the sigmas/flip sign follow listing 16.
SG_FN SgFrame sgEvalFrame(vec3 n, vec3 dPdx, vec3 dPdy) {
    return sgPrologue(n, dPdx, dPdy, true, SG_BFACE_NONE);
}
SG_FN SgFrame sgEvalFrameN(vec3 n) { return sgEvalFrame(n, vec3(0.0f), vec3(0.0f)); }

#define SG_K_RESOLVE 0
#define SG_K_TSPACE_TO_DERIV 1
#define SG_K_TBN 2
#define SG_K_BASIS 3
#define SG_K_PERTURBED 4
#define SG_K_SCALE_DEPENDENT 5
#define SG_K_VOLUME 6
#define SG_K_TRIPLANAR_WEIGHTS 7
#define SG_K_TRIPLANAR 8
#define SG_K_DECAL 9
#define SG_K_PROLOGUE 10
#define SG_K_MIKKTS_BASIS 11
#define SG_K_SCREEN_DERIV_OF_POS 12
#define SG_K_PARALLAX_PROJECT 13
#define SG_K_TEXOFFS_TO_SURFACE 14
#define SG_K_SCREEN_DERIV_SURFGRAD 15
#define SG_K_DERIV_TO_TSPACE 16
#define SG_K_REPROLOGUE 17
#define SG_K_BUMP_SCALE 18
#define SG_K_DERIV_SCALE 19
#define SG_K_DERIV_BLEND 20
#define SG_K_DERIV_MODULATE 21
#define SG_K_DERIV_CURVE 22
#define SG_K_DERIV_DEFORM 23
#define SG_K_DERIV_SINE_WARP 24
#define SG_K_DECAL_VOLUME 25
#define SG_K_HEIGHT_3TAP 26
#define SG_K_BOUNDED_SCALE 27
#define SG_K_COUNT 28

SG_FN void sgEvalFrameOut(SG_INOUT(SgEvalOut) y, SgFrame f) {
    sgOut3(y, 0, f.nrmBase);
    sgOut3(y, 3, f.sigmaX);
    sgOut3(y, 6, f.sigmaY);
    sgOut1(y, 9, f.flipSign);
    sgOut1(y, 10, f.resolveSign);
}

SG_FN SgEvalOut sgEvalKernel(int kernel, SgEvalIn x) {
    SgEvalOut y;
    for (int i = 0; i < SG_EVAL_OUT; ++i) y.v[i] = 0.0f;
    if (kernel == SG_K_RESOLVE) {
        SgFrame f = sgEvalFrameN(sgIn3(x, 0));
        f.resolveSign = x.v[6] < 0.0f ? -1.0f : 1.0f;
        sgOut3(y, 0, sgResolve(f, sgIn3(x, 3)));
    } else if (kernel == SG_K_TSPACE_TO_DERIV) {
        sgOut2(y, 0, sgTspaceNormalToDeriv(sgIn2(x, 0), sgInBool(x, 2)));
    } else if (kernel == SG_K_TBN) {
        sgOut3(y, 0, sgSurfgradFromTBN(sgIn2(x, 0), sgIn3(x, 2), sgIn3(x, 5)));
    } else if (kernel == SG_K_BASIS) {
        SgFrame f = sgEvalFrame(sgIn3(x, 0), sgIn3(x, 3), sgIn3(x, 6));
        vec3 t;
        vec3 b;
        sgGenBasisTB(f, sgIn2(x, 9), sgIn2(x, 11), t, b);
        sgOut3(y, 0, t);
        sgOut3(y, 3, b);
    } else if (kernel == SG_K_PERTURBED) {
        sgOut3(y, 0, sgSurfgradFromPerturbedNormal(sgEvalFrameN(sgIn3(x, 0)), sgIn3(x, 3)));
    } else if (kernel == SG_K_SCALE_DEPENDENT) {
        SgFrame f = sgEvalFrame(sgIn3(x, 0), sgIn3(x, 3), sgIn3(x, 6));
        sgOut3(y, 0, sgSurfgradScaleDependent(f, sgIn2(x, 9), sgIn2(x, 11), sgIn2(x, 13),
                                              sgIn2(x, 15)));
    } else if (kernel == SG_K_VOLUME) {
        sgOut3(y, 0, sgSurfgradFromVolumeGradient(sgEvalFrameN(sgIn3(x, 0)), sgIn3(x, 3)));
    } else if (kernel == SG_K_TRIPLANAR_WEIGHTS) {
        sgOut3(y, 0, sgTriplanarWeights(sgIn3(x, 0), x.v[3]));
    } else if (kernel == SG_K_TRIPLANAR) {
        SgFrame f = sgEvalFrameN(sgIn3(x, 0));
        vec3 w = sgTriplanarWeights(f.nrmBase, x.v[3]);
        sgOut3(y, 0, sgSurfgradFromTriplanar(f, w, sgIn2(x, 4), sgIn2(x, 6), sgIn2(x, 8),
                                             sgInBool(x, 10), sgInBool(x, 11)));
    } else if (kernel == SG_K_DECAL) {
        sgOut3(y, 0, sgSurfgradFromDecal(sgEvalFrameN(sgIn3(x, 0)), sgIn2(x, 3), sgIn3(x, 5),
                                         sgIn3(x, 8), sgInBool(x, 11)));
    } else if (kernel == SG_K_PROLOGUE) {
        SgFrame f = sgPrologue(sgIn3(x, 0), sgIn3(x, 3), sgIn3(x, 6), sgInBool(x, 9),
                               int(x.v[10]));
        sgEvalFrameOut(y, f);
    } else if (kernel == SG_K_MIKKTS_BASIS) {
        vec3 t;
        vec3 b;
        sgMikktsBasis(sgIn3(x, 0), sgIn4(x, 3), t, b);
        sgOut3(y, 0, t);
        sgOut3(y, 3, b);
    } else if (kernel == SG_K_SCREEN_DERIV_OF_POS) {
        mat4 m = mat4(sgIn4(x, 6), sgIn4(x, 10), sgIn4(x, 14), sgIn4(x, 18));
        vec3 dx;
        vec3 dy;
        sgScreenDerivOfPos(dx, dy, sgIn3(x, 0), sgIn3(x, 3), m, x.v[22], x.v[23]);
        sgOut3(y, 0, dx);
        sgOut3(y, 3, dy);
    } else if (kernel == SG_K_PARALLAX_PROJECT) {
        SgFrame f = sgEvalFrame(sgIn3(x, 0), sgIn3(x, 3), sgIn3(x, 6));
        sgOut2(y, 0, sgProjectVecToTextureSpace(f, sgIn3(x, 9), sgIn2(x, 12), sgIn2(x, 14),
                                                x.v[16], sgInBool(x, 17)));
    } else if (kernel == SG_K_TEXOFFS_TO_SURFACE) {
        SgFrame f = sgEvalFrame(sgIn3(x, 0), sgIn3(x, 3), sgIn3(x, 6));
        sgOut3(y, 0, sgTexSpaceOffsToSurface(f, sgIn2(x, 9), sgIn2(x, 11), sgIn2(x, 13)));
    } else if (kernel == SG_K_SCREEN_DERIV_SURFGRAD) {
        SgFrame f = sgEvalFrame(sgIn3(x, 0), sgIn3(x, 3), sgIn3(x, 6));
        sgOut3(y, 0, sgSurfgradFromScreenDeriv(f, sgIn2(x, 9)));
    } else if (kernel == SG_K_DERIV_TO_TSPACE) {
        sgOut3(y, 0, sgDerivToTspaceNormal(sgIn2(x, 0), sgInBool(x, 2)));
    } else if (kernel == SG_K_REPROLOGUE) {
        SgFrame f = sgPrologue(sgIn3(x, 0), sgIn3(x, 3), sgIn3(x, 6), sgInBool(x, 9),
                               int(x.v[10]));
        f = sgReprologue(f, sgIn3(x, 11), sgIn3(x, 3), sgIn3(x, 6));
        sgEvalFrameOut(y, f);
    } else if (kernel == SG_K_BUMP_SCALE) {
        sgOut3(y, 0, sgBumpScale(x.v[0], sgIn3(x, 1)));
    } else if (kernel == SG_K_DERIV_SCALE) {
        sgOut2(y, 0, sgDerivScale(sgIn2(x, 0), x.v[2]));
    } else if (kernel == SG_K_DERIV_BLEND) {
        vec2 d[SG_DERIV_MAX_LAYERS];
        float w[SG_DERIV_MAX_LAYERS];
        for (int i = 0; i < SG_DERIV_MAX_LAYERS; ++i) {
            d[i] = vec2(0.0f);
            w[i] = 0.0f;
        }
        for (int i = 0; i < 4; ++i) {
            d[i] = sgIn2(x, 1 + 2 * i);
            w[i] = x.v[9 + i];
        }
        sgOut2(y, 0, sgDerivBlend(d, w, min(int(x.v[0]), 4)));
    } else if (kernel == SG_K_DERIV_MODULATE) {
        sgOut2(y, 0, sgDerivModulate(sgIn2(x, 0), x.v[2], sgIn2(x, 3), x.v[5]));
    } else if (kernel == SG_K_DERIV_CURVE) {
        float slope = sgCurveBoostSlope(x.v[2], x.v[3], x.v[4]);
        sgOut2(y, 0, sgDerivCurve(sgIn2(x, 0), slope));
        sgOut1(y, 2, sgCurveBoostValue(x.v[2], x.v[3], x.v[4]));
    } else if (kernel == SG_K_DERIV_DEFORM) {
        mat2 j = mat2(sgIn2(x, 2), sgIn2(x, 4));
        sgOut2(y, 0, sgDerivDeform(sgIn2(x, 0), j));
    } else if (kernel == SG_K_DERIV_SINE_WARP) {
        sgOut2(y, 0, sgDerivDeform(sgIn2(x, 0), sgSineWarpJacobian(x.v[2], x.v[3], x.v[4])));
    } else if (kernel == SG_K_DECAL_VOLUME) {
        sgOut3(y, 0, sgDecalVolumeGradient(sgIn2(x, 0), sgIn3(x, 2), sgIn3(x, 5), sgInBool(x, 8)));
    } else if (kernel == SG_K_BOUNDED_SCALE) {
        sgOut3(y, 0, sgBoundedScale3(sgIn3(x, 0), abs(sgIn4(x, 3))));
    } else if (kernel == SG_K_HEIGHT_3TAP) {
        sgOut2(y, 0, sgHeightDeriv3Tap(x.v[0], x.v[1], x.v[2]));
    }
    return y;
}

#endif
