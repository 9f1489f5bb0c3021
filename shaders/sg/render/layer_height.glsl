// Bump layer: height map, displacement style (scale dependent). Mikkelsen
// 2019, section 2.5: listing 9 (3-tap forward differences of the height in
// screen space) and listing 8 with isDerivScreenSpace (eq. 3 of Mikkelsen
// 2010). The bumps are those of the displaced surface p + h * n: they grow
// steeper when the map tiles more densely or the surface shrinks.
#ifndef SG_RENDER_LAYER_HEIGHT_GLSL
#define SG_RENDER_LAYER_HEIGHT_GLSL

#include "sg/render/common.glsl"

// Record r0 = (scale, channel, 0, 0): displacement = scale * channel value,
// in world units.
struct SgHeightParams {
    float scale;
    int channel;
};

SG_FN SgHeightParams sgUnpackHeight(vec4 r0) {
    SgHeightParams p;
    p.scale = r0.x;
    p.channel = sgRecInt(r0.y);
    return p;
}

SG_FN vec3 sgLayerHeight(SgFrame f, SgUvFrame uv, SgHeightParams p, sampler2D tex) {
    float hll = sgTexelChannel(textureGrad(tex, uv.st, uv.dSTdx, uv.dSTdy), p.channel);
    float hlr = sgTexelChannel(textureGrad(tex, uv.st + uv.dSTdx, uv.dSTdx, uv.dSTdy), p.channel);
    float hul = sgTexelChannel(textureGrad(tex, uv.st + uv.dSTdy, uv.dSTdx, uv.dSTdy), p.channel);
    vec2 dHdxy = p.scale * sgHeightDeriv3Tap(hll, hlr, hul);
    return sgSurfgradFromScreenDeriv(f, dHdxy);
}

#endif
