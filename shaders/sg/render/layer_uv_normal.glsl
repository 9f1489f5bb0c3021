// Bump layer: tangent-space normal map on any texture coordinate set.
// Mikkelsen 2019, listing 4 (normal to derivative, green-channel
// convention), listing 5 (TBN-style surface gradient), listing 6 / section
// 2.2 (the basis: per-pixel or vertex tangents, chosen per UV set by the
// caller through SgUvFrame), listing 2/3 (bump scale as `strength`).
// The bump strength does not depend on the tiling rate (TBN style,
// section 2.5); use a height or texel-space derivative layer for
// displacement-style bumps.
#ifndef SG_RENDER_LAYER_UV_NORMAL_GLSL
#define SG_RENDER_LAYER_UV_NORMAL_GLSL

#include "sg/render/common.glsl"

// Record r0 = (strength, encoding SG_ENC_*, flipV, heightChannel);
// r1 = (heightScale, 0, 0, 0). heightChannel (-1: none) names a channel
// holding the height whose derivative the map stores; only derivative-space
// modifiers (curves, modulate) read it. flipV: false for OpenGL-style maps
// (green up with a lower-left origin), true for DirectX-style (green down).
struct SgUvNormalParams {
    float strength;
    int encoding;
    bool flipV;
    int heightChannel;
    float heightScale;
};

SG_FN SgUvNormalParams sgUnpackUvNormal(vec4 r0, vec4 r1) {
    SgUvNormalParams p;
    p.strength = r0.x;
    p.encoding = sgRecInt(r0.y);
    p.flipV = sgRecBool(r0.z);
    p.heightChannel = sgRecInt(r0.w);
    p.heightScale = r1.x;
    return p;
}

// Surface gradient of the layer at the pixel.
SG_FN vec3 sgLayerUvNormal(SgUvFrame uv, SgUvNormalParams p, sampler2D tex) {
    vec2 d = sgSampleTspaceDeriv(tex, uv.st, uv.dSTdx, uv.dSTdy, p.encoding, p.flipV);
    return sgSurfgradFromTBN(sgBumpScale(p.strength, d), uv.vT, uv.vB);
}

#endif
