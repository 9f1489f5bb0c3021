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
#ifndef SG_RENDER_LAYER_FEATURE_GLSL
#define SG_RENDER_LAYER_FEATURE_GLSL

#include "sg/render/common.glsl"
#include "sg/features/fetch.glsl"
#include "sg/features/profile.glsl"

// Records r0 = (strength, paperMode, map size N (texels), tiling);
// r1 = (offset.xy, hasBase, base encoding); r2 = (base flipV, 0, 0, 0).
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

// baseMap is read only when p.hasBase (bind any texture otherwise).
SG_FN vec3 sgLayerFeature(SgUvFrame uv, SgFeatureLayerParams p, SgFeatProfile pr, SG_FEAT_CORNER_SAMPLER corners,
                          SG_FEAT_EDGE_SAMPLER edges, sampler2D baseMap) {
    vec2 texelPos = (uv.st * p.tiling + p.offset) * p.mapSize;
    SgFeatResult r = sgFeatSample(corners, edges, texelPos);
    vec2 baseDeriv = vec2(0.0f);
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

#endif
