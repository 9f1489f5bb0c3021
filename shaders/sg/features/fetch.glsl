// Fetching one texel of the feature maps and sampling the reconstruction at
// a texel-space position: the entry points a renderer calls (with the
// profile functions of profile.glsl). Layout: surfgrad/features/feature_maps.h and
// docs/features.md.
//
// Textures (both RGBA32UI, read with texelFetch only, level 0; no
// filtering: set GL_NEAREST, integer textures are incomplete with linear
// filters):
//   cornerPairs  N x (N+1): texel (i, j) holds grid corners (i, j) and
//                (i+1, j) as half floats and the configuration of texel
//                (i, j): x = packHalf2x16(d(i, j), d(i+1, j)),
//                y = packHalf2x16(grad(i, j)), z = packHalf2x16(grad(i+1, j)),
//                w = configuration word (layout.glsl; 0 in row N).
//   edges        N x N: texel (i, j) holds the edge words of its edges
//                S, E, N, W (layout.glsl).
// Row j of each texture is texture row j (OpenGL's t = 0 row first), so y
// points up as in texel space. A texel costs three fetches: its corner pair
// row j, the pair row j+1 and its edges. 32 bytes per texel.
//
// The same source compiles as C++: surfgrad/features/feature_maps.h defines the
// sampler types SgFeatCornerSampler / SgFeatEdgeSampler over CPU arrays and
// the texelFetch/textureSize overloads used here.
#ifndef SG_FEATURES_FETCH_GLSL
#define SG_FEATURES_FETCH_GLSL

#include "sg/features/evaluate.glsl"
// (Included whatever SG_FEAT_NEAR says: the #include expansion is textual
// and once per file, so an #include inside #if would hide the file from
// later includers; near.glsl compiles its code only with SG_FEAT_NEAR 1.)
#include "sg/features/near.glsl"

#ifdef SG_CPP
#define SG_FEAT_CORNER_SAMPLER const SgFeatCornerSampler&
#define SG_FEAT_EDGE_SAMPLER const SgFeatEdgeSampler&
#elif defined(SG_HLSL)
#define SG_FEAT_CORNER_SAMPLER Texture2D<uint4>
#define SG_FEAT_EDGE_SAMPLER Texture2D<uint4>
#else
#define SG_FEAT_CORNER_SAMPLER usampler2D
#define SG_FEAT_EDGE_SAMPLER usampler2D
#endif

// The data of texel ij (0 <= ij < N): 3 fetches.
SG_FN SgFeatTexel sgFeatFetch(SG_FEAT_CORNER_SAMPLER corners, SG_FEAT_EDGE_SAMPLER edges, ivec2 ij) {
    uvec4 lo = texelFetch(corners, ij, 0);                     // corners SW, SE
    uvec4 hi = texelFetch(corners, ivec2(ij.x, ij.y + 1), 0);  // corners NW, NE
    vec2 dLo = sgUnpackHalf2x16(lo.x);
    vec2 dHi = sgUnpackHalf2x16(hi.x);
    SgFeatTexel tx;
    tx.dist = vec4(dLo.x, dLo.y, dHi.y, dHi.x);
    tx.grad0 = sgUnpackHalf2x16(lo.y);
    tx.grad1 = sgUnpackHalf2x16(lo.z);
    tx.grad2 = sgUnpackHalf2x16(hi.z);
    tx.grad3 = sgUnpackHalf2x16(hi.y);
    tx.cfg = lo.w;
    // Fetched for every texel: where branches run under masks, skipping it
    // for texels without features saves nothing.
    tx.edges = texelFetch(edges, ij, 0);
    return tx;
}

// Texel containing texel-space point texelPos (clamped to the map: the map
// is clamp-to-edge; the right and top borders belong to the last texel).
SG_FN ivec2 sgFeatTexelOf(ivec2 size, vec2 texelPos, SG_OUT(vec2) local) {
    vec2 pc = clamp(texelPos, sgVec2(0.0f), vec2(size));
    ivec2 ij = min(ivec2(floor(pc)), size - sgIvec2(1));
    local = pc - vec2(ij);
    return ij;
}

// Distance (texels), unit gradient and side at texel-space texelPos (for a
// map of N texels per unit of uv with v up, texelPos = uv * N).
SG_FN SgFeatResult sgFeatSample(SG_FEAT_CORNER_SAMPLER corners, SG_FEAT_EDGE_SAMPLER edges, vec2 texelPos) {
    vec2 local;
    ivec2 ij = sgFeatTexelOf(textureSize(edges, 0), texelPos, local);
    return sgFeatEval(sgFeatFetch(corners, edges, ij), local);
}


// ---------------------------------------------------------------------------
// Exact near field (near.glsl), compiled only with SG_FEAT_NEAR 1 (for maps
// baked with it: effects on demand). Within the band the distance, gradient
// and side are those of the input curves; outside it the interpolation
// above. Costs 1 fetch of the list header per sample, and in the band 2
// per listed piece (docs/features.md).
#if SG_FEAT_NEAR
SG_FN SgFeatResult sgFeatSampleNear(SG_FEAT_CORNER_SAMPLER corners, SG_FEAT_EDGE_SAMPLER edges,
                                    SG_FEAT_NEAR_SAMPLER nearMap, SG_FEAT_PIECE_SAMPLER pieces, vec2 texelPos) {
    vec2 local;
    ivec2 ij = sgFeatTexelOf(textureSize(edges, 0), texelPos, local);
    uvec4 header = texelFetch(nearMap, ij, 0);
    if (sgFeatInBand(header)) return sgFeatNearEval(nearMap, pieces, header, ij, local);
    return sgFeatEval(sgFeatFetch(corners, edges, ij), local);
}
#endif

#endif
