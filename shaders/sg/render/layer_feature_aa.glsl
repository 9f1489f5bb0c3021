// Antialiased feature-curve layer (layer kind feature with "antialias":
// "lean"): the exact evaluator of Parilov, Rosenberg, Zorin (TR2005-872)
// and Parilov, Zorin (TOG 2008) while the pixel footprint is below a texel,
// blending continuously into a prefiltered chain of slope moments (LEAN
// mapping, Olano and Baker 2010, sections 3-4) above it, its covariance
// added to the frame's slope covariance with the layer's Jacobian
// strength * [vT vB] (sg/render/antialias.glsl; Mikkelsen 2019, listing 5).
//
// The chain (built when the scene loads, shaders/sg/render/layer_feature.cpp,
// featureChainTexture): level 0 texel (i, j) holds the averages over the
// texel square [i, i+1] x [j, j+1] (texel space) of the layer's slope d on a
// flat base (sgFeatAaSlope) and of its second moments:
//   texA = (E[d.x], E[d.y], E[d.x^2], E[d.y^2]),  texB.x = E[d.x d.y];
// smaller levels are box averages of level 0 (makeTexture), so every level
// holds the true average over its footprint. The chain spans the map's
// [0, N]^2 as st' = st * tiling + offset in [0, 1]^2, clamped at the border
// like the evaluator.
//
// Switch: rho = GL's footprint (OpenGL 4.5 eq. 8.7/8.8) in map texels,
// w = smoothstep(0, 1, log2 rho): exact (w = 0) up to one texel, the chain
// alone (w = 1) from two texels, continuous (C1 in log2 rho) in between.
// Between, the layer's slope distribution is the mixture of the exact
// sample (a point mass, weight 1 - w) and the chain's distribution (mean m,
// covariance C, weight w): mean (1 - w) d + w m, covariance
// w C + w (1 - w) (d - m)(d - m)^T. Both are continuous in w, so the
// radiance does not jump at the switch.
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
    return sgFeatDeriv(r, pr, vec2(0.0f));
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

// Weight of the chain: 0 up to one texel, 1 from two, smoothstep in log2
// between. A zero footprint (magnification to a point) gives 0.
SG_FN float sgFeatAaChainWeight(float rhoTexels) {
    return smoothstep(0.0f, 1.0f, log2(max(rhoTexels, 1e-30f)));
}

// The layer's distribution at chain weight w from the exact slope dExact
// (read only when w < 1) and the chain (read only when w > 0): the surface
// gradient of its mean, its covariance added to slopeCov.
SG_FN vec3 sgFeatAaCombine(SgUvFrame uv, SgFeatureLayerParams p, vec2 dExact, float w,
                           sampler2D chainA, sampler2D chainB, SG_INOUT(mat3) slopeCov) {
    vec2 mean = dExact;
    vec3 cov = vec3(0.0f);
    if (w > 0.0f) {
        vec2 st = uv.st * p.tiling + p.offset;
        vec2 dx = uv.dSTdx * p.tiling;
        vec2 dy = uv.dSTdy * p.tiling;
        vec4 a = textureGrad(chainA, st, dx, dy);
        vec4 b = textureGrad(chainB, st, dx, dy);
        vec2 mChain = vec2(a.x, a.y);
        vec3 cChain = sgLeanCovariance(mChain, vec3(a.z, a.w, b.x));
        vec2 diff = dExact - mChain;
        float k = w * (1.0f - w);
        mean = mix(dExact, mChain, w);
        cov = w * cChain + k * vec3(diff.x * diff.x, diff.y * diff.y, diff.x * diff.y);
    }
    vec3 ja = p.strength * uv.vT;
    vec3 jb = p.strength * uv.vB;
    slopeCov = slopeCov + sgSlopeCovToFrame(cov, ja, jb);
    return sgSurfgradFromTBN(sgBumpScale(p.strength, mean), uv.vT, uv.vB);
}

// As sgLayerFeature; layers with aa.lean take the switch (baseMap unread),
// the others are today's layer (chainA, chainB unread).
SG_FN vec3 sgLayerFeatureAa(SgUvFrame uv, SgFeatureLayerParams p, SgFeatureAaParams aa, SgFeatProfile pr,
                            SG_FEAT_CORNER_SAMPLER corners, SG_FEAT_EDGE_SAMPLER edges,
                            sampler2D baseMap, sampler2D chainA, sampler2D chainB,
                            SG_INOUT(mat3) slopeCov) {
    if (!aa.lean) return sgLayerFeature(uv, p, pr, corners, edges, baseMap);
    float w = sgFeatAaChainWeight(sgFeatAaFootprintTexels(uv, p));
    vec2 dExact = vec2(0.0f);
    if (w < 1.0f) {
        SgFeatResult r = sgFeatSample(corners, edges, sgFeatureLayerTexelPos(uv, p));
        dExact = sgFeatAaSlope(r, pr, p.paperMode);
    }
    return sgFeatAaCombine(uv, p, dExact, w, chainA, chainB, slopeCov);
}

#if SG_FEAT_NEAR
// As sgLayerFeatureNear, with the switch for layers with aa.lean.
SG_FN vec3 sgLayerFeatureNearAa(SgUvFrame uv, SgFeatureLayerParams p, SgFeatureAaParams aa,
                                SgFeatProfile pr,
                                SG_FEAT_CORNER_SAMPLER corners, SG_FEAT_EDGE_SAMPLER edges,
                                SG_FEAT_NEAR_SAMPLER nearMap, SG_FEAT_PIECE_SAMPLER pieces,
                                sampler2D baseMap, sampler2D chainA, sampler2D chainB,
                                SG_INOUT(mat3) slopeCov) {
    if (!aa.lean) return sgLayerFeatureNear(uv, p, pr, corners, edges, nearMap, pieces, baseMap);
    float w = sgFeatAaChainWeight(sgFeatAaFootprintTexels(uv, p));
    vec2 dExact = vec2(0.0f);
    if (w < 1.0f) {
        vec2 texelPos = sgFeatureLayerTexelPos(uv, p);
        if (p.nearExact) {
            SgFeatResult r = sgFeatSampleNear(corners, edges, nearMap, pieces, texelPos);
            dExact = sgFeatAaSlope(r, sgFeatCurveProfile(pieces, pr, r), p.paperMode);
        } else {
            dExact = sgFeatAaSlope(sgFeatSample(corners, edges, texelPos), pr, p.paperMode);
        }
    }
    return sgFeatAaCombine(uv, p, dExact, w, chainA, chainB, slopeCov);
}
#endif

#endif
