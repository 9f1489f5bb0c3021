// The feature evaluator's decode and partition in binary64 (see
// shared_double.h): the SAME formulas as shaders/sg/features/evaluate.glsl,
// compiled from the copy surfgrad_double_sources generates through
// surfgrad/shaders/glsl_cpp_double.h (float literals and types made double). This
// translation unit must not include the binary32 build (the include guards
// are shared; the header checks it).
#include "shared_double.h"

#define SG_GLSL_DOUBLE_SOURCE "sgd/features/evaluate.glsl"
#include "surfgrad/shaders/glsl_cpp_double.h"

namespace sg::features::detail {

namespace {

namespace G = sg::glsl_double;

PEdge toEdge(const G::SgFeatCurve& c) {
    return {{c.p0, c.p1, c.p2}, c.curved};
}

G::SgFeatGeom geomOf(const SharedGeom& s) {
    // Only the fields sgFeatSpoke / sgFeatFindSeg / sgFeatSegFrom read.
    G::SgFeatGeom g{};
    auto curve = [](const PEdge& e) {
        return G::sgFeatMakeCurve(e.c.p0, e.c.p1, e.c.p2, e.curved);
    };
    g.nseg = s.nseg;
    for (int k = 0; k < 2; ++k) {
        g.segA[k] = s.segA[k];
        g.segB[k] = s.segB[k];
        g.seg[k] = curve(s.seg[k]);
    }
    for (int e = 0; e < 4; ++e) g.q[e] = s.q[e];
    g.pathV = curve(s.pathV);
    g.pathH = curve(s.pathH);
    g.uV = s.uV;
    g.uH = s.uH;
    return g;
}

} // namespace

SharedGeom sharedDecode(uint32_t cfg, const uint32_t edges[4]) {
    G::SgFeatTexel tx{};
    tx.dist = glm::dvec4(0.0);
    tx.grad0 = tx.grad1 = tx.grad2 = tx.grad3 = glm::dvec2(0.0);
    tx.cfg = cfg;
    tx.edges = glm::uvec4(edges[0], edges[1], edges[2], edges[3]);
    const G::SgFeatGeom g = G::sgFeatDecode(tx);
    SharedGeom s;
    for (int e = 0; e < 4; ++e) {
        s.q[e] = g.q[e];
        s.tang[e] = g.tang[e];
        s.pt[e] = g.pt[e];
    }
    s.nseg = g.nseg;
    for (int k = 0; k < 2; ++k) {
        s.segA[k] = g.segA[k];
        s.segB[k] = g.segB[k];
        s.seg[k] = toEdge(g.seg[k]);
    }
    s.pathV = toEdge(g.pathV);
    s.pathH = toEdge(g.pathH);
    s.discV = g.discV;
    s.discH = g.discH;
    s.rm = g.rm;
    s.uV = g.uV;
    s.uH = g.uH;
    return s;
}

PEdge sharedSpoke(const SharedGeom& g, int e) {
    return toEdge(G::sgFeatSpoke(geomOf(g), e));
}

PEdge sharedDiagonal(const SharedGeom& s, int ea, int eb) {
    const G::SgFeatGeom g = geomOf(s);
    const int sd = G::sgFeatFindSeg(g, ea, eb);
    return toEdge(sd >= 0 ? G::sgFeatSegFrom(g, sd, ea) : G::sgFeatMakeLine(s.q[ea], s.q[eb]));
}

bool sharedTangentIntersection(dvec2 q0, dvec2 t0, dvec2 q2, dvec2 t2, dvec2& mid) {
    bool ok = false;
    mid = G::sgFeatTangentIntersection(q0, t0, q2, t2, ok);
    return ok;
}

} // namespace sg::features::detail
