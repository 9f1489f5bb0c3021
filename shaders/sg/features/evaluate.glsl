// Runtime reconstruction of the distance to the feature curves and of its
// gradient inside one texel, never interpolating across a curve:
// Parilov, Zorin, "Real-Time Rendering of Textures with Feature Curves"
// (TOG 2008), section 5 and the appendix ("code outline"), and Parilov,
// Rosenberg, Zorin (TR2005-872) section 4.3 for straight segments.
//
//  1. Decode the texel's edge points q_S, q_E, q_N, q_W (signature S; the
//     default position 0.5 on edges without a point) and its segments
//     (configuration C); a curved segment's middle control point is the
//     intersection of the tangent lines at its ends (appendix step 2).
//  2. The 8-triangle partition (section 5.1, Fig. 4 and 9): the "vertical"
//     path q_S -> q_N and the "horizontal" path q_W -> q_E (a segment when
//     one joins those edges, else a straight line) meet at the centre r_m;
//     they cut the texel into four quadrants, and each quadrant's diagonal
//     q_a -> q_b (a segment or a straight line) cuts it into a corner
//     triangle and an inner triangle. Every segment is a partition edge.
//  3. Locate p: the quadrant by two side tests, then the triangle by one
//     (section 5.2: linear, or the implicit form of Eq. 4).
//  4. Reachable corners (appendix step 3): the corners on the same side of
//     every segment as p. Values (d, grad) at the triangle's vertices come
//     from reachable corners only: a corner keeps its sample; an edge vertex
//     interpolates its edge's reachable corners (two: linear; one: copy;
//     none: the value at the other end of a segment through it, step
//     3.1.3), with d = 0 on a discontinuity point (step 3.2); r_m
//     interpolates its path's end values (step 4), along the discontinuity
//     when one passes through r_m, else the average of both paths
//     (TR2005-872, Fig. 7).
//  5. Interpolate in the triangle (section 5.3): barycentric for straight
//     triangles, the radial map of Eq. 9 for a 1C-triangle (one curved
//     edge), and for a 2C-triangle Eq. 10 with the auxiliary point r at
//     infinity along the straight edge (rays parallel to that edge), which
//     keeps every intersection a closed-form quadratic instead of Bezier
//     clipping; it reproduces the vertex values along all three edges as
//     Eq. 10 does. The gradient is normalized (section 3.2, TR2005 Eq. 2).
//
// Distance is exactly 0 on the segments: both ends of a segment carry
// d = 0, and every interpolation scheme reproduces edge values.
#ifndef SG_FEATURES_EVALUATE_GLSL
#define SG_FEATURES_EVALUATE_GLSL

#include "sg/features/curve.glsl"

// Decoded texel (steps 1-2). Arrays are indexed by edge or corner number.
struct SgFeatGeom {
    vec2 q[4];        // edge vertices (texel-local)
    vec2 tang[4];     // unit tangent of the curve at the edge point
    bool angles;      // tangents are stored (layout.glsl bit 20)
    bool pt[4];       // edge carries a discontinuity point
    float t[4];       // position of the edge vertex along its edge
    vec3 cv[4];       // corner samples (d, grad.x, grad.y)
    int nseg;         // number of segments (0..2)
    int segA[2];      // edge of each segment's first end
    int segB[2];      // edge of each segment's second end
    SgFeatCurve seg[2]; // segment s runs from q[segA[s]] to q[segB[s]]
    SgFeatCurve pathV;  // q_S -> q_N
    SgFeatCurve pathH;  // q_W -> q_E
    bool discV;       // pathV is a segment (a discontinuity)
    bool discH;
    vec2 rm;          // centre vertex
    float uV;         // parameter of rm on pathV
    float uH;         // parameter of rm on pathH
};

SG_FN vec2 sgFeatCornerPos(int k) {
    return vec2(k == 1 || k == 2 ? 1.0f : 0.0f, k >= 2 ? 1.0f : 0.0f);
}
// Corners at t = 0 and t = 1 of edge e (t runs along +x or +y).
SG_FN int sgFeatEdgeCorner0(int e) { return e == SG_FEAT_E ? SG_FEAT_SE : (e == SG_FEAT_N ? SG_FEAT_NW : SG_FEAT_SW); }
SG_FN int sgFeatEdgeCorner1(int e) {
    return e == SG_FEAT_S ? SG_FEAT_SE : (e == SG_FEAT_W ? SG_FEAT_NW : SG_FEAT_NE);
}
SG_FN vec2 sgFeatEdgePoint(int e, float t) {
    if (e == SG_FEAT_S) return vec2(t, 0.0f);
    if (e == SG_FEAT_E) return vec2(1.0f, t);
    if (e == SG_FEAT_N) return vec2(t, 1.0f);
    return vec2(0.0f, t);
}

// Index of the segment joining edges a and b, or -1.
SG_FN int sgFeatFindSeg(SgFeatGeom g, int a, int b) {
    for (int s = 0; s < 2; ++s) {
        if (s < g.nseg && ((g.segA[s] == a && g.segB[s] == b) || (g.segA[s] == b && g.segB[s] == a))) return s;
    }
    return -1;
}

// Segment s oriented from edge a to the other end.
SG_FN SgFeatCurve sgFeatSegFrom(SgFeatGeom g, int s, int a) {
    return g.segA[s] == a ? g.seg[s] : sgFeatReverse(g.seg[s]);
}

// Parameter on c0 where it crosses c1 (both curved), by bisection on the
// sign of c1's implicit form along c0; the bake guarantees exactly one
// crossing with opposite signs at c0's ends (X configurations only).
SG_FN float sgFeatCurveCurveParam(SgFeatCurve c0, SgFeatCurve c1) {
    float lo = 0.0f;
    float hi = 1.0f;
    bool loSign = sgFeatImplicit(c1, c0.p0) >= 0.0f;
    for (int i = 0; i < 22; ++i) {
        float mid = 0.5f * (lo + hi);
        if ((sgFeatImplicit(c1, sgFeatCurvePoint(c0, mid)) >= 0.0f) == loSign) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return 0.5f * (lo + hi);
}

SG_FN SgFeatGeom sgFeatDecode(SgFeatTexel tx) {
    SgFeatGeom g;
    g.cv[0] = vec3(tx.dist.x, tx.grad0.x, tx.grad0.y);
    g.cv[1] = vec3(tx.dist.y, tx.grad1.x, tx.grad1.y);
    g.cv[2] = vec3(tx.dist.z, tx.grad2.x, tx.grad2.y);
    g.cv[3] = vec3(tx.dist.w, tx.grad3.x, tx.grad3.y);
    g.angles = sgFeatHasAngles(tx.cfg);
    for (int e = 0; e < 4; ++e) {
        uint w = e == 0 ? tx.edges.x : (e == 1 ? tx.edges.y : (e == 2 ? tx.edges.z : tx.edges.w));
        g.pt[e] = sgFeatEdgeHasPoint(tx.cfg, e);
        g.t[e] = g.pt[e] ? sgFeatEdgePos(w) : 0.5f;
        g.q[e] = sgFeatEdgePoint(e, g.t[e]);
        float theta = g.pt[e] ? sgFeatEdgeAngle(w) : 0.0f;
        g.tang[e] = vec2(cos(theta), sin(theta));
    }
    g.nseg = min(sgFeatSegCount(tx.cfg), 2);
    for (int s = 0; s < 2; ++s) {
        int a = sgFeatSegEdgeA(tx.cfg, s);
        int b = sgFeatSegEdgeB(tx.cfg, s);
        g.segA[s] = a;
        g.segB[s] = b;
        bool curved = s < g.nseg && sgFeatSegCurved(tx.cfg, s);
        bool ok = false;
        vec2 mid = sgFeatTangentIntersection(g.q[a], g.tang[a], g.q[b], g.tang[b], ok);
        g.seg[s] = sgFeatMakeCurve(g.q[a], mid, g.q[b], curved && ok);
    }
    int sV = sgFeatFindSeg(g, SG_FEAT_S, SG_FEAT_N);
    int sH = sgFeatFindSeg(g, SG_FEAT_W, SG_FEAT_E);
    g.discV = sV >= 0;
    g.discH = sH >= 0;
    g.pathV = g.discV ? sgFeatSegFrom(g, sV, SG_FEAT_S) : sgFeatMakeLine(g.q[SG_FEAT_S], g.q[SG_FEAT_N]);
    g.pathH = g.discH ? sgFeatSegFrom(g, sH, SG_FEAT_W) : sgFeatMakeLine(g.q[SG_FEAT_W], g.q[SG_FEAT_E]);
    // Centre vertex r_m: the crossing of the two paths.
    if (g.pathV.curved && g.pathH.curved) {
        g.uV = sgFeatCurveCurveParam(g.pathV, g.pathH);
        g.uH = sgFeatCurveCurveParam(g.pathH, g.pathV);
        g.rm = sgFeatCurvePoint(g.pathV, g.uV);
    } else if (g.pathV.curved) {
        vec2 dirH = g.pathH.p2 - g.pathH.p0;
        g.uV = sgFeatLineCurveParam(g.pathV, g.pathH.p0, dirH, false);
        g.rm = sgFeatCurvePoint(g.pathV, g.uV);
        g.uH = clamp(dot(g.rm - g.pathH.p0, dirH) / max(dot(dirH, dirH), 1e-12f), 0.0f, 1.0f);
    } else {
        vec2 dirV = g.pathV.p2 - g.pathV.p0;
        g.uH = sgFeatLineCurveParam(g.pathH, g.pathV.p0, dirV, false);
        g.rm = sgFeatCurvePoint(g.pathH, g.uH);
        g.uV = clamp(dot(g.rm - g.pathV.p0, dirV) / max(dot(dirV, dirV), 1e-12f), 0.0f, 1.0f);
    }
    return g;
}

// Bit k set when corner k is on the same side as p of every segment
// (appendix step 3). Segment s splits the corners into those met walking
// counter-clockwise from its first end to its second end (corners
// segA+1 .. segB) and the others; corner segA+1 is the reference point of
// the side test.
SG_FN int sgFeatReachMask(SgFeatGeom g, vec2 p) {
    int mask = 15;
    for (int s = 0; s < 2; ++s) {
        if (s < g.nseg) {
            int a = g.segA[s];
            int arcLen = (g.segB[s] - a + 4) % 4;
            bool pOnRefSide = sgFeatSameSide(g.seg[s], p, sgFeatCornerPos((a + 1) % 4));
            for (int k = 0; k < 4; ++k) {
                bool inArc = ((k - a - 1 + 8) % 4) < arcLen;
                if (inArc != pOnRefSide) mask &= ~(1 << k);
            }
        }
    }
    return mask;
}

// Value at edge vertex e from the reachable corners of its edge; ok = false
// when neither is reachable.
SG_FN vec3 sgFeatEdgeValueBasic(SgFeatGeom g, int reach, int e, SG_OUT(bool) ok) {
    int c0 = sgFeatEdgeCorner0(e);
    int c1 = sgFeatEdgeCorner1(e);
    bool r0 = ((reach >> c0) & 1) != 0;
    bool r1 = ((reach >> c1) & 1) != 0;
    vec3 v = vec3(0.0f);
    if (r0 && r1) {
        v = mix(g.cv[c0], g.cv[c1], g.t[e]);
    } else if (r0) {
        v = g.cv[c0];
    } else if (r1) {
        v = g.cv[c1];
    }
    ok = r0 || r1;
    if (g.pt[e]) v.x = 0.0f; // step 3.2
    return v;
}

// Value at edge vertex e from the corners only (appendix steps 3.1-3.2).
SG_FN vec3 sgFeatEdgeValueCorners(SgFeatGeom g, int reach, int e) {
    bool ok = false;
    vec3 v = sgFeatEdgeValueBasic(g, reach, e, ok);
    if (ok) return v;
    // Step 3.1.3: e is the common end of two segments and p lies between
    // them: take the gradient at the other end of either segment.
    for (int s = 0; s < 2; ++s) {
        if (s < g.nseg && (g.segA[s] == e || g.segB[s] == e)) {
            int other = g.segA[s] == e ? g.segB[s] : g.segA[s];
            bool ok2 = false;
            vec3 w = sgFeatEdgeValueBasic(g, reach, other, ok2);
            if (ok2) return vec3(v.x, w.y, w.z);
        }
    }
    // Not reached for valid configurations (every region holds a corner);
    // keep a finite answer: the mean of the reachable corners.
    vec3 sum = vec3(0.0f);
    float n = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if (((reach >> k) & 1) != 0) {
            sum += g.cv[k];
            n += 1.0f;
        }
    }
    vec3 m = n > 0.0f ? sum / n : vec3(0.0f);
    return vec3(v.x, m.y, m.z);
}

// On a discontinuity point the gradient is the curve's unit normal there
// (known from the signature's tangent angle), exact on the curve where the
// corner samples only approximate it (they are smoothed, and turn near the
// medial axis). It is oriented towards p's side: towards the one reachable
// corner of the edge (the curve crosses the edge there, so the edge leads
// into p's region); when both or neither are reachable (a curve ending on
// the edge, or p between two segments meeting there), like the corner
// interpolation of appendix step 3.1 that it replaces. Both texels sharing
// the point use the same angle and the same orientation, so the gradient
// stays continuous across the texel edge. An addition to the papers, which
// interpolate the corner gradients here.
SG_FN vec3 sgFeatOnCurveNormal(SgFeatGeom g, int reach, int e, vec3 v) {
    if (!g.pt[e] || !g.angles) return v;
    vec2 n = vec2(-g.tang[e].y, g.tang[e].x);
    int c0 = sgFeatEdgeCorner0(e);
    int c1 = sgFeatEdgeCorner1(e);
    bool r0 = ((reach >> c0) & 1) != 0;
    bool r1 = ((reach >> c1) & 1) != 0;
    vec2 ref = vec2(v.y, v.z);
    if (r0 != r1) ref = sgFeatCornerPos(r0 ? c0 : c1) - g.q[e];
    float s = dot(n, ref);
    if (!(abs(s) > 0.05f * sqrt(dot(ref, ref)))) return v; // orientation unclear: keep
    return vec3(v.x, s > 0.0f ? n.x : -n.x, s > 0.0f ? n.y : -n.y);
}

SG_FN vec3 sgFeatEdgeValue(SgFeatGeom g, int reach, int e) {
    return sgFeatOnCurveNormal(g, reach, e, sgFeatEdgeValueCorners(g, reach, e));
}

// Value at the centre vertex r_m (step 4).
SG_FN vec3 sgFeatCentreValue(SgFeatGeom g, int reach) {
    vec3 alongV = mix(sgFeatEdgeValue(g, reach, SG_FEAT_S), sgFeatEdgeValue(g, reach, SG_FEAT_N), g.uV);
    vec3 alongH = mix(sgFeatEdgeValue(g, reach, SG_FEAT_W), sgFeatEdgeValue(g, reach, SG_FEAT_E), g.uH);
    if (g.discV && !g.discH) return alongV;
    if (g.discH && !g.discV) return alongH;
    return 0.5f * (alongV + alongH);
}

// Spoke of the partition from edge vertex q[e] to r_m (part of pathV for
// S/N, of pathH for W/E).
SG_FN SgFeatCurve sgFeatSpoke(SgFeatGeom g, int e) {
    if (e == SG_FEAT_S) return sgFeatSubCurve(g.pathV, 0.0f, g.uV);
    if (e == SG_FEAT_N) return sgFeatSubCurve(g.pathV, 1.0f, g.uV);
    if (e == SG_FEAT_W) return sgFeatSubCurve(g.pathH, 0.0f, g.uH);
    return sgFeatSubCurve(g.pathH, 1.0f, g.uH);
}

// Straight triangle: barycentric interpolation.
SG_FN vec3 sgFeatBary(vec2 a, vec2 b, vec2 c, vec3 va, vec3 vb, vec3 vc, vec2 p) {
    float area = sgFeatCross(b - a, c - a);
    if (!(abs(area) > 1e-12f)) return (va + vb + vc) / 3.0f;
    float wa = sgFeatCross(b - p, c - p) / area;
    float wb = sgFeatCross(c - p, a - p) / area;
    return wa * va + wb * vb + (1.0f - wa - wb) * vc;
}

// 1C-triangle <p1, p2, q> (Eq. 9): the curved edge c runs from p1 (u = 0,
// value v1) to p2 (u = 1, value v2); q (value vq) is joined to both by
// straight edges. The ray from q through p meets c at p' = c(u) and
// s = |p' - p| / |p' - q|; V = (1 - s) mix(v1, v2, u) + s vq.
SG_FN vec3 sg1CTriangle(SgFeatCurve c, vec2 q, vec3 v1, vec3 v2, vec3 vq, vec2 p) {
    vec2 r = p - q;
    float rr = dot(r, r);
    if (!(rr > 1e-14f)) return vq;
    float u = sgFeatLineCurveParam(c, q, r, true);
    float lambda = dot(sgFeatCurvePoint(c, u) - q, r) / rr; // p' = q + lambda r
    float s = lambda > 1.0f ? 1.0f - 1.0f / lambda : 0.0f;
    return (1.0f - s) * mix(v1, v2, u) + s * vq;
}

// 2C-triangle (Eq. 10): curved edges c1 from X (value vx) to Y (vy) and c2
// from Z (vz) to Y share Y; [X, Z] is straight. The line through p parallel
// to Z - X meets c1 at c1(u) and c2 at c2(v); s is p's fraction between
// them; V = (1 - s) mix(vx, vy, u) + s mix(vz, vy, v).
SG_FN vec3 sg2CTriangle(SgFeatCurve c1, SgFeatCurve c2, vec3 vx, vec3 vy, vec3 vz, vec2 p) {
    vec2 dir = c2.p0 - c1.p0;
    float u = sgFeatLineCurveParam(c1, p, dir, false);
    float v = sgFeatLineCurveParam(c2, p, dir, false);
    vec2 a = sgFeatCurvePoint(c1, u);
    float den = dot(sgFeatCurvePoint(c2, v) - a, dir);
    float s = abs(den) > 1e-20f ? clamp(dot(p - a, dir) / den, 0.0f, 1.0f) : 0.5f;
    return (1.0f - s) * mix(vx, vy, u) + s * mix(vz, vy, v);
}

SG_FN float sgFeatSideFromMask(SgFeatTexel tx, int reach) {
    float sum = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if (((reach >> k) & 1) != 0) sum += sgFeatCornerLeft(tx.cfg, k) ? 1.0f : -1.0f;
    }
    return sum >= 0.0f ? 1.0f : -1.0f;
}

// The reconstruction at texel-local p in [0, 1]^2 (values outside are
// clamped). Never NaN or Inf for finite texel data.
SG_FN SgFeatResult sgFeatEval(SgFeatTexel tx, vec2 pIn) {
    vec2 p = clamp(pIn, vec2(0.0f), vec2(1.0f));
    SgFeatResult res;
    vec3 val;
    if ((tx.cfg & SG_FEAT_CFG_FEATURE_BITS) == 0u) {
        // No discontinuity: bilinear interpolation (TR2005 section 4.3).
        vec3 c0 = vec3(tx.dist.x, tx.grad0.x, tx.grad0.y);
        vec3 c1 = vec3(tx.dist.y, tx.grad1.x, tx.grad1.y);
        vec3 c2 = vec3(tx.dist.z, tx.grad2.x, tx.grad2.y);
        vec3 c3 = vec3(tx.dist.w, tx.grad3.x, tx.grad3.y);
        val = mix(mix(c0, c1, p.x), mix(c3, c2, p.x), p.y);
        float sideB = mix(mix(sgFeatCornerLeft(tx.cfg, 0) ? 1.0f : -1.0f, sgFeatCornerLeft(tx.cfg, 1) ? 1.0f : -1.0f, p.x),
                          mix(sgFeatCornerLeft(tx.cfg, 3) ? 1.0f : -1.0f, sgFeatCornerLeft(tx.cfg, 2) ? 1.0f : -1.0f, p.x), p.y);
        res.side = sideB >= 0.0f ? 1.0f : -1.0f;
    } else {
        SgFeatGeom g = sgFeatDecode(tx);
        int reach = sgFeatReachMask(g, p);
        res.side = sgFeatSideFromMask(tx, reach);
        // Step 4: quadrant by the two paths (references: the midpoints of
        // the west and south edges, never on a path), then the triangle by
        // the quadrant's diagonal (reference: the quadrant's corner).
        bool west = sgFeatSameSide(g.pathV, p, vec2(0.0f, 0.5f));
        bool south = sgFeatSameSide(g.pathH, p, vec2(0.5f, 0.0f));
        int k = west ? (south ? SG_FEAT_SW : SG_FEAT_NW) : (south ? SG_FEAT_SE : SG_FEAT_NE);
        int ea = (k + 3) % 4;
        int eb = k;
        int sd = sgFeatFindSeg(g, ea, eb);
        SgFeatCurve diag = sd >= 0 ? sgFeatSegFrom(g, sd, ea) : sgFeatMakeLine(g.q[ea], g.q[eb]);
        vec2 corner = sgFeatCornerPos(k);
        vec3 va = sgFeatEdgeValue(g, reach, ea);
        vec3 vb = sgFeatEdgeValue(g, reach, eb);
        if (sgFeatSameSide(diag, p, corner)) {
            vec3 vc = g.cv[k];
            val = diag.curved ? sg1CTriangle(diag, corner, va, vb, vc, p)
                              : sgFeatBary(g.q[ea], g.q[eb], corner, va, vb, vc, p);
        } else {
            vec3 vm = sgFeatCentreValue(g, reach);
            SgFeatCurve spokeA = sgFeatSpoke(g, ea); // q_a -> r_m
            SgFeatCurve spokeB = sgFeatSpoke(g, eb); // q_b -> r_m
            int nCurved = (diag.curved ? 1 : 0) + (spokeA.curved ? 1 : 0) + (spokeB.curved ? 1 : 0);
            if (nCurved == 0) {
                val = sgFeatBary(g.q[ea], g.q[eb], g.rm, va, vb, vm, p);
            } else if (nCurved == 1) {
                if (diag.curved) {
                    val = sg1CTriangle(diag, g.rm, va, vb, vm, p);
                } else if (spokeA.curved) {
                    val = sg1CTriangle(spokeA, g.q[eb], va, vm, vb, p);
                } else {
                    val = sg1CTriangle(spokeB, g.q[ea], vb, vm, va, p);
                }
            } else if (!diag.curved) {
                // Both spokes curved (two segments cross at r_m): they share r_m.
                val = sg2CTriangle(spokeA, spokeB, va, vm, vb, p);
            } else if (spokeA.curved) {
                // diag and spokeA share q_a.
                val = sg2CTriangle(sgFeatReverse(diag), sgFeatReverse(spokeA), vb, va, vm, p);
            } else {
                // diag and spokeB share q_b.
                val = sg2CTriangle(diag, sgFeatReverse(spokeB), va, vb, vm, p);
            }
        }
    }
    res.dist = max(val.x, 0.0f);
    res.grad = sgSafeNormalize2(vec2(val.y, val.z), vec2(0.0f));
    return res;
}

#endif
