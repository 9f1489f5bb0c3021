// Where a tessellated point of an adaptive patch is evaluated, so that
// patches of the same depth meet without cracks, bit for bit (shared
// GLSL/C++ subset: the GPU tessellation evaluation stage and the CPU
// reference take the same decision).
//
// The two patches of a shared edge compute its integer level from the same
// two corner vertices (sg/patch/tess_level.glsl), so GL's tessellator puts
// n + 1 points on it from both sides, at domain coordinates that are i / n
// only up to the tessellator's precision (fixed point on llvmpipe). Each
// side recovers the integer i = round(t n), maps it to the owner patch's
// edge (n - i when the owner runs the edge the other way) and evaluates the
// owner at exactly j / n: both sides then evaluate one patch at one
// parameter. Corners go to their owner's corner. The owners come from
// sg::mesh::AdaptivePatches (edgeOwners, cornerOwners: the patch of lowest
// index). Interior points stay on the patch itself.
//
// Transition edges (a patch at depth d against two patches at depth d + 1,
// one on each half; AdaptivePatches::transitionMask): the coarse side's
// level is nLo + nHi, the two halves' own levels (the control stage
// computes each from the half's corner vertices as the fine patch does),
// so both sides put the same points on the edge. Point i of the coarse
// edge is point i of the lower half (i < nLo), the midpoint (i = nLo: the
// halves' shared corner, at its corner owner) or point i - nLo of the
// upper half, each evaluated by the half's fine owner at j / nLo or
// j / nHi: the fine side's own parameter from the same integers (the same
// approach as OpenSubdiv's tessOuterLo / tessOuterHi levels, here with the
// points themselves taken from the fine side).
#ifndef SG_PATCH_WATERTIGHT_GLSL
#define SG_PATCH_WATERTIGHT_GLSL

#include "sg/compat.glsl"

// A patch and a (u,v) of its unit square.
struct SgPatchSite {
    uint patchIndex;
    vec2 uv;
};

// (u,v) on edge k (0: u = 0, 1: v = 0, 2: u = 1, 3: v = 1) at parameter t
// along it (+v for edges 0 and 2, +u for 1 and 3).
SG_FN vec2 sgPatchEdgeUv(int k, float t) {
    return k == 0 ? vec2(0.0f, t) : k == 1 ? vec2(t, 0.0f) : k == 2 ? vec2(1.0f, t) : vec2(t, 1.0f);
}

// A patch's transition edges (AdaptivePatches: transitionLo, transitionHi,
// transitionMid per edge in GL's order) and the lower halves' levels
// (loLevel[k] = 0: edge k is not a transition edge).
struct SgPatchTransitions {
    uvec4 lo;
    uvec4 hi;
    uvec4 mid;
    vec4 loLevel;
};

// No transition edges.
SG_FN SgPatchTransitions sgPatchNoTransitions() {
    SgPatchTransitions t;
    t.lo = sgUvec4(0u);
    t.hi = sgUvec4(0u);
    t.mid = sgUvec4(0u);
    t.loLevel = sgVec4(0.0f);
    return t;
}

// The site of a corner owner ((owner << 2) | owner's corner).
SG_FN SgPatchSite sgPatchCornerSite(uint owner) {
    uint oc = owner & 3u;
    SgPatchSite s;
    s.patchIndex = owner >> 2u;
    s.uv = vec2(oc == 1u || oc == 2u ? 1.0f : 0.0f, oc >= 2u ? 1.0f : 0.0f);
    return s;
}

// The site of point i of n on an edge owned by `owner` ((owner << 3) |
// (owner's edge << 1) | flip), i counted in this side's direction.
SG_FN SgPatchSite sgPatchEdgeSite(uint owner, int i, int n) {
    int j = (owner & 1u) != 0u ? n - i : i;
    SgPatchSite s;
    s.patchIndex = owner >> 3u;
    s.uv = sgPatchEdgeUv(int((owner >> 1u) & 3u), float(j) / float(n));
    return s;
}

// The site at which patch `self` evaluates its domain point uv (GL's
// gl_TessCoord), given its edge and corner owners (AdaptivePatches
// encoding), its transition edges and its four outer levels (integers,
// GL's order: edges u = 0, v = 0, u = 1, v = 1; a transition edge's is the
// sum of its halves').
SG_FN SgPatchSite sgPatchEvalSite(uint self, uvec4 edgeOwners, uvec4 cornerOwners,
                                  SgPatchTransitions tr, vec4 outer, vec2 uv) {
    bool u0 = uv.x == 0.0f, u1 = uv.x == 1.0f, v0 = uv.y == 0.0f, v1 = uv.y == 1.0f;
    SgPatchSite s;
    s.patchIndex = self;
    s.uv = uv;
    if ((u0 || u1) && (v0 || v1)) {
        int corner = v0 ? (u0 ? 0 : 1) : (u1 ? 2 : 3);
        s = sgPatchCornerSite(cornerOwners[corner]);
    } else if (u0 || u1 || v0 || v1) {
        int k = u0 ? 0 : v0 ? 1 : u1 ? 2 : 3;
        float t = (k == 0 || k == 2) ? uv.y : uv.x;
        int n = max(int(outer[k]), 1);
        int i = int(floor(t * float(n) + 0.5f));
        int nLo = int(tr.loLevel[k]);
        if (nLo <= 0 || nLo >= n)
            s = sgPatchEdgeSite(edgeOwners[k], i, n);
        else if (i < nLo)
            s = sgPatchEdgeSite(tr.lo[k], i, nLo);
        else if (i == nLo)
            s = sgPatchCornerSite(tr.mid[k]);
        else
            s = sgPatchEdgeSite(tr.hi[k], i - nLo, n - nLo);
    }
    return s;
}

#endif // SG_PATCH_WATERTIGHT_GLSL
