// Fetching one texel of the feature maps and sampling the reconstruction at
// a texel-space position: the entry points a renderer calls (with the
// profile functions of profile.glsl). Layout: surfgrad/feature_maps.h and
// docs/features.md.
//
// Textures (both read with texelFetch only, level 0; no filtering, so the
// sampler state does not matter):
//   corners  RGBA32F,  (N+1) x (N+1): texel (i, j) is the grid corner at
//            texel-space point (i, j): R = distance (texels), G, B = the
//            smoothed distance gradient, A = float(configuration word of
//            texel (i, j)) (0 in the last row and column).
//   edges    RGBA32UI, N x N: texel (i, j) holds the edge words of its edges
//            S, E, N, W (layout.glsl). Only fetched for texels with features.
// Row j of each texture is texture row j (OpenGL's t = 0 row first), so y
// points up as in texel space.
//
// The same source compiles as C++: surfgrad/feature_maps.h defines the
// sampler types SgFeatCornerSampler / SgFeatEdgeSampler over CPU arrays and
// the texelFetch/textureSize overloads used here.
#ifndef SG_FEATURES_FETCH_GLSL
#define SG_FEATURES_FETCH_GLSL

#include "sg/features/evaluate.glsl"

#ifdef SG_CPP
#define SG_FEAT_CORNER_SAMPLER const SgFeatCornerSampler&
#define SG_FEAT_EDGE_SAMPLER const SgFeatEdgeSampler&
#else
#define SG_FEAT_CORNER_SAMPLER sampler2D
#define SG_FEAT_EDGE_SAMPLER usampler2D
#endif

// The data of texel ij (0 <= ij < N): 4 fetches, plus 1 when it has features.
SG_FN SgFeatTexel sgFeatFetch(SG_FEAT_CORNER_SAMPLER corners, SG_FEAT_EDGE_SAMPLER edges, ivec2 ij) {
    vec4 c00 = texelFetch(corners, ij, 0);
    vec4 c10 = texelFetch(corners, ivec2(ij.x + 1, ij.y), 0);
    vec4 c11 = texelFetch(corners, ivec2(ij.x + 1, ij.y + 1), 0);
    vec4 c01 = texelFetch(corners, ivec2(ij.x, ij.y + 1), 0);
    SgFeatTexel tx;
    tx.dist = vec4(c00.x, c10.x, c11.x, c01.x);
    tx.grad0 = vec2(c00.y, c00.z);
    tx.grad1 = vec2(c10.y, c10.z);
    tx.grad2 = vec2(c11.y, c11.z);
    tx.grad3 = vec2(c01.y, c01.z);
    // Exact: the word has 21 bits.
    tx.cfg = uint(max(c00.w, 0.0f));
    tx.edges = (tx.cfg & SG_FEAT_CFG_FEATURE_BITS) != 0u ? texelFetch(edges, ij, 0) : uvec4(0u);
    return tx;
}

// Texel containing texel-space point texelPos (clamped to the map: the map
// is clamp-to-edge; the right and top borders belong to the last texel).
SG_FN ivec2 sgFeatTexelOf(ivec2 size, vec2 texelPos, SG_OUT(vec2) local) {
    vec2 pc = clamp(texelPos, vec2(0.0f), vec2(size));
    ivec2 ij = min(ivec2(floor(pc)), size - ivec2(1));
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

#endif
