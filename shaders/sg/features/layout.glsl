// Feature maps: the texel layout shared by the bake (features/src/, through
// surfgrad/features/feature_maps.h) and the runtime evaluator (evaluate.glsl).
// Parilov, Zorin, "Real-Time Rendering of Textures with Feature Curves"
// (TOG 2008), section 4 (configurations C and signatures S per texel) and
// section 6 ("Memory consumption"); Parilov, Rosenberg, Zorin (TR2005-872)
// section 4.1 for the linear case. The packing below is ours.
//
// Texel space (every position in this module): x right, y up, in texels;
// texel (i, j) covers [i, i+1] x [j, j+1]; a map of N x N texels covers
// [0, N]^2. Distances are in texels.
//
// Inside one texel the evaluator works in LOCAL coordinates p - (i, j) in
// [0, 1]^2. The texel's four edges and corners are numbered
// counter-clockwise (the paper numbers edges clockwise from 1; only the
// numbering differs):
//
//        NW(3) ---- N(2) ---- NE(2)
//          |                    |
//        W(3)                 E(1)        corner k lies between
//          |                    |         edges (k+3)%4 and k
//        SW(0) ---- S(0) ---- SE(1)
//
// An edge point's position t runs along +x on S/N edges and along +y on
// W/E edges (from the left/bottom corner, as in the paper's Fig. 7).
#ifndef SG_FEATURES_LAYOUT_GLSL
#define SG_FEATURES_LAYOUT_GLSL

#include "sg/compat.glsl"

#ifdef GL_ES
// The feature maps are 32-bit integer textures; ES 3.00 gives usampler2D no
// default precision.
precision highp usampler2D;
#endif

// 1: the full evaluator (maps baked in quadratic mode, and linear maps);
// 0: straight segments only, cheaper (maps baked in linear mode). Define it
// before including any sg/features file.
#ifndef SG_FEAT_CURVED
#define SG_FEAT_CURVED 1
#endif
// 1: the exact near field (near.glsl) for maps baked with it; 0: not
// compiled. Define it before including any sg/features file.
#ifndef SG_FEAT_NEAR
#define SG_FEAT_NEAR 0
#endif

#define SG_FEAT_S 0
#define SG_FEAT_E 1
#define SG_FEAT_N 2
#define SG_FEAT_W 3
#define SG_FEAT_SW 0
#define SG_FEAT_SE 1
#define SG_FEAT_NE 2
#define SG_FEAT_NW 3

// ---------------------------------------------------------------------------
// Configuration word of a texel (the paper's C plus flags), 21 bits so it is
// exact in a binary32 float:
//   bits  0-1   number of discontinuity segments (0, 1 or 2)
//   bits  2-3   segment 0: edge of its first end point
//   bits  4-5   segment 0: edge of its second end point
//   bit   6     segment 0 is a quadratic Bezier (else a straight segment)
//   bits  7-8   segment 1: first edge
//   bits  9-10  segment 1: second edge
//   bit   11    segment 1 is a quadratic Bezier
//   bits 12-15  edge S, E, N, W carries a discontinuity point (distance 0
//               there, even when no segment of this texel ends on it: a
//               curve of the neighbour texel ends on the shared edge)
//   bits 16-19  corner SW, SE, NE, NW lies LEFT of its nearest input curve
//               (with respect to the curve's direction; for one-sided
//               profiles such as the step)
// A texel with (cfg & SG_FEAT_CFG_FEATURE_BITS) == 0 has no discontinuity
// and is interpolated bilinearly.
#define SG_FEAT_CFG_FEATURE_BITS 0xFFFFu
#define SG_FEAT_CFG_SEGMENT_BITS 0x0FFFu
#define SG_FEAT_CFG_EDGE_SHIFT 12
#define SG_FEAT_CFG_SIDE_SHIFT 16

SG_FN int sgFeatSegCount(uint cfg) { return int(cfg & 3u); }
SG_FN int sgFeatSegEdgeA(uint cfg, int s) { return int((cfg >> uint(2 + 5 * s)) & 3u); }
SG_FN int sgFeatSegEdgeB(uint cfg, int s) { return int((cfg >> uint(4 + 5 * s)) & 3u); }
SG_FN bool sgFeatSegCurved(uint cfg, int s) { return ((cfg >> uint(6 + 5 * s)) & 1u) != 0u; }
SG_FN bool sgFeatEdgeHasPoint(uint cfg, int e) {
    return ((cfg >> uint(SG_FEAT_CFG_EDGE_SHIFT + e)) & 1u) != 0u;
}
SG_FN bool sgFeatHasAngles(uint cfg) { return ((cfg >> 20u) & 1u) != 0u; }
SG_FN bool sgFeatCornerLeft(uint cfg, int k) {
    return ((cfg >> uint(SG_FEAT_CFG_SIDE_SHIFT + k)) & 1u) != 0u;
}

// ---------------------------------------------------------------------------
// Edge word (the paper's signature pair (d, theta) of one edge), 32 bits:
//   bits  0-15  position t on the edge, unorm16: t = value / 65535
//   bits 16-31  tangent angle theta of the curve at the point, measured
//               from +x (the paper's "horizon"), a line direction in
//               [-pi/2, pi/2], stored as u = tan(theta / 2) in [-1, 1]:
//               code a in 1..65535 with u = (a - 32768) / 32767. The unit
//               tangent is then ((1 - u^2), 2u) / (1 + u^2): no
//               trigonometry in the shader; 0 and +-pi/2 are exact and the
//               angle step is at most 3.1e-5 radians.
// The bake stores positions and angles already rounded to these grids, so
// the C++ and GLSL evaluators see identical values. Edges without a point
// hold the paper's default (t, theta) = (0.5, 0).
#define SG_FEAT_PI 3.14159265358979f
// (Multiplications by the reciprocal, not divisions: identical in both
// builds, and a few ulps from the bake's exact grid values.)
SG_FN float sgFeatEdgePos(uint w) { return float(w & 0xFFFFu) * (1.0f / 65535.0f); }
SG_FN vec2 sgFeatEdgeTangent(uint w) {
    float u = (float(w >> 16u) - 32768.0f) * (1.0f / 32767.0f);
    float uu = u * u;
    return vec2(1.0f - uu, 2.0f * u) / (1.0f + uu);
}

// Tangents at a segment's two ends whose cross product is at most this are
// parallel: the segment is straight (sgFeatTangentIntersection). The bake
// keeps the curved segments it stores far above it (bake_quadratic.cpp).
#define SG_FEAT_PARALLEL_SIN 1e-6f

// Smallest and largest position of an edge point: the bake moves points off
// the texel corners by this much (curves through corners and along texel
// edges), so no partition triangle degenerates. 2^-10 texels.
#define SG_FEAT_EDGE_MARGIN 0.0009765625f

// ---------------------------------------------------------------------------
// Everything the evaluator needs about one texel: the samples at its four
// corners and its configuration and signature. Filled from the textures by
// sgFeatFetch (fetch.glsl) or from C++ arrays (surfgrad/features/feature_maps.h).
struct SgFeatTexel {
    vec4 dist;   // distance at corners SW, SE, NE, NW (texels, >= 0)
    vec2 grad0;  // distance gradient samples at SW, SE, NE, NW (smoothed;
    vec2 grad1;  //   length <= 1, 0 where no curve lies within the band)
    vec2 grad2;
    vec2 grad3;
    uint cfg;    // configuration word (above)
    uvec4 edges; // edge words of edges S, E, N, W (zero when cfg has no
                 //   feature bits: they are not fetched then)
};

// What the evaluator returns for a point.
struct SgFeatResult {
    float dist;  // reconstructed distance to the feature curves, texels (>= 0)
    vec2 grad;   // unit gradient of dist, texel space; (0, 0) only where
                 // every contributing sample is 0 (no curve within the band)
    float side;  // +1 when the point lies left of its nearest curve, else -1
    int profile; // exact near field: the nearest curve's entry in the map's
                 // profile table; -1: the layer's profile (always, in the
                 // paper's interpolation)
    float width; // exact near field: the nearest curve's profile width at the
                 // closest point (texels); 0: the layer's width
};

#endif
