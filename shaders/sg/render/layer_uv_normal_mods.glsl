// Bump layer: tangent-space normal map edited in derivative space
// (sg/render/layer_uv_normal.glsl + sg/render/deriv_mods.glsl; Loviscach
// 2008 on top of Mikkelsen 2019 listings 4 and 5). Compiled in only for
// layers that have modifiers.
#ifndef SG_RENDER_LAYER_UV_NORMAL_MODS_GLSL
#define SG_RENDER_LAYER_UV_NORMAL_MODS_GLSL

#include "sg/render/layer_uv_normal.glsl"
#include "sg/render/deriv_mods.glsl"

// mask is read only by MODULATE modifiers (bind any texture otherwise).
SG_FN vec3 sgLayerUvNormalMods(SgUvFrame uv, SgUvNormalParams p, SgDerivMods m, sampler2D tex,
                               sampler2D mask) {
    mat2 jac;
    vec2 st = sgDerivModsWarp(m, uv.st, jac);
    vec2 dSTdx = jac * uv.dSTdx;
    vec2 dSTdy = jac * uv.dSTdy;
    vec4 texel = textureGrad(tex, st, dSTdx, dSTdy);
    SgHeightDeriv s;
    s.d = sgTspaceNormalToDeriv(sgDecodeNormalXY(texel, p.encoding), p.flipV);
    s.h = p.heightChannel >= 0 ? p.heightScale * sgTexelChannel(texel, p.heightChannel) : 0.0f;
    s = sgApplyDerivMods(m, s, jac, mask, st, dSTdx, dSTdy);
    return sgSurfgradFromTBN(sgBumpScale(p.strength, s.d), uv.vT, uv.vB);
}

#endif
