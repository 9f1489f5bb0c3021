// Antialiased tangent-space normal map (layer kind uv_normal with
// "antialias": "lean" or "toksvig"): the layer's mean slope and the
// covariance of its slopes within the pixel footprint, from textures that
// filter linearly (sg/lean.glsl), carried into the frame with the layer's
// own Jacobian (sg/render/antialias.glsl). Olano and Baker 2010 (LEAN,
// sections 3-4); Toksvig 2005; Mikkelsen 2019, listings 4 and 5.
//
// The moment textures and their sampling: sg/render/slope_dist.glsl.
#ifndef SG_RENDER_LAYER_UV_NORMAL_AA_GLSL
#define SG_RENDER_LAYER_UV_NORMAL_AA_GLSL

#include "sg/render/antialias.glsl"
#include "sg/render/layer_uv_normal.glsl"
#include "sg/render/slope_dist.glsl"

// The layer's surface gradient (listing 5 on the mean slope, times the
// strength) and, added to slopeCov, its covariance mapped by the same
// Jacobian strength * [vT vB].
SG_FN vec3 sgUvNormalAaSurfgrad(SgUvFrame uv, SgUvNormalParams p, SgSlopeDist s,
                                SG_INOUT(mat3) slopeCov) {
    vec3 a = p.strength * uv.vT;
    vec3 b = p.strength * uv.vB;
    slopeCov = slopeCov + sgSlopeCovToFrame(s.cov, a, b);
    return sgSurfgradFromTBN(sgBumpScale(p.strength, s.mean), uv.vT, uv.vB);
}

SG_FN vec3 sgLayerUvNormalLean(SgUvFrame uv, SgUvNormalParams p, sampler2D texA, sampler2D texB,
                               SG_INOUT(mat3) slopeCov) {
    SgSlopeDist s = sgSampleLeanSlopes(texA, texB, uv.st, uv.dSTdx, uv.dSTdy, p.flipV);
    return sgUvNormalAaSurfgrad(uv, p, s, slopeCov);
}

SG_FN vec3 sgLayerUvNormalToksvig(SgUvFrame uv, SgUvNormalParams p, sampler2D texA,
                                  SG_INOUT(mat3) slopeCov) {
    SgSlopeDist s = sgSampleToksvigSlopes(texA, uv.st, uv.dSTdx, uv.dSTdy, p.flipV);
    return sgUvNormalAaSurfgrad(uv, p, s, slopeCov);
}

#endif
