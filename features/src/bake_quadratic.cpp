// Quadratic mode of the feature-map bake: validation of the discontinuity
// signatures and their local constrained optimisation. Parilov, Zorin,
// "Real-Time Rendering of Textures with Feature Curves" (TOG 2008):
// section 4 (invalid signatures, Eq. 2 and the thin-plate energy of Eq. 3),
// section 5.2 (the Eq. 7 safety test of the implicit side test and the
// theta_min straightening rule) and section 5.3 (the curvilinear triangles
// the runtime interpolates in, which the validation keeps well formed).
//
// Signature of a segment: its two edge points and the tangent angles there;
// the middle control point is the intersection of the two tangent lines. A
// signature is INVALID when the runtime (shaders/sg/features/evaluate.glsl)
// could not use it: parallel tangents that are not a straight segment, a
// curve leaving the texel (the paper asks for the middle control point
// inside the texel, which implies it but straightens curves that hug an
// edge), an implicit side test that the parabola's other parts would fool
// (Eq. 7, then an exact test), or a partition triangle that is not
// star-shaped (1C) / monotone and ordered (2C) for its interpolation
// scheme. Straightening rules (always valid): theta_min, flat pieces, the
// flatter of two crossing curves.
//
// Optimisation. The paper minimises the thin-plate energy of the affected
// segments (this texel's and the connected ones in its four edge
// neighbours, Eq. 2) over their control points, with linear inequalities
// (control points inside their texels), nonlinear equalities (G1 continuity
// through the shared edge points, points on their edges) and SQP. We
// optimise over the signatures instead, (t, theta) of this texel's edge
// points: the equality constraints then hold by construction (a shared
// angle IS G1 continuity; t IS a point on the edge), and what remains is
// "every affected texel valid". That constraint is not smooth (it counts
// roots and checks star-shapedness), so instead of SQP we use a
// pattern (compass) search with an extreme-barrier merit (Audet and Dennis,
// 2006): infeasible trial points are ranked by their violation and never
// beat a feasible one. On the smooth part of the problem compass search
// converges to a stationary point like SQP (Lewis and Torczon, 1999); with
// at most eight variables it costs a few hundred validations. The energy
// adds a fidelity term (kFidelityWeight times the squared distance from the
// input curve's farthest-from-chord point in the texel to the segment:
// without it the thin-plate energy straightens curves the search only needs
// to nudge) and a weak anchor 0.25 (t - t_initial)^2 keeping points near
// the centre of mass of the input crossings. Starts: the current signature; the paper's Eq. 7
// remedy (middle point moved onto the chord's perpendicular bisector, x0 = 0); tangents from the
// neighbouring edge points (Catmull-Rom). A texel the search cannot make valid has its segments
// straightened, which is always valid (the linear partition of TR2005).
//
// The geometry validated is the runtime's own: edge points and tangents are
// decoded from the 16-bit edge words, middle control points, the partition
// (paths, r_m, spokes, diagonals) come from the binary64 build of
// evaluate.glsl (shared_double.h), with its thresholds; the margins below
// only keep the runtime's binary32 decisions away from them.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "bake_internal.h"
#include "shared_double.h"

namespace sg::features::detail {

namespace {

// Margins (texels unless stated). They keep the runtime's binary32
// decisions away from their thresholds.
constexpr double kFlatDeviation = 1e-3;   // straight when the curve deviates less from its chord
constexpr double kExtensionMargin = 1e-3; // parabola extension kept this far from the texel
constexpr double kStarMargin = 1e-3;      // sine of the smallest sweep angle (1C)
constexpr double kOrderMargin = 1e-4;     // separation of 2C edges
constexpr double kAreaMargin = 1e-6;      // straight inner triangle orientation
constexpr double kSliverArea = 0.005;     // 1C triangles this thin need not be star-shaped
constexpr double kCurveMargin = 1e-4;     // curve interior kept this far inside the texel
constexpr double kInwardSin = 1e-3;       // curves leave their end points into the texel
// Tangents closer to parallel than this are not a curved segment (a margin
// far above the runtime's SG_FEAT_PARALLEL_SIN = 1e-6, where the middle
// control point would be ill-conditioned); such a segment is straight when
// both tangents follow its chord within kChordSin, else invalid.
constexpr double kParallelSin = 1e-3;
constexpr double kChordSin = 2e-3;
// Weight of the squared distance from the input curve's sample to the
// segment, added to the thin-plate energy (texels^-2 vs. the energy's
// texels^2). The thin-plate energy of a one-texel piece of a circle of
// radius R is about 0.2 / R^2; with this weight a 0.01-texel miss costs as
// much as that energy for R = 1.4 texels, so the optimisation keeps the
// input's shape and the energy only decides what the input leaves open
// (merged points, angles at junctions).
constexpr double kFidelityWeight = 1000.0;

dvec2 cornerPos(int k) {
    return {(k == 1 || k == 2) ? 1.0 : 0.0, k >= 2 ? 1.0 : 0.0};
}

double posOf(const Grid& g, int i, int j, int e) {
    return const_cast<Grid&>(g).pos(i, j, e);
}
double angOf(const Grid& g, int i, int j, int e) {
    return const_cast<Grid&>(g).ang(i, j, e);
}

// Exact safety of the implicit side test: the parabola outside u in [0, 1]
// never comes within kExtensionMargin of the closed texel (it can only
// enter by crossing an edge line within the edge's extent).
bool extensionSafe(const Quad& c) {
    dvec2 a = c.a(), b = c.b();
    for (int axis = 0; axis < 2; ++axis) {
        for (double val : {0.0, 1.0}) {
            double r[2];
            int n = quadRoots(a[axis], b[axis], c.p0[axis] - val, r);
            for (int k = 0; k < n; ++k) {
                if (r[k] >= -1e-7 && r[k] <= 1.0 + 1e-7) continue;
                double other = c.at(r[k])[1 - axis];
                if (other >= -kExtensionMargin && other <= 1.0 + kExtensionMargin) return false;
            }
        }
    }
    return true;
}

// 1C check: the curve X -> Y seen from q sweeps monotonically in the sense
// of the straight triangle (X, Y, q): every ray from q meets it once (Eq. 9).
double starViolation(const Quad& c, dvec2 q) {
    // Every scheme of sec. 5.3 interpolates convexly (s, u in [0, 1]), so a
    // triangle that is not star-shaped still yields values within the hull
    // of its vertex values; only its inside values can be misplaced. A
    // sliver (a curve hugging an edge, area below 1/200 texel) is accepted:
    // its vertices carry nearly equal values (all on one side of the curve).
    double area = 0.0;
    dvec2 prev = q;
    for (int k = 0; k <= 16; ++k) {
        dvec2 cur = c.at(k / 16.0);
        area += cross2(prev, cur);
        prev = cur;
    }
    area += cross2(prev, q);
    if (std::fabs(0.5 * area) < kSliverArea) return 0.0;
    double orient = cross2(c.p0 - q, c.p2 - q);
    if (std::fabs(orient) < 1e-9) return 0.1;
    double sgn = orient > 0 ? 1.0 : -1.0;
    double worst = 1e30;
    auto probe = [&](double u) {
        dvec2 r = c.at(u) - q, d = c.tangent(u);
        double len = std::sqrt(glm::dot(r, r) * glm::dot(d, d));
        double s = len > 0 ? sgn * cross2(r, d) / len : -1.0;
        worst = std::min(worst, s);
    };
    for (int k = 0; k <= 8; ++k) probe(k / 8.0);
    // The unnormalized sweep rate is quadratic in u; probe its extremum too.
    dvec2 a = c.a(), p10 = c.p1 - c.p0;
    double A = 2.0 * cross2(p10, a), B = 2.0 * cross2(c.p0 - q, a);
    if (std::fabs(A) > 1e-14) {
        double u = -B / (2.0 * A);
        if (u > 0.0 && u < 1.0) probe(u);
    }
    return std::max(0.0, kStarMargin - worst);
}

// 2C check: c1 runs X -> Y, c2 runs Z -> Y, [X, Z] straight. Lines parallel
// to Z - X must meet each curve once (monotone height) with c1 before c2.
double twoCViolation(const Quad& c1, const Quad& c2) {
    dvec2 X = c1.p0, Y = c1.p2, Z = c2.p0;
    dvec2 D = Z - X;
    double lenD = glm::length(D);
    if (lenD < 1e-6) return 1.0;
    dvec2 dh = D / lenD;
    dvec2 n{-dh.y, dh.x};
    if (glm::dot(n, Y - X) < 0) n = -n;
    double H = glm::dot(n, Y - X);
    double v = 0.0;
    if (H < 1e-4) v += 0.01 + (1e-4 - H);
    for (const Quad* c : {&c1, &c2}) {
        dvec2 d0 = c->tangent(0.0), d1 = c->tangent(1.0);
        double l0 = glm::length(d0), l1 = glm::length(d1);
        double s0 = l0 > 0 ? glm::dot(n, d0) / l0 : -1.0;
        double s1 = l1 > 0 ? glm::dot(n, d1) / l1 : -1.0;
        v += std::max(0.0, kStarMargin - s0) + std::max(0.0, -1e-9 - s1);
    }
    if (v > 0) return v;
    auto crossAt = [&](const Quad& c, double h, double& x) {
        dvec2 a = c.a(), b = c.b();
        double r[2];
        int k = quadRoots(glm::dot(n, a), glm::dot(n, b), glm::dot(n, c.p0 - X) - h, r);
        for (int m = 0; m < k; ++m) {
            if (r[m] >= -1e-9 && r[m] <= 1.0 + 1e-9) {
                x = glm::dot(dh, c.at(std::clamp(r[m], 0.0, 1.0)) - X);
                return true;
            }
        }
        return false;
    };
    for (int k = 1; k < 16; ++k) {
        double h = H * k / 16.0, x1 = 0, x2 = 0;
        if (!crossAt(c1, h, x1) || !crossAt(c2, h, x2)) {
            v += 0.01;
            continue;
        }
        v += std::max(0.0, kOrderMargin - (x2 - x1));
    }
    return v;
}

} // namespace

bool eq7Safe(const Quad& c) {
    // Eq. 5-7 in the frame where b0 = (-1/2, 0), b2 = (1/2, 0); distances
    // are converted back to texels (times the chord length L) before the
    // comparison with the texel diameter sqrt(2).
    dvec2 e = c.p2 - c.p0;
    double L = glm::length(e);
    if (L <= 0) return false;
    dvec2 ex = e / L, ey{-ex.y, ex.x};
    dvec2 m = 0.5 * (c.p0 + c.p2);
    double x0 = glm::dot(c.p1 - m, ex) / L, y0 = glm::dot(c.p1 - m, ey) / L;
    double nb1 = std::sqrt(x0 * x0 + y0 * y0);
    if (std::fabs(y0) < 1e-12) return true; // straight
    // v: coordinate across the parabola's axis (the axis is v = vAxis).
    double vAxis = -x0 * y0 / (4.0 * nb1 * nb1 * nb1);
    double v0 = y0 / (2.0 * nb1), v2 = -v0;
    double d0 = v0 - vAxis, d1 = -vAxis, d2 = v2 - vAxis;
    bool sameSide = (d0 > 0 && d1 > 0 && d2 > 0) || (d0 < 0 && d1 < 0 && d2 < 0);
    double dmin = std::min({std::fabs(d0), std::fabs(d1), std::fabs(d2)});
    return sameSide && L * dmin > std::sqrt(2.0);
}

LocalTexel decodeTexel(const Grid& g, int i, int j) {
    LocalTexel t;
    // Edge points through their 16-bit words, as the runtime reads them.
    for (int e = 0; e < 4; ++e) {
        double p = posOf(g, i, j, e);
        t.pt[e] = p >= 0.0;
        t.edgeWords[e] = t.pt[e] ? packEdgeWord(p, angOf(g, i, j, e)) : 0u;
        if (t.pt[e]) t.edgeFlags |= 1u << (SG_FEAT_CFG_EDGE_SHIFT + e);
    }
    const SharedGeom geom = sharedDecode(t.configWord(), t.edgeWords);
    for (int e = 0; e < 4; ++e) {
        t.q[e] = geom.q[e];
        t.tang[e] = geom.tang[e];
    }
    size_t ti = g.ti(i, j);
    unsigned mask = g.segMask[ti];
    unsigned quad = g.quadMask[ti] & ~unsigned(g.straightMask[ti]);
    for (int p = 0; p < kPairCount && t.nseg < 2; ++p) {
        if (!(mask & (1u << p))) continue;
        int s = t.nseg++;
        t.pair[s] = p;
        t.a[s] = kPairEdges[p][0];
        t.b[s] = kPairEdges[p][1];
        t.candidate[s] = (quad & (1u << p)) != 0;
        dvec2 qa = t.q[t.a[s]], qb = t.q[t.b[s]];
        t.seg[s] = {qa, 0.5 * (qa + qb), qb};
        t.curved[s] = false;
        auto it = g.targets.find(Grid::targetKey(ti, p));
        if (it != g.targets.end() && it->second.count > 0) {
            t.hasTarget[s] = true;
            t.target[s] = it->second.sum / double(it->second.count);
        }
    }
    return t;
}

uint32_t LocalTexel::configWord() const {
    uint32_t word = uint32_t(nseg) | edgeFlags | (1u << 20); // angles present
    for (int s = 0; s < nseg; ++s) {
        word |= uint32_t(a[s]) << (2 + 5 * s);
        word |= uint32_t(b[s]) << (4 + 5 * s);
        if (curved[s]) word |= 1u << (6 + 5 * s);
    }
    return word;
}

double segmentEnergy(const LocalTexel& t, int s, bool fidelity) {
    if (!t.candidate[s]) return 0.0;
    const int a = t.a[s], b = t.b[s];
    dvec2 qa = t.q[a], qb = t.q[b];
    dvec2 b1;
    double energy = 0.0;
    if (!sharedTangentIntersection(qa, t.tang[a], qb, t.tang[b], b1)) {
        // Parallel tangents: straight (no energy) when they follow the chord.
        dvec2 ch = glm::normalize(qb - qa);
        bool collinear = std::fabs(cross2(ch, t.tang[a])) < kChordSin &&
                         std::fabs(cross2(ch, t.tang[b])) < kChordSin;
        if (!collinear) return 1e3;
        b1 = 0.5 * (qa + qb);
    } else {
        dvec2 d = qa - 2.0 * b1 + qb;
        energy = 4.0 * glm::dot(d, d); // Eq. 3
    }
    if (fidelity && t.hasTarget[s]) {
        double u;
        energy += kFidelityWeight * closestParam(Quad{qa, b1, qb}, false, t.target[s], u);
    }
    return energy;
}

namespace {

// Angle between the tangent line at edge point e and the edge itself.
double edgeAngle(const LocalTexel& t, int e) {
    const double theta = std::atan2(std::fabs(t.tang[e].y), std::fabs(t.tang[e].x));
    return (e == 0 || e == 2) ? theta : 0.5 * M_PI - theta;
}

// The straightening rules and the checks of one candidate segment s
// (decides t.curved[s] and t.seg[s]); returns its violation.
double checkSegment(LocalTexel& t, int s, ValidationCounters* counters) {
    t.curved[s] = false;
    if (!t.candidate[s]) return 0.0;
    const int a = t.a[s], b = t.b[s];
    const dvec2 qa = t.q[a], qb = t.q[b];
    const double L = glm::length(qb - qa);
    const dvec2 ch = (qb - qa) / L;
    dvec2 b1;
    if (std::fabs(cross2(t.tang[a], t.tang[b])) < kParallelSin ||
        !sharedTangentIntersection(qa, t.tang[a], qb, t.tang[b], b1)) {
        // Parallel tangents: a straight segment if they follow the chord.
        if (std::fabs(cross2(ch, t.tang[a])) < kChordSin &&
            std::fabs(cross2(ch, t.tang[b])) < kChordSin) {
            if (counters) ++counters->flat;
            return 0.0;
        }
        return 1.0;
    }
    if (0.5 * std::fabs(cross2(ch, b1 - qa)) < kFlatDeviation) {
        if (counters) ++counters->flat;
        return 0.0;
    }
    // The curve must stay inside the texel away from its ends: it leaves
    // both end points into the texel and its interior extremes in x and y
    // lie in [margin, 1 - margin]. (The paper requires b1 inside the texel,
    // which implies this but rejects curves that hug a texel edge; this is
    // what the runtime needs.)
    const Quad cc{qa, b1, qb};
    double out = 0.0;
    for (int end = 0; end < 2; ++end) {
        int e = end == 0 ? a : b;
        dvec2 q = end == 0 ? qa : qb;
        dvec2 inward = e == 0   ? dvec2(0, 1)
                       : e == 1 ? dvec2(-1, 0)
                       : e == 2 ? dvec2(0, -1)
                                : dvec2(1, 0);
        double len = glm::length(b1 - q);
        double sn = len > 0 ? glm::dot(b1 - q, inward) / len : -1.0;
        out += std::max(0.0, kInwardSin - sn);
    }
    for (int axis = 0; axis < 2; ++axis) {
        double ac = cc.a()[axis], bc = cc.b()[axis];
        if (std::fabs(ac) < 1e-14) continue;
        double u = -bc / (2.0 * ac);
        if (u <= 0.0 || u >= 1.0) continue;
        double v = cc.at(u)[axis];
        out += std::max(0.0, kCurveMargin - v) + std::max(0.0, v - (1.0 - kCurveMargin));
    }
    // theta_min rule (sec. 5.2): the angle between the tangent and the texel
    // edge at each end must exceed theta_min(y0) = |atan(2 y0) - atan(4 y0)|
    // (y0: height of b1 over the chord in the frame of Eq. 5); below it the
    // segment becomes straight.
    const double y0 = std::fabs(cross2(ch, b1 - 0.5 * (qa + qb))) / L;
    const double thetaMin = std::fabs(std::atan(2.0 * y0) - std::atan(4.0 * y0));
    if (edgeAngle(t, a) < thetaMin || edgeAngle(t, b) < thetaMin) {
        if (counters) ++counters->thetaMin;
        return 0.0;
    }
    // A curve leaving the texel (measured above) is invalid; the amount it
    // leaves by ranks infeasible trial points in the search.
    if (out > 0.0) return out;
    const bool eq7 = eq7Safe(cc);
    if (!eq7 && counters) ++counters->eq7;
    if (!eq7 && !extensionSafe(cc)) return 0.5;
    t.seg[s] = cc;
    t.curved[s] = true;
    return 0.0;
}

// Two curved segments crossing the texel (S-N and W-E): the runtime
// intersects a line with a curve in closed form, so the flatter one becomes
// straight.
void crossingRule(LocalTexel& t, ValidationCounters* counters) {
    if (!(t.nseg == 2 && t.curved[0] && t.curved[1] && t.pair[0] == 4 && t.pair[1] == 5)) return;
    auto dev = [&](int s) {
        return std::fabs(
            cross2(glm::normalize(t.seg[s].p2 - t.seg[s].p0), t.seg[s].p1 - t.seg[s].p0));
    };
    const int flat = dev(0) <= dev(1) ? 0 : 1;
    t.curved[flat] = false;
    t.seg[flat] = {t.q[t.a[flat]], 0.5 * (t.q[t.a[flat]] + t.q[t.b[flat]]), t.q[t.b[flat]]};
    if (counters) ++counters->cross;
}

// The runtime's 8-triangle partition of the texel with its final curved
// bits (the binary64 build of sgFeatDecode): r_m must be one clean
// line/curve intersection, and each quadrant's corner and inner triangles
// must suit their interpolation scheme (sec. 5.3).
double partitionViolation(const LocalTexel& t) {
    const SharedGeom g = sharedDecode(t.configWord(), t.edgeWords);
    if (g.pathV.curved || g.pathH.curved) {
        const PEdge& cur = g.pathV.curved ? g.pathV : g.pathH;
        const PEdge& lin = g.pathV.curved ? g.pathH : g.pathV;
        dvec2 d = lin.c.p2 - lin.c.p0;
        double r[2];
        int n = quadRoots(cross2(cur.c.a(), d), cross2(cur.c.b(), d),
                          cross2(cur.c.p0 - lin.c.p0, d), r);
        int inside = 0;
        for (int k = 0; k < n; ++k) inside += r[k] >= -1e-9 && r[k] <= 1.0 + 1e-9;
        if (inside != 1) return 0.5;
        double ul = glm::dot(g.rm - lin.c.p0, d) / glm::dot(d, d);
        if (ul <= 1e-4 || ul >= 1.0 - 1e-4) return 0.5;
    }
    double viol = 0.0;
    for (int k = 0; k < 4; ++k) {
        int ea = (k + 3) % 4, eb = k;
        const PEdge diag = sharedDiagonal(g, ea, eb);
        const dvec2 corner = cornerPos(k);
        if (diag.curved) viol += starViolation(diag.c, corner);
        const PEdge sa = sharedSpoke(g, ea), sb = sharedSpoke(g, eb);
        const int nc = int(diag.curved) + int(sa.curved) + int(sb.curved);
        if (nc == 0) {
            double sIn = cross2(t.q[eb] - t.q[ea], g.rm - t.q[ea]);
            double sC = cross2(t.q[eb] - t.q[ea], corner - t.q[ea]);
            viol += std::max(0.0, kAreaMargin - (sC > 0 ? -sIn : sIn));
        } else if (nc == 1) {
            if (diag.curved)
                viol += starViolation(diag.c, g.rm);
            else if (sa.curved)
                viol += starViolation(sa.c, t.q[eb]);
            else
                viol += starViolation(sb.c, t.q[ea]);
        } else if (!diag.curved) {
            viol += twoCViolation(sa.c, sb.c);
        } else if (sa.curved) {
            viol += twoCViolation(diag.c.reversed(), sa.c.reversed());
        } else {
            viol += twoCViolation(diag.c, sb.c.reversed());
        }
    }
    return viol;
}

} // namespace

double validateTexel(LocalTexel& t, ValidationCounters* counters) {
    double viol = 0.0;
    for (int s = 0; s < t.nseg; ++s) viol += checkSegment(t, s, counters);
    crossingRule(t, counters);
    bool anyCurved = false;
    for (int s = 0; s < t.nseg; ++s) anyCurved |= t.curved[s];
    if (viol > 0.0 || !anyCurved) return viol; // straight partitions are always valid
    return partitionViolation(t);
}

} // namespace sg::features::detail
