// Bump layer: feature-curve maps (creases, grooves, seams that stay sharp at
// any magnification): Parilov, Rosenberg, Zorin (TR2005-872) and Parilov,
// Zorin (TOG 2008), evaluated by the shared reconstruction of
// shaders/sg/features/ (distance d and its unit gradient, never
// interpolated across a curve). The profile h(d) becomes a texture-space
// derivative (sg/features/profile.glsl) and, like a tangent-space normal
// map, a TBN-style surface gradient (Mikkelsen 2019, listing 5), so the
// features add to every other layer.
//   surfgrad mode - deriv = (1 - b) h' grad d + b baseDeriv (slopes blend);
//   paper mode    - Eq. 1 of the papers blends the profile's normal with the
//                   base normal; the result's derivative (listing 4) is used.
// Without a base map the base is flat (derivative 0, normal +z).
// With SG_FEAT_NEAR 1 (some layer of the program uses a map's exact near
// field), sgLayerFeatureNear also reads the near-field textures: within the
// band the exact distance to the curves, and each curve's own profile and
// width (sg/features/near.glsl).
#ifndef SG_RENDER_LAYER_FEATURE_GLSL
#define SG_RENDER_LAYER_FEATURE_GLSL

#include "sg/render/common.glsl"
#include "sg/features/fetch.glsl"
#include "sg/features/profile.glsl"

// Records r0 = (strength, paperMode, map size N (texels), tiling);
// r1 = (offset.xy, hasBase, base encoding); r2 = (base flipV, nearExact, 0, 0).
// texelPos = (st * tiling + offset) * N (the map is clamped at its border).
struct SgFeatureLayerParams {
    float strength;
    bool paperMode;
    float mapSize;
    float tiling;
    vec2 offset;
    bool hasBase;
    int baseEncoding;
    bool baseFlipV;
    bool nearExact; // the layer uses its map's exact near field
};

SG_FN SgFeatureLayerParams sgUnpackFeatureLayer(vec4 r0, vec4 r1, vec4 r2) {
    SgFeatureLayerParams p;
    p.strength = r0.x;
    p.paperMode = sgRecBool(r0.y);
    p.mapSize = r0.z;
    p.tiling = r0.w;
    p.offset = vec2(r1.x, r1.y);
    p.hasBase = sgRecBool(r1.z);
    p.baseEncoding = sgRecInt(r1.w);
    p.baseFlipV = sgRecBool(r2.x);
    p.nearExact = sgRecBool(r2.y);
    return p;
}

// Profile records p0 = (kind SG_FEAT_PROFILE_*, depth, w0, w) in texels,
// p1 = (table count, 0, 0, 0), t0..t3 = the 16 table heights.
SG_FN SgFeatProfile sgUnpackFeatProfile(vec4 p0, vec4 p1, vec4 t0, vec4 t1, vec4 t2, vec4 t3) {
    SgFeatProfile pr;
    pr.kind = sgRecInt(p0.x);
    pr.depth = p0.y;
    pr.w0 = p0.z;
    pr.w = p0.w;
    pr.tableCount = sgRecInt(p1.x);
    pr.table[0] = t0.x;
    pr.table[1] = t0.y;
    pr.table[2] = t0.z;
    pr.table[3] = t0.w;
    pr.table[4] = t1.x;
    pr.table[5] = t1.y;
    pr.table[6] = t1.z;
    pr.table[7] = t1.w;
    pr.table[8] = t2.x;
    pr.table[9] = t2.y;
    pr.table[10] = t2.z;
    pr.table[11] = t2.w;
    pr.table[12] = t3.x;
    pr.table[13] = t3.y;
    pr.table[14] = t3.z;
    pr.table[15] = t3.w;
    return pr;
}

// The layer's surface gradient from a sampled result r and its profile.
SG_FN vec3 sgLayerFeatureFrom(SgUvFrame uv, SgFeatureLayerParams p, SgFeatProfile pr, SgFeatResult r,
                              sampler2D baseMap) {
    vec2 baseDeriv = sgVec2(0.0f);
    if (p.hasBase) {
        baseDeriv = sgSampleTspaceDeriv(baseMap, uv.st, uv.dSTdx, uv.dSTdy, p.baseEncoding, p.baseFlipV);
    }
    vec2 d;
    if (p.paperMode) {
        vec3 n = sgFeatNormalPaper(r, pr, sgDerivToTspaceNormal(baseDeriv, false));
        d = sgTspaceNormalToDeriv(vec2(n.x, n.y), false);
    } else {
        d = sgFeatDeriv(r, pr, baseDeriv);
    }
    return sgSurfgradFromTBN(sgBumpScale(p.strength, d), uv.vT, uv.vB);
}

SG_FN vec2 sgFeatureLayerTexelPos(SgUvFrame uv, SgFeatureLayerParams p) {
    return (uv.st * p.tiling + p.offset) * p.mapSize;
}

// baseMap is read only when p.hasBase (bind any texture otherwise).
SG_FN vec3 sgLayerFeature(SgUvFrame uv, SgFeatureLayerParams p, SgFeatProfile pr, SG_FEAT_CORNER_SAMPLER corners,
                          SG_FEAT_EDGE_SAMPLER edges, sampler2D baseMap) {
    SgFeatResult r = sgFeatSample(corners, edges, sgFeatureLayerTexelPos(uv, p));
    return sgLayerFeatureFrom(uv, p, pr, r, baseMap);
}

#if SG_FEAT_NEAR
// As sgLayerFeature, with the exact near field when p.nearExact (the near
// textures are read only then; bind any RGBA32UI texture otherwise).
SG_FN vec3 sgLayerFeatureNear(SgUvFrame uv, SgFeatureLayerParams p, SgFeatProfile pr, SG_FEAT_CORNER_SAMPLER corners,
                              SG_FEAT_EDGE_SAMPLER edges, SG_FEAT_NEAR_SAMPLER nearMap, SG_FEAT_PIECE_SAMPLER pieces,
                              sampler2D baseMap) {
    vec2 texelPos = sgFeatureLayerTexelPos(uv, p);
    SgFeatResult r;
    SgFeatProfile prc = pr;
    if (p.nearExact) {
        r = sgFeatSampleNear(corners, edges, nearMap, pieces, texelPos);
        prc = sgFeatCurveProfile(pieces, pr, r);
    } else {
        r = sgFeatSample(corners, edges, texelPos);
    }
    return sgLayerFeatureFrom(uv, p, prc, r, baseMap);
}
#endif

#endif
