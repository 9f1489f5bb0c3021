// Evaluation kernels: one entry point per shared function, reading its
// arguments from a flat float record and writing its results to another.
// The SAME kernels run on the CPU (bump/include/surfgrad/bump/eval_kernels.h)
// and in a compute shader (eval.comp.glsl through gl/'s compute harness),
// which is what the CPU/GPU parity suite, `surfgrad selftest` and
// `surfgrad eval [--gpu]` compare.
//
// ONE DECLARATION PER FUNCTION (the convention of sg/record.glsl; the worked
// example is in docs/architecture.md, "Adding a shared function"). Each
// function below has one block:
//
//   SG_EVAL_<NAME>_IN(F), SG_EVAL_<NAME>_OUT(F)   its record layouts, as field
//       lists F(type, json_key, (doc, options)); the options are read by the
//       C++ table only (surfgrad/bump/eval_kernels.h): sgDefault(v) (the key may
//       be omitted), sgRange(lo, hi) (the values an int takes), and how the
//       parity records fill the field, sgGen* (default: a random vector of
//       random magnitude; eval_inputs.cpp);
//   sgEval<Name>(SgEvalIn sgRecIn)  the kernel: SG_REC_READ declares a local
//       per input field, the body calls the function and assigns a local per
//       output field (an output named like an input reuses its local), and
//       SG_REC_RETURN writes them;
//   SG_EVAL_<NAME>(X)  its entry:
//       X(name, id, kernel, IN, OUT, summary, measure, tolerance, illShare,
//         reason, inputs)
//       name       the entry's name (`surfgrad eval NAME`), a string
//       id         its kernel id, the list position (SG_EVAL_KERNEL of the
//                  compute program)
//       summary    what it computes, with the paper's listing
//       measure    Mixed: |gpu - cpu|_inf / max(1, |cpu|_inf) per output
//                  field; Relative: / |cpu|_inf (parity, parity.h)
//       tolerance  the largest measure the parity suite accepts on
//                  well-conditioned records
//       illShare   the largest share of records it may exclude as
//                  ill-conditioned or explained by backward error
//       reason     why these two numbers (a string)
//       inputs     how its parity records are made: fieldInputs (each field
//                  by its sgGen option, then the adversarial relations
//                  between n, dpdx, dpdy, dstdx, dstdy) or a generator of
//                  its own (bump/src/eval_inputs.cpp)
//
// and SG_EVAL_KERNELS at the end lists the blocks in id order. The GLSL
// dispatch (sgEvalKernel), the C++ table (sg::eval::entries(): names,
// layouts, slots, docs, JSON defaults and ranges, tolerances, generators)
// and the parity tests are all expanded from it.
//
// Strings in these macros are wrapped in parentheses and avoid < > # and
// quote characters (see sg/record.glsl).
//
// Tolerances. Measured with 100,000 records per function (seed 20261122) on
// Mesa 22.3 llvmpipe (LLVM 15, 256-bit) against GCC 12 -O3 on x86-64 (SSE,
// no FMA contraction). What makes two binary32 builds of one source differ
// on well-conditioned records:
//  - llvmpipe contracts a*b+c into FMAs where it likes (one rounding instead
//    of two: a difference of an ulp of the larger product, which grows by
//    the cancellation factor of the sum);
//  - llvmpipe's inversesqrt is 1/sqrt (correctly rounded sqrt, then a
//    division): within 1 ulp of GLM's 1/std::sqrt;
//  - llvmpipe's transcendental functions are polynomial approximations:
//    pow = exp2(k log2 x) (relative error grows with |k log2 x|), atan with a
//    relative error up to 2.1e-5 (measured: atan(1) = 0.78539485, atan(1e-10)
//    = 9.9998e-11), cos with range reduction in binary32;
//  - llvmpipe's vertex stage flushes denormals to zero and its compute
//    stage keeps them, like GPUs differ (the shared code decides every "is
//    it zero?" with SG_FLT_MIN and flushes denormal inputs where they could
//    decide a sign, so every build takes the same branch; the remaining
//    differences are below 1.2e-38 in absolute value). The GLSL 3.30 and
//    ES 3.00 suites run on the vertex stage (eval.vert.glsl), GLSL 4.50 on
//    the compute stage: the tolerances hold for both.
// A well-conditioned record (condition number below ~5 at tolerance 1e-5)
// should then agree to a few ulps times its cancellation: 1e-5 is ~80 ulps
// of an O(1) result, which no well-conditioned record comes near except
// where a transcendental function is involved (stated per function).
//
// Ill-conditioned shares: the adversarial 40% of records put a large part
// of their mass exactly on the singular configurations (horizon, parallel
// derivatives, zero determinants), so a function whose formula has a
// singularity there excludes a few to a few tens of percent. Each bound is
// the measured share plus about half again (it catches a regression that
// makes a function ill-conditioned everywhere).
#ifndef SG_EVAL_KERNELS_GLSL
#define SG_EVAL_KERNELS_GLSL

#include "sg/record.glsl"
#include "sg/surfgrad.glsl"
#include "sg/deriv_edit.glsl"
#include "sg/lean.glsl"

#define SG_EVAL_IN 28
#define SG_EVAL_OUT 12

struct SgEvalIn {
    float v[SG_EVAL_IN];
};
struct SgEvalOut {
    float v[SG_EVAL_OUT];
};
SG_REC_DEFINE_IO(SgEvalIn, SgEvalOut, SG_EVAL_OUT)

// A frame for kernels that take {n, dpdx, dpdy}: front-facing, mode NONE,
// so nrmBase = normalize(n) and the sigmas/flip sign follow listing 16.
SG_FN SgFrame sgEvalFrame(vec3 n, vec3 dPdx, vec3 dPdy) {
    return sgPrologue(n, dPdx, dPdy, true, SG_BFACE_NONE);
}
SG_FN SgFrame sgEvalFrameN(vec3 n) { return sgEvalFrame(n, sgVec3(0.0f), sgVec3(0.0f)); }

// Fields several functions share.
#define SG_EVAL_N_IN(F) F(vec3, n, ("base normal (unit length; normalized if not)", sgGenNormal))
#define SG_EVAL_DPDXY_IN(F)                                                                        \
    F(vec3, dpdx, ("d(position)/d(screen x), position units per pixel", sgGenScreenDerivX))      \
    F(vec3, dpdy, ("d(position)/d(screen y), position units per pixel", sgGenScreenDerivY))
#define SG_EVAL_FRAME_IN(F) SG_EVAL_N_IN(F) SG_EVAL_DPDXY_IN(F)
#define SG_EVAL_DSTDXY_IN(F)                                                                       \
    F(vec2, dstdx, ("d(uv)/d(screen x)", sgGenUvDerivX))                                          \
    F(vec2, dstdy, ("d(uv)/d(screen y)", sgGenUvDerivY))
#define SG_EVAL_SG_OUT(F) F(vec3, sg, ("surface gradient (tangent to the surface)"))
#define SG_EVAL_FRAME_OUT(F)                                                                       \
    F(vec3, nrm_base, ("base normal after the double-sided rule"))                                \
    F(vec3, sigma_x, ("dpdx projected onto the tangent plane"))                                   \
    F(vec3, sigma_y, ("dpdy projected onto the tangent plane"))                                   \
    F(float, flip_sign, ("orientation sign of (dpdx, dpdy, n)"))                                  \
    F(float, resolve_sign, ("-1 for back faces in flip mode"))
#define SG_EVAL_DOUBLE_SIDED_IN(F)                                                                 \
    F(bool, front_facing, ("gl_FrontFacing", sgDefault(1)))                                       \
    F(int, bface_mode, ("0 none, 1 mirror, 2 flip", sgDefault(0), sgRange(0, 2)))

// Reasons shared by several functions.
#define SG_EVAL_WHY_NORMALIZING ("normalizing functions: measured 6e-7 at most (1-5 ulps)")
#define SG_EVAL_WHY_JACOBIAN                                                                       \
    ("listings 8, 10, 11: 1/det of the screen or UV Jacobian, singular for parallel derivatives "  \
     "(edge-on views, degenerate UVs) and clamped at FLT_EPSILON; measured 1e-5 at most "        \
     "(scale-dependent, which chains three products before the division), 17-26% excluded")
#define SG_EVAL_WHY_PROJECTION                                                                     \
    ("projections onto the tangent plane: cancellation when the gradient is nearly along n; "    \
     "measured 2.2e-6 at most")
#define SG_EVAL_WHY_FRAME                                                                          \
    ("frame sigmas (projection cancellation) and orientation signs decided by a triple product " \
     "that is zero for parallel dPdx, dPdy; measured 6.8e-6 at most, 8-9% excluded")
#define SG_EVAL_WHY_LINEAR                                                                         \
    ("linear derivative algebra (Loviscach): the same products and sums in both builds; "        \
     "measured 0 (no FMA contraction happened), cancellation in sums excludes a few percent")

// ---------------------------------------------------------------------------
// resolve (L1)
#define SG_EVAL_RESOLVE_IN(F)                                                                      \
    SG_EVAL_N_IN(F)                                                                               \
    F(vec3, sg, ("surface gradient (tangent to the surface)"))                                    \
    F(float, resolve_sign, ("+1, or -1 for back faces in flip mode (negates the result)",          \
                            sgDefault(1), sgGenSign))
#define SG_EVAL_RESOLVE_OUT(F) F(vec3, n, ("perturbed unit normal"))
SG_FN SgEvalOut sgEvalResolve(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_RESOLVE_IN)
    SgFrame f = sgEvalFrameN(n);
    f.resolveSign = resolve_sign < 0.0f ? -1.0f : 1.0f;
    n = sgResolve(f, sg);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_RESOLVE_OUT)
}
#define SG_EVAL_RESOLVE(X)                                                                         \
    X(("resolve"), 0, sgEvalResolve, SG_EVAL_RESOLVE_IN, SG_EVAL_RESOLVE_OUT,                      \
      ("resolve_sign * normalize(n - sg) (L1)"), Mixed, 1e-5, 0.02, SG_EVAL_WHY_NORMALIZING,      \
      fieldInputs)

// ---------------------------------------------------------------------------
// tspace-to-deriv (L4)
#define SG_EVAL_TSPACE_TO_DERIV_IN(F)                                                              \
    F(vec2, m, ("normal-map xy channels in [-1, 1]", sgGenNormalMapXY))                            \
    F(bool, flip_v, ("green channel points down for a lower-left origin", sgDefault(0)))
#define SG_EVAL_TSPACE_TO_DERIV_OUT(F) F(vec2, d, ("derivative dH/d(s, t) w.r.t. +s, +t"))
SG_FN SgEvalOut sgEvalTspaceToDeriv(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_TSPACE_TO_DERIV_IN)
    SG_REC_DECLARE(SG_EVAL_TSPACE_TO_DERIV_OUT)
    d = sgTspaceNormalToDeriv(m, flip_v);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_TSPACE_TO_DERIV_OUT)
}
#define SG_EVAL_TSPACE_TO_DERIV(X)                                                                 \
    X(("tspace-to-deriv"), 1, sgEvalTspaceToDeriv, SG_EVAL_TSPACE_TO_DERIV_IN,                     \
      SG_EVAL_TSPACE_TO_DERIV_OUT,                                                                \
      ("tangent-space normal xy to derivative, clamped to |d| of 128 at most (L4)"), Mixed, 1e-5, \
      0.10,                                                                                       \
      ("m on the unit circle (half of the adversarial records): d = m/m_z with m_z going to 0 "   \
       "is singular until the 1/128 clamp of listing 4 takes over; CPU and GPU are "             \
       "bit-identical (measured 0)"),                                                             \
      fieldInputs)

// ---------------------------------------------------------------------------
// tbn (L5)
#define SG_EVAL_TBN_IN(F)                                                                          \
    F(vec2, d, ("derivative")) F(vec3, t, ("tangent")) F(vec3, b, ("bitangent"))
SG_FN SgEvalOut sgEvalTbn(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_TBN_IN)
    SG_REC_DECLARE(SG_EVAL_SG_OUT)
    sg = sgSurfgradFromTBN(d, t, b);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_SG_OUT)
}
#define SG_EVAL_TBN(X)                                                                             \
    X(("tbn"), 2, sgEvalTbn, SG_EVAL_TBN_IN, SG_EVAL_SG_OUT, ("d.x * t + d.y * b (L5)"), Mixed,    \
      1e-5, 0.05,                                                                                 \
      ("two products and a sum, the same operations in both builds (measured 0); cancellation "  \
       "in the sum excludes 0.13% of records; the share bound is the general 5%"),               \
      fieldInputs)

// ---------------------------------------------------------------------------
// basis (L6, L16)
#define SG_EVAL_BASIS_IN(F)                                                                        \
    SG_EVAL_FRAME_IN(F)                                                                           \
    F(vec2, st, ("texture coordinate at the pixel (sets the rounding of the derivatives)", sgDefault(0))) \
    SG_EVAL_DSTDXY_IN(F)
#define SG_EVAL_BASIS_OUT(F)                                                                       \
    F(vec3, t, ("tangent (direction of +s), as long as the chart weight"))                    \
    F(vec3, b, ("bitangent (direction of +t), as long as t"))
SG_FN SgEvalOut sgEvalBasis(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_BASIS_IN)
    SG_REC_DECLARE(SG_EVAL_BASIS_OUT)
    sgGenBasisTB(sgEvalFrame(n, dpdx, dpdy), st, dstdx, dstdy, t, b);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_BASIS_OUT)
}
#define SG_EVAL_BASIS(X)                                                                           \
    X(("basis"), 3, sgEvalBasis, SG_EVAL_BASIS_IN, SG_EVAL_BASIS_OUT,                              \
      ("procedural tangent/bitangent from UV derivatives (L6, L16)"), Mixed, 1e-5, 0.10,         \
      ("orthogonal frame from the UV Jacobian, scaled by the chart weight (0 where sign(det) "   \
       "would be noise); measured below 5e-7, 2.5% excluded (the slope of the fade, parallel "    \
       "sigmas)"),                                                                                \
      fieldInputs)

// ---------------------------------------------------------------------------
// perturbed (L7)
#define SG_EVAL_PERTURBED_IN(F)                                                                    \
    SG_EVAL_N_IN(F) F(vec3, v, ("perturbed normal, same space as n, any length"))
SG_FN SgEvalOut sgEvalPerturbed(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_PERTURBED_IN)
    SG_REC_DECLARE(SG_EVAL_SG_OUT)
    sg = sgSurfgradFromPerturbedNormal(sgEvalFrameN(n), v);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_SG_OUT)
}
#define SG_EVAL_PERTURBED(X)                                                                       \
    X(("perturbed"), 4, sgEvalPerturbed, SG_EVAL_PERTURBED_IN, SG_EVAL_SG_OUT,                     \
      ("surface gradient of a perturbed normal v (L7)"), Mixed, 1e-5, 0.25,                        \
      ("listing 7: 1/(n.v) amplifies the cancellation in n.v at the horizon (relative "          \
       "condition |v|/|n.v|); measured 5.0e-6, 16% excluded"),                                    \
      fieldInputs)

// ---------------------------------------------------------------------------
// scale-dependent (L8)
#define SG_EVAL_SCALE_DEPENDENT_IN(F)                                                              \
    SG_EVAL_FRAME_IN(F)                                                                           \
    F(vec2, deriv, ("dH/d(u, v), height units per texel"))                                        \
    F(vec2, dstdx, ("d(uv)/d(screen x), normalized uv", sgGenUvDerivX))                            \
    F(vec2, dstdy, ("d(uv)/d(screen y), normalized uv", sgGenUvDerivY))                            \
    F(vec2, dim, ("texture size in texels (w, h)", sgGenTexSize))
SG_FN SgEvalOut sgEvalScaleDependent(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_SCALE_DEPENDENT_IN)
    SG_REC_DECLARE(SG_EVAL_SG_OUT)
    sg = sgSurfgradScaleDependent(sgEvalFrame(n, dpdx, dpdy), deriv, dstdx, dstdy, dim);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_SG_OUT)
}
#define SG_EVAL_SCALE_DEPENDENT(X)                                                                 \
    X(("scale-dependent"), 5, sgEvalScaleDependent, SG_EVAL_SCALE_DEPENDENT_IN, SG_EVAL_SG_OUT,    \
      ("scale-dependent bump (L8)"), Mixed, 2e-5, 0.35, SG_EVAL_WHY_JACOBIAN, fieldInputs)

// ---------------------------------------------------------------------------
// volume (L12)
#define SG_EVAL_VOLUME_IN(F) SG_EVAL_N_IN(F) F(vec3, grad, ("volume gradient of the height"))
SG_FN SgEvalOut sgEvalVolume(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_VOLUME_IN)
    SG_REC_DECLARE(SG_EVAL_SG_OUT)
    sg = sgSurfgradFromVolumeGradient(sgEvalFrameN(n), grad);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_SG_OUT)
}
#define SG_EVAL_VOLUME(X)                                                                          \
    X(("volume"), 6, sgEvalVolume, SG_EVAL_VOLUME_IN, SG_EVAL_SG_OUT,                              \
      ("volume gradient to surface gradient (L12)"), Mixed, 1e-5, 0.05, SG_EVAL_WHY_PROJECTION,    \
      fieldInputs)

// ---------------------------------------------------------------------------
// triplanar-weights (L14)
#define SG_EVAL_TRIPLANAR_WEIGHTS_IN(F)                                                            \
    F(vec3, n, ("normal", sgGenNormal))                                                            \
    F(float, k, ("sharpness exponent, positive", sgDefault(3), sgGenExponent))
#define SG_EVAL_TRIPLANAR_WEIGHTS_OUT(F) F(vec3, w, ("weights, sum 1"))
SG_FN SgEvalOut sgEvalTriplanarWeights(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_TRIPLANAR_WEIGHTS_IN)
    SG_REC_DECLARE(SG_EVAL_TRIPLANAR_WEIGHTS_OUT)
    w = sgTriplanarWeights(n, k);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_TRIPLANAR_WEIGHTS_OUT)
}
#define SG_EVAL_TRIPLANAR_WEIGHTS(X)                                                               \
    X(("triplanar-weights"), 7, sgEvalTriplanarWeights, SG_EVAL_TRIPLANAR_WEIGHTS_IN,              \
      SG_EVAL_TRIPLANAR_WEIGHTS_OUT, ("triplanar blend weights (L14)"), Mixed, 1e-5, 0.05,         \
      ("llvmpipe pow = exp2(k log2 x): error grows with k (up to 316 on the adversarial set, "    \
       "condition number k); measured 1.1e-6"),                                                   \
      fieldInputs)

// ---------------------------------------------------------------------------
// triplanar (L13 with L14 weights)
#define SG_EVAL_TRIPLANAR_IN(F)                                                                    \
    SG_EVAL_N_IN(F)                                                                               \
    F(float, k, ("sharpness exponent, positive", sgDefault(3), sgGenExponent))                    \
    F(vec2, dx, ("derivative of the x-plane map, sampled at (z, y)"))                             \
    F(vec2, dy, ("derivative of the y-plane map, sampled at (x, z)"))                             \
    F(vec2, dz, ("derivative of the z-plane map, sampled at (x, y)"))                             \
    F(bool, right_handed, ("right-handed frame: (-z, y), (x, -z)", sgDefault(0)))                 \
    F(bool, upper_left, ("texture origin upper-left", sgDefault(0)))
SG_FN SgEvalOut sgEvalTriplanar(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_TRIPLANAR_IN)
    SG_REC_DECLARE(SG_EVAL_SG_OUT)
    SgFrame f = sgEvalFrameN(n);
    vec3 w = sgTriplanarWeights(f.nrmBase, k);
    sg = sgSurfgradFromTriplanar(f, w, dx, dy, dz, right_handed, upper_left);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_SG_OUT)
}
#define SG_EVAL_TRIPLANAR(X)                                                                       \
    X(("triplanar"), 8, sgEvalTriplanar, SG_EVAL_TRIPLANAR_IN, SG_EVAL_SG_OUT,                     \
      ("triplanar surface gradient (L13 with L14 weights)"), Mixed, 1e-5, 0.20,                   \
      ("the pow of triplanar-weights (error grows with k, condition number k); measured 2.2e-6, " \
       "14% of records excluded (large k)"),                                                      \
      fieldInputs)

// ---------------------------------------------------------------------------
// decal (L15)
#define SG_EVAL_DECAL_IN(F)                                                                        \
    SG_EVAL_N_IN(F)                                                                               \
    F(vec2, d, ("derivative of the decal map"))                                                   \
    F(vec3, axis_x, ("projector x axis (unit)", sgGenDirection))                                  \
    F(vec3, axis_y, ("projector y axis (unit)", sgGenDirection))                                  \
    F(bool, upper_left, ("texture origin upper-left", sgDefault(0)))
SG_FN SgEvalOut sgEvalDecal(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DECAL_IN)
    SG_REC_DECLARE(SG_EVAL_SG_OUT)
    sg = sgSurfgradFromDecal(sgEvalFrameN(n), d, axis_x, axis_y, upper_left);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_SG_OUT)
}
#define SG_EVAL_DECAL(X)                                                                           \
    X(("decal"), 9, sgEvalDecal, SG_EVAL_DECAL_IN, SG_EVAL_SG_OUT,                                 \
      ("decal projector surface gradient (L15)"), Mixed, 1e-5, 0.05, SG_EVAL_WHY_PROJECTION,       \
      fieldInputs)

// ---------------------------------------------------------------------------
// prologue (L16, section 2.10)
#define SG_EVAL_PROLOGUE_IN(F)                                                                     \
    F(vec3, n, ("interpolated vertex normal (any length)", sgGenNormal))                          \
    SG_EVAL_DPDXY_IN(F) SG_EVAL_DOUBLE_SIDED_IN(F)
SG_FN SgEvalOut sgEvalPrologue(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_PROLOGUE_IN)
    SgFrame f = sgPrologue(n, dpdx, dpdy, front_facing, bface_mode);
    SG_REC_DECLARE(SG_EVAL_FRAME_OUT)
    nrm_base = f.nrmBase;
    sigma_x = f.sigmaX;
    sigma_y = f.sigmaY;
    flip_sign = f.flipSign;
    resolve_sign = f.resolveSign;
    SG_REC_RETURN(SgEvalOut, SG_EVAL_FRAME_OUT)
}
#define SG_EVAL_PROLOGUE(X)                                                                        \
    X(("prologue"), 10, sgEvalPrologue, SG_EVAL_PROLOGUE_IN, SG_EVAL_FRAME_OUT,                    \
      ("pixel-shader prologue (L16, section 2.10)"), Mixed, 1e-5, 0.15, SG_EVAL_WHY_FRAME,         \
      fieldInputs)

// ---------------------------------------------------------------------------
// mikkts-basis (section 2.2, L16)
#define SG_EVAL_MIKKTS_BASIS_IN(F)                                                                 \
    F(vec3, n, ("interpolated vertex normal, unnormalized", sgGenNormal))                         \
    F(vec4, tangent, ("interpolated tangent xyz, sign w", sgGenTangent))
#define SG_EVAL_MIKKTS_BASIS_OUT(F)                                                                \
    F(vec3, t, ("tangent * renorm")) F(vec3, b, ("sign(w) cross(n, t) * renorm"))
SG_FN SgEvalOut sgEvalMikktsBasis(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_MIKKTS_BASIS_IN)
    SG_REC_DECLARE(SG_EVAL_MIKKTS_BASIS_OUT)
    sgMikktsBasis(n, tangent, t, b);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_MIKKTS_BASIS_OUT)
}
#define SG_EVAL_MIKKTS_BASIS(X)                                                                    \
    X(("mikkts-basis"), 11, sgEvalMikktsBasis, SG_EVAL_MIKKTS_BASIS_IN, SG_EVAL_MIKKTS_BASIS_OUT,  \
      ("mikktspace-compliant basis scaled by 1/|n| (section 2.2, L16)"), Mixed, 1e-5, 0.02,       \
      SG_EVAL_WHY_NORMALIZING, fieldInputs)

// ---------------------------------------------------------------------------
// screen-deriv-of-pos (L17)
#define SG_EVAL_SCREEN_DERIV_OF_POS_IN(F)                                                          \
    F(vec3, pos, ("surface position"))                                                            \
    F(vec3, n, ("surface normal"))                                                                \
    F(mat4, inv_view_proj_scr, ("screen to position space, column-major mat4"))                   \
    F(float, x, ("window x (pixel centre at .5)"))                                                \
    F(float, y, ("window y (pixel centre at .5)"))
#define SG_EVAL_SCREEN_DERIV_OF_POS_OUT(F)                                                         \
    F(vec3, dpdx, ("d(position)/d(screen x), position units per pixel"))                          \
    F(vec3, dpdy, ("d(position)/d(screen y), position units per pixel"))
SG_FN SgEvalOut sgEvalScreenDerivOfPos(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_SCREEN_DERIV_OF_POS_IN)
    SG_REC_DECLARE(SG_EVAL_SCREEN_DERIV_OF_POS_OUT)
    sgScreenDerivOfPos(dpdx, dpdy, pos, n, inv_view_proj_scr, x, y);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_SCREEN_DERIV_OF_POS_OUT)
}
#define SG_EVAL_SCREEN_DERIV_OF_POS(X)                                                             \
    X(("screen-deriv-of-pos"), 12, sgEvalScreenDerivOfPos, SG_EVAL_SCREEN_DERIV_OF_POS_IN,         \
      SG_EVAL_SCREEN_DERIV_OF_POS_OUT, ("analytic dPdx/dPdy (L17)"), Relative, 1e-4, 0.60,         \
      ("listing 17, relative measure: the pixel ray is a difference of near-plane and eye "       \
       "points (cancellation about far/near) and the plane intersection divides by n.D (edge-on " \
       "views); measured 1.4e-6 relative; the condition probe at tolerance 1e-4 excludes "        \
       "records with condition number above about 50 (edge-on planes, eyes far from the "         \
       "origin)"),                                                                                \
      cameraInputs)

// ---------------------------------------------------------------------------
// parallax-project (L10)
#define SG_EVAL_PARALLAX_PROJECT_IN(F)                                                             \
    SG_EVAL_FRAME_IN(F)                                                                           \
    F(vec3, dir, ("unit direction", sgGenDirection))                                              \
    SG_EVAL_DSTDXY_IN(F)                                                                          \
    F(float, bump_scale, ("displacement per unit height", sgDefault(1)))                          \
    F(bool, skip_proj, ("basic parallax (no projection)", sgDefault(0)))
#define SG_EVAL_PARALLAX_PROJECT_OUT(F)                                                            \
    F(vec2, offset, ("texture-space offset, normalized uv"))
SG_FN SgEvalOut sgEvalParallaxProject(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_PARALLAX_PROJECT_IN)
    SG_REC_DECLARE(SG_EVAL_PARALLAX_PROJECT_OUT)
    offset = sgProjectVecToTextureSpace(sgEvalFrame(n, dpdx, dpdy), dir, dstdx, dstdy, bump_scale,
                                        skip_proj);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_PARALLAX_PROJECT_OUT)
}
#define SG_EVAL_PARALLAX_PROJECT(X)                                                                \
    X(("parallax-project"), 13, sgEvalParallaxProject, SG_EVAL_PARALLAX_PROJECT_IN,                \
      SG_EVAL_PARALLAX_PROJECT_OUT, ("direction to texture space (L10)"), Mixed, 2e-5, 0.35,       \
      SG_EVAL_WHY_JACOBIAN, fieldInputs)

// ---------------------------------------------------------------------------
// texoffs-to-surface (L11)
#define SG_EVAL_TEXOFFS_TO_SURFACE_IN(F)                                                           \
    SG_EVAL_FRAME_IN(F)                                                                           \
    SG_EVAL_DSTDXY_IN(F)                                                                          \
    F(vec2, offset, ("texture-space offset, normalized uv"))
#define SG_EVAL_TEXOFFS_TO_SURFACE_OUT(F)                                                          \
    F(vec3, p, ("offset in the tangent plane, position units"))
SG_FN SgEvalOut sgEvalTexoffsToSurface(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_TEXOFFS_TO_SURFACE_IN)
    SG_REC_DECLARE(SG_EVAL_TEXOFFS_TO_SURFACE_OUT)
    p = sgTexSpaceOffsToSurface(sgEvalFrame(n, dpdx, dpdy), dstdx, dstdy, offset);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_TEXOFFS_TO_SURFACE_OUT)
}
#define SG_EVAL_TEXOFFS_TO_SURFACE(X)                                                              \
    X(("texoffs-to-surface"), 14, sgEvalTexoffsToSurface, SG_EVAL_TEXOFFS_TO_SURFACE_IN,           \
      SG_EVAL_TEXOFFS_TO_SURFACE_OUT, ("texture offset to surface (L11)"), Mixed, 2e-5, 0.35,      \
      SG_EVAL_WHY_JACOBIAN, fieldInputs)

// ---------------------------------------------------------------------------
// screen-deriv-surfgrad (L8, isDerivScreenSpace)
#define SG_EVAL_SCREEN_DERIV_SURFGRAD_IN(F)                                                        \
    SG_EVAL_FRAME_IN(F) F(vec2, dhdxy, ("(dH/dx, dH/dy) per pixel"))
SG_FN SgEvalOut sgEvalScreenDerivSurfgrad(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_SCREEN_DERIV_SURFGRAD_IN)
    SG_REC_DECLARE(SG_EVAL_SG_OUT)
    sg = sgSurfgradFromScreenDeriv(sgEvalFrame(n, dpdx, dpdy), dhdxy);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_SG_OUT)
}
#define SG_EVAL_SCREEN_DERIV_SURFGRAD(X)                                                           \
    X(("screen-deriv-surfgrad"), 15, sgEvalScreenDerivSurfgrad, SG_EVAL_SCREEN_DERIV_SURFGRAD_IN,  \
      SG_EVAL_SG_OUT,                                                                             \
      ("surface gradient from screen-space height derivatives (L8, isDerivScreenSpace)"), Mixed,  \
      2e-5, 0.35, SG_EVAL_WHY_JACOBIAN, fieldInputs)

// ---------------------------------------------------------------------------
// deriv-to-tspace
#define SG_EVAL_DERIV_TO_TSPACE_IN(F)                                                              \
    F(vec2, d, ("derivative")) F(bool, flip_v, ("see tspace-to-deriv", sgDefault(0)))
#define SG_EVAL_DERIV_TO_TSPACE_OUT(F) F(vec3, m, ("unit tangent-space normal"))
SG_FN SgEvalOut sgEvalDerivToTspace(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DERIV_TO_TSPACE_IN)
    SG_REC_DECLARE(SG_EVAL_DERIV_TO_TSPACE_OUT)
    m = sgDerivToTspaceNormal(d, flip_v);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_DERIV_TO_TSPACE_OUT)
}
#define SG_EVAL_DERIV_TO_TSPACE(X)                                                                 \
    X(("deriv-to-tspace"), 16, sgEvalDerivToTspace, SG_EVAL_DERIV_TO_TSPACE_IN,                    \
      SG_EVAL_DERIV_TO_TSPACE_OUT, ("derivative to unit tangent-space normal"), Mixed, 1e-5, 0.02, \
      SG_EVAL_WHY_NORMALIZING, fieldInputs)

// ---------------------------------------------------------------------------
// reprologue (sections 2.11, 3)
#define SG_EVAL_REPROLOGUE_IN(F)                                                                   \
    F(vec3, n, ("interpolated vertex normal", sgGenNormal))                                       \
    SG_EVAL_DPDXY_IN(F) SG_EVAL_DOUBLE_SIDED_IN(F)                                                \
    F(vec3, resolved, ("normal after the first resolve", sgGenDirection))
SG_FN SgEvalOut sgEvalReprologue(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_REPROLOGUE_IN)
    SgFrame f = sgPrologue(n, dpdx, dpdy, front_facing, bface_mode);
    f = sgReprologue(f, resolved, dpdx, dpdy);
    SG_REC_DECLARE(SG_EVAL_FRAME_OUT)
    nrm_base = f.nrmBase;
    sigma_x = f.sigmaX;
    sigma_y = f.sigmaY;
    flip_sign = f.flipSign;
    resolve_sign = f.resolveSign;
    SG_REC_RETURN(SgEvalOut, SG_EVAL_FRAME_OUT)
}
#define SG_EVAL_REPROLOGUE(X)                                                                      \
    X(("reprologue"), 17, sgEvalReprologue, SG_EVAL_REPROLOGUE_IN, SG_EVAL_FRAME_OUT,              \
      ("post-resolve frame (sections 2.11, 3)"), Mixed, 1e-5, 0.15, SG_EVAL_WHY_FRAME,             \
      fieldInputs)

// ---------------------------------------------------------------------------
// bump-scale (L2)
#define SG_EVAL_BUMP_SCALE_IN(F)                                                                   \
    F(float, scale, ("bump scale")) F(vec3, sg, ("surface gradient (tangent to the surface)"))
SG_FN SgEvalOut sgEvalBumpScale(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_BUMP_SCALE_IN)
    sg = sgBumpScale(scale, sg);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_SG_OUT)
}
#define SG_EVAL_BUMP_SCALE(X)                                                                      \
    X(("bump-scale"), 18, sgEvalBumpScale, SG_EVAL_BUMP_SCALE_IN, SG_EVAL_SG_OUT,                  \
      ("scale * sg (L2)"), Mixed, 1e-5, 0.02, SG_EVAL_WHY_LINEAR, fieldInputs)

// ---------------------------------------------------------------------------
// deriv-scale (L3; Loviscach scaling)
#define SG_EVAL_DERIV_SCALE_IN(F) F(vec2, d, ("derivative")) F(float, alpha, ("height scale"))
#define SG_EVAL_DERIV_OUT(F) F(vec2, d, ("derivative"))
SG_FN SgEvalOut sgEvalDerivScale(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DERIV_SCALE_IN)
    d = sgDerivScale(d, alpha);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_DERIV_OUT)
}
#define SG_EVAL_DERIV_SCALE(X)                                                                     \
    X(("deriv-scale"), 19, sgEvalDerivScale, SG_EVAL_DERIV_SCALE_IN, SG_EVAL_DERIV_OUT,            \
      ("derivative of alpha * h (L3; Loviscach scaling)"), Mixed, 1e-5, 0.02, SG_EVAL_WHY_LINEAR, \
      fieldInputs)

// ---------------------------------------------------------------------------
// deriv-blend (Loviscach)
#define SG_EVAL_DERIV_BLEND_IN(F)                                                                  \
    F(int, count, ("number of layers, 0..4", sgDefault(2), sgRange(0, 4)))                        \
    F(vec2, d0, ("layer 0", sgDefault(0))) F(vec2, d1, ("layer 1", sgDefault(0)))                 \
    F(vec2, d2, ("layer 2", sgDefault(0))) F(vec2, d3, ("layer 3", sgDefault(0)))                 \
    F(float, w0, ("weight 0", sgDefault(0))) F(float, w1, ("weight 1", sgDefault(0)))             \
    F(float, w2, ("weight 2", sgDefault(0))) F(float, w3, ("weight 3", sgDefault(0)))
SG_FN SgEvalOut sgEvalDerivBlend(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DERIV_BLEND_IN)
    vec2 layers[SG_DERIV_MAX_LAYERS];
    float weights[SG_DERIV_MAX_LAYERS];
    for (int i = 0; i < SG_DERIV_MAX_LAYERS; ++i) {
        layers[i] = sgVec2(0.0f);
        weights[i] = 0.0f;
    }
    layers[0] = d0;
    layers[1] = d1;
    layers[2] = d2;
    layers[3] = d3;
    weights[0] = w0;
    weights[1] = w1;
    weights[2] = w2;
    weights[3] = w3;
    SG_REC_DECLARE(SG_EVAL_DERIV_OUT)
    d = sgDerivBlend(layers, weights, min(count, 4));
    SG_REC_RETURN(SgEvalOut, SG_EVAL_DERIV_OUT)
}
#define SG_EVAL_DERIV_BLEND(X)                                                                     \
    X(("deriv-blend"), 20, sgEvalDerivBlend, SG_EVAL_DERIV_BLEND_IN, SG_EVAL_DERIV_OUT,            \
      ("sum of w_i * d_i over up to 4 layers (Loviscach)"), Mixed, 1e-5, 0.02,                     \
      SG_EVAL_WHY_LINEAR, fieldInputs)

// ---------------------------------------------------------------------------
// deriv-modulate (Loviscach)
#define SG_EVAL_DERIV_MODULATE_IN(F)                                                               \
    F(vec2, d1, ("derivative of h1")) F(float, h1, ("height h1", sgGenSymmetric))                 \
    F(vec2, d2, ("derivative of h2")) F(float, h2, ("height h2", sgGenSymmetric))
SG_FN SgEvalOut sgEvalDerivModulate(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DERIV_MODULATE_IN)
    SG_REC_DECLARE(SG_EVAL_DERIV_OUT)
    d = sgDerivModulate(d1, h1, d2, h2);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_DERIV_OUT)
}
#define SG_EVAL_DERIV_MODULATE(X)                                                                  \
    X(("deriv-modulate"), 21, sgEvalDerivModulate, SG_EVAL_DERIV_MODULATE_IN, SG_EVAL_DERIV_OUT,   \
      ("derivative of h1 * h2 (Loviscach)"), Mixed, 1e-5, 0.02, SG_EVAL_WHY_LINEAR, fieldInputs)

// ---------------------------------------------------------------------------
// deriv-curve (Loviscach)
#define SG_EVAL_DERIV_CURVE_IN(F)                                                                  \
    F(vec2, d, ("derivative of h")) F(float, h, ("height", sgGenSymmetric))                       \
    F(float, p, ("boost width P, not negative", sgGenPositive))                                   \
    F(float, hc, ("boost centre H", sgGenSymmetric))
#define SG_EVAL_DERIV_CURVE_OUT(F)                                                                 \
    F(vec2, d, ("derivative of f(h)")) F(float, f, ("f(h), f(H) = 0"))
SG_FN SgEvalOut sgEvalDerivCurve(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DERIV_CURVE_IN)
    float f = sgCurveBoostValue(h, p, hc);
    d = sgDerivCurve(d, sgCurveBoostSlope(h, p, hc));
    SG_REC_RETURN(SgEvalOut, SG_EVAL_DERIV_CURVE_OUT)
}
#define SG_EVAL_DERIV_CURVE(X)                                                                     \
    X(("deriv-curve"), 22, sgEvalDerivCurve, SG_EVAL_DERIV_CURVE_IN, SG_EVAL_DERIV_CURVE_OUT,      \
      ("derivative of f(h), df/dh = 1 / (1 + P (h - H)^2) (Loviscach)"), Mixed, 4e-5, 0.10,      \
      ("curves: f = atan(sqrt(P)(h - H)) / sqrt(P) goes through the llvmpipe atan (relative "     \
       "error up to 2.1e-5, measured 2.0e-5 on f)"),                                              \
      fieldInputs)

// ---------------------------------------------------------------------------
// deriv-deform (Loviscach)
#define SG_EVAL_DERIV_DEFORM_IN(F)                                                                 \
    F(vec2, d, ("derivative sampled at (s, t)"))                                                  \
    F(vec2, ds_du_dt_du, ("Jacobian column (ds/du, dt/du)"))                                      \
    F(vec2, ds_dv_dt_dv, ("Jacobian column (ds/dv, dt/dv)"))
#define SG_EVAL_DERIV_UV_OUT(F) F(vec2, d, ("derivative w.r.t. (u, v)"))
SG_FN SgEvalOut sgEvalDerivDeform(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DERIV_DEFORM_IN)
    d = sgDerivDeform(d, mat2(ds_du_dt_du, ds_dv_dt_dv));
    SG_REC_RETURN(SgEvalOut, SG_EVAL_DERIV_UV_OUT)
}
#define SG_EVAL_DERIV_DEFORM(X)                                                                    \
    X(("deriv-deform"), 23, sgEvalDerivDeform, SG_EVAL_DERIV_DEFORM_IN, SG_EVAL_DERIV_UV_OUT,      \
      ("derivative of h(s(u, v), t(u, v)) (Loviscach)"), Mixed, 1e-5, 0.10,                       \
      ("linear derivative algebra (a 2x2 Jacobian product): the same products and sums in both " \
       "builds, measured 0; cancellation in the products excludes 5.6% of records"),             \
      fieldInputs)

// ---------------------------------------------------------------------------
// deriv-sine-warp (Loviscach example)
#define SG_EVAL_DERIV_SINE_WARP_IN(F)                                                              \
    F(vec2, d, ("derivative sampled at (s, t)")) F(float, u, ("u", sgGenSymmetric))               \
    F(float, a, ("amplitude A")) F(float, b, ("frequency B"))
SG_FN SgEvalOut sgEvalDerivSineWarp(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DERIV_SINE_WARP_IN)
    d = sgDerivDeform(d, sgSineWarpJacobian(u, a, b));
    SG_REC_RETURN(SgEvalOut, SG_EVAL_DERIV_UV_OUT)
}
#define SG_EVAL_DERIV_SINE_WARP(X)                                                                 \
    X(("deriv-sine-warp"), 24, sgEvalDerivSineWarp, SG_EVAL_DERIV_SINE_WARP_IN,                    \
      SG_EVAL_DERIV_UV_OUT, ("deform with s = u, t = v + A sin(B u) (Loviscach example)"), Mixed, \
      2e-5, 0.20,                                                                                 \
      ("sine warp: cos(B u) in binary32 on both sides; huge phases are ill-conditioned (13% "     \
       "excluded), moderate ones differ by the llvmpipe cos error times the slope A B; "          \
       "measured 8.3e-6"),                                                                        \
      fieldInputs)

// ---------------------------------------------------------------------------
// decal-volume (section 2.9)
#define SG_EVAL_DECAL_VOLUME_IN(F)                                                                 \
    F(vec2, d, ("derivative of the decal map"))                                                   \
    F(vec3, axis_x, ("projector x axis", sgGenDirection))                                         \
    F(vec3, axis_y, ("projector y axis", sgGenDirection))                                         \
    F(bool, upper_left, ("texture origin upper-left", sgDefault(0)))
#define SG_EVAL_DECAL_VOLUME_OUT(F) F(vec3, grad, ("volume gradient"))
SG_FN SgEvalOut sgEvalDecalVolume(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DECAL_VOLUME_IN)
    SG_REC_DECLARE(SG_EVAL_DECAL_VOLUME_OUT)
    grad = sgDecalVolumeGradient(d, axis_x, axis_y, upper_left);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_DECAL_VOLUME_OUT)
}
#define SG_EVAL_DECAL_VOLUME(X)                                                                    \
    X(("decal-volume"), 25, sgEvalDecalVolume, SG_EVAL_DECAL_VOLUME_IN, SG_EVAL_DECAL_VOLUME_OUT,  \
      ("volume gradient of one decal (section 2.9)"), Mixed, 1e-5, 0.05, SG_EVAL_WHY_PROJECTION,   \
      fieldInputs)

// ---------------------------------------------------------------------------
// height-3tap (L9)
#define SG_EVAL_HEIGHT_3TAP_IN(F)                                                                  \
    F(float, hll, ("H(st)", sgGenSymmetric)) F(float, hlr, ("H(st + dstdx)", sgGenSymmetric))     \
    F(float, hul, ("H(st + dstdy)", sgGenSymmetric))
#define SG_EVAL_HEIGHT_3TAP_OUT(F) F(vec2, dhdxy, ("(dH/dx, dH/dy)"))
SG_FN SgEvalOut sgEvalHeight3Tap(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_HEIGHT_3TAP_IN)
    SG_REC_DECLARE(SG_EVAL_HEIGHT_3TAP_OUT)
    dhdxy = sgHeightDeriv3Tap(hll, hlr, hul);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_HEIGHT_3TAP_OUT)
}
#define SG_EVAL_HEIGHT_3TAP(X)                                                                     \
    X(("height-3tap"), 26, sgEvalHeight3Tap, SG_EVAL_HEIGHT_3TAP_IN, SG_EVAL_HEIGHT_3TAP_OUT,      \
      ("3-tap screen-space height derivative (L9)"), Mixed, 1e-5, 0.02, SG_EVAL_WHY_LINEAR,        \
      fieldInputs)

// ---------------------------------------------------------------------------
// bounded-scale (compat.glsl)
#define SG_EVAL_BOUNDED_SCALE_IN(F)                                                                \
    F(vec3, v, ("vector")) F(vec4, f, ("four factors (absolute values are used)"))
#define SG_EVAL_BOUNDED_SCALE_OUT(F) F(vec3, v, ("scaled vector, components within 1e18"))
SG_FN SgEvalOut sgEvalBoundedScale(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_BOUNDED_SCALE_IN)
    v = sgBoundedScale3(v, abs(f));
    SG_REC_RETURN(SgEvalOut, SG_EVAL_BOUNDED_SCALE_OUT)
}
#define SG_EVAL_BOUNDED_SCALE(X)                                                                   \
    X(("bounded-scale"), 27, sgEvalBoundedScale, SG_EVAL_BOUNDED_SCALE_IN,                         \
      SG_EVAL_BOUNDED_SCALE_OUT,                                                                  \
      ("v * |f.x f.y f.z f.w| kept within SG_BIG along v (overflow-free scaling, compat.glsl)"),  \
      Mixed, 1e-5, 0.02, SG_EVAL_WHY_LINEAR, fieldInputs)

// ---------------------------------------------------------------------------
// height-central (Loviscach, "Birth"; the normal-map toolkit's from-height)
#define SG_EVAL_HEIGHT_CENTRAL_IN(F)                                                               \
    F(float, hl, ("h one texel left", sgGenSymmetric))                                            \
    F(float, hr, ("h one texel right", sgGenSymmetric))                                           \
    F(float, hd, ("h one texel below", sgGenSymmetric))                                           \
    F(float, hu, ("h one texel above", sgGenSymmetric))
#define SG_EVAL_HEIGHT_CENTRAL_OUT(F) F(vec2, d, ("(dh/du, dh/dv) per texel"))
SG_FN SgEvalOut sgEvalHeightCentral(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_HEIGHT_CENTRAL_IN)
    SG_REC_DECLARE(SG_EVAL_HEIGHT_CENTRAL_OUT)
    d = sgHeightDerivCentral(hl, hr, hd, hu);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_HEIGHT_CENTRAL_OUT)
}
#define SG_EVAL_HEIGHT_CENTRAL(X)                                                                  \
    X(("height-central"), 28, sgEvalHeightCentral, SG_EVAL_HEIGHT_CENTRAL_IN,                      \
      SG_EVAL_HEIGHT_CENTRAL_OUT, ("central-difference height derivative (Loviscach, Birth)"),     \
      Mixed, 1e-5, 0.02, SG_EVAL_WHY_LINEAR, fieldInputs)

// ---------------------------------------------------------------------------
// curve-hermite (Loviscach, Curves (4))
#define SG_EVAL_CURVE_HERMITE_IN(F)                                                                \
    F(float, x, ("curve input", sgGenSymmetric)) F(vec4, knots, ("(x0, y0, x1, y1)"))             \
    F(vec2, slopes, ("end slopes (m0, m1)"))
#define SG_EVAL_CURVE_HERMITE_OUT(F) F(vec2, f, ("(f(x), df/dx at x)"))
SG_FN SgEvalOut sgEvalCurveHermite(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_CURVE_HERMITE_IN)
    SG_REC_DECLARE(SG_EVAL_CURVE_HERMITE_OUT)
    f = sgCurveHermite(x, knots, slopes);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_CURVE_HERMITE_OUT)
}
#define SG_EVAL_CURVE_HERMITE(X)                                                                   \
    X(("curve-hermite"), 29, sgEvalCurveHermite, SG_EVAL_CURVE_HERMITE_IN,                         \
      SG_EVAL_CURVE_HERMITE_OUT,                                                                  \
      ("cubic Hermite curve segment, value and slope (Loviscach, Curves (4))"), Mixed, 1e-5,      \
      0.03,                                                                                       \
      ("polynomial written around the chord (no cancellation of large basis terms): measured " \
       "0; 1.6% ill-conditioned (steep secants of short segments)"),                             \
      fieldInputs)

// ---------------------------------------------------------------------------
// deriv-mask-blend (Loviscach, blending with a mask by the product rule)
#define SG_EVAL_DERIV_MASK_BLEND_IN(F)                                                             \
    F(vec2, da, ("derivative of hA")) F(float, ha, ("height hA", sgGenSymmetric))                 \
    F(vec2, db, ("derivative of hB")) F(float, hb, ("height hB", sgGenSymmetric))                 \
    F(float, m, ("mask", sgGenSymmetric)) F(vec2, dm, ("derivative of the mask"))
SG_FN SgEvalOut sgEvalDerivMaskBlend(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_DERIV_MASK_BLEND_IN)
    SG_REC_DECLARE(SG_EVAL_DERIV_OUT)
    d = sgDerivMaskBlend(da, ha, db, hb, m, dm);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_DERIV_OUT)
}
#define SG_EVAL_DERIV_MASK_BLEND(X)                                                                \
    X(("deriv-mask-blend"), 30, sgEvalDerivMaskBlend, SG_EVAL_DERIV_MASK_BLEND_IN,                 \
      SG_EVAL_DERIV_OUT, ("derivative of (1 - m) hA + m hB (Loviscach, blend and modulation)"),    \
      Mixed, 1e-5, 0.06,                                                                          \
      ("two products summed: measured 1.4e-6; cancellation in the sum excludes 3.9%"),           \
      fieldInputs)

// ---------------------------------------------------------------------------
// lean-second (LEAN, lean.glsl)
#define SG_EVAL_LEAN_SECOND_IN(F) F(vec2, d, ("slope"))
#define SG_EVAL_LEAN_SECOND_OUT(F) F(vec3, m, ("(x^2, y^2, xy)"))
SG_FN SgEvalOut sgEvalLeanSecond(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_LEAN_SECOND_IN)
    SG_REC_DECLARE(SG_EVAL_LEAN_SECOND_OUT)
    m = sgLeanSecondMoments(d);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_LEAN_SECOND_OUT)
}
#define SG_EVAL_LEAN_SECOND(X)                                                                     \
    X(("lean-second"), 31, sgEvalLeanSecond, SG_EVAL_LEAN_SECOND_IN, SG_EVAL_LEAN_SECOND_OUT,      \
      ("second slope moments (x^2, y^2, xy) (LEAN)"), Mixed, 1e-5, 0.02,                          \
      ("three products, the same in both builds: measured 0"), fieldInputs)

// ---------------------------------------------------------------------------
// lean-covariance (LEAN, lean.glsl)
#define SG_EVAL_LEAN_COVARIANCE_IN(F)                                                              \
    F(vec2, b, ("filtered mean slope")) F(vec3, m, ("filtered second moments"))
#define SG_EVAL_LEAN_COVARIANCE_OUT(F) F(vec3, cov, ("(var x, var y, cov xy)"))
SG_FN SgEvalOut sgEvalLeanCovariance(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_LEAN_COVARIANCE_IN)
    SG_REC_DECLARE(SG_EVAL_LEAN_COVARIANCE_OUT)
    cov = sgLeanCovariance(b, m);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_LEAN_COVARIANCE_OUT)
}
#define SG_EVAL_LEAN_COVARIANCE(X)                                                                 \
    X(("lean-covariance"), 32, sgEvalLeanCovariance, SG_EVAL_LEAN_COVARIANCE_IN,                   \
      SG_EVAL_LEAN_COVARIANCE_OUT,                                                                \
      ("slope covariance M - B B^T, clamped positive semi-definite (LEAN)"), Mixed, 1e-5, 0.02,   \
      ("products and differences, clamps decided on the same values: measured 0; 0.3% "     \
       "ill-conditioned (M - B B^T cancels)"),                                                    \
      fieldInputs)

// ---------------------------------------------------------------------------
// toksvig-variance (Toksvig 2005, lean.glsl)
#define SG_EVAL_TOKSVIG_VARIANCE_IN(F) F(vec3, n, ("average of unit normals"))
#define SG_EVAL_TOKSVIG_VARIANCE_OUT(F) F(float, s2, ("variance"))
SG_FN SgEvalOut sgEvalToksvigVariance(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_TOKSVIG_VARIANCE_IN)
    SG_REC_DECLARE(SG_EVAL_TOKSVIG_VARIANCE_OUT)
    s2 = sgToksvigVariance(n);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_TOKSVIG_VARIANCE_OUT)
}
#define SG_EVAL_TOKSVIG_VARIANCE(X)                                                                \
    X(("toksvig-variance"), 33, sgEvalToksvigVariance, SG_EVAL_TOKSVIG_VARIANCE_IN,                \
      SG_EVAL_TOKSVIG_VARIANCE_OUT, ("(1 - |N|) / |N| of an average of unit normals (Toksvig)"),  \
      Mixed, 1e-5, 0.02,                                                                          \
      ("a length (llvmpipe 1/sqrt within 1 ulp) and one division by it, clamped at 2^-20: "      \
       "measured 2.4e-7"),                                                                        \
      fieldInputs)

// ---------------------------------------------------------------------------
// toksvig-factor (Toksvig 2005, lean.glsl)
#define SG_EVAL_TOKSVIG_FACTOR_IN(F)                                                               \
    F(float, s2, ("variance", sgGenPositive)) F(float, p, ("specular exponent", sgGenPositive))
#define SG_EVAL_TOKSVIG_FACTOR_OUT(F) F(float, k, ("factor in (0, 1]"))
SG_FN SgEvalOut sgEvalToksvigFactor(SgEvalIn sgRecIn) {
    SG_REC_READ(SG_EVAL_TOKSVIG_FACTOR_IN)
    SG_REC_DECLARE(SG_EVAL_TOKSVIG_FACTOR_OUT)
    k = sgToksvigFactor(s2, p);
    SG_REC_RETURN(SgEvalOut, SG_EVAL_TOKSVIG_FACTOR_OUT)
}
#define SG_EVAL_TOKSVIG_FACTOR(X)                                                                  \
    X(("toksvig-factor"), 34, sgEvalToksvigFactor, SG_EVAL_TOKSVIG_FACTOR_IN,                      \
      SG_EVAL_TOKSVIG_FACTOR_OUT, ("1 / (1 + p s2): Blinn-Phong exponent scale (Toksvig)"), Mixed, \
      1e-5, 0.02, ("one product and one division, the same in both builds: measured 0"),          \
      fieldInputs)

// ---------------------------------------------------------------------------
// The list, in id order.
#define SG_EVAL_KERNELS(X)                                                                         \
    SG_EVAL_RESOLVE(X)                                                                            \
    SG_EVAL_TSPACE_TO_DERIV(X)                                                                    \
    SG_EVAL_TBN(X)                                                                                \
    SG_EVAL_BASIS(X)                                                                              \
    SG_EVAL_PERTURBED(X)                                                                          \
    SG_EVAL_SCALE_DEPENDENT(X)                                                                    \
    SG_EVAL_VOLUME(X)                                                                             \
    SG_EVAL_TRIPLANAR_WEIGHTS(X)                                                                  \
    SG_EVAL_TRIPLANAR(X)                                                                          \
    SG_EVAL_DECAL(X)                                                                              \
    SG_EVAL_PROLOGUE(X)                                                                           \
    SG_EVAL_MIKKTS_BASIS(X)                                                                       \
    SG_EVAL_SCREEN_DERIV_OF_POS(X)                                                                \
    SG_EVAL_PARALLAX_PROJECT(X)                                                                   \
    SG_EVAL_TEXOFFS_TO_SURFACE(X)                                                                 \
    SG_EVAL_SCREEN_DERIV_SURFGRAD(X)                                                              \
    SG_EVAL_DERIV_TO_TSPACE(X)                                                                    \
    SG_EVAL_REPROLOGUE(X)                                                                         \
    SG_EVAL_BUMP_SCALE(X)                                                                         \
    SG_EVAL_DERIV_SCALE(X)                                                                        \
    SG_EVAL_DERIV_BLEND(X)                                                                        \
    SG_EVAL_DERIV_MODULATE(X)                                                                     \
    SG_EVAL_DERIV_CURVE(X)                                                                        \
    SG_EVAL_DERIV_DEFORM(X)                                                                       \
    SG_EVAL_DERIV_SINE_WARP(X)                                                                    \
    SG_EVAL_DECAL_VOLUME(X)                                                                       \
    SG_EVAL_HEIGHT_3TAP(X)                                                                        \
    SG_EVAL_BOUNDED_SCALE(X)                                                                      \
    SG_EVAL_HEIGHT_CENTRAL(X)                                                                     \
    SG_EVAL_CURVE_HERMITE(X)                                                                      \
    SG_EVAL_DERIV_MASK_BLEND(X)                                                                   \
    SG_EVAL_LEAN_SECOND(X)                                                                        \
    SG_EVAL_LEAN_COVARIANCE(X)                                                                    \
    SG_EVAL_TOKSVIG_VARIANCE(X)                                                                   \
    SG_EVAL_TOKSVIG_FACTOR(X)

#define SG_EVAL_DISPATCH(name, id, kernel, IN, OUT, summary, measure, tolerance, illShare, reason, \
                         inputs)                                                                  \
    if (kernelId == id) return kernel(x);

// The kernel with id kernelId on record x (zeros for an unknown id).
SG_FN SgEvalOut sgEvalKernel(int kernelId, SgEvalIn x) {
    SG_EVAL_KERNELS(SG_EVAL_DISPATCH)
    SgEvalOut y;
    sgRecClear(y);
    return y;
}

#endif
