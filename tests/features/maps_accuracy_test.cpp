// Accuracy of the reconstructed distance and gradient against exact
// distances computed in double from the input curves (maps_test_util.h):
// zero on the curves, close to the true distance near them, the gradient
// pointing away from the curve on the sample's own side (no value
// interpolated across a curve) and within a stated angle of the exact one.
// Parilov, Zorin (TOG 2008) sec. 3.2 (DFR1-2), sec. 5; TR2005-872 sec. 4.
#include <cstdlib>
#include <random>

#include "maps_test_util.h"

using namespace sg::features;
using namespace sgtest;

namespace {

struct Accuracy {
    double onCurve = 0;       // max reconstructed d at points on the input curves
    double err[4] = {0};      // max |d - exact| at the offsets below
    double angleDeg[4] = {0}; // max angle between reconstructed and exact gradient
    int wrongSide[4] = {0};   // gradient pointing back across the curve
    int samples = 0;          // distance samples
    int gradSamples = 0;      // gradient samples (clear of the medial axis)
};
constexpr double kOffsets[4] = {0.01, 0.05, 0.2, 0.5};

// Points on each curve and at kOffsets on both sides of it, skipping points
// within `skip` texels of a curve end or junction (valence != 2: the maps
// end curves on texel boundaries), points off the map, and offset points
// whose nearest curve point is elsewhere (another curve is closer).
Accuracy measure(const CurveNetwork& net, const GpuFeatureMaps& g, double skip, int perSegment) {
    Accuracy a;
    const double n = g.size;
    forCurvePoints(net, perSegment, [&](dvec2 q, dvec2 tan, size_t seg) {
        if (distToSpecialPoint(net, q) < skip) return;
        if (q.x < 0 || q.y < 0 || q.x > n || q.y > n) return;
        // Where another curve passes within 1.5 texels the two share texels
        // (crossings, merged points): not an exact-reproduction case.
        if (otherCurveClearance(net, q, net.segments[seg].curve, 0.0) >= 0.75) {
            double dq = sample(g, glm::vec2(q)).dist;
            if (std::getenv("SG_TEST_VERBOSE") && dq > 1e-4)
                std::printf("  on-curve %.4f %.4f: %.2e\n", q.x, q.y, dq);
            a.onCurve = std::max(a.onCurve, dq);
        }
        dvec2 nrm(-tan.y, tan.x);
        for (int k = 0; k < 4; ++k) {
            for (double sd : {-1.0, 1.0}) {
                dvec2 p = q + sd * kOffsets[k] * nrm;
                if (p.x < 0 || p.y < 0 || p.x > n || p.y > n) continue;
                Closest c = closest(net, p);
                if (c.dist < kOffsets[k] * (1.0 - 1e-6) || distToSpecialPoint(net, c.point) < skip)
                    continue;
                double clearance =
                    otherCurveClearance(net, p, net.segments[c.segment].curve, c.dist);
                if (clearance < 0.75) continue; // a crossing or another curve within ~1.5 texels
                auto r = sample(g, glm::vec2(p));
                ++a.samples;
                a.err[k] = std::max(a.err[k], std::fabs(double(r.dist) - c.dist));
                if (clearance < 2.0) continue; // gradient smoothed across the medial axis
                ++a.gradSamples;
                dvec2 exactGrad = (p - c.point) / c.dist;
                double cosA =
                    std::clamp(exactGrad.x * r.grad.x + exactGrad.y * r.grad.y, -1.0, 1.0);
                a.angleDeg[k] = std::max(a.angleDeg[k], std::acos(cosA) * 180.0 / M_PI);
                if (cosA <= 0.0) ++a.wrongSide[k];
                if (std::getenv("SG_TEST_VERBOSE") &&
                    (cosA <= 0.0 || std::fabs(double(r.dist) - c.dist) > 0.05))
                    std::printf("  p %.4f %.4f off %.2f side %+.0f: d %.4f exact %.4f cos %.3f\n",
                                p.x, p.y, kOffsets[k], sd, r.dist, c.dist, cosA);
            }
        }
    });
    return a;
}

void report(const char* name, const Accuracy& a) {
    std::printf("%s: %d (%d) samples, on-curve d <= %.2e, |d err| at 0.01/0.05/0.2/0.5: %.4f %.4f "
                "%.4f %.4f, "
                "gradient deg: %.2f %.2f %.2f %.2f, wrong side %d %d %d %d\n",
                name, a.samples, a.gradSamples, a.onCurve, a.err[0], a.err[1], a.err[2], a.err[3],
                a.angleDeg[0], a.angleDeg[1], a.angleDeg[2], a.angleDeg[3], a.wrongSide[0],
                a.wrongSide[1], a.wrongSide[2], a.wrongSide[3]);
}

CurveNetwork randomPolylines(int size, int count, unsigned seed) {
    NetBuilder b;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(2.0, size - 2.0), ang(0.0, 2 * M_PI), len(2.0, 9.0);
    for (int c = 0; c < count; ++c) {
        std::vector<dvec2> pts{{pos(rng), pos(rng)}};
        double a = ang(rng);
        for (int k = 0; k < 4; ++k) {
            a += 0.6 * (ang(rng) / M_PI - 1.0);
            dvec2 nx = pts.back() + len(rng) * dvec2(std::cos(a), std::sin(a));
            nx = glm::clamp(nx, dvec2(1.0), dvec2(size - 1.0));
            if (glm::length(nx - pts.back()) > 0.5) pts.push_back(nx);
        }
        if (pts.size() >= 2) b.polyline(pts);
    }
    return b.net;
}

CurveNetwork curvyNetwork() {
    NetBuilder b;
    b.circle({20.3, 21.7}, 9.2, 12);
    b.circle({44.1, 44.6}, 5.3, 8, 0.4);
    b.circle({47.9, 16.2}, 2.6, 6, 0.9); // tight: radius 2.6 texels
    b.begin();
    b.quad({4.2, 58.3}, {18.0, 40.0}, {30.3, 59.1});
    b.quad({30.3, 59.1}, {40.0, 70.0}, {59.4, 57.2});
    return b.net;
}

} // namespace

// Straight segments, linear mode: the adjusted network equals the input
// away from junctions, so the zero set is exact up to the 16-bit edge
// positions (1.5e-5 texels) and binary32 evaluation.
TEST(FeatureMapsAccuracy, LinearPolylines) {
    CurveNetwork net = randomPolylines(64, 10, 7);
    BakeStats st;
    FeatureMaps m = bake(net, texelSpace(64, BakeMode::Linear), &st);
    GpuFeatureMaps g = m.packGpu();
    Accuracy a = measure(net, g, 1.5, 24);
    report("linear polylines", a);
    EXPECT_GT(a.samples, 2000);
    EXPECT_GT(a.gradSamples, 1000);
    // 1e-4: quantized edge points (7.6e-6 texels) times the gradient scale,
    // plus binary32 rounding of the sample position (~4e-6 at 64 texels).
    EXPECT_LT(a.onCurve, 1e-4);
    // Straight segments: the distance is linear in the partition triangles
    // next to the curve and exact at the corners; measured <= 0.003.
    for (double e : a.err) EXPECT_LT(e, 0.01);
    // Gradient: the curve's normal on the curve (exact up to the 16-bit
    // angle), turning towards the smoothed corner samples inside the texel:
    // measured 0.9 / 4.7 / 11.8 / 17.1 degrees.
    EXPECT_LT(a.angleDeg[0], 2.0);
    EXPECT_LT(a.angleDeg[1], 8.0);
    EXPECT_LT(a.angleDeg[3], 25.0);
    for (int w : a.wrongSide) EXPECT_EQ(w, 0);
}

// Quadratic curves, quadratic mode: curved segments reproduce the input
// pieces exactly (end points, tangents) up to the 16-bit signature.
TEST(FeatureMapsAccuracy, QuadraticCurves) {
    CurveNetwork net = curvyNetwork();
    BakeStats st;
    FeatureMaps m = bake(net, texelSpace(64, BakeMode::Quadratic), &st);
    GpuFeatureMaps g = m.packGpu();
    EXPECT_GT(st.curvedSegments, 100);
    Accuracy a = measure(net, g, 1.5, 48);
    report("quadratic curves", a);
    EXPECT_GT(a.samples, 2000);
    // On the curve: pieces are reproduced up to the 16-bit signature and the
    // optimisation of invalid signatures; measured 1.7e-3.
    EXPECT_LT(a.onCurve, 5e-3);
    // Near the curve the distance is interpolated linearly towards the
    // corners; inside a circle of radius r the true distance bends by about
    // d^2 / (2 r) over that span: 0.048 at d = 0.5 for r = 2.6 (measured
    // 0.069 there, 0.025 at d = 0.05).
    EXPECT_LT(a.err[0], 0.03);
    EXPECT_LT(a.err[3], 0.08);
    // Gradient: measured 2.7 / 5.5 / 9.8 / 14.2 degrees.
    EXPECT_LT(a.angleDeg[0], 5.0);
    EXPECT_LT(a.angleDeg[3], 20.0);
    for (int w : a.wrongSide) EXPECT_EQ(w, 0);
}

// The same curves in linear mode: chords replace the curve in each texel,
// so on-curve distances reach the chord's sagitta (r (1 - cos(h/2)) for a
// texel-sized piece of a circle of radius r: 0.05 texels for r = 2.6).
TEST(FeatureMapsAccuracy, QuadraticCurvesLinearMode) {
    CurveNetwork net = curvyNetwork();
    FeatureMaps m = bake(net, texelSpace(64, BakeMode::Linear));
    GpuFeatureMaps g = m.packGpu();
    Accuracy a = measure(net, g, 1.5, 48);
    report("curves, linear mode", a);
    EXPECT_LT(a.onCurve, 0.1);
    // Points closer to the curve than the chord's sagitta can lie on the
    // chord's other side; from 0.2 texels on, none does.
    EXPECT_EQ(a.wrongSide[2], 0);
    EXPECT_EQ(a.wrongSide[3], 0);
}

TEST(FeatureMapsAccuracy, AllFinite) {
    for (BakeMode mode : {BakeMode::Linear, BakeMode::Quadratic}) {
        FeatureMaps m = bake(curvyNetwork(), texelSpace(64, mode));
        expectAllFinite(m.packGpu(), 6);
    }
}

// C0 continuity across texel edges (TOG 2008 DFR1b, DFR2): both texels
// sharing an edge interpolate the same values along it, so d and the
// gradient agree on its two sides. Checked on every texel edge of the map
// at 1/16-texel steps, 1e-4 texels to either side, away from curve ends and
// junctions (where the configuration of one texel may have dropped a
// segment its neighbour keeps: TOG 2008 Fig. 6 right).
TEST(FeatureMapsAccuracy, ContinuousAcrossTexelEdges) {
    for (BakeMode mode : {BakeMode::Linear, BakeMode::Quadratic}) {
        CurveNetwork net = curvyNetwork();
        FeatureMaps m = bake(net, texelSpace(64, mode));
        GpuFeatureMaps g = m.packGpu();
        double worstD = 0, worstAngle = 0;
        int checked = 0;
        for (int e = 1; e < 64; ++e) {
            for (int k = 0; k < 64 * 16; ++k) {
                float t = (float(k) + 0.5f) / 16.0f;
                for (int dir = 0; dir < 2; ++dir) {
                    glm::vec2 a =
                        dir ? glm::vec2(float(e) - 1e-4f, t) : glm::vec2(t, float(e) - 1e-4f);
                    glm::vec2 b =
                        dir ? glm::vec2(float(e) + 1e-4f, t) : glm::vec2(t, float(e) + 1e-4f);
                    if (distToSpecialPoint(net, dvec2(a)) < 1.5) continue;
                    auto ra = sample(g, a), rb = sample(g, b);
                    // Next to a curve the two sides may straddle it; beyond the
                    // band (no curve within 16 texels) there is no gradient.
                    if (std::min(ra.dist, rb.dist) < 2e-3f || std::max(ra.dist, rb.dist) >= 15.0f)
                        continue;
                    ++checked;
                    worstD = std::max(worstD, double(std::fabs(ra.dist - rb.dist)));
                    double cosA = std::clamp(double(ra.grad.x * rb.grad.x + ra.grad.y * rb.grad.y),
                                             -1.0, 1.0);
                    double ang = std::acos(cosA) * 180.0 / M_PI;
                    if (std::getenv("SG_TEST_VERBOSE") && ang > 0.5)
                        std::printf("  jump %.2f deg at %.4f %.4f: d %.4f %.4f grad (%.3f %.3f) "
                                    "(%.3f %.3f)\n",
                                    ang, a.x, a.y, ra.dist, rb.dist, ra.grad.x, ra.grad.y,
                                    rb.grad.x, rb.grad.y);
                    worstAngle = std::max(worstAngle, ang);
                }
            }
        }
        std::printf("%s: %d edge samples, max |d jump| %.2e, max gradient jump %.3f deg\n",
                    toString(mode), checked, worstD, worstAngle);
        EXPECT_GT(checked, 100000);
        // The 2e-4 texel step between the two samples times |grad d| <= 1,
        // plus binary32 rounding.
        EXPECT_LT(worstD, 5e-4);
        // The gradient is interpolated linearly between vertex values
        // shared by both sides: only the step and rounding separate them.
        EXPECT_LT(worstAngle, 0.5);
    }
}
