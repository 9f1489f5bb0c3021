// The runtime evaluator's decode and partition (shaders/sg/features/
// evaluate.glsl: sgFeatDecode, sgFeatSpoke, sgFeatFindSeg, sgFeatSegFrom,
// sgFeatTangentIntersection) evaluated in binary64 from a generated double
// copy of the same source (shared_double.cpp), for the bake's validation of
// signatures (bake_quadratic.cpp): the bake checks the very geometry the
// shader builds, with the shader's own thresholds, instead of a second copy
// of its formulas. Texel-local coordinates (layout.glsl).
#pragma once

#include <cstdint>

#include "bake_geometry.h"

namespace sg::features::detail {

// A partition edge: a quadratic (a straight one keeps its chord midpoint as
// p1, as the runtime does) and whether it is curved.
struct PEdge {
    Quad c;
    bool curved = false;
};

// SgFeatGeom in binary64.
struct SharedGeom {
    dvec2 q[4];    // edge vertices
    dvec2 tang[4]; // unit tangents at the edge points ((1, 0) without a point)
    bool pt[4] = {false, false, false, false};
    int nseg = 0;
    int segA[2] = {0, 0}, segB[2] = {0, 0};
    PEdge seg[2];
    PEdge pathV, pathH; // q_S -> q_N, q_W -> q_E
    bool discV = false, discH = false;
    dvec2 rm{0.0};
    double uV = 0.5, uH = 0.5;
};

// sgFeatDecode of a texel with configuration word `cfg` and edge words
// `edges` (S, E, N, W; layout.glsl).
SharedGeom sharedDecode(uint32_t cfg, const uint32_t edges[4]);
// sgFeatSpoke: the part of the path from edge vertex e to r_m.
PEdge sharedSpoke(const SharedGeom& g, int e);
// The quadrant diagonal from edge ea to edge eb: the segment joining them
// (oriented from ea) or the straight line (sgFeatFindSeg, sgFeatSegFrom).
PEdge sharedDiagonal(const SharedGeom& g, int ea, int eb);
// sgFeatTangentIntersection: false when the tangents are parallel to the
// runtime's threshold (the segment is then straight).
bool sharedTangentIntersection(dvec2 q0, dvec2 t0, dvec2 q2, dvec2 t2, dvec2& mid);

} // namespace sg::features::detail
