// Bump layer: derivative map edited in derivative space
// (sg/render/layer_deriv_map.glsl + sg/render/deriv_mods.glsl). Compiled in
// only for layers that have modifiers.
#ifndef SG_RENDER_LAYER_DERIV_MAP_MODS_GLSL
#define SG_RENDER_LAYER_DERIV_MAP_MODS_GLSL

#include "sg/render/layer_deriv_map.glsl"
#include "sg/render/deriv_mods.glsl"

SG_FN vec3 sgLayerDerivMapMods(SgFrame f, SgUvFrame uv, SgDerivMapParams p, SgDerivMods m,
                               sampler2D tex, sampler2D mask) {
    mat2 jac;
    vec2 st = sgDerivModsWarp(m, uv.st, jac);
    vec2 dSTdx = jac * uv.dSTdx;
    vec2 dSTdy = jac * uv.dSTdy;
    SgHeightDeriv s;
    s.d = sgSampleDerivMap(tex, st, dSTdx, dSTdy, p);
    s.h = 0.0f;
    if (p.heightChannel >= 0) {
        s.h = p.heightScale * sgTexelChannel(textureGrad(tex, st, dSTdx, dSTdy), p.heightChannel);
    }
    s = sgApplyDerivMods(m, s, jac, mask, st, dSTdx, dSTdy);
    return sgDerivMapSurfgrad(f, uv, p, s.d, vec2(textureSize(tex, 0)));
}

#endif
