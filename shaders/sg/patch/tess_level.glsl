// Screen-space tessellation levels of patch edges, shared by the GPU
// tessellation control stage and the CPU reference renderer (shared
// GLSL/C++ subset): both tessellate every patch edge into the same number
// of segments.
//
// An edge is measured as the sphere through its two end points (centre the
// midpoint, diameter the chord) projected at its distance from the camera:
// levels = diameter * focalPx / distance / pixelsPerEdge (the "sphere"
// metric of Niessner et al., "Feature-adaptive GPU rendering of
// Catmull-Clark subdivision surfaces", ACM TOG 31(1), 2012, section 5,
// rather than the projected chord, which vanishes for edges seen end-on and
// is undefined across the camera plane). Crack-freedom: the result depends
// on the two end points only, symmetrically (a + b and |a - b| are exact
// under the exchange of a and b), so the two patches sharing an edge compute
// the same level bit for bit when they pass the same end points.
#ifndef SG_PATCH_TESS_LEVEL_GLSL
#define SG_PATCH_TESS_LEVEL_GLSL

#include "sg/compat.glsl"

// Largest tessellation level GL guarantees (GL_MAX_TESS_GEN_LEVEL >= 64).
#define SG_TESS_MAX_LEVEL 64.0f

// Integer tessellation level (integer / equal_spacing: the level GL uses
// after rounding up) of the edge from relA to relB, camera-relative world
// positions (world position minus camera position, the space of uModelRel),
// for a pinhole camera of focal length focalPx in pixels (viewport height /
// (2 tan(fovY / 2))) and a target of pixelsPerEdge pixels per segment
// (> 0). Within [1, maxLevel] (maxLevel in [1, SG_TESS_MAX_LEVEL]). Hard
// cases: a zero-length edge -> 1; an edge through or behind the camera
// (distance of its midpoint below half its chord) -> measured at the
// distance of half its chord, i.e. as if it filled the view, so maxLevel at
// most; non-finite input -> 1.
SG_FN float sgPatchEdgeTessLevel(vec3 relA, vec3 relB, float focalPx, float pixelsPerEdge,
                                 float maxLevel) {
    vec3 mid = (relA + relB) * 0.5f;
    float diameter = length(relA - relB);
    float dist = max(length(mid), 0.5f * diameter);
    float levels = diameter * focalPx / (dist * pixelsPerEdge);
    // NaN (0/0, inf/inf) and negative values fail the first test.
    if (!(levels >= 1.0f)) return 1.0f;
    return min(ceil(levels), maxLevel);
}

// The largest level of an edge that is one half of a coarser patch's
// transition edge (sg::mesh::AdaptivePatches::transitionMask): the coarse
// side tessellates the whole edge with the sum of its halves' levels, so
// each half is capped at half the maximum (at least 1) and the sum stays
// within maxLevel (for maxLevel >= 2; at 1 the sum is 2, within GL's
// guaranteed 64). Both sides compute each half with this cap.
SG_FN float sgPatchHalfMaxLevel(float maxLevel) {
    return max(floor(maxLevel * 0.5f), 1.0f);
}

// Focal length in pixels of a perspective projection matrix projRel
// (camera-relative world -> clip, GL conventions) for a viewport
// heightPx pixels high: projRel[1][1] is 1 / tan(fovY / 2) for the usual
// perspective matrices, so this is heightPx / (2 tan(fovY / 2)).
SG_FN float sgPatchFocalPx(float projYScale, float heightPx) {
    return 0.5f * heightPx * abs(projYScale);
}

#endif // SG_PATCH_TESS_LEVEL_GLSL
