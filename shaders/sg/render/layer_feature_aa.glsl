// Antialiased feature-curve layer (layer kind feature with "antialias":
// "lean"): the exact evaluator of Parilov, Rosenberg, Zorin (TR2005-872)
// and Parilov, Zorin (TOG 2008) while the pixel footprint is below a texel,
// blending continuously into a prefiltered chain of slope moments (LEAN
// mapping, Olano and Baker 2010, sections 3-4) above it, its covariance
// added to the frame's slope covariance with the layer's Jacobian
// strength * [vT vB] (sg/render/antialias.glsl; Mikkelsen 2019, listing 5).
//
// The chain (built when the scene loads, render/src/layers/layer_feature.cpp,
// featureChainTexture): level 0 texel (i, j) holds the averages over the
// texel square [i, i+1] x [j, j+1] (texel space) of the layer's slope d on a
// flat base (sgFeatAaSlope) and of its second moments:
//   texA = (E[d.x], E[d.y], E[d.x^2], E[d.y^2]),  texB.x = E[d.x d.y];
// smaller levels are box averages of level 0 (makeTexture), so every level
// holds the true average over its footprint. The chain spans the map's
// [0, N]^2 as st' = st * tiling + offset in [0, 1]^2, clamped at the border
// like the evaluator.
//
// Switch: rho = GL's footprint (OpenGL 4.5 eq. 8.7/8.8) in map texels.
// The layer's slope distribution is the chain's covariance C (read at the
// footprint's level: trilinear, continuous in rho) about the mean
// mix(d, m, w), d the exact sample at the pixel's centre, m the chain's
// mean, w = smoothstep(0, 1, log2 rho): the exact mean up to one texel
// (where the chain's level 0 is coarser than the pixel), the chain's from
// two. Below one texel C is level 0's one-texel spread scaled by rho^2 (a
// smooth field's variance grows with the footprint's area), fading to 0 at
// 1/8 texel. Mean and covariance are continuous in rho, and the spread
// grows with the footprint as the supersampled truth's does, so the
// radiance neither steps nor overshoots at the switch (docs/accuracy-cost.md,
// table 10, measures it). A mixture reading (point mass d with weight 1 - w,
// covariance w C + w (1 - w)(d - m)(d - m)^T) was measured first: its
// between-term widens the lobe within a few 1/16-octave steps above one
// texel where d is far from m, a visible pop (0.198 against the truth's
// 0.023).
#ifndef SG_RENDER_LAYER_FEATURE_AA_GLSL
#define SG_RENDER_LAYER_FEATURE_AA_GLSL

#include "sg/lean.glsl"
#include "sg/render/antialias.glsl"
#include "sg/render/layer_feature.glsl"

// Record r2 of the feature layer, slot z (which sgUnpackFeatureLayer leaves
// 0): whether the layer antialiases ("antialias": "lean").
struct SgFeatureAaParams {
    bool lean;
};

SG_FN SgFeatureAaParams sgUnpackFeatureAa(vec4 r2) {
    SgFeatureAaParams a;
    a.lean = sgRecBool(r2.z);
    return a;
}

// The slope (texel-space derivative) of the layer on a flat base at a
// sampled result r: the quantity the chain averages and the exact branch
// uses (the base map does not combine with "lean").
SG_FN vec2 sgFeatAaSlope(SgFeatResult r, SgFeatProfile pr, bool paperMode) {
    if (paperMode) {
        vec3 n = sgFeatNormalPaper(r, pr, vec3(0.0f, 0.0f, 1.0f));
        return sgTspaceNormalToDeriv(vec2(n.x, n.y), false);
    }
    return sgFeatDeriv(r, pr, sgVec2(0.0f));
}

// A result far from every curve (no slope): what the layer holds where the
// chain alone is used and the evaluator is skipped.
SG_FN SgFeatResult sgFeatAaFarResult() {
    SgFeatResult r;
    r.dist = 1e4f;
    r.grad = sgVec2(0.0f);
    r.side = 1.0f;
    r.profile = -1;
    r.width = 0.0f;
    return r;
}

// The chain's moment texels of one slope d (level 0 averages these).
SG_FN void sgFeatAaMomentTexel(vec2 d, SG_OUT(vec4) a, SG_OUT(vec4) b) {
    vec3 m = sgLeanSecondMoments(d);
    a = vec4(d.x, d.y, m.x, m.y);
    b = vec4(m.z, 0.0f, 0.0f, 1.0f);
}

// The pixel footprint in map texels: rho of OpenGL 4.5 eq. 8.7/8.8 (what
// selects the chain's level).
SG_FN float sgFeatAaFootprintTexels(SgUvFrame uv, SgFeatureLayerParams p) {
    float k = p.tiling * p.mapSize;
    return max(length(uv.dSTdx * k), length(uv.dSTdy * k));
}

// Weight of the chain's MEAN: 0 up to one texel, 1 from two, smoothstep in
// log2 between. A zero footprint (magnification to a point) gives 0.
SG_FN float sgFeatAaChainWeight(float rhoTexels) {
    return smoothstep(0.0f, 1.0f, log2(max(rhoTexels, 1e-30f)));
}

// Share of the chain's COVARIANCE: the spread of the slopes over a
// footprint of rho texels. From one texel on the chain itself holds it
// (trilinear at the footprint's level, continuous in rho); below, level 0
// (the one-texel spread) scaled by rho^2, the growth of a smooth field's
// variance with the footprint's area, reaching 0 at 1/8 texel so that
// strongly magnified pixels skip the chain reads. Continuous everywhere:
// the lobe widens as the truth's spread does, with no step at the switch.
SG_FN float sgFeatAaCovScale(float rhoTexels) {
    const float r0 = 1.0f / 64.0f; // (1/8 texel)^2
    return clamp((rhoTexels * rhoTexels - r0) / (1.0f - r0), 0.0f, 1.0f);
}

// The layer's distribution at footprint rho from the exact slope dExact
// (read only when the mean weight w < 1) and the chain (read only when the
// covariance share is above 0): the surface gradient of its mean
// mix(dExact, chain mean, w), the chain's covariance times
// sgFeatAaCovScale added to slopeCov.
SG_FN vec3 sgFeatAaCombine(SgUvFrame uv, SgFeatureLayerParams p, vec2 dExact, float rhoTexels,
                           sampler2D chainA, sampler2D chainB, SG_INOUT(mat3) slopeCov) {
    vec2 mean = dExact;
    vec3 cov = sgVec3(0.0f);
    float covScale = sgFeatAaCovScale(rhoTexels);
    if (covScale > 0.0f) {
        vec2 st = uv.st * p.tiling + p.offset;
        vec2 dx = uv.dSTdx * p.tiling;
        vec2 dy = uv.dSTdy * p.tiling;
        vec4 a = textureGrad(chainA, st, dx, dy);
        vec4 b = textureGrad(chainB, st, dx, dy);
        vec2 mChain = vec2(a.x, a.y);
        mean = mix(dExact, mChain, sgFeatAaChainWeight(rhoTexels));
        cov = covScale * sgLeanCovariance(mChain, vec3(a.z, a.w, b.x));
    }
    vec3 ja = p.strength * uv.vT;
    vec3 jb = p.strength * uv.vB;
    slopeCov = slopeCov + sgSlopeCovToFrame(cov, ja, jb);
    return sgSurfgradFromTBN(sgBumpScale(p.strength, mean), uv.vT, uv.vB);
}

// As sgLayerFeature; layers with aa.lean take the switch (baseMap unread),
// the others are today's layer (chainA, chainB unread). One evaluator call
// site for both, skipped only where the chain alone is used: a GPU that
// executes both sides of a divergent branch (llvmpipe does) would
// otherwise run the evaluator twice.
SG_FN vec3 sgLayerFeatureAa(SgUvFrame uv, SgFeatureLayerParams p, SgFeatureAaParams aa, SgFeatProfile pr,
                            SG_FEAT_CORNER_SAMPLER corners, SG_FEAT_EDGE_SAMPLER edges,
                            sampler2D baseMap, sampler2D chainA, sampler2D chainB,
                            SG_INOUT(mat3) slopeCov) {
    float rho = sgFeatAaFootprintTexels(uv, p);
    SgFeatResult r = sgFeatAaFarResult();
    if (!aa.lean || sgFeatAaChainWeight(rho) < 1.0f)
        r = sgFeatSample(corners, edges, sgFeatureLayerTexelPos(uv, p));
    if (!aa.lean) return sgLayerFeatureFrom(uv, p, pr, r, baseMap);
    vec2 dExact = sgFeatAaSlope(r, pr, p.paperMode);
    return sgFeatAaCombine(uv, p, dExact, rho, chainA, chainB, slopeCov);
}

#if SG_FEAT_NEAR
// As sgLayerFeatureNear, with the switch for layers with aa.lean (one
// evaluator call site, as sgLayerFeatureAa).
SG_FN vec3 sgLayerFeatureNearAa(SgUvFrame uv, SgFeatureLayerParams p, SgFeatureAaParams aa,
                                SgFeatProfile pr,
                                SG_FEAT_CORNER_SAMPLER corners, SG_FEAT_EDGE_SAMPLER edges,
                                SG_FEAT_NEAR_SAMPLER nearMap, SG_FEAT_PIECE_SAMPLER pieces,
                                sampler2D baseMap, sampler2D chainA, sampler2D chainB,
                                SG_INOUT(mat3) slopeCov) {
    float rho = sgFeatAaFootprintTexels(uv, p);
    SgFeatResult r = sgFeatAaFarResult();
    SgFeatProfile prc = pr;
    if (!aa.lean || sgFeatAaChainWeight(rho) < 1.0f) {
        vec2 texelPos = sgFeatureLayerTexelPos(uv, p);
        if (p.nearExact) {
            r = sgFeatSampleNear(corners, edges, nearMap, pieces, texelPos);
            prc = sgFeatCurveProfile(pieces, pr, r);
        } else {
            r = sgFeatSample(corners, edges, texelPos);
        }
    }
    if (!aa.lean) return sgLayerFeatureFrom(uv, p, prc, r, baseMap);
    vec2 dExact = sgFeatAaSlope(r, prc, p.paperMode);
    return sgFeatAaCombine(uv, p, dExact, rho, chainA, chainB, slopeCov);
}
#endif

#endif
