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
//     triangle and an inner triangle. Every segment is a partition edge. At
//     most one path is curved (the bake straightens one of two crossing
//     curves), so r_m is one closed-form line/curve intersection.
//  3. Locate p: the quadrant by two side tests, then the triangle by one
//     (section 5.2: linear, or the implicit form of Eq. 4).
//  4. Reachable corners (appendix step 3): the corners on the same side of
//     every segment as p. Values (d, grad) at the triangle's vertices come
//     from reachable corners only: a corner keeps its sample; an edge vertex
//     interpolates its edge's reachable corners (two: linear; one: copy;
//     none: the value at the other end of a segment through it, step
//     3.1.3; we use the mean of the region's corners), with d = 0 on a
//     discontinuity point (step 3.2) and, there, the gradient replaced by
//     the curve's normal (our addition, see sgFeatOnCurveNormal); r_m
//     interpolates its path's end values (step 4),
//     along the discontinuity when one passes through r_m, else the average
//     of both paths (TR2005-872, Fig. 7).
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
//
// Cost. GPUs without real branching (llvmpipe runs divergent branches under
// execution masks) pay for every path the code contains, so the code is
// arranged to compute each quantity once: four edge values, one triangle
// selection, one interpolation of each kind. SG_FEAT_CURVED 0 compiles the
// straight-segment evaluator only (no implicit forms, no curvilinear
// triangles): use it for maps baked in linear mode. It gives the same
// results as the full evaluator on such maps.
#ifndef SG_FEATURES_EVALUATE_GLSL
#define SG_FEATURES_EVALUATE_GLSL

#include "sg/features/curve.glsl"

// Decoded texel (steps 1-2). Arrays are indexed by edge or corner number.
struct SgFeatGeom {
    vec2 q[4];          // edge vertices (texel-local)
    vec2 tang[4];       // unit tangent of the curve at each edge point
    bool pt[4];         // edge carries a discontinuity point
    float t[4];         // position of the edge vertex along its edge
    vec3 cv[4];         // corner samples (d, grad.x, grad.y)
    bool angles;        // tangents are stored (layout.glsl bit 20)
    int nseg;           // number of segments (0..2)
    int segA[2];        // edge of each segment's first end
    int segB[2];        // edge of each segment's second end
    SgFeatCurve seg[2]; // segment s runs from q[segA[s]] to q[segB[s]]
    SgFeatCurve pathV;  // q_S -> q_N
    SgFeatCurve pathH;  // q_W -> q_E
    bool discV;         // pathV is a segment (a discontinuity)
    bool discH;
    vec2 rm;            // centre vertex
    float uV;           // parameter of rm on pathV
    float uH;           // parameter of rm on pathH
};

// Element i of a 4-array given as its elements, by selects: GPUs without
// real branching execute a dynamically indexed local array as a loop over
// lanes, selects as a few vector operations. All indexing of the arrays
// above with data-dependent indices goes through these.
SG_FN vec2 sgFeatPick2(vec2 a, vec2 b, vec2 c, vec2 d, int i) { return i == 0 ? a : (i == 1 ? b : (i == 2 ? c : d)); }
SG_FN vec3 sgFeatPick3(vec3 a, vec3 b, vec3 c, vec3 d, int i) { return i == 0 ? a : (i == 1 ? b : (i == 2 ? c : d)); }
SG_FN vec2 sgFeatQ(SgFeatGeom g, int i) { return sgFeatPick2(g.q[0], g.q[1], g.q[2], g.q[3], i); }
SG_FN vec2 sgFeatTang(SgFeatGeom g, int i) { return sgFeatPick2(g.tang[0], g.tang[1], g.tang[2], g.tang[3], i); }
SG_FN vec3 sgFeatCv(SgFeatGeom g, int i) { return sgFeatPick3(g.cv[0], g.cv[1], g.cv[2], g.cv[3], i); }

SG_FN vec2 sgFeatCornerPos(int k) {
    return vec2(k == 1 || k == 2 ? 1.0f : 0.0f, k >= 2 ? 1.0f : 0.0f);
}
// Corners at t = 0 and t = 1 of edge e (t runs along +x or +y).
SG_FN int sgFeatEdgeCorner0(int e) { return e == SG_FEAT_E ? SG_FEAT_SE : (e == SG_FEAT_N ? SG_FEAT_NW : SG_FEAT_SW); }
SG_FN int sgFeatEdgeCorner1(int e) {
    return e == SG_FEAT_S ? SG_FEAT_SE : (e == SG_FEAT_W ? SG_FEAT_NW : SG_FEAT_NE);
}
SG_FN vec2 sgFeatEdgePoint(int e, float t) {
    return vec2(e == SG_FEAT_E ? 1.0f : (e == SG_FEAT_W ? 0.0f : t), e == SG_FEAT_N ? 1.0f : (e == SG_FEAT_S ? 0.0f : t));
}

// Index of the segment joining edges a and b, or -1.
SG_FN int sgFeatFindSeg(SgFeatGeom g, int a, int b) {
    bool s0 = g.nseg > 0 && ((g.segA[0] == a && g.segB[0] == b) || (g.segA[0] == b && g.segB[0] == a));
    bool s1 = g.nseg > 1 && ((g.segA[1] == a && g.segB[1] == b) || (g.segA[1] == b && g.segB[1] == a));
    return s1 ? 1 : (s0 ? 0 : -1);
}

// Segment s oriented from edge a to the other end.
SG_FN SgFeatCurve sgFeatSegFrom(SgFeatGeom g, int s, int a) {
    SgFeatCurve c = s == 0 ? g.seg[0] : g.seg[1];
    int first = s == 0 ? g.segA[0] : g.segA[1];
    return first == a ? c : sgFeatReverse(c);
}

SG_FN void sgFeatDecodeEdge(uint cfg, uint w, int e, SG_OUT(bool) pt, SG_OUT(float) t, SG_OUT(vec2) q,
                            SG_OUT(vec2) tang) {
    pt = sgFeatEdgeHasPoint(cfg, e);
    t = pt ? sgFeatEdgePos(w) : 0.5f;
    q = sgFeatEdgePoint(e, t);
    tang = pt ? sgFeatEdgeTangent(w) : vec2(1.0f, 0.0f);
}

// The segment from edge a to edge b; its middle control point is where the
// end tangents meet (appendix step 2).
SG_FN SgFeatCurve sgFeatDecodeSeg(SgFeatGeom g, int a, int b, bool curved) {
    vec2 qa = sgFeatQ(g, a);
    vec2 qb = sgFeatQ(g, b);
#if SG_FEAT_CURVED
    bool ok = false;
    vec2 mid = sgFeatTangentIntersection(qa, sgFeatTang(g, a), qb, sgFeatTang(g, b), ok);
    // A straight segment keeps the midpoint: curve evaluation (r_m) relies
    // on B(u) being the linear interpolation then.
    bool c = curved && ok;
    return sgFeatMakeCurve(qa, c ? mid : 0.5f * (qa + qb), qb, c);
#else
    return sgFeatMakeLine(qa, qb);
#endif
}

SG_FN SgFeatGeom sgFeatDecode(SgFeatTexel tx) {
    SgFeatGeom g;
    g.cv[0] = vec3(tx.dist.x, tx.grad0.x, tx.grad0.y);
    g.cv[1] = vec3(tx.dist.y, tx.grad1.x, tx.grad1.y);
    g.cv[2] = vec3(tx.dist.z, tx.grad2.x, tx.grad2.y);
    g.cv[3] = vec3(tx.dist.w, tx.grad3.x, tx.grad3.y);
    g.angles = sgFeatHasAngles(tx.cfg);
    // Written out per edge and segment (no loops): constant indices keep
    // the arrays in registers on every GPU.
    sgFeatDecodeEdge(tx.cfg, tx.edges.x, 0, g.pt[0], g.t[0], g.q[0], g.tang[0]);
    sgFeatDecodeEdge(tx.cfg, tx.edges.y, 1, g.pt[1], g.t[1], g.q[1], g.tang[1]);
    sgFeatDecodeEdge(tx.cfg, tx.edges.z, 2, g.pt[2], g.t[2], g.q[2], g.tang[2]);
    sgFeatDecodeEdge(tx.cfg, tx.edges.w, 3, g.pt[3], g.t[3], g.q[3], g.tang[3]);
    g.nseg = min(sgFeatSegCount(tx.cfg), 2);
    g.segA[0] = sgFeatSegEdgeA(tx.cfg, 0);
    g.segB[0] = sgFeatSegEdgeB(tx.cfg, 0);
    g.segA[1] = sgFeatSegEdgeA(tx.cfg, 1);
    g.segB[1] = sgFeatSegEdgeB(tx.cfg, 1);
    g.seg[0] = sgFeatDecodeSeg(g, g.segA[0], g.segB[0], g.nseg > 0 && sgFeatSegCurved(tx.cfg, 0));
    g.seg[1] = sgFeatDecodeSeg(g, g.segA[1], g.segB[1], g.nseg > 1 && sgFeatSegCurved(tx.cfg, 1));
    int sV = sgFeatFindSeg(g, SG_FEAT_S, SG_FEAT_N);
    int sH = sgFeatFindSeg(g, SG_FEAT_W, SG_FEAT_E);
    g.discV = sV >= 0;
    g.discH = sH >= 0;
    g.pathV = g.discV ? sgFeatSegFrom(g, sV, SG_FEAT_S) : sgFeatMakeLine(g.q[0], g.q[2]);
    g.pathH = g.discH ? sgFeatSegFrom(g, sH, SG_FEAT_W) : sgFeatMakeLine(g.q[3], g.q[1]);
    // The bake never stores two curved paths; treat a second one as its
    // chord so r_m stays one line/curve intersection.
    if (g.pathV.curved) g.pathH.curved = false;
    // Centre vertex r_m: where the straight path (as a line) meets the other.
    bool vCurved = g.pathV.curved;
    SgFeatCurve other = vCurved ? g.pathV : g.pathH;
    SgFeatCurve straight = vCurved ? g.pathH : g.pathV;
    vec2 dir = straight.p2 - straight.p0;
    float u = sgFeatLineCurveParam(other, straight.p0, dir, false);
    g.rm = sgFeatCurvePoint(other, u);
    float ul = clamp(dot(g.rm - straight.p0, dir) / max(dot(dir, dir), 1e-12f), 0.0f, 1.0f);
    g.uV = vCurved ? u : ul;
    g.uH = vCurved ? ul : u;
    return g;
}

// Bit k set when corner k is on the same side as p of every segment
// (appendix step 3). Segment s splits the corners into those met walking
// counter-clockwise from its first end to its second end (corners
// segA+1 .. segB) and the others; corner segA+1 is the reference point of
// the side test.
SG_FN int sgFeatSegReach(SgFeatCurve c, int a, int b, bool present, vec2 p) {
    int arcLen = (b - a + 4) & 3;
    int base = (1 << arcLen) - 1;
    int r = (a + 1) & 3;
    int arc = ((base << r) | (base >> (4 - r))) & 15;
    bool pOnRefSide = sgFeatSameSide(c, p, sgFeatCornerPos(r));
    return present ? (pOnRefSide ? arc : (~arc & 15)) : 15;
}

SG_FN int sgFeatReachMask(SgFeatGeom g, vec2 p) {
    return sgFeatSegReach(g.seg[0], g.segA[0], g.segB[0], g.nseg > 0, p) &
           sgFeatSegReach(g.seg[1], g.segA[1], g.segB[1], g.nseg > 1, p);
}

// Values (d, grad) at the four edge vertices for p's region (appendix
// steps 3.1-3.2), the addition of sgFeatOnCurveNormal included.
struct SgFeatEdgeValues {
    vec3 v[4];
};

// On a discontinuity point the gradient is the curve's unit normal there
// (from the signature's tangent angle): exact on the curve, where the corner
// samples only approximate it (they are smoothed, and turn near the medial
// axis). Where a segment of this texel ends on the edge, the curve separates
// the edge's two corners and exactly one is reachable: the normal points
// towards it (the edge leads from the point into p's region), and both
// texels sharing the point see the same angle and corner, so the gradient
// stays continuous across the texel edge. Where a curve merely ends on the
// edge (both corners reachable) or two segments meet with p between them
// (none), the corner values of appendix step 3.1 orient it. (Measured on an
// eight-ray star, this gives fewer gradient jumps across texel edges than
// keeping the corner values there.) An addition to the papers, which always
// interpolate the corner gradients here.
SG_FN vec3 sgFeatOnCurveNormal(SgFeatGeom g, int reach, int e, vec3 v) {
    vec2 tg = sgFeatTang(g, e);
    vec2 n = vec2(-tg.y, tg.x);
    int c0 = sgFeatEdgeCorner0(e);
    int c1 = sgFeatEdgeCorner1(e);
    bool r0 = ((reach >> c0) & 1) != 0;
    bool r1 = ((reach >> c1) & 1) != 0;
    vec2 ref = r0 != r1 ? sgFeatCornerPos(r0 ? c0 : c1) - sgFeatQ(g, e) : vec2(v.y, v.z);
    float s = dot(n, ref);
    bool pt = e == 0 ? g.pt[0] : (e == 1 ? g.pt[1] : (e == 2 ? g.pt[2] : g.pt[3]));
    // |s| > 0.05 |ref|: with an unclear orientation (a curve nearly along the
    // edge) the corner values stay.
    bool use = pt && g.angles && s * s > 0.0025f * dot(ref, ref);
    vec2 o = s > 0.0f ? n : -n;
    return use ? vec3(v.x, o.x, o.y) : v;
}

// Step 3.1-3.2 for edge e: the reachable corners of its edge; ok = false
// when neither is reachable (then `mean`, the mean of the region's reachable
// corners).
SG_FN vec3 sgFeatEdgeBasic(SgFeatGeom g, int reach, int e, vec3 mean, SG_OUT(bool) ok) {
    int c0 = sgFeatEdgeCorner0(e);
    int c1 = sgFeatEdgeCorner1(e);
    bool r0 = ((reach >> c0) & 1) != 0;
    bool r1 = ((reach >> c1) & 1) != 0;
    vec3 v0 = sgFeatCv(g, c0);
    vec3 v1 = sgFeatCv(g, c1);
    float t = e == 0 ? g.t[0] : (e == 1 ? g.t[1] : (e == 2 ? g.t[2] : g.t[3]));
    vec3 v = r0 && r1 ? mix(v0, v1, t) : (r0 ? v0 : (r1 ? v1 : mean));
    ok = r0 || r1;
    bool pt = e == 0 ? g.pt[0] : (e == 1 ? g.pt[1] : (e == 2 ? g.pt[2] : g.pt[3]));
    return vec3(pt ? 0.0f : v.x, v.y, v.z); // step 3.2
}

SG_FN SgFeatEdgeValues sgFeatEdgeValues(SgFeatGeom g, int reach) {
    float w0 = float(reach & 1);
    float w1 = float((reach >> 1) & 1);
    float w2 = float((reach >> 2) & 1);
    float w3 = float((reach >> 3) & 1);
    vec3 mean = (w0 * g.cv[0] + w1 * g.cv[1] + w2 * g.cv[2] + w3 * g.cv[3]) / max(w0 + w1 + w2 + w3, 1.0f);
    // Step 3.1.3 (an edge point with no reachable corner: the common end of
    // two segments with p between them): the paper takes the value at
    // another segment end; we take the mean of the region's corners
    // (sgFeatEdgeBasic's fallback), which needs no data-dependent indexing.
    // Between two segments that leave one point along one tangent the true
    // gradient flips at their medial axis anyway.
    bool ok = false;
    SgFeatEdgeValues r;
    r.v[0] = sgFeatOnCurveNormal(g, reach, 0, sgFeatEdgeBasic(g, reach, 0, mean, ok));
    r.v[1] = sgFeatOnCurveNormal(g, reach, 1, sgFeatEdgeBasic(g, reach, 1, mean, ok));
    r.v[2] = sgFeatOnCurveNormal(g, reach, 2, sgFeatEdgeBasic(g, reach, 2, mean, ok));
    r.v[3] = sgFeatOnCurveNormal(g, reach, 3, sgFeatEdgeBasic(g, reach, 3, mean, ok));
    return r;
}

// Value at the centre vertex r_m (step 4).
SG_FN vec3 sgFeatCentreValue(SgFeatGeom g, SgFeatEdgeValues ev) {
    vec3 alongV = mix(ev.v[SG_FEAT_S], ev.v[SG_FEAT_N], g.uV);
    vec3 alongH = mix(ev.v[SG_FEAT_W], ev.v[SG_FEAT_E], g.uH);
    if (g.discV && !g.discH) return alongV;
    if (g.discH && !g.discV) return alongH;
    return 0.5f * (alongV + alongH);
}

// Spoke of the partition from edge vertex q[e] to r_m (part of pathV for
// S/N, of pathH for W/E).
SG_FN SgFeatCurve sgFeatSpoke(SgFeatGeom g, int e) {
    bool vert = e == SG_FEAT_S || e == SG_FEAT_N;
    bool start = e == SG_FEAT_S || e == SG_FEAT_W;
    return sgFeatSubCurve(vert ? g.pathV : g.pathH, start ? 0.0f : 1.0f, vert ? g.uV : g.uH);
}

// Straight triangle: barycentric interpolation.
SG_FN vec3 sgFeatBary(vec2 a, vec2 b, vec2 c, vec3 va, vec3 vb, vec3 vc, vec2 p) {
    float area = sgFeatCross(b - a, c - a);
    float inv = abs(area) > 1e-12f ? 1.0f / area : 0.0f;
    float wa = abs(area) > 1e-12f ? sgFeatCross(b - p, c - p) * inv : 1.0f / 3.0f;
    float wb = abs(area) > 1e-12f ? sgFeatCross(c - p, a - p) * inv : 1.0f / 3.0f;
    return wa * va + wb * vb + (1.0f - wa - wb) * vc;
}

// 1C-triangle <p1, p2, q> (Eq. 9): the curved edge c runs from p1 (u = 0,
// value v1) to p2 (u = 1, value v2); q (value vq) is joined to both by
// straight edges. The ray from q through p meets c at p' = c(u) and
// s = |p' - p| / |p' - q|; V = (1 - s) mix(v1, v2, u) + s vq.
SG_FN vec3 sg1CTriangle(SgFeatCurve c, vec2 q, vec3 v1, vec3 v2, vec3 vq, vec2 p) {
    vec2 r = p - q;
    float rr = dot(r, r);
    float u = sgFeatLineCurveParam(c, q, r, true);
    float lambda = dot(sgFeatCurvePoint(c, u) - q, r) / max(rr, 1e-20f); // p' = q + lambda r
    float s = lambda > 1.0f ? 1.0f - 1.0f / lambda : 0.0f;
    vec3 v = (1.0f - s) * mix(v1, v2, u) + s * vq;
    return rr > 1e-14f ? v : vq;
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

SG_FN float sgFeatCornerSign(uint cfg, int k) { return sgFeatCornerLeft(cfg, k) ? 1.0f : -1.0f; }

// The reconstruction at texel-local p in [0, 1]^2 (values outside are
// clamped). Never NaN or Inf for finite texel data.
SG_FN SgFeatResult sgFeatEval(SgFeatTexel tx, vec2 pIn) {
    vec2 p = clamp(pIn, sgVec2(0.0f), sgVec2(1.0f));
    SgFeatResult res;
    // No discontinuity: bilinear interpolation (TR2005 section 4.3).
    vec3 c0 = vec3(tx.dist.x, tx.grad0.x, tx.grad0.y);
    vec3 c1 = vec3(tx.dist.y, tx.grad1.x, tx.grad1.y);
    vec3 c2 = vec3(tx.dist.z, tx.grad2.x, tx.grad2.y);
    vec3 c3 = vec3(tx.dist.w, tx.grad3.x, tx.grad3.y);
    vec3 val = mix(mix(c0, c1, p.x), mix(c3, c2, p.x), p.y);
    float sideB = mix(mix(sgFeatCornerSign(tx.cfg, 0), sgFeatCornerSign(tx.cfg, 1), p.x),
                      mix(sgFeatCornerSign(tx.cfg, 3), sgFeatCornerSign(tx.cfg, 2), p.x), p.y);
    res.side = sideB >= 0.0f ? 1.0f : -1.0f;
    if ((tx.cfg & SG_FEAT_CFG_FEATURE_BITS) != 0u) {
        SgFeatGeom g = sgFeatDecode(tx);
        int reach = sgFeatReachMask(g, p);
        float sum = float(reach & 1) * sgFeatCornerSign(tx.cfg, 0) + float((reach >> 1) & 1) * sgFeatCornerSign(tx.cfg, 1) +
                    float((reach >> 2) & 1) * sgFeatCornerSign(tx.cfg, 2) + float((reach >> 3) & 1) * sgFeatCornerSign(tx.cfg, 3);
        res.side = sum >= 0.0f ? 1.0f : -1.0f;
        // Step 4: quadrant by the two paths (references: the midpoints of
        // the west and south edges, never on a path), then the triangle by
        // the quadrant's diagonal (reference: the quadrant's corner).
        bool west = sgFeatSameSide(g.pathV, p, vec2(0.0f, 0.5f));
        bool south = sgFeatSameSide(g.pathH, p, vec2(0.5f, 0.0f));
        int k = west ? (south ? SG_FEAT_SW : SG_FEAT_NW) : (south ? SG_FEAT_SE : SG_FEAT_NE);
        int ea = (k + 3) & 3;
        int eb = k;
        int sd = sgFeatFindSeg(g, ea, eb);
        SgFeatCurve diag = sd >= 0 ? sgFeatSegFrom(g, sd, ea) : sgFeatMakeLine(sgFeatQ(g, ea), sgFeatQ(g, eb));
        vec2 corner = sgFeatCornerPos(k);
        bool inCorner = sgFeatSameSide(diag, p, corner);
        SgFeatEdgeValues ev = sgFeatEdgeValues(g, reach);
        vec3 va = sgFeatPick3(ev.v[0], ev.v[1], ev.v[2], ev.v[3], ea);
        vec3 vb = sgFeatPick3(ev.v[0], ev.v[1], ev.v[2], ev.v[3], eb);
        vec3 vc = sgFeatCv(g, k);
        vec3 vm = sgFeatCentreValue(g, ev);
        vec2 qa = sgFeatQ(g, ea);
        vec2 qb = sgFeatQ(g, eb);
        // The triangle: corner (qa, qb, corner) or inner (qa, qb, r_m).
        vec2 apex = inCorner ? corner : g.rm;
        vec3 vApex = inCorner ? vc : vm;
        vec3 straight = sgFeatBary(qa, qb, apex, va, vb, vApex, p);
#if SG_FEAT_CURVED
        SgFeatCurve spokeA = sgFeatSpoke(g, ea); // q_a -> r_m
        SgFeatCurve spokeB = sgFeatSpoke(g, eb); // q_b -> r_m
        bool cA = !inCorner && spokeA.curved;
        bool cB = !inCorner && spokeB.curved;
        int nCurved = (diag.curved ? 1 : 0) + (cA ? 1 : 0) + (cB ? 1 : 0);
        // 1C: the curved edge, its end values and the opposite vertex.
        SgFeatCurve oneC = diag.curved ? diag : (cA ? spokeA : spokeB);
        vec2 oneQ = diag.curved ? apex : (cA ? qb : qa);
        vec3 oneV1 = diag.curved ? va : (cA ? va : vb);
        vec3 oneV2 = diag.curved ? vb : vm;
        vec3 oneVq = diag.curved ? vApex : (cA ? vb : va);
        vec3 curved1 = sg1CTriangle(oneC, oneQ, oneV1, oneV2, oneVq, p);
        // 2C: curves X -> Y and Z -> Y sharing Y (r_m when both spokes are
        // curved, else the end the diagonal shares with the curved spoke).
        SgFeatCurve twoC1 = !diag.curved ? spokeA : (cA ? sgFeatReverse(diag) : diag);
        SgFeatCurve twoC2 = !diag.curved ? spokeB : sgFeatReverse(cA ? spokeA : spokeB);
        vec3 twoVx = !diag.curved ? va : (cA ? vb : va);
        vec3 twoVy = !diag.curved ? vm : (cA ? va : vb);
        vec3 twoVz = !diag.curved ? vb : vm;
        vec3 curved2 = sg2CTriangle(twoC1, twoC2, twoVx, twoVy, twoVz, p);
        val = nCurved == 0 ? straight : (nCurved == 1 ? curved1 : curved2);
#else
        val = straight;
#endif
    }
    res.dist = max(val.x, 0.0f);
    // Gradient samples have length <= 1, so no overflow guard is needed; a
    // vanishing one (no curve within the band) stays 0.
    vec2 gr = vec2(val.y, val.z);
    float l2 = dot(gr, gr);
    res.grad = l2 > 1e-24f ? gr * inversesqrt(l2) : sgVec2(0.0f);
    res.profile = -1;
    res.width = 0.0f;
    return res;
}

#endif
