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
//                                m = gain * mask, dm by central differences of
//                                the mask (one texel apart), per st unit
//   DEFORM   (A, B)              samples at the warp (s, t + A sin(B s)) and
//                                d' = J^T d (chain rule, "Deformation (2)-(4)")
// h and d share units: h per unit of st (the layer's height scale converts
// the stored height channel); a layer without a height channel has h = 0.
// DEFORM acts on the lookup, so it must be the first modifier (validated).
#ifndef SG_RENDER_DERIV_MODS_GLSL
#define SG_RENDER_DERIV_MODS_GLSL

#include "sg/render/common.glsl"
#include "sg/deriv_edit.glsl"

#define SG_MOD_MAX 4
#define SG_MOD_NONE 0
#define SG_MOD_SCALE 1
#define SG_MOD_CURVE 2
#define SG_MOD_MODULATE 3
#define SG_MOD_DEFORM 4

// Records: one vec4 per modifier, (kind, a, b, c) with
//   SCALE (1, alpha, 0, 0); CURVE (2, P, H, 0);
//   MODULATE (3, mask channel, gain, 0); DEFORM (4, A, B, 0).
struct SgDerivMods {
    vec4 op0;
    vec4 op1;
    vec4 op2;
    vec4 op3;
    int count;
};

SG_FN SgDerivMods sgUnpackDerivMods(vec4 r0, vec4 r1, vec4 r2, vec4 r3) {
    SgDerivMods m;
    m.op0 = r0;
    m.op1 = r1;
    m.op2 = r2;
    m.op3 = r3;
    m.count = 0;
    if (sgRecInt(r0.x) != SG_MOD_NONE) m.count = 1;
    if (m.count == 1 && sgRecInt(r1.x) != SG_MOD_NONE) m.count = 2;
    if (m.count == 2 && sgRecInt(r2.x) != SG_MOD_NONE) m.count = 3;
    if (m.count == 3 && sgRecInt(r3.x) != SG_MOD_NONE) m.count = 4;
    return m;
}

SG_FN vec4 sgDerivModOp(SgDerivMods m, int i) {
    if (i == 0) return m.op0;
    if (i == 1) return m.op1;
    if (i == 2) return m.op2;
    return m.op3;
}

// The warped lookup coordinate and the warp's Jacobian (identity when the
// first modifier is not DEFORM).
SG_FN vec2 sgDerivModsWarp(SgDerivMods m, vec2 st, SG_OUT(mat2) jac) {
    jac = mat2(1.0f);
    if (m.count > 0 && sgRecInt(m.op0.x) == SG_MOD_DEFORM) {
        jac = sgSineWarpJacobian(st.x, m.op0.y, m.op0.z);
        return vec2(st.x, st.y + m.op0.y * sin(m.op0.z * st.x));
    }
    return st;
}

// A height and its derivative, the state the modifiers transform.
struct SgHeightDeriv {
    float h;
    vec2 d;
};

// Applies the modifiers to a sample taken at the warped coordinate st (with
// the warped screen derivatives dSTdx/dSTdy for the mask lookups). mask is
// read only by MODULATE.
SG_FN SgHeightDeriv sgApplyDerivMods(SgDerivMods m, SgHeightDeriv s, mat2 jac, sampler2D mask,
                                     vec2 st, vec2 dSTdx, vec2 dSTdy) {
    SgHeightDeriv r = s;
    for (int i = 0; i < SG_MOD_MAX; ++i) {
        if (i >= m.count) break;
        vec4 op = sgDerivModOp(m, i);
        int kind = sgRecInt(op.x);
        if (kind == SG_MOD_SCALE) {
            r.d = sgDerivScale(r.d, op.y);
            r.h = op.y * r.h;
        } else if (kind == SG_MOD_CURVE) {
            r.d = sgDerivCurve(r.d, sgCurveBoostSlope(r.h, op.y, op.z));
            r.h = sgCurveBoostValue(r.h, op.y, op.z);
        } else if (kind == SG_MOD_MODULATE) {
            int ch = sgRecInt(op.y);
            vec2 texel = vec2(1.0f) / vec2(textureSize(mask, 0));
            float mc = op.z * sgTexelChannel(textureGrad(mask, st, dSTdx, dSTdy), ch);
            float ms1 = sgTexelChannel(textureGrad(mask, st + vec2(texel.x, 0.0f), dSTdx, dSTdy), ch);
            float ms0 = sgTexelChannel(textureGrad(mask, st - vec2(texel.x, 0.0f), dSTdx, dSTdy), ch);
            float mt1 = sgTexelChannel(textureGrad(mask, st + vec2(0.0f, texel.y), dSTdx, dSTdy), ch);
            float mt0 = sgTexelChannel(textureGrad(mask, st - vec2(0.0f, texel.y), dSTdx, dSTdy), ch);
            vec2 dm = op.z * vec2((ms1 - ms0) / (2.0f * texel.x), (mt1 - mt0) / (2.0f * texel.y));
            r.d = sgDerivModulate(r.d, r.h, dm, mc);
            r.h = r.h * mc;
        } else if (kind == SG_MOD_DEFORM) {
            // The lookup was warped by sgDerivModsWarp; the derivative of
            // h(warp(s, t)) is J^T times the derivative at the warped point.
            r.d = sgDerivDeform(r.d, jac);
        }
    }
    return r;
}

#endif
