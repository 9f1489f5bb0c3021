// Bump layer: derivative map (the texture stores dH/ds, dH/dt directly;
// Mikkelsen 2019, section 2.1: derivatives blend linearly, unlike normals).
//   TBN style     - derivative per unit of s and t, applied with the basis
//                   of the UV set (listing 5): strength independent of tiling;
//   texel space   - derivative in height units per texel (listing 8):
//                   displacement-style, scale dependent (section 2.5).
#ifndef SG_RENDER_LAYER_DERIV_MAP_GLSL
#define SG_RENDER_LAYER_DERIV_MAP_GLSL

#include "sg/render/common.glsl"

// Record r0 = (strength, signedTexels, range, texelSpace);
// r1 = (flipV, heightChannel, heightScale, 0).
// signedTexels: the texels hold the signed derivative (float maps); else
// d = (2 * rg - 1) * range (unorm maps). heightChannel (-1: none) holds the
// height, read only by derivative-space modifiers (sg/render/deriv_mods.glsl).
struct SgDerivMapParams {
    float strength;
    bool signedTexels;
    float range;
    bool texelSpace;
    bool flipV;
    int heightChannel;
    float heightScale;
};

SG_FN SgDerivMapParams sgUnpackDerivMap(vec4 r0, vec4 r1) {
    SgDerivMapParams p;
    p.strength = r0.x;
    p.signedTexels = sgRecBool(r0.y);
    p.range = r0.z;
    p.texelSpace = sgRecBool(r0.w);
    p.flipV = sgRecBool(r1.x);
    p.heightChannel = sgRecInt(r1.y);
    p.heightScale = r1.z;
    return p;
}

SG_FN vec2 sgSampleDerivMap(sampler2D tex, vec2 st, vec2 dSTdx, vec2 dSTdy, SgDerivMapParams p) {
    vec4 texel = textureGrad(tex, st, dSTdx, dSTdy);
    vec2 d = p.signedTexels ? vec2(texel.x, texel.y)
                            : p.range * vec2(2.0f * texel.x - 1.0f, 2.0f * texel.y - 1.0f);
    if (p.flipV) d.y = -d.y;
    return d;
}

// Surface gradient from a derivative already sampled (and possibly edited).
SG_FN vec3 sgDerivMapSurfgrad(SgFrame f, SgUvFrame uv, SgDerivMapParams p, vec2 d, vec2 texDim) {
    vec2 ds = sgBumpScale(p.strength, d);
    if (p.texelSpace) return sgSurfgradScaleDependent(f, ds, uv.dSTdx, uv.dSTdy, texDim);
    return sgSurfgradFromTBN(ds, uv.vT, uv.vB);
}

SG_FN vec3 sgLayerDerivMap(SgFrame f, SgUvFrame uv, SgDerivMapParams p, sampler2D tex) {
    vec2 d = sgSampleDerivMap(tex, uv.st, uv.dSTdx, uv.dSTdy, p);
    return sgDerivMapSurfgrad(f, uv, p, d, vec2(textureSize(tex, 0)));
}

#endif
