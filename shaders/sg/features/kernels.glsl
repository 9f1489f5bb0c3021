// Evaluation kernels of the feature-curve functions: one entry point per
// shared function, reading its arguments from a flat float record and
// writing its results to another. The SAME kernels run on the CPU
// (sg::features::evalKernelCpu, surfgrad/features/feature_maps.h) and in a compute
// shader (kernels.comp.glsl via sg::gl::runCompute), which the CPU/GPU
// parity test (tests/features/maps_gpu_test.cpp) compares, kernel by kernel.
//
// ONE DECLARATION PER KERNEL (the convention of sg/record.glsl): the list
// SG_FEAT_KERNELS below has one entry per kernel,
//   X(name, id, function, IN, OUT, tolerance, reason, inputs)
//     name       its name in the C++ table (sg::features::kernels())
//     id         SG_FEAT_K_* (the dispatch below; the compute define)
//     function   SgFeatEvalOut function(SgFeatEvalIn sgRecIn)
//     IN, OUT    its field lists: the record layouts, in order
//     tolerance  the largest CPU/GPU difference the parity test accepts,
//                max over outputs of |cpu - gpu| / max(1, |cpu|)
//     reason     why that tolerance (a string)
//     inputs     the C++ generator of its parity records
//                (features/src/kernel_inputs.cpp)
// and the GLSL dispatch, the C++ table (names, slots, docs, tolerances) and
// the parity test are all expanded from it.
#ifndef SG_FEATURES_KERNELS_GLSL
#define SG_FEATURES_KERNELS_GLSL

#include "sg/record.glsl"
#include "sg/features/evaluate.glsl"
#include "sg/features/profile.glsl"
#include "sg/features/near.glsl"

#define SG_FEAT_EVAL_IN 32
#define SG_FEAT_EVAL_OUT 8

struct SgFeatEvalIn {
    float v[SG_FEAT_EVAL_IN];
};
struct SgFeatEvalOut {
    float v[SG_FEAT_EVAL_OUT];
};
SG_REC_DEFINE_IO(SgFeatEvalIn, SgFeatEvalOut, SG_FEAT_EVAL_OUT)

// ---------------------------------------------------------------------------
// eval: sgFeatEval on one texel (evaluate.glsl).
#define SG_FEAT_K_EVAL 0
#define SG_FEAT_EVAL_IN_FIELDS(F)                                                                     \
    F(vec4, cornerDist, ("distance at corners SW, SE, NE, NW (texels, non-negative)"))                         \
    F(vec2, grad0, ("gradient sample at SW (length at most 1)"))                                            \
    F(vec2, grad1, ("gradient sample at SE"))                                                          \
    F(vec2, grad2, ("gradient sample at NE"))                                                          \
    F(vec2, grad3, ("gradient sample at NW"))                                                          \
    F(uint, cfg, ("configuration word (layout.glsl)"))                                                 \
    F(uint, edgeS, ("edge word of edge S (layout.glsl)"))                                              \
    F(uint, edgeE, ("edge word of edge E"))                                                            \
    F(uint, edgeN, ("edge word of edge N"))                                                            \
    F(uint, edgeW, ("edge word of edge W"))                                                            \
    F(vec2, local, ("texel-local point in [0, 1]^2"))
#define SG_FEAT_EVAL_OUT_FIELDS(F)                                                                    \
    F(float, dist, ("reconstructed distance (texels)"))                                                \
    F(vec2, grad, ("unit gradient, texel space"))                                                      \
    F(float, side, ("+1 left of the nearest curve, else -1"))

SG_FN SgFeatEvalOut sgFeatKernelEval(SgFeatEvalIn sgRecIn) {
    SG_REC_READ(SG_FEAT_EVAL_IN_FIELDS)
    SgFeatTexel tx;
    tx.dist = cornerDist;
    tx.grad0 = grad0;
    tx.grad1 = grad1;
    tx.grad2 = grad2;
    tx.grad3 = grad3;
    tx.cfg = cfg;
    tx.edges = uvec4(edgeS, edgeE, edgeN, edgeW);
    SgFeatResult r = sgFeatEval(tx, local);
    SG_REC_DECLARE(SG_FEAT_EVAL_OUT_FIELDS)
    dist = r.dist;
    grad = r.grad;
    side = r.side;
    SG_REC_RETURN(SgFeatEvalOut, SG_FEAT_EVAL_OUT_FIELDS)
}

// ---------------------------------------------------------------------------
// profile: the profile and its two compositions (profile.glsl).
#define SG_FEAT_K_PROFILE 1
#define SG_FEAT_PROFILE_IN_FIELDS(F)                                                                  \
    F(float, dist, ("distance d (texels)"))                                                            \
    F(vec2, grad, ("unit gradient of d"))                                                              \
    F(float, side, ("+1 left of the curve, -1 right"))                                                 \
    F(int, kind, ("SG_FEAT_PROFILE_*"))                                                                \
    F(float, depth, ("depth D (texels)"))                                                              \
    F(float, w0, ("blend start (texels)"))                                                             \
    F(float, w, ("profile half-width (texels)"))                                                       \
    F(int, tableCount, ("table heights used (2..16)"))                                                 \
    F(vec4, table0, ("table heights 0-3 (units of D)"))                                                \
    F(vec4, table1, ("table heights 4-7"))                                                             \
    F(vec4, table2, ("table heights 8-11"))                                                            \
    F(vec4, table3, ("table heights 12-15"))                                                           \
    F(vec2, baseDeriv, ("texture-space derivative of the base layer"))                                      \
    F(vec3, baseNormal, ("unit tangent-space normal of the base layer"))
#define SG_FEAT_PROFILE_OUT_FIELDS(F)                                                                 \
    F(vec2, deriv, ("sgFeatDeriv (surfgrad composition)"))                                             \
    F(vec3, normal, ("sgFeatNormalPaper (Eq. 1 composition)"))                                         \
    F(float, height, ("h(d), texels"))                                                                 \
    F(float, slope, ("slope dh/dd"))                                                                         \
    F(float, blend, ("b(d)"))

SG_FN SgFeatEvalOut sgFeatKernelProfile(SgFeatEvalIn sgRecIn) {
    SG_REC_READ(SG_FEAT_PROFILE_IN_FIELDS)
    SgFeatResult r;
    r.dist = dist;
    r.grad = grad;
    r.side = side;
    r.profile = -1;
    r.width = 0.0f;
    SgFeatProfile pr;
    pr.kind = kind;
    pr.depth = depth;
    pr.w0 = w0;
    pr.w = w;
    pr.tableCount = tableCount;
    for (int i = 0; i < 4; ++i) {
        pr.table[i] = table0[i];
        pr.table[4 + i] = table1[i];
        pr.table[8 + i] = table2[i];
        pr.table[12 + i] = table3[i];
    }
    SG_REC_DECLARE(SG_FEAT_PROFILE_OUT_FIELDS)
    deriv = sgFeatDeriv(r, pr, baseDeriv);
    normal = sgFeatNormalPaper(r, pr, baseNormal);
    vec2 hs = sgFeatProfileHeightSlope(pr, r.dist, r.side);
    height = hs.x;
    slope = hs.y;
    blend = sgFeatBlend(pr, r.dist);
    SG_REC_RETURN(SgFeatEvalOut, SG_FEAT_PROFILE_OUT_FIELDS)
}

// ---------------------------------------------------------------------------
// near-piece: the exact closest point of one piece (near.glsl), compiled
// with the near field (kernels compile with SG_FEAT_NEAR 1, see
// kernels.comp.glsl).
#define SG_FEAT_K_NEAR_PIECE 2
#define SG_FEAT_NEAR_PIECE_IN_FIELDS(F)                                                               \
    F(vec2, p0, ("first control point (texels)"))                                                    \
    F(vec2, p1, ("middle control point"))                                                            \
    F(vec2, p2, ("last control point"))                                                              \
    F(bool, curved, ("quadratic (else the line p0 p2)"))                                             \
    F(vec2, query, ("the query point (texels)"))
#define SG_FEAT_NEAR_PIECE_OUT_FIELDS(F)                                                              \
    F(float, dist, ("distance to the piece (texels)"))                                               \
    F(vec2, grad, ("unit gradient of the distance"))                                                 \
    F(float, side, ("+1 left of the piece, else -1"))

SG_FN SgFeatEvalOut sgFeatKernelNearPiece(SgFeatEvalIn sgRecIn) {
    SG_REC_READ(SG_FEAT_NEAR_PIECE_IN_FIELDS)
    SG_REC_DECLARE(SG_FEAT_NEAR_PIECE_OUT_FIELDS)
#if SG_FEAT_NEAR
    SgFeatPiece c;
    c.p0 = p0;
    c.p1 = p1;
    c.p2 = p2;
    c.curved = curved;
    c.profile = -1;
    c.width0 = 0.0f;
    c.width1 = 0.0f;
    SgFeatResult r = sgFeatNearResult(sgFeatClosestOnPiece(c, query), c);
    dist = r.dist;
    grad = r.grad;
    side = r.side;
#else
    dist = 0.0f;
    grad = sgVec2(0.0f);
    side = 0.0f;
#endif
    SG_REC_RETURN(SgFeatEvalOut, SG_FEAT_NEAR_PIECE_OUT_FIELDS)
}

// ---------------------------------------------------------------------------
// The kernel list.
#define SG_FEAT_KERNELS(X)                                                                            \
    X(eval, SG_FEAT_K_EVAL, sgFeatKernelEval, SG_FEAT_EVAL_IN_FIELDS, SG_FEAT_EVAL_OUT_FIELDS, 1e-4,  \
      ("binary32 in both builds; they differ by FMA contraction and library sqrt/inversesqrt (a few "  \
      "ulps, measured 4e-7 on d and the gradient); records within 1e-3 texels of a curve, where the " \
      "side is decided by rounding, are not generated"),                                               \
      kernelInputsEval)                                                                               \
    X(profile, SG_FEAT_K_PROFILE, sgFeatKernelProfile, SG_FEAT_PROFILE_IN_FIELDS,                     \
      SG_FEAT_PROFILE_OUT_FIELDS, 1e-5,                                                               \
      ("polynomials, sin/cos and one sqrt/normalize in binary32: a few ulps of values up to ~10 "      \
      "(slopes 2 D / w)"),                                                                             \
      kernelInputsProfile)                                                                            \
    X(near_piece, SG_FEAT_K_NEAR_PIECE, sgFeatKernelNearPiece, SG_FEAT_NEAR_PIECE_IN_FIELDS,          \
      SG_FEAT_NEAR_PIECE_OUT_FIELDS, 1e-4,                                                            \
      ("binary32 Newton iterations on both builds (FMA contraction would move the foot point by "   \
      "ulps; measured 0, bit-identical on llvmpipe); "                                                \
      "records within 1e-3 texels of the piece, with two near-equal minima, or near a centre of "     \
      "curvature (where the foot point is ill-conditioned) are not generated"),                       \
      kernelInputsNearPiece)
#define SG_FEAT_K_COUNT 3

#define SG_FEAT_KERNEL_DISPATCH(name, id, function, IN, OUT, tolerance, reason, inputs)              \
    if (kernel == id) return function(x);

SG_FN SgFeatEvalOut sgFeatEvalKernel(int kernel, SgFeatEvalIn x) {
    SG_FEAT_KERNELS(SG_FEAT_KERNEL_DISPATCH)
    SgFeatEvalOut y;
    sgRecClear(y);
    return y;
}

#endif
