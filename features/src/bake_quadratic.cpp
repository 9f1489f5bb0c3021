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
#include <algorithm>
#include <chrono>
#include <cmath>

#include "bake_internal.h"

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
// Weight of the squared distance from the input curve's sample to the
// segment, added to the thin-plate energy (texels^-2 vs. the energy's
// texels^2). The thin-plate energy of a one-texel piece of a circle of
// radius R is about 0.2 / R^2; with this weight a 0.01-texel miss costs as
// much as that energy for R = 1.4 texels, so the optimisation keeps the
// input's shape and the energy only decides what the input leaves open
// (merged points, angles at junctions).
constexpr double kFidelityWeight = 1000.0;

dvec2 edgePoint(int e, double t) {
    switch (e) {
    case 0:
        return {t, 0.0};
    case 1:
        return {1.0, t};
    case 2:
        return {t, 1.0};
    default:
        return {0.0, t};
    }
}

dvec2 cornerPos(int k) {
    return {(k == 1 || k == 2) ? 1.0 : 0.0, k >= 2 ? 1.0 : 0.0};
}

dvec2 dirOf(double theta) {
    return {std::cos(theta), std::sin(theta)};
}

double posOf(const Grid& g, int i, int j, int e) {
    return const_cast<Grid&>(g).pos(i, j, e);
}
double angOf(const Grid& g, int i, int j, int e) {
    return const_cast<Grid&>(g).ang(i, j, e);
}

// Middle control point from the signature; false when the tangent lines
// are (nearly) parallel.
bool tangentIntersection(dvec2 qa, double ta, dvec2 qb, double tb, dvec2& b1, double minSin) {
    dvec2 da = dirOf(ta), db = dirOf(tb);
    double den = cross2(da, db);
    if (std::fabs(den) < minSin) return false;
    b1 = qa + (cross2(qb - qa, db) / den) * da;
    return true;
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

struct PEdge {
    Quad c;
    bool curved = false;
};

PEdge lineEdge(dvec2 a, dvec2 b) {
    return {{a, 0.5 * (a + b), b}, false};
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
    for (int e = 0; e < 4; ++e) {
        double p = posOf(g, i, j, e);
        t.pt[e] = p >= 0.0;
        t.t[e] = t.pt[e] ? p : 0.5;
        t.theta[e] = t.pt[e] ? angOf(g, i, j, e) : 0.0;
        t.q[e] = edgePoint(e, t.t[e]);
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

double segmentEnergy(const LocalTexel& t, int s) {
    if (!t.candidate[s]) return 0.0;
    dvec2 qa = t.q[t.a[s]], qb = t.q[t.b[s]];
    dvec2 b1;
    double energy = 0.0;
    if (!tangentIntersection(qa, t.theta[t.a[s]], qb, t.theta[t.b[s]], b1, 1e-9)) {
        dvec2 ch = glm::normalize(qb - qa);
        bool collinear = std::fabs(cross2(ch, dirOf(t.theta[t.a[s]]))) < 1e-6 &&
                         std::fabs(cross2(ch, dirOf(t.theta[t.b[s]]))) < 1e-6;
        if (!collinear) return 1e3;
        b1 = 0.5 * (qa + qb);
    } else {
        dvec2 d = qa - 2.0 * b1 + qb;
        energy = 4.0 * glm::dot(d, d); // Eq. 3
    }
    if (t.hasTarget[s]) {
        double u;
        energy += kFidelityWeight * closestParam(Quad{qa, b1, qb}, false, t.target[s], u);
    }
    return energy;
}

double validateTexel(LocalTexel& t, ValidationCounters* counters) {
    double viol = 0.0;
    for (int s = 0; s < t.nseg; ++s) {
        t.curved[s] = false;
        if (!t.candidate[s]) continue;
        int a = t.a[s], b = t.b[s];
        dvec2 qa = t.q[a], qb = t.q[b];
        dvec2 chord = qb - qa;
        double L = glm::length(chord);
        dvec2 ch = chord / L;
        dvec2 b1;
        if (!tangentIntersection(qa, t.theta[a], qb, t.theta[b], b1, 1e-3)) {
            // Parallel tangents: a straight segment if they follow the chord.
            if (std::fabs(cross2(ch, dirOf(t.theta[a]))) < 2e-3 &&
                std::fabs(cross2(ch, dirOf(t.theta[b]))) < 2e-3) {
                if (counters) ++counters->flat;
            } else {
                viol += 1.0;
            }
            continue;
        }
        if (0.5 * std::fabs(cross2(ch, b1 - qa)) < kFlatDeviation) {
            if (counters) ++counters->flat;
            continue;
        }
        // The curve must stay inside the texel away from its ends: it
        // leaves both end points into the texel and its interior extremes
        // in x and y lie in [margin, 1 - margin]. (The paper requires b1
        // inside the texel, which implies this but rejects curves that
        // hug a texel edge; this is what the runtime needs.)
        Quad cc{qa, b1, qb};
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
        // theta_min rule (sec. 5.2): the angle between the tangent and the
        // texel edge at each end must exceed theta_min(y0) =
        // |atan(2 y0) - atan(4 y0)| (y0: height of b1 over the chord in the
        // frame of Eq. 5); below it the segment becomes straight.
        dvec2 m = 0.5 * (qa + qb);
        double y0 = std::fabs(cross2(ch, b1 - m)) / L;
        double thetaMin = std::fabs(std::atan(2.0 * y0) - std::atan(4.0 * y0));
        auto edgeAngle = [&](int e) {
            double th = std::fabs(t.theta[e]);
            return (e == 0 || e == 2) ? th : 0.5 * M_PI - th;
        };
        if (edgeAngle(a) < thetaMin || edgeAngle(b) < thetaMin) {
            if (counters) ++counters->thetaMin;
            continue;
        }
        // A curve leaving the texel (measured above) is invalid; the
        // amount it leaves by ranks infeasible trial points in the search.
        if (out > 0.0) {
            viol += out;
            continue;
        }
        Quad c{qa, b1, qb};
        bool eq7 = eq7Safe(c);
        if (!eq7 && counters) ++counters->eq7;
        if (!eq7 && !extensionSafe(c)) {
            viol += 0.5;
            continue;
        }
        t.seg[s] = c;
        t.curved[s] = true;
    }
    // Two curved segments crossing the texel (S-N and W-E): the runtime
    // intersects a line with a curve in closed form, so the flatter one
    // becomes straight.
    if (t.nseg == 2 && t.curved[0] && t.curved[1] && t.pair[0] == 4 && t.pair[1] == 5) {
        auto dev = [&](int s) {
            return std::fabs(
                cross2(glm::normalize(t.seg[s].p2 - t.seg[s].p0), t.seg[s].p1 - t.seg[s].p0));
        };
        int flat = dev(0) <= dev(1) ? 0 : 1;
        t.curved[flat] = false;
        t.seg[flat] = {t.q[t.a[flat]], 0.5 * (t.q[t.a[flat]] + t.q[t.b[flat]]), t.q[t.b[flat]]};
        if (counters) ++counters->cross;
    }
    bool anyCurved = false;
    for (int s = 0; s < t.nseg; ++s) anyCurved |= t.curved[s];
    if (viol > 0.0 || !anyCurved) return viol; // straight partitions are always valid

    // The partition of evaluate.glsl, in double.
    auto segBetween = [&](int ea, int eb, PEdge& out) {
        for (int s = 0; s < t.nseg; ++s) {
            if (t.a[s] == ea && t.b[s] == eb) {
                out = {t.seg[s], t.curved[s]};
                return true;
            }
            if (t.a[s] == eb && t.b[s] == ea) {
                out = {t.seg[s].reversed(), t.curved[s]};
                return true;
            }
        }
        return false;
    };
    PEdge pathV = lineEdge(t.q[0], t.q[2]), pathH = lineEdge(t.q[3], t.q[1]);
    segBetween(0, 2, pathV);
    segBetween(3, 1, pathH);
    double uV = 0.5, uH = 0.5;
    dvec2 rm;
    if (pathV.curved || pathH.curved) {
        const PEdge& cur = pathV.curved ? pathV : pathH;
        const PEdge& lin = pathV.curved ? pathH : pathV;
        dvec2 d = lin.c.p2 - lin.c.p0;
        double r[2];
        int n = quadRoots(cross2(cur.c.a(), d), cross2(cur.c.b(), d),
                          cross2(cur.c.p0 - lin.c.p0, d), r);
        int inside = 0;
        double u = 0.5;
        for (int k = 0; k < n; ++k) {
            if (r[k] >= -1e-9 && r[k] <= 1.0 + 1e-9) {
                ++inside;
                u = std::clamp(r[k], 0.0, 1.0);
            }
        }
        if (inside != 1) return 0.5;
        rm = cur.c.at(u);
        double ul = glm::dot(rm - lin.c.p0, d) / glm::dot(d, d);
        if (ul <= 1e-4 || ul >= 1.0 - 1e-4) return 0.5;
        (pathV.curved ? uV : uH) = u;
        (pathV.curved ? uH : uV) = ul;
    } else {
        // Two straight paths: they always cross inside (one vertex on each
        // side of the square).
        dvec2 dv = pathV.c.p2 - pathV.c.p0, dh = pathH.c.p2 - pathH.c.p0;
        double den = cross2(dv, dh);
        uV = std::clamp(cross2(pathH.c.p0 - pathV.c.p0, dh) / den, 0.0, 1.0);
        uH = std::clamp(cross2(pathH.c.p0 - pathV.c.p0, dv) / den, 0.0, 1.0);
        rm = pathV.c.at(uV);
    }
    auto spoke = [&](int e) -> PEdge {
        if (e == 0) return {pathV.c.sub(0.0, uV), pathV.curved};
        if (e == 2) return {pathV.c.sub(1.0, uV), pathV.curved};
        if (e == 3) return {pathH.c.sub(0.0, uH), pathH.curved};
        return {pathH.c.sub(1.0, uH), pathH.curved};
    };
    // Each quadrant: the corner triangle and the inner triangle must suit
    // their interpolation scheme (sec. 5.3).
    for (int k = 0; k < 4; ++k) {
        int ea = (k + 3) % 4, eb = k;
        PEdge diag = lineEdge(t.q[ea], t.q[eb]);
        segBetween(ea, eb, diag);
        dvec2 corner = cornerPos(k);
        if (diag.curved) viol += starViolation(diag.c, corner);
        PEdge sa = spoke(ea), sb = spoke(eb);
        int nc = int(diag.curved) + int(sa.curved) + int(sb.curved);
        if (nc == 0) {
            double sIn = cross2(t.q[eb] - t.q[ea], rm - t.q[ea]);
            double sC = cross2(t.q[eb] - t.q[ea], corner - t.q[ea]);
            viol += std::max(0.0, kAreaMargin - (sC > 0 ? -sIn : sIn));
        } else if (nc == 1) {
            if (diag.curved)
                viol += starViolation(diag.c, rm);
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

namespace {

// Neighbour of texel (i, j) across edge e and the edge's index there.
void across(int i, int j, int e, int& ni, int& nj, int& ne) {
    static const int di[4] = {0, 1, 0, -1}, dj[4] = {-1, 0, 1, 0};
    ni = i + di[e];
    nj = j + dj[e];
    ne = (e + 2) % 4;
}

bool touchesCandidate(const Grid& g, int i, int j, int e) {
    if (i < 0 || j < 0 || i >= g.n || j >= g.n) return false;
    size_t ti = g.ti(i, j);
    unsigned m = g.segMask[ti] & g.quadMask[ti] & ~unsigned(g.straightMask[ti]);
    for (int p = 0; p < kPairCount; ++p) {
        if ((m & (1u << p)) && (kPairEdges[p][0] == e || kPairEdges[p][1] == e)) return true;
    }
    return false;
}

double texelViolation(const Grid& g, int i, int j) {
    if (i < 0 || j < 0 || i >= g.n || j >= g.n) return 0.0;
    LocalTexel t = decodeTexel(g, i, j);
    return validateTexel(t, nullptr);
}

double texelEnergy(const Grid& g, int i, int j) {
    if (i < 0 || j < 0 || i >= g.n || j >= g.n) return 0.0;
    LocalTexel t = decodeTexel(g, i, j);
    double e = 0.0;
    for (int s = 0; s < t.nseg; ++s) e += segmentEnergy(t, s);
    return e;
}

double angleOf(dvec2 d) {
    return wrapAngle(std::atan2(d.y, d.x));
}

// Optimises the signature of texel (i, j); true when it ends valid.
bool optimizeTexel(Grid& g, int i, int j) {
    struct Var {
        int e;
        int ni, nj;
        double t0;
    };
    std::vector<Var> vars;
    for (int e = 0; e < 4; ++e) {
        if (g.pos(i, j, e) < 0.0) continue;
        int ni, nj, ne;
        across(i, j, e, ni, nj, ne);
        if (touchesCandidate(g, i, j, e) || touchesCandidate(g, ni, nj, ne)) {
            vars.push_back({e, ni, nj, g.pos(i, j, e)});
        }
    }
    if (vars.empty()) return false;
    const size_t nv = vars.size();
    std::vector<double> x(2 * nv), saved(2 * nv);
    auto read = [&](std::vector<double>& v) {
        for (size_t k = 0; k < nv; ++k) {
            v[2 * k] = g.pos(i, j, vars[k].e);
            v[2 * k + 1] = g.ang(i, j, vars[k].e);
        }
    };
    auto write = [&](const std::vector<double>& v) {
        for (size_t k = 0; k < nv; ++k) {
            g.pos(i, j, vars[k].e) = quantizePos(v[2 * k]);
            g.ang(i, j, vars[k].e) = quantizeAngle(v[2 * k + 1]);
        }
    };
    read(saved);
    double nb0 = 0.0;
    for (const auto& v : vars) nb0 += texelViolation(g, v.ni, v.nj);
    // Extreme-barrier merit: infeasible points rank by violation above any
    // feasible energy.
    auto merit = [&](const std::vector<double>& v) {
        write(v);
        double vt = texelViolation(g, i, j);
        double nb = 0.0;
        for (const auto& w : vars) nb += texelViolation(g, w.ni, w.nj);
        if (vt > 0.0 || nb > nb0 + 1e-12) return 1e9 + vt + std::max(0.0, nb - nb0);
        double energy = texelEnergy(g, i, j);
        for (size_t k = 0; k < nv; ++k) {
            energy += texelEnergy(g, vars[k].ni, vars[k].nj);
            double dt = g.pos(i, j, vars[k].e) - vars[k].t0;
            energy += 0.25 * dt * dt;
        }
        return energy;
    };

    // Starts.
    std::vector<std::vector<double>> starts{saved};
    LocalTexel t = decodeTexel(g, i, j);
    {
        // Eq. 7 remedy: b1 onto the chord's perpendicular bisector (x0 = 0).
        std::vector<double> s = saved;
        for (int sg = 0; sg < t.nseg; ++sg) {
            if (!t.candidate[sg]) continue;
            int a = t.a[sg], b = t.b[sg];
            dvec2 qa = t.q[a], qb = t.q[b], b1;
            if (!tangentIntersection(qa, t.theta[a], qb, t.theta[b], b1, 1e-9)) continue;
            dvec2 m = 0.5 * (qa + qb), ch = glm::normalize(qb - qa), nrm{-ch.y, ch.x};
            double h = std::clamp(glm::dot(b1 - m, nrm), -0.45, 0.45);
            dvec2 sym = m + h * nrm;
            for (size_t k = 0; k < nv; ++k) {
                if (vars[k].e == a) s[2 * k + 1] = angleOf(sym - qa);
                if (vars[k].e == b) s[2 * k + 1] = angleOf(sym - qb);
            }
        }
        starts.push_back(s);
    }
    {
        // Catmull-Rom: tangent at an edge point along the line through the
        // other ends of the segments on its two sides.
        std::vector<double> s = saved;
        for (size_t k = 0; k < nv; ++k) {
            int e = vars[k].e, ni, nj, ne;
            across(i, j, e, ni, nj, ne);
            dvec2 here{0.0}, there{0.0};
            bool hasHere = false, hasThere = false;
            for (int sg = 0; sg < t.nseg && !hasHere; ++sg) {
                if (t.a[sg] == e) {
                    here = t.q[t.b[sg]];
                    hasHere = true;
                } else if (t.b[sg] == e) {
                    here = t.q[t.a[sg]];
                    hasHere = true;
                }
            }
            if (ni >= 0 && nj >= 0 && ni < g.n && nj < g.n) {
                LocalTexel u = decodeTexel(g, ni, nj);
                for (int sg = 0; sg < u.nseg && !hasThere; ++sg) {
                    int o = u.a[sg] == ne ? u.b[sg] : (u.b[sg] == ne ? u.a[sg] : -1);
                    if (o >= 0) {
                        there = u.q[o] + dvec2(ni - i, nj - j);
                        hasThere = true;
                    }
                }
            }
            if (hasHere && hasThere && glm::length(there - here) > 1e-6)
                s[2 * k + 1] = angleOf(there - here);
        }
        starts.push_back(s);
    }
    double best = 1e300;
    for (const auto& s : starts) {
        double m = merit(s);
        if (m < best) {
            best = m;
            x = s;
        }
    }
    // Compass search: poll +-step along every coordinate, move to the best
    // improving point and double the steps, else halve them. Small first
    // steps: most invalid signatures need only a nudge.
    double stepT = 1.0 / 128.0, stepA = 1.0 / 32.0;
    int evals = 0;
    while (stepT >= 1.0 / 8192.0 && evals < 320) {
        std::vector<double> bestY;
        double bestM = best;
        for (size_t k = 0; k < 2 * nv; ++k) {
            for (double sgn : {1.0, -1.0}) {
                std::vector<double> y = x;
                y[k] += sgn * ((k % 2 == 0) ? stepT : stepA);
                double m = merit(y);
                ++evals;
                if (m < bestM - 1e-12) {
                    bestM = m;
                    bestY = y;
                }
            }
        }
        if (!bestY.empty()) {
            best = bestM;
            x = bestY;
            stepT = std::min(stepT * 2.0, 1.0 / 8.0);
            stepA = std::min(stepA * 2.0, 0.5);
        } else {
            stepT *= 0.5;
            stepA *= 0.5;
        }
    }
    if (best >= 1e9) {
        write(saved);
        return false;
    }
    write(x);
    return true;
}

} // namespace

void optimizeSignatures(Grid& g, BakeStats& stats,
                        const std::function<void(const char*, double)>& progress) {
    const int n = g.n;
    std::vector<std::pair<int, int>> work;
    ValidationCounters counters;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            size_t ti = g.ti(i, j);
            if (!(g.segMask[ti] & g.quadMask[ti])) continue;
            LocalTexel t = decodeTexel(g, i, j);
            if (validateTexel(t, &counters) > 0.0) work.emplace_back(i, j);
        }
    }
    stats.eq7Failures = counters.eq7;
    stats.invalidTexels = int(work.size());
    auto last = std::chrono::steady_clock::now();
    for (size_t w = 0; w < work.size(); ++w) {
        auto [i, j] = work[w];
        size_t ti = g.ti(i, j);
        if (texelViolation(g, i, j) <= 0.0 || optimizeTexel(g, i, j)) {
            ++stats.optimizedTexels;
        } else {
            g.straightMask[ti] |= g.segMask[ti];
            ++stats.fallbackTexels;
        }
        auto now = std::chrono::steady_clock::now();
        if (progress && now - last > std::chrono::milliseconds(200)) {
            progress("optimize", double(w + 1) / double(work.size()));
            last = now;
        }
    }
    // Safety net: anything still invalid becomes straight (always valid).
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            size_t ti = g.ti(i, j);
            if (!(g.segMask[ti] & g.quadMask[ti] & ~g.straightMask[ti])) continue;
            if (texelViolation(g, i, j) > 0.0) {
                g.straightMask[ti] |= g.segMask[ti];
                ++stats.fallbackTexels;
            }
        }
    }
    if (progress) progress("optimize", 1.0);
}

} // namespace sg::features::detail
