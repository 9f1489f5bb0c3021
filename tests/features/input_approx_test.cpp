// Quadratic approximation of cubics and elliptical arcs (curve_approx.cpp):
// the proven Hausdorff bound checked by dense sampling against the exact
// curves, exact endpoint sharing, minimal piece counts; network checks and
// junction detection (curve_check.cpp).
#include "input_test_util.h"

#include "surfgrad/base/io.h"

#include <cstdio>
#include <numbers>
#include <random>

namespace sg::features::test {
namespace {

constexpr double kPi = std::numbers::pi;

// Rounding in the construction: coordinates here are <= ~100, so double
// rounding contributes ~1e-13; the sampled measurement is conservative.
constexpr double kRoundingSlack = 1e-11;

void expectChained(const std::vector<Segment>& segs, glm::dvec2 first, glm::dvec2 last) {
    ASSERT_FALSE(segs.empty());
    EXPECT_EQ(segs.front().p0, first);
    EXPECT_EQ(segs.back().p2, last);
    for (std::size_t i = 1; i < segs.size(); ++i)
        EXPECT_EQ(segs[i - 1].p2, segs[i].p0) << "piece " << i;
}

TEST(InputApprox, CubicWithinToleranceBySampling) {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> coord(-50.0, 50.0);
    std::vector<std::array<glm::dvec2, 4>> cubics = {
        {{{0, 0}, {0, 100}, {100, 100}, {100, 0}}},   // arch
        {{{0, 0}, {100, 100}, {0, 100}, {100, 0}}},   // self-intersecting loop
        {{{0, 0}, {100, 50}, {0, 50}, {100, 100}}},   // S-curve (inflection)
        {{{0, 0}, {100, 100}, {0, 100}, {0, 0}}},     // closed loop p0 == p3
        {{{0, 0}, {60, 0}, {40, 0}, {100, 0}}},       // collinear, non-monotone speed
        {{{0, 0}, {100, 100}, {0, 100}, {100, 0.0}}}, // cusp-like
    };
    for (int i = 0; i < 16; ++i) {
        cubics.push_back({{{coord(rng), coord(rng)},
                           {coord(rng), coord(rng)},
                           {coord(rng), coord(rng)},
                           {coord(rng), coord(rng)}}});
    }
    double worstRatio = 0.0;
    std::size_t pieces = 0, kinks = 0, midpointPieces = 0;
    for (double tol : {1e-1, 1e-3}) {
        for (const auto& c : cubics) {
            std::vector<Segment> segs;
            const double bound = appendCubicAsQuadratics(c[0], c[1], c[2], c[3], tol, 3, segs);
            EXPECT_LE(bound, tol);
            expectChained(segs, c[0], c[3]);
            for (const Segment& s : segs) {
                EXPECT_EQ(s.curve, 3);
                EXPECT_EQ(s.kind, Segment::Kind::Quadratic);
            }
            const double h = hausdorff([&](double t) { return evalCubic(c.data(), t); }, segs);
            EXPECT_LE(h, tol + kRoundingSlack) << "tol " << tol;
            worstRatio = std::max(worstRatio, h / tol);
            // G1: joints between pieces keep the tangent direction (the
            // pieces use the cubic's own tangents), except after a fallback
            // to the midpoint construction, which only straight runs or
            // cusps need.
            for (std::size_t i = 1; i < segs.size(); ++i) {
                const glm::dvec2 tin = segs[i - 1].p2 - segs[i - 1].p1,
                                 tout = segs[i].p1 - segs[i].p0;
                if (glm::length(tin) == 0.0 || glm::length(tout) == 0.0) continue;
                const double sinKink =
                    (tin.x * tout.y - tin.y * tout.x) / (glm::length(tin) * glm::length(tout));
                if (std::abs(sinKink) > 1e-6 || glm::dot(tin, tout) < 0.0) ++kinks;
            }
            pieces += segs.size();
            // Piece count of the uniform midpoint construction, for comparison.
            const double d = glm::length(c[3] - 3.0 * c[2] + 3.0 * c[1] - c[0]);
            midpointPieces +=
                std::size_t(std::max(1.0, std::ceil(std::cbrt(std::sqrt(3.0) / 36.0 * d / tol))));
        }
    }
    std::printf(
        "cubic: max measured Hausdorff / tolerance = %.4f; %zu pieces (uniform midpoint: %zu), "
        "%zu joints not G1\n",
        worstRatio, pieces, midpointPieces, kinks);
    // Only pieces that fall back to the midpoint construction (parallel end
    // tangents, cusps) may leave kinks: 4 of 1013 joints on this set.
    EXPECT_LE(kinks, 6u);
}

TEST(InputApprox, QuadraticInCubicFormIsExact) {
    // A degree-elevated quadratic has zero third difference: one piece whose
    // control point is the quadratic's.
    const glm::dvec2 q0{0, 0}, q1{30, 30}, q2{60, 0};
    std::vector<Segment> segs;
    const double bound = appendCubicAsQuadratics(q0, q0 + 2.0 / 3.0 * (q1 - q0),
                                                 q2 + 2.0 / 3.0 * (q1 - q2), q2, 1e-9, 0, segs);
    ASSERT_EQ(segs.size(), 1u);
    EXPECT_NEAR(segs[0].p1.x, 30.0, 1e-12);
    EXPECT_NEAR(segs[0].p1.y, 30.0, 1e-12);
    EXPECT_LE(bound, 1e-12);
}

TEST(InputApprox, ArcWithinToleranceBySampling) {
    struct Case {
        glm::dvec2 center, axisX, axisY;
        double start, sweep;
    };
    const std::vector<Case> cases = {
        {{0, 0}, {1, 0}, {0, 1}, 0.0, 0.5 * kPi},                      // unit quarter circle
        {{5, -3}, {40, 0}, {0, 40}, 0.3, 2.0 * kPi},                   // full circle
        {{0, 0}, {30, 0}, {0, 10}, -1.0, -4.0},                        // ellipse, negative sweep
        {{0, 0}, {30 * 0.8, 30 * 0.6}, {-8 * 0.6, 8 * 0.8}, 2.0, 5.5}, // rotated ellipse
        {{10, 10}, {20, 0}, {15, 10}, 0.0, kPi},                       // sheared (skewX) circle
        {{0, 0}, {50, 0}, {0, 50}, 1.0, 1e-3},                         // tiny sweep
    };
    double worstRatio = 0.0;
    for (double tol : {1e-1, 1e-3, 1e-5}) {
        for (const Case& c : cases) {
            ArcParams arc;
            arc.center = c.center;
            arc.axisX = c.axisX;
            arc.axisY = c.axisY;
            arc.startAngle = c.start;
            arc.sweepAngle = c.sweep;
            auto f = [&](double t) {
                const double a = c.start + t * c.sweep;
                return c.center + std::cos(a) * c.axisX + std::sin(a) * c.axisY;
            };
            arc.start = f(0.0);
            arc.end = f(1.0);
            std::vector<Segment> segs;
            const double bound = appendArcAsQuadratics(arc, tol, 1, segs);
            EXPECT_LE(bound, tol);
            expectChained(segs, arc.start, arc.end);
            EXPECT_GE(double(segs.size()), std::ceil(std::abs(c.sweep) / (0.5 * kPi) - 1e-12));
            const double h = hausdorff(f, segs);
            EXPECT_LE(h, tol + kRoundingSlack) << "tol " << tol << " sweep " << c.sweep;
            worstRatio = std::max(worstRatio, h / tol);
        }
    }
    std::printf("arc: max measured Hausdorff / tolerance = %.4f\n", worstRatio);
}

TEST(InputApprox, QuarterCircleKnownAnswer) {
    // Unit quarter circle in one piece: control point at the tangent
    // intersection (1, 1); error (cos h + 1/cos h)/2 - 1 at h = 45 degrees.
    ArcParams arc;
    arc.startAngle = 0.0;
    arc.sweepAngle = 0.5 * kPi;
    arc.start = {1, 0};
    arc.end = {0, 1};
    std::vector<Segment> segs;
    const double bound = appendArcAsQuadratics(arc, 0.1, 0, segs);
    ASSERT_EQ(segs.size(), 1u);
    EXPECT_NEAR(segs[0].p1.x, 1.0, 1e-15);
    EXPECT_NEAR(segs[0].p1.y, 1.0, 1e-15);
    const double h = std::cos(kPi / 4);
    EXPECT_NEAR(bound, (h + 1.0 / h) / 2.0 - 1.0, 1e-15);
    // |B(1/2)| - 1 is that error exactly.
    EXPECT_NEAR(glm::length(evalSegment(segs[0], 0.5)) - 1.0, bound, 1e-15);
}

TEST(InputApprox, ToleranceResolution) {
    ApproxOptions rel;
    EXPECT_DOUBLE_EQ(resolveTolerance(rel, 24.0, "x"), 24.0 * 1e-4);
    ApproxOptions abs;
    abs.tolerance = 0.5;
    EXPECT_DOUBLE_EQ(resolveTolerance(abs, 24.0, "x"), 0.5);
    ApproxOptions tiny;
    tiny.tolerance = 1e-12;
    expectThrowsWith([&] { resolveTolerance(tiny, 24.0, "x"); }, "below 1e-9 of the drawing size");
    ApproxOptions nan;
    nan.tolerance = NAN;
    EXPECT_THROW(resolveTolerance(nan, 24.0, "x"), io::InputError);
}

TEST(InputApprox, TooManyPiecesIsAnError) {
    std::vector<Segment> segs;
    expectThrowsWith(
        [&] {
            appendCubicAsQuadratics({0, 0}, {1e9, 1e9}, {-1e9, 1e9}, {1, 0}, 1e-12, 0, segs,
                                    "f.svg", "path #1");
        },
        "raise the tolerance");
}

CurveNetwork star(int arms) {
    CurveNetwork net;
    net.source = "star";
    for (int i = 0; i < arms; ++i) {
        const double a = 2.0 * kPi * i / arms;
        Segment s;
        s.p0 = {0.0, 0.0};
        s.p2 = {std::cos(a), std::sin(a)};
        s.p1 = 0.5 * (s.p0 + s.p2);
        s.curve = i;
        net.segments.push_back(s);
        net.curves.push_back({});
    }
    return net;
}

TEST(InputStructure, JunctionsOfAStarAndASquare) {
    CurveNetwork net = star(8);
    checkNetwork(net);
    const auto js = findJunctions(net);
    ASSERT_EQ(js.size(), 9u); // centre + 8 tips
    int centre = 0;
    for (const auto& j : js) {
        if (j.pos == glm::dvec2(0.0)) {
            EXPECT_EQ(j.valence(), 8);
            ++centre;
        } else {
            EXPECT_EQ(j.valence(), 1);
        }
    }
    EXPECT_EQ(centre, 1);

    // A closed square: four valence-2 corners; -0.0 and +0.0 are one point.
    CurveNetwork sq;
    const glm::dvec2 c[4] = {{-0.0, 0}, {1, 0}, {1, 1}, {0.0, 1}};
    for (int i = 0; i < 4; ++i) {
        Segment s;
        s.p0 = c[i];
        s.p2 = c[(i + 1) % 4];
        s.p1 = 0.5 * (s.p0 + s.p2);
        sq.segments.push_back(s);
    }
    sq.curves.push_back({"sq", "", -1.0, true});
    checkNetwork(sq);
    const auto sj = findJunctions(sq);
    ASSERT_EQ(sj.size(), 4u);
    for (const auto& j : sj) EXPECT_EQ(j.valence(), 2);
}

TEST(InputStructure, CheckNetworkNamesTheProblem) {
    auto expectError = [](const CurveNetwork& net, const char* element, const char* reason) {
        try {
            checkNetwork(net);
            ADD_FAILURE() << "no error for " << reason;
        } catch (const io::InputError& e) {
            EXPECT_EQ(e.element(), element);
            SG_EXPECT_CONTAINS(e.reason(), reason);
        }
    };
    CurveNetwork empty;
    expectError(empty, "", "empty");
    CurveNetwork net = star(2);
    net.segments[1].p2.x = NAN;
    expectError(net, "segment 1", "not finite");
    net = star(2);
    net.segments[1].p1 += glm::dvec2(0.1, 0.0);
    expectError(net, "segment 1", "midpoint");
    net = star(2);
    net.segments[0].p2 = net.segments[0].p0;
    net.segments[0].p1 = net.segments[0].p0;
    expectError(net, "segment 0", "zero-length");
    net = star(2);
    net.segments[1].curve = 0; // same curve, but not connected
    net.curves.pop_back();
    expectError(net, "segment 1", "previous segment of its curve ends at");
    net = star(2);
    net.curves[0].closed = true;
    expectError(net, "curve 0", "marked closed");
    net = star(2);
    net.segments[1].curve = 5;
    expectError(net, "segment 1", "out of range");
}

} // namespace
} // namespace sg::features::test
