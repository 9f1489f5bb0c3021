// Bump layer: tangent-space normal map edited in derivative space
// (sg/render/layer_uv_normal.glsl + sg/render/deriv_mods.glsl; Loviscach
// 2008 on top of Mikkelsen 2019 listings 4 and 5). The assembled program
// samples the map as a height and derivative, applies the layer's
// modifiers one call each, then turns the derivative into the surface
// gradient. Compiled in only for layers that have modifiers.
#ifndef SG_RENDER_LAYER_UV_NORMAL_MODS_GLSL
#define SG_RENDER_LAYER_UV_NORMAL_MODS_GLSL

#include "sg/render/layer_uv_normal.glsl"
#include "sg/render/deriv_mods.glsl"

// The map at st (possibly warped) as a derivative (listing 4) and the
// height of its height channel (0 without one).
SG_FN SgHeightDeriv sgSampleUvNormalHD(sampler2D tex, vec2 st, vec2 dSTdx, vec2 dSTdy, SgUvNormalParams p) {
    vec4 texel = textureGrad(tex, st, dSTdx, dSTdy);
    SgHeightDeriv s;
    s.d = sgTspaceNormalToDeriv(sgDecodeNormalXY(texel, p.encoding), p.flipV);
    s.h = p.heightChannel >= 0 ? p.heightScale * sgTexelChannel(texel, p.heightChannel) : 0.0f;
    return s;
}

// The edited derivative as a TBN-style surface gradient (listing 5).
SG_FN vec3 sgUvNormalSurfgrad(SgUvFrame uv, SgUvNormalParams p, SgHeightDeriv s) {
    return sgSurfgradFromTBN(sgBumpScale(p.strength, s.d), uv.vT, uv.vB);
}

#endif
