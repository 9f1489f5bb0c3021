// Bump layer: derivative map edited in derivative space
// (sg/render/layer_deriv_map.glsl + sg/render/deriv_mods.glsl): sampled as
// a height and derivative, edited by one call per modifier, then turned
// into the surface gradient by sgDerivMapSurfgradHD. Compiled in only for
// layers that have modifiers.
#ifndef SG_RENDER_LAYER_DERIV_MAP_MODS_GLSL
#define SG_RENDER_LAYER_DERIV_MAP_MODS_GLSL

#include "sg/render/layer_deriv_map.glsl"
#include "sg/render/deriv_mods.glsl"

SG_FN SgHeightDeriv sgSampleDerivMapHD(sampler2D tex, vec2 st, vec2 dSTdx, vec2 dSTdy, SgDerivMapParams p) {
    SgHeightDeriv s;
    s.d = sgSampleDerivMap(tex, st, dSTdx, dSTdy, p);
    s.h = 0.0f;
    if (p.heightChannel >= 0) {
        s.h = p.heightScale * sgTexelChannel(textureGrad(tex, st, dSTdx, dSTdy), p.heightChannel);
    }
    return s;
}

// The surface gradient of the edited sample (listing 5 or 8 on hd.d).
SG_FN vec3 sgDerivMapSurfgradHD(SgFrame f, SgUvFrame uv, SgDerivMapParams p, SgHeightDeriv hd,
                                sampler2D tex) {
    return sgDerivMapSurfgrad(f, uv, p, hd.d, vec2(textureSize(tex, 0)));
}

#endif
