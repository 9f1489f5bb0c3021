// Derivative-space modifiers of a UV layer (uv_normal, deriv_map):
// Loviscach, "Care and Feeding of Normal Vectors" (GDC 2008), the
// operations of sg/deriv_edit.glsl applied to the conceptual height h of a
// layer and its derivative d = (dh/ds, dh/dt), before the derivative becomes
// a surface gradient (Mikkelsen 2019, listing 5 or 8). Each modifier maps
// (h, d) to (h', d') exactly as the operation on the height field would:
//   SCALE    (alpha)             h' = alpha h,     d' = alpha d
//   CURVE    (P, H)              h' = f(h),        d' = f'(h) d,
//                                f' = 1 / (1 + P (h - H)^2)       ("Curves (5)")
//   MODULATE (mask channel, gain) h' = h m,        d' = d m + h dm ("Modulation"),
//                                m = gain * mask at the lookup coordinate, dm by
//                                central differences of the mask (one texel
//                                apart), per st unit, through the warp's
//                                Jacobian like the map's derivative
//   DEFORM   (A, B)              samples at the warp (s, t + A sin(B s)) and
//                                d' = J^T d (chain rule, "Deformation (2)-(4)")
// h and d share units: h per unit of st (the layer's height scale converts
// the stored height channel); a layer without a height channel has h = 0.
// DEFORM acts on the lookup, so it must be the first modifier (validated).
#ifndef SG_RENDER_DERIV_MODS_GLSL
#define SG_RENDER_DERIV_MODS_GLSL

#include "sg/render/common.glsl"
#include "sg/deriv_edit.glsl"

// Record ids (x of each record); the C++ registry entries
// (sg/render/deriv_mods.cpp) use these names, not copies of the numbers.
#define SG_MOD_SCALE 1
#define SG_MOD_CURVE 2
#define SG_MOD_MODULATE 3
#define SG_MOD_DEFORM 4

// Records: one vec4 per modifier, (kind, a, b, c) with
//   SCALE (1, alpha, 0, 0); CURVE (2, P, H, 0);
//   MODULATE (3, mask channel, gain, 0); DEFORM (4, A, B, 0).
// The assembled program calls one function per modifier, in order, so only
// the modifier kinds a layer uses are compiled in and no branch depends on
// a uniform (render/src/plan.cpp).

// A height and its derivative, the state the modifiers transform.
struct SgHeightDeriv {
    float h;
    vec2 d;
};

// DEFORM, part 1: the warped lookup coordinate st' = (s, t + A sin(B s))
// and the warp's Jacobian J (column-major: columns d/ds and d/dt).
SG_FN vec2 sgModWarp(vec4 op, vec2 st, SG_OUT(mat2) jac) {
    jac = sgSineWarpJacobian(st.x, op.y, op.z);
    return vec2(st.x, st.y + op.y * sin(op.z * st.x));
}

// DEFORM: a screen derivative of st carried to the warped lookup, J v
// (GLSL's `jac * v`, written by columns: the subset never multiplies a
// matrix by a vector, since HLSL holds the transpose, sg/compat.hlsl). The
// assembled modifier block calls it for dx and dy (render/src/layers/deriv_mods.cpp).
SG_FN vec2 sgModWarpDeriv(mat2 jac, vec2 v) {
    return jac[0] * v.x + jac[1] * v.y;
}

// The lookup's Jacobian without DEFORM: the identity (GLSL's mat2(1.0f);
// HLSL's float2x2(1.0f) is a matrix of ones, not the identity).
SG_FN mat2 sgModNoWarp() {
    return mat2(vec2(1.0f, 0.0f), vec2(0.0f, 1.0f));
}

// DEFORM, part 2: the derivative of h(warp(s, t)) is J^T times the
// derivative sampled at the warped point (the height is unchanged).
SG_FN SgHeightDeriv sgModDeform(SgHeightDeriv s, mat2 jac) {
    SgHeightDeriv r = s;
    r.d = sgDerivDeform(s.d, jac);
    return r;
}

SG_FN SgHeightDeriv sgModScale(SgHeightDeriv s, vec4 op) {
    SgHeightDeriv r;
    r.d = sgDerivScale(s.d, op.y);
    r.h = op.y * s.h;
    return r;
}

SG_FN SgHeightDeriv sgModCurve(SgHeightDeriv s, vec4 op) {
    SgHeightDeriv r;
    r.d = sgDerivCurve(s.d, sgCurveBoostSlope(s.h, op.y, op.z));
    r.h = sgCurveBoostValue(s.h, op.y, op.z);
    return r;
}

// MODULATE by a mask sampled at st (the layer's lookup coordinate: warped
// when the layer's first modifier is DEFORM) with the layer's screen
// derivatives. dm by central differences one texel apart is the mask's
// derivative w.r.t. the lookup coordinate; the mask as the layer sees it,
// m(w(s, t)), has the derivative J^T dm (chain rule, "Deformation (2)"),
// exactly as the map's derivative (sgModDeform). jac: the warp's Jacobian
// from sgModWarp, the identity without DEFORM.
SG_FN SgHeightDeriv sgModModulate(SgHeightDeriv s, vec4 op, sampler2D mask, vec2 st, vec2 dSTdx,
                                  vec2 dSTdy, mat2 jac) {
    int ch = sgRecInt(op.y);
    vec2 texel = sgVec2(1.0f) / vec2(textureSize(mask, 0));
    float mc = op.z * sgTexelChannel(textureGrad(mask, st, dSTdx, dSTdy), ch);
    float ms1 = sgTexelChannel(textureGrad(mask, st + vec2(texel.x, 0.0f), dSTdx, dSTdy), ch);
    float ms0 = sgTexelChannel(textureGrad(mask, st - vec2(texel.x, 0.0f), dSTdx, dSTdy), ch);
    float mt1 = sgTexelChannel(textureGrad(mask, st + vec2(0.0f, texel.y), dSTdx, dSTdy), ch);
    float mt0 = sgTexelChannel(textureGrad(mask, st - vec2(0.0f, texel.y), dSTdx, dSTdy), ch);
    vec2 dmAtLookup = op.z * vec2((ms1 - ms0) / (2.0f * texel.x), (mt1 - mt0) / (2.0f * texel.y));
    vec2 dm = sgDerivDeform(dmAtLookup, jac);
    SgHeightDeriv r;
    r.d = sgDerivModulate(s.d, s.h, dm, mc);
    r.h = s.h * mc;
    return r;
}

#endif
