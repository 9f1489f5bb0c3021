// Slope distributions of normal maps within a pixel footprint, shared by
// the antialiased layer kinds that read tangent-space normal maps
// (uv_normal, triplanar, decal): the mean slope and the covariance of the
// slopes, from moment textures that filter linearly. Olano and Baker 2010
// (LEAN, sections 3-4); Toksvig 2005; the moment math is sg/lean.glsl.
//
// Moment textures (built when the scene loads, from the layer's map through
// sgUvNormalMomentTexel below, mip chains of box averages):
//   LEAN    - texA = (E[d.x], E[d.y], E[d.x^2], E[d.y^2]), texB.x = E[d.x d.y];
//   Toksvig - texA.xyz = E[n], n = sgDerivToTspaceNormal(d) the unit normal.
// d is the file's slope (listing 4 with flipV false); the layer's green
// convention is applied after filtering (d.y and cov xy change sign).
#ifndef SG_RENDER_SLOPE_DIST_GLSL
#define SG_RENDER_SLOPE_DIST_GLSL

#include "sg/lean.glsl"
#include "sg/render/common.glsl"

#define SG_AA_LEAN 1
#define SG_AA_TOKSVIG 2

// Level-0 texels of the moment textures of one map texel (mode SG_AA_*):
// out a (texA) and b (texB, LEAN only).
SG_FN void sgUvNormalMomentTexel(vec4 texel, int encoding, int mode, SG_OUT(vec4) a,
                                 SG_OUT(vec4) b) {
    vec2 d = sgTspaceNormalToDeriv(sgDecodeNormalXY(texel, encoding), false);
    if (mode == SG_AA_LEAN) {
        vec3 m = sgLeanSecondMoments(d);
        a = vec4(d.x, d.y, m.x, m.y);
        b = vec4(m.z, 0.0f, 0.0f, 1.0f);
    } else {
        vec3 n = sgDerivToTspaceNormal(d, false);
        a = vec4(n.x, n.y, n.z, 1.0f);
        b = vec4(0.0f, 0.0f, 0.0f, 1.0f);
    }
}

// A slope distribution: mean slope and covariance (var x, var y, cov xy).
struct SgSlopeDist {
    vec2 mean;
    vec3 cov;
};

// The green convention after filtering: t flips, so d.y and cov xy do.
SG_FN SgSlopeDist sgSlopeDistFlipV(SgSlopeDist s, bool flipV) {
    if (flipV) {
        s.mean.y = -s.mean.y;
        s.cov.z = -s.cov.z;
    }
    return s;
}

// LEAN: filtered first and second moments -> mean and covariance.
SG_FN SgSlopeDist sgSampleLeanSlopes(sampler2D texA, sampler2D texB, vec2 st, vec2 dSTdx,
                                     vec2 dSTdy, bool flipV) {
    vec4 a = textureGrad(texA, st, dSTdx, dSTdy);
    vec4 b = textureGrad(texB, st, dSTdx, dSTdy);
    SgSlopeDist s;
    s.mean = vec2(a.x, a.y);
    s.cov = sgLeanCovariance(s.mean, vec3(a.z, a.w, b.x));
    return sgSlopeDistFlipV(s, flipV);
}

// Toksvig: the filtered unit normal's length gives an isotropic variance
// s2 per axis (sgToksvigVariance); the mean slope is that of the
// renormalised average normal (listing 4).
SG_FN SgSlopeDist sgSampleToksvigSlopes(sampler2D texA, vec2 st, vec2 dSTdx, vec2 dSTdy,
                                        bool flipV) {
    vec4 a = textureGrad(texA, st, dSTdx, dSTdy);
    vec3 n = vec3(a.x, a.y, a.z);
    float s2 = sgToksvigVariance(n);
    vec3 nUnit = sgSafeNormalize(n, vec3(0.0f, 0.0f, 1.0f));
    SgSlopeDist s;
    s.mean = sgTspaceNormalToDeriv(vec2(nUnit.x, nUnit.y), false);
    s.cov = vec3(s2, s2, 0.0f);
    return sgSlopeDistFlipV(s, flipV);
}

// Either measure (mode SG_AA_LEAN or SG_AA_TOKSVIG): Toksvig reads texA
// only (texB may be any sampler, e.g. texA again).
SG_FN SgSlopeDist sgSampleSlopes(int mode, sampler2D texA, sampler2D texB, vec2 st, vec2 dSTdx,
                                 vec2 dSTdy, bool flipV) {
    if (mode == SG_AA_LEAN) return sgSampleLeanSlopes(texA, texB, st, dSTdx, dSTdy, flipV);
    return sgSampleToksvigSlopes(texA, st, dSTdx, dSTdy, flipV);
}

#endif
