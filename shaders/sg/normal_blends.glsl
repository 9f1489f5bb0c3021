// The common ways of blending two tangent-space normal maps, beside the
// surface-gradient sum: what engines ship, kept for comparison. Table 3 of
// bench_accuracy_cost (docs/accuracy-cost.md) measures them against the
// normal of the summed heights; the three.js example (examples/web) offers
// them beside its surface gradients. Written once in the GLSL/C++/HLSL
// subset (sg/compat.glsl), so the GPU pass, the C++ test (tests/study) and
// the page run the same code.
//
// Every method blends a base tangent-space normal a and a detail
// tangent-space normal b (unit, z up, same UV set) into one tangent-space
// normal. Sources of the classic methods: Barre-Brisebois & Hill, "Blending
// in Detail" (2012): linear, overlay, partial-derivative, whiteout, UDN,
// reoriented normal mapping (RNM). The surface-gradient method is
// Mikkelsen 2019 (listing 4 per map, eq. 3: the derivatives add, listing 5,
// listing 1), which is also Loviscach 2008 "Adding and Blending" and the
// partial-derivative blend. Their ground truth here: the normal of the SUMMED
// heights h_a + h_b (Mikkelsen 2019 eq. 2-3). RNM answers another question
// (the detail map re-oriented to follow the base's perturbed normal) and is
// measured against the same truth anyway, because "add two bump maps" is
// what users ask it to do.
#ifndef SG_NORMAL_BLENDS_GLSL
#define SG_NORMAL_BLENDS_GLSL

#include "sg/surfgrad.glsl"

#define SG_NORMAL_BLEND_Z vec3(0.0f, 0.0f, 1.0f)

// normalize(a + b).
SG_FN vec3 sgNormalBlendLinear(vec3 a, vec3 b) { return sgSafeNormalize(a + b, SG_NORMAL_BLEND_Z); }

// Photoshop overlay per channel on the [0,1]-encoded maps, then decoded and
// normalized.
SG_FN float sgNormalBlendOverlay1(float x, float y) {
    return x < 0.5f ? 2.0f * x * y : 1.0f - 2.0f * (1.0f - x) * (1.0f - y);
}
SG_FN vec3 sgNormalBlendOverlay(vec3 a, vec3 b) {
    vec3 x = a * 0.5f + sgVec3(0.5f);
    vec3 y = b * 0.5f + sgVec3(0.5f);
    vec3 r = vec3(sgNormalBlendOverlay1(x.x, y.x), sgNormalBlendOverlay1(x.y, y.y), sgNormalBlendOverlay1(x.z, y.z));
    return sgSafeNormalize(r * 2.0f - sgVec3(1.0f), SG_NORMAL_BLEND_Z);
}

// UDN: the detail's xy added, the base's z kept.
SG_FN vec3 sgNormalBlendUdn(vec3 a, vec3 b) { return sgSafeNormalize(vec3(a.x + b.x, a.y + b.y, a.z), SG_NORMAL_BLEND_Z); }

// Whiteout: xy added, z multiplied.
SG_FN vec3 sgNormalBlendWhiteout(vec3 a, vec3 b) {
    return sgSafeNormalize(vec3(a.x + b.x, a.y + b.y, a.z * b.z), SG_NORMAL_BLEND_Z);
}

// Reoriented normal mapping: b rotated by the rotation taking +z to a.
// Unit output for unit inputs (not normalized again, as published).
SG_FN vec3 sgNormalBlendRnm(vec3 a, vec3 b) {
    vec3 t = a + SG_NORMAL_BLEND_Z;
    vec3 u = b * vec3(-1.0f, -1.0f, 1.0f);
    return t * (dot(t, u) / t.z) - u;
}

// Surface gradients (Mikkelsen 2019): each map to its derivative (listing 4),
// the derivatives add (eq. 3), TBN-style surface gradient (listing 5) in the
// frame (vT, vB, f.nrmBase), resolve (listing 1). Returns the final normal
// in the frame's space (the other methods return a tangent-space normal that
// the caller still has to rotate by the TBN matrix: sgTangentNormalToFrame).
SG_FN vec3 sgNormalBlendSurfgrad(SgFrame f, vec3 vT, vec3 vB, vec3 a, vec3 b) {
    vec2 d = sgTspaceNormalToDeriv(vec2(a.x, a.y), false) + sgTspaceNormalToDeriv(vec2(b.x, b.y), false);
    return sgResolve(f, sgSurfgradFromTBN(d, vT, vB));
}

// A tangent-space normal to the frame's space: normalize(T x + B y + N z).
SG_FN vec3 sgTangentNormalToFrame(SgFrame f, vec3 vT, vec3 vB, vec3 n) {
    return sgSafeNormalize(vT * n.x + vB * n.y + f.nrmBase * n.z, f.nrmBase);
}

// Method index -> blended normal in the frame's space (the GPU pass selects
// the method with a compile-time define instead; this is for C++ loops).
#define SG_NORMAL_BLEND_SURFGRAD 0
#define SG_NORMAL_BLEND_LINEAR 1
#define SG_NORMAL_BLEND_OVERLAY 2
#define SG_NORMAL_BLEND_UDN 3
#define SG_NORMAL_BLEND_WHITEOUT 4
#define SG_NORMAL_BLEND_RNM 5
#define SG_NORMAL_BLEND_COUNT 6
SG_FN vec3 sgNormalBlend(int method, SgFrame f, vec3 vT, vec3 vB, vec3 a, vec3 b) {
    if (method == SG_NORMAL_BLEND_SURFGRAD) return sgNormalBlendSurfgrad(f, vT, vB, a, b);
    vec3 n = sgNormalBlendRnm(a, b);
    if (method == SG_NORMAL_BLEND_LINEAR) n = sgNormalBlendLinear(a, b);
    if (method == SG_NORMAL_BLEND_OVERLAY) n = sgNormalBlendOverlay(a, b);
    if (method == SG_NORMAL_BLEND_UDN) n = sgNormalBlendUdn(a, b);
    if (method == SG_NORMAL_BLEND_WHITEOUT) n = sgNormalBlendWhiteout(a, b);
    return sgTangentNormalToFrame(f, vT, vB, n);
}

#endif
