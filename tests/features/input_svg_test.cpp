// SVG input (input_svg.cpp): every path command absolute and relative
// against hand-computed segments, number syntax, arcs (flags, out-of-range
// radii), basic shapes, transforms, the y flip, hostile XML, and every
// lucide icon in data/svg.
//
// All drawings use viewBox "0 0 100 100", so the y flip is y' = 100 - y.
#include "input_test_util.h"

#include "surfgrad/base/io.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <unistd.h>

namespace sg::features::test {
namespace {

using V = glm::dvec2;
constexpr double kPi = std::numbers::pi;

std::string doc(const std::string& body) {
    return R"~(<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100">)~" + body + "</svg>";
}
std::string path(const std::string& d) {
    return doc("<path d=\"" + d + "\"/>");
}

CurveNetwork svg(const std::string& text, double tol = 0.0) {
    SvgOptions opt;
    opt.approx.tolerance = tol;
    return parseSvg(text, "t.svg", opt);
}

// Flipped point of user-space (x, y).
V F(double x, double y) {
    return {x, 100.0 - y};
}

void expectLine(const Segment& s, V a, V b) {
    EXPECT_EQ(s.kind, Segment::Kind::Line);
    EXPECT_EQ(s.p0, a);
    EXPECT_EQ(s.p2, b);
}
void expectQuad(const Segment& s, V a, V c, V b) {
    EXPECT_EQ(s.kind, Segment::Kind::Quadratic);
    EXPECT_EQ(s.p0, a);
    EXPECT_NEAR(s.p1.x, c.x, 1e-12);
    EXPECT_NEAR(s.p1.y, c.y, 1e-12);
    EXPECT_EQ(s.p2, b);
}

void expectError(const std::string& text, const std::string& element, const std::string& reason) {
    try {
        svg(text);
        ADD_FAILURE() << "accepted: " << text;
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.file(), "t.svg");
        EXPECT_EQ(e.element(), element) << e.what();
        SG_EXPECT_CONTAINS(e.reason(), reason) << e.what();
    }
}

TEST(InputSvg, MoveLineAbsoluteAndRelative) {
    const auto net = svg(path("M10 20 L30 40 l10 0 L 50,50"));
    ASSERT_EQ(net.segments.size(), 3u);
    expectLine(net.segments[0], F(10, 20), F(30, 40));
    expectLine(net.segments[1], F(30, 40), F(40, 40));
    expectLine(net.segments[2], F(40, 40), F(50, 50));
    EXPECT_EQ(net.curves.size(), 1u);
    EXPECT_FALSE(net.curves[0].closed);
    EXPECT_EQ(net.curves[0].name, "path #1");
}

TEST(InputSvg, HorizontalVertical) {
    const auto net = svg(path("M10 10 H30 v20 h-5 V5"));
    ASSERT_EQ(net.segments.size(), 4u);
    expectLine(net.segments[0], F(10, 10), F(30, 10));
    expectLine(net.segments[1], F(30, 10), F(30, 30));
    expectLine(net.segments[2], F(30, 30), F(25, 30));
    expectLine(net.segments[3], F(25, 30), F(25, 5));
}

TEST(InputSvg, ImplicitRepetition) {
    // Pairs after M are L; after m they are l; other commands repeat.
    auto net = svg(path("M10 20 30 40 50 60"));
    ASSERT_EQ(net.segments.size(), 2u);
    expectLine(net.segments[1], F(30, 40), F(50, 60));
    net = svg(path("m10 20 5 5 5 5"));
    ASSERT_EQ(net.segments.size(), 2u);
    expectLine(net.segments[0], F(10, 20), F(15, 25));
    expectLine(net.segments[1], F(15, 25), F(20, 30));
    net = svg(path("M0 0 h10 10 v5 5"));
    ASSERT_EQ(net.segments.size(), 4u);
    expectLine(net.segments[3], F(20, 5), F(20, 10));
    net = svg(path("M0 0 Q10 10 20 0 30 -10 40 0"));
    ASSERT_EQ(net.segments.size(), 2u);
    expectQuad(net.segments[1], F(20, 0), F(30, -10), F(40, 0));
}

TEST(InputSvg, NumberSyntaxEdgeCases) {
    auto net = svg(path("M.5.5L1e1-2"));
    ASSERT_EQ(net.segments.size(), 1u);
    expectLine(net.segments[0], F(0.5, 0.5), F(10, -2));
    net = svg(path("M-1-2L3,4l.5E1+2"));
    ASSERT_EQ(net.segments.size(), 2u);
    expectLine(net.segments[0], F(-1, -2), F(3, 4));
    expectLine(net.segments[1], F(3, 4), F(8, 6));
    net = svg(path("M0,0l10-10-.5.5"));
    ASSERT_EQ(net.segments.size(), 2u);
    expectLine(net.segments[1], F(10, -10), F(9.5, -9.5));
    net = svg(path("\n\tM 1 1 \r\n L 2 2 "));
    ASSERT_EQ(net.segments.size(), 1u);
}

TEST(InputSvg, QuadraticAndSmoothQuadratic) {
    auto net = svg(path("M0 0 Q10 10 20 0 T40 0"));
    ASSERT_EQ(net.segments.size(), 2u);
    expectQuad(net.segments[0], F(0, 0), F(10, 10), F(20, 0));
    expectQuad(net.segments[1], F(20, 0), F(30, -10), F(40, 0)); // reflected control
    net = svg(path("m0 0 q10 10 20 0 t20 0 t20 0"));
    ASSERT_EQ(net.segments.size(), 3u);
    expectQuad(net.segments[1], F(20, 0), F(30, -10), F(40, 0));
    expectQuad(net.segments[2], F(40, 0), F(50, 10), F(60, 0));
    // T after a non-quadratic command: the control is the current point.
    net = svg(path("M0 0 L10 0 T20 10"));
    ASSERT_EQ(net.segments.size(), 2u);
    expectQuad(net.segments[1], F(10, 0), F(10, 0), F(20, 10));
}

TEST(InputSvg, CubicAndSmoothCubicKnownAnswers) {
    // Degree-elevated quadratics: C is exact in one quadratic piece, and S
    // reflects the previous second control point.
    auto net = svg(path("M0 0 C20 20 40 20 60 0 S100 -20 120 0"), 1e-6);
    ASSERT_EQ(net.segments.size(), 2u);
    expectQuad(net.segments[0], F(0, 0), F(30, 30), F(60, 0));
    expectQuad(net.segments[1], F(60, 0), F(90, -30), F(120, 0));
    net = svg(path("m0 0 c20 20 40 20 60 0 s40 -20 60 0"), 1e-6);
    ASSERT_EQ(net.segments.size(), 2u);
    expectQuad(net.segments[1], F(60, 0), F(90, -30), F(120, 0));
    // S after a non-cubic: first control is the current point.
    net = svg(path("M0 0 L30 0 S30 30 60 0"), 1e-6);
    // cubic (30,0) (30,0) (30,30) (60,0) is not a quadratic: several pieces.
    EXPECT_GT(net.segments.size(), 2u);
    EXPECT_EQ(net.segments[1].p0, F(30, 0));
    EXPECT_EQ(net.segments.back().p2, F(60, 0));
}

TEST(InputSvg, CubicThroughLoaderWithinTolerance) {
    // A skewed cubic: the bound holds in output units after the transform.
    const double tol = 1e-3;
    const auto net = svg(
        doc(R"~(<g transform="skewX(30) scale(1.5 0.5)"><path d="M10 80 C 90 -40 0 130 70 20"/></g>)~"),
        tol);
    const double k = std::tan(kPi / 6);
    auto T = [&](V p) {
        V s{1.5 * p.x, 0.5 * p.y};
        return F(s.x + k * s.y, s.y);
    };
    const V c[4] = {T({10, 80}), T({90, -40}), T({0, 130}), T({70, 20})};
    const double h = hausdorff([&](double t) { return evalCubic(c, t); }, net.segments);
    EXPECT_LE(h, tol + 1e-11);
    EXPECT_EQ(net.segments.front().p0, c[0]);
    EXPECT_EQ(net.segments.back().p2, c[3]);
}

// Center and sweep direction of the four flag combinations, from
// (40,50) to (60,50) with r = 20: centers at (50, 50 -/+ sqrt(300)).
TEST(InputSvg, ArcFlagsSelectCenterAndDirection) {
    const double s = std::sqrt(300.0);
    struct Case {
        const char* flags;
        V center;   // user space
        V midpoint; // user space point the arc passes through
        V avoided;  // point of the other arcs it must not pass through
    };
    const Case cases[] = {
        {"0 0", {50, 50 - s}, {50, 50 - s + 20}, {50, 50 - s - 20}},
        {"1 1", {50, 50 - s}, {50, 50 - s - 20}, {50, 50 - s + 20}},
        {"0 1", {50, 50 + s}, {50, 50 + s - 20}, {50, 50 + s + 20}},
        {"1 0", {50, 50 + s}, {50, 50 + s + 20}, {50, 50 + s - 20}},
    };
    const double tol = 1e-4;
    for (const Case& c : cases) {
        const auto net = svg(path(std::string("M40 50 A20 20 0 ") + c.flags + " 60 50"), tol);
        const V centerF = F(c.center.x, c.center.y);
        for (const Segment& seg : net.segments) {
            for (int j = 0; j <= 16; ++j) {
                EXPECT_NEAR(glm::length(evalSegment(seg, j / 16.0) - centerF), 20.0, tol + 1e-9)
                    << c.flags;
            }
        }
        EXPECT_LE(distToSegments(F(c.midpoint.x, c.midpoint.y), net.segments), tol + 1e-9)
            << c.flags;
        EXPECT_GT(distToSegments(F(c.avoided.x, c.avoided.y), net.segments), 1.0) << c.flags;
        EXPECT_EQ(net.segments.front().p0, F(40, 50));
        EXPECT_EQ(net.segments.back().p2, F(60, 50));
    }
}

TEST(InputSvg, ArcOutOfRangeRadii) {
    const double tol = 1e-4;
    // Radii too small: scaled up uniformly until they span the endpoints
    // (F.6.6): a half circle of radius 10 about (50, 50).
    auto net = svg(path("M40 50 A5 5 0 0 1 60 50"), tol);
    for (const Segment& seg : net.segments) {
        for (int j = 0; j <= 8; ++j)
            EXPECT_NEAR(glm::length(evalSegment(seg, j / 8.0) - F(50, 50)), 10.0, tol + 1e-9);
    }
    // sweep = 1 in y-down user space goes through (50, 40).
    EXPECT_LE(distToSegments(F(50, 40), net.segments), tol + 1e-9);
    // Negative radii: absolute values.
    const auto neg = svg(path("M40 50 A-5 -5 0 0 1 60 50"), tol);
    ASSERT_EQ(neg.segments.size(), net.segments.size());
    for (std::size_t i = 0; i < neg.segments.size(); ++i)
        EXPECT_EQ(neg.segments[i].p1, net.segments[i].p1);
    // A zero radius is a straight line.
    net = svg(path("M10 10 A0 5 0 0 1 20 20"));
    ASSERT_EQ(net.segments.size(), 1u);
    expectLine(net.segments[0], F(10, 10), F(20, 20));
    // Equal endpoints omit the arc.
    net = svg(path("M10 10 A5 5 0 1 1 10 10 L20 10"));
    ASSERT_EQ(net.segments.size(), 1u);
    expectLine(net.segments[0], F(10, 10), F(20, 10));
}

TEST(InputSvg, RotatedEllipticalArcWithinTolerance) {
    // rx 30, ry 10 rotated 30 degrees, from the ellipse point at angle 0.2
    // to the one at angle 2.5 (sweep positive, small arc).
    const double tol = 1e-4, rx = 30, ry = 10, phi = kPi / 6;
    const V c{50, 50};
    auto E = [&](double a) {
        return V{c.x + rx * std::cos(phi) * std::cos(a) - ry * std::sin(phi) * std::sin(a),
                 c.y + rx * std::sin(phi) * std::cos(a) + ry * std::cos(phi) * std::sin(a)};
    };
    const V a = E(0.2), b = E(2.5);
    char d[256];
    std::snprintf(d, sizeof d, "M%.17g %.17g A30 10 30 0 1 %.17g %.17g", a.x, a.y, b.x, b.y);
    const auto net = svg(path(d), tol);
    const double h = hausdorff(
        [&](double t) {
            const V p = E(0.2 + t * 2.3);
            return F(p.x, p.y);
        },
        net.segments);
    EXPECT_LE(h, tol + 1e-9); // endpoints printed to 17 digits: ~1e-14 off
    // Arc flags need no separators: "1010 0" is flags 1, 0 then x = 10.
    const auto packed = svg(path("M10 10a5 5 0 1010 0"));
    EXPECT_EQ(packed.segments.back().p2, F(20, 10));
}

TEST(InputSvg, CloseAndSubpaths) {
    auto net = svg(path("M10 10 L20 10 L20 20 Z"));
    ASSERT_EQ(net.segments.size(), 3u);
    expectLine(net.segments[2], F(20, 20), F(10, 10));
    EXPECT_TRUE(net.curves[0].closed);
    // Already at the start: Z adds no zero-length segment.
    net = svg(path("M10 10 L20 10 L10 10 z"));
    EXPECT_EQ(net.segments.size(), 2u);
    EXPECT_TRUE(net.curves[0].closed);
    // A command after Z starts a new subpath at the closed subpath's start.
    net = svg(path("M10 10 L20 10 20 20 Z L30 30"));
    ASSERT_EQ(net.curves.size(), 2u);
    expectLine(net.segments.back(), F(10, 10), F(30, 30));
    EXPECT_EQ(net.segments.back().curve, 1);
    // m after Z is relative to the subpath start.
    net = svg(path("M10 10 L20 10 Z m5 5 l1 0"));
    expectLine(net.segments.back(), F(15, 15), F(16, 15));
    // Two subpaths, two curves with the element's name.
    net = svg(doc(R"~(<path id="p" d="M0 0 L1 1 M5 5 L6 6"/>)~"));
    ASSERT_EQ(net.curves.size(), 2u);
    EXPECT_EQ(net.curves[1].name, "p");
    // A lone moveto or a zero-length line makes no curve.
    net = svg(path("M1 1 M2 2 L2 2 M3 3 L4 4"));
    EXPECT_EQ(net.curves.size(), 1u);
    EXPECT_EQ(net.segments.size(), 1u);
}

TEST(InputSvg, PathErrors) {
    expectError(path("L10 10"), "path #1 command 1 'L'", "must start with M or m");
    expectError(path("10 10"), "path #1 command 1", "must start with M or m");
    expectError(path("M10"), "path #1 command 1 'M'", "expected a number (y)");
    expectError(path("M10 10 X 5"), "path #1 command 2 'X'", "unknown path command");
    expectError(path("M10 10 A5 5 0 2 0 20 20"), "path #1 command 2 'A'",
                "expected a flag 0 or 1 (large-arc-flag)");
    expectError(path("M1e999 0"), "path #1 command 1 'M'", "out of range");
    expectError(path("M1e13 0"), "path #1 command 1 'M'", "exceeds the coordinate limit");
    expectError(path("M0 0 L1 1 Z 5"), "path #1 command 3 'Z'", "unexpected character '5'");
    expectError(path("M0 0 L1 1 # 2"), "path #1 command 2 'L'", "unexpected character '#'");
    expectError(doc(R"~(<path d="M0 0 L1 1"/><path d="M0 0 C"/>)~"), "path #2 command 2 'C'",
                "expected a number (x)");
}

TEST(InputSvg, BasicShapes) {
    auto net = svg(doc(R"~(<line x1="1" y1="2" x2="3" y2="4"/>)~"));
    ASSERT_EQ(net.segments.size(), 1u);
    expectLine(net.segments[0], F(1, 2), F(3, 4));
    EXPECT_EQ(net.curves[0].name, "line #1");

    net = svg(doc(
        R"~(<polyline points="0,0 10,0 10,10"/><polygon id="tri" points="20 20, 30 20 25 30"/>)~"));
    ASSERT_EQ(net.curves.size(), 2u);
    EXPECT_FALSE(net.curves[0].closed);
    EXPECT_TRUE(net.curves[1].closed);
    EXPECT_EQ(net.curves[1].name, "tri");
    EXPECT_EQ(net.segments.size(), 5u);
    expectLine(net.segments[4], F(25, 30), F(20, 20));

    net = svg(doc(R"~(<rect x="10" y="20" width="30" height="40"/>)~"));
    ASSERT_EQ(net.segments.size(), 4u);
    expectLine(net.segments[0], F(10, 20), F(40, 20));
    expectLine(net.segments[3], F(10, 60), F(10, 20));
    EXPECT_TRUE(net.curves[0].closed);

    // Zero width/height/radius disables rendering; an empty drawing is an error.
    expectError(doc(R"~(<rect width="0" height="5"/><circle r="0"/>)~"), "", "no curves");
    expectError(doc(R"~(<rect width="-1" height="5"/>)~"), "rect #1 attribute 'width'",
                "must not be negative");
    expectError(doc(R"~(<polyline points="0 0 1"/>)~"), "polyline #1 attribute 'points'",
                "odd number");
}

TEST(InputSvg, RoundedRect) {
    const double tol = 1e-4;
    // rx only: ry = rx; straight sides shortened by the radii.
    auto net = svg(doc(R"~(<rect x="10" y="20" width="30" height="40" rx="5"/>)~"), tol);
    EXPECT_TRUE(net.curves[0].closed);
    glm::dvec2 lo, hi;
    net.bounds(lo, hi);
    EXPECT_EQ(lo, F(10, 60));
    EXPECT_EQ(hi, F(40, 20));
    expectLine(net.segments[0], F(15, 20), F(35, 20));
    // The corner arc stays on the circle of radius 5 about (35, 25).
    int arcPieces = 0;
    for (const Segment& s : net.segments) {
        if (s.kind != Segment::Kind::Quadratic) continue;
        ++arcPieces;
        const V c = s.p0.x > 25 ? (s.p0.y > 50 ? F(35, 25) : F(35, 55))
                                : (s.p0.y > 50 ? F(15, 25) : F(15, 55));
        EXPECT_NEAR(glm::length(evalSegment(s, 0.5) - c), 5.0, tol + 1e-9);
    }
    EXPECT_GE(arcPieces, 4);
    // rx larger than half the width is clamped: no zero-length side segment.
    net = svg(doc(R"~(<rect width="10" height="40" rx="50" ry="5"/>)~"), tol);
    for (const Segment& s : net.segments) EXPECT_FALSE(s.p0 == s.p2 && s.p0 == s.p1);
    net.bounds(lo, hi);
    EXPECT_EQ(lo, F(0, 40));
    EXPECT_EQ(hi, F(10, 0));
}

TEST(InputSvg, CircleAndEllipse) {
    const double tol = 1e-4;
    auto net = svg(doc(R"~(<circle cx="50" cy="40" r="20"/>)~"), tol);
    ASSERT_EQ(net.curves.size(), 1u);
    EXPECT_TRUE(net.curves[0].closed);
    EXPECT_EQ(net.segments.front().p0, F(70, 40));
    const double h = hausdorff(
        [&](double t) {
            return F(50 + 20 * std::cos(2 * kPi * t), 40 + 20 * std::sin(2 * kPi * t));
        },
        net.segments);
    EXPECT_LE(h, tol + 1e-11);
    net = svg(doc(R"~(<ellipse cx="50" cy="40" rx="30" ry="10" transform="rotate(90 50 40)"/>)~"),
              tol);
    const double he = hausdorff(
        [&](double t) {
            const double a = 2 * kPi * t;
            return F(50 - 10 * std::sin(a),
                     40 + 30 * std::cos(a)); // rotated by 90 degrees about the centre
        },
        net.segments);
    EXPECT_LE(he, tol + 1e-11);
}

TEST(InputSvg, Transforms) {
    auto first = [](const std::string& body) { return svg(doc(body)).segments.at(0); };
    Segment s = first(R"~(<line x1="1" y1="2" x2="3" y2="4" transform="translate(10, 20)"/>)~");
    expectLine(s, F(11, 22), F(13, 24));
    s = first(R"~(<line x1="1" y1="2" x2="3" y2="4" transform="translate(10)"/>)~");
    expectLine(s, F(11, 2), F(13, 4));
    s = first(R"~(<line x1="1" y1="2" x2="3" y2="4" transform="scale(2)"/>)~");
    expectLine(s, F(2, 4), F(6, 8));
    s = first(R"~(<line x1="1" y1="2" x2="3" y2="4" transform="scale(2 3)"/>)~");
    expectLine(s, F(2, 6), F(6, 12));
    s = first(R"~(<line x1="1" y1="2" x2="3" y2="4" transform="matrix(1 2 3 4 5 6)"/>)~");
    expectLine(s, F(1 + 6 + 5, 2 + 8 + 6), F(3 + 12 + 5, 6 + 16 + 6));
    // The list applies right to left: translate(scale(p)).
    s = first(R"~(<line x1="1" y1="2" x2="3" y2="4" transform="translate(10,0) scale(2)"/>)~");
    expectLine(s, F(12, 4), F(16, 8));
    // Groups compose with the element's own transform.
    s = first(
        R"~(<g transform="translate(10 0)"><g transform="scale(2)"><line x1="1" y1="2" x2="3" y2="4"/></g></g>)~");
    expectLine(s, F(12, 4), F(16, 8));
    // rotate about a point, skews.
    s = first(R"~(<line x1="20" y1="10" x2="10" y2="10" transform="rotate(90 10 10)"/>)~");
    EXPECT_NEAR(s.p0.x, 10, 1e-12);
    EXPECT_NEAR(s.p0.y, 100 - 20, 1e-12);
    s = first(R"~(<line x1="0" y1="10" x2="1" y2="10" transform="skewX(45)"/>)~");
    EXPECT_NEAR(s.p0.x, 10, 1e-12);
    s = first(R"~(<line x1="10" y1="0" x2="10" y2="1" transform="skewY(45)"/>)~");
    EXPECT_NEAR(s.p0.y, 100 - 10, 1e-12);
    // Singular transforms hide the element (SVG 1.1 7.5).
    const auto net = svg(doc(
        R"~(<line x1="0" y1="0" x2="1" y2="1" transform="scale(0)"/><line x1="0" y1="0" x2="1" y2="1"/>)~"));
    EXPECT_EQ(net.segments.size(), 1u);
    expectError(doc(R"~(<line x2="1" transform="rotate(1 2)"/>)~"), "line #1 transform",
                "rotate() takes 1 or 3 numbers, got 2");
    expectError(doc(R"~(<line x2="1" transform="spin(3)"/>)~"), "line #1 transform",
                "unknown transform function");
    expectError(doc(R"~(<line x2="1" transform="scale(2"/>)~"), "line #1 transform", "missing ')'");
}

TEST(InputSvg, YFlipFollowsTheViewBox) {
    // viewBox "0 -10 100 50": y' = 2 * (-10) + 50 - y = 30 - y.
    auto net = svg(R"~(<svg viewBox="0 -10 100 50"><line x1="0" y1="-10" x2="5" y2="40"/></svg>)~");
    expectLine(net.segments[0], V(0, 40), V(5, -10));
    // No viewBox: y' = height - y (in px).
    net = svg(R"~(<svg height="1in"><line x1="0" y1="0" x2="5" y2="6"/></svg>)~");
    expectLine(net.segments[0], V(0, 96), V(5, 90));
    // Nested svg: viewBox 0 0 10 10 into a 50x50 viewport at (20, 0).
    net = svg(doc(
        R"~(<svg x="20" width="50" height="50" viewBox="0 0 10 10"><line x1="1" y1="1" x2="2" y2="1"/></svg>)~"));
    expectLine(net.segments[0], F(25, 5), F(30, 5));
}

TEST(InputSvg, IgnoredAndHiddenContent) {
    const auto net = svg(doc(R"~(
        <title>t</title><defs><path d="M0 0 L9 9"/></defs>
        <g display="none"><line x2="5"/></g><line x2="5" style="fill: none; display : none"/>
        <inkscape:thing><line x2="7"/></inkscape:thing>
        <svg:line x1="1" y1="1" x2="3" y2="3"/>)~"));
    ASSERT_EQ(net.segments.size(), 1u);
    expectLine(net.segments[0], F(1, 1), F(3, 3));
    expectError(doc(R"~(<use href="#a"/>)~"), "use #1", "not supported");
    expectError(doc(R"~(<text>hi</text>)~"), "text #1", "not supported");
}

TEST(InputSvg, HostileXml) {
    // Comments, CDATA, PIs and a DOCTYPE with entity declarations are
    // skipped; declared entities are never expanded.
    const std::string prolog =
        "<?xml version=\"1.0\"?>\n<!DOCTYPE svg [ <!ENTITY a \"&b;&b;\"> <!-- ] > --> ]>\n";
    auto net = svg(prolog + doc("<!-- <line x2='99'/> --><![CDATA[ <line x2='98'/> ]]><path d=\"M0 "
                                "0&#32;L&#x31;0 10\"/>"));
    ASSERT_EQ(net.segments.size(), 1u);
    expectLine(net.segments[0], F(0, 0), F(10, 10));
    expectError(prolog + doc("<path d=\"M0 0 L&a;\"/>"), "line 3", "entity &a; is not supported");
    expectError(doc("<!-- never closed"), "line 1", "unterminated comment");
    expectError(doc("<g><line x2='1'/>"), "line 1", "end tag </svg> does not match <g>");
    expectError(doc("<line x2='1' x2='2'/>"), "line 1", "duplicate attribute x2");
    expectError(doc("<line x2=1/>"), "line 1", "must be quoted");
    expectError("<html/>", "line 1", "root element is <html>, not <svg>");
    expectError("just text", "", "no <svg> element");
    expectError(doc("<line x2='1'/>") + "<svg/>", "line 1", "after the root element");
    expectError(R"~(<svg viewBox="0 0 100 100"><line x2="1"/>)~", "line 1", "is not closed");
    // Deep nesting: a clear error, no recursion.
    std::string deep = R"~(<svg viewBox="0 0 100 100">)~";
    for (int i = 0; i < 100000; ++i) deep += "<g>";
    expectError(deep, "line 1", "nested deeper than 256");
    // A huge attribute is read in linear time.
    std::string d = "M0 0";
    for (int i = 0; i < 200000; ++i)
        d += " L" + std::to_string(i % 50) + " " + std::to_string((i * 7) % 50);
    net = svg(path(d));
    EXPECT_GT(net.segments.size(), 150000u);
}

// The full message of the error svg(text) throws ("" when none).
std::string errorOf(const std::string& text) {
    try {
        svg(text);
    } catch (const io::InputError& e) {
        return e.what();
    }
    return "";
}

TEST(InputSvg, DoctypeEntitiesAreNeverExpanded) {
    // An internal DTD subset declaring an entity: the declaration is skipped
    // and changes nothing; a reference to the entity is an error naming the
    // file and its line, and nothing is expanded.
    const std::string dtd = "<?xml version=\"1.0\"?>\n"
                            "<!DOCTYPE svg [\n"
                            "  <!ENTITY a \"M0 0 L10 10\">\n"
                            "]>\n";
    auto net = svg(dtd + doc("<path d=\"M0 0 L10 10\"/>"));
    ASSERT_EQ(net.segments.size(), 1u);
    EXPECT_EQ(errorOf(dtd + doc("\n<path d=\"&a;\"/>")),
              "t.svg: line 6: entity &a; is not supported (only &lt; &gt; &amp; &quot; &apos; and "
              "numeric references; DTD entities are never expanded)");
    // A billion-laughs chain (10^9 "lol" if expanded) fails at once, at the
    // reference, in any attribute.
    std::string laughs = "<!DOCTYPE svg [\n<!ENTITY l0 \"lol\">\n"; // lines 1-2
    for (int i = 1; i < 10; ++i) {                                  // lines 3-11
        laughs += "<!ENTITY l" + std::to_string(i) + " \"";
        for (int k = 0; k < 10; ++k) laughs += "&l" + std::to_string(i - 1) + ";";
        laughs += "\">\n";
    }
    laughs += "]>\n"; // line 12
    expectError(laughs + doc("<path id=\"&l9;\" d=\"M0 0 L1 1\"/>"), "line 13",
                "entity &l9; is not supported");
    // Text is not read (it draws nothing): a reference there changes nothing.
    net = svg(dtd + doc("<title>&a;</title><path d=\"M0 0 L10 10\"/>"));
    ASSERT_EQ(net.segments.size(), 1u);
}

TEST(InputSvg, NestingAndAttributeLimits) {
    // The root, `groups` nested <g> (one per line) and a <line> inside.
    auto nested = [](int groups) {
        std::string s = R"~(<svg viewBox="0 0 100 100">)~";
        for (int i = 0; i < groups; ++i) s += "\n<g>";
        s += "<line x2=\"1\"/>";
        for (int i = 0; i < groups; ++i) s += "</g>";
        return s + "</svg>";
    };
    // 256 levels load; the <line> at level 257 (line 256) is an error,
    // also in a well-formed document.
    EXPECT_EQ(svg(nested(254)).segments.size(), 1u);
    expectError(nested(255), "line 256", "elements nested deeper than 256 levels");
    // 256 attributes on one element load; the 257th is an error.
    auto attrs = [](int n) {
        std::string s = "<line x2=\"1\"";
        for (int i = 1; i < n; ++i) s += " a" + std::to_string(i) + "=\"\"";
        return doc("\n" + s + "/>");
    };
    EXPECT_EQ(svg(attrs(256)).segments.size(), 1u);
    expectError(attrs(257), "line 2", "more than 256 attributes on one element");
}

TEST(InputSvg, SizeLimitIsCheckedBeforeParsing) {
    // One byte over the limit: rejected before the XML is read (this text
    // is not XML at all).
    std::string big(kMaxSvgBytes + 1, 'x');
    expectError(big, "",
                "SVG is " + std::to_string(kMaxSvgBytes + 1) + " bytes; limit is " +
                    std::to_string(kMaxSvgBytes));
    big = {};
    // loadSvg: the file's size is checked before it is read (a sparse file).
    const auto file = std::filesystem::temp_directory_path() /
                      ("sg_svg_size_" + std::to_string(::getpid()) + ".svg");
    std::ofstream(file).close();
    std::filesystem::resize_file(file, kMaxSvgBytes + 1);
    try {
        loadSvg(file);
        ADD_FAILURE() << "accepted a file over the limit";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.file(), file.string());
        SG_EXPECT_CONTAINS(e.reason(), "limit is " + std::to_string(kMaxSvgBytes));
    }
    std::filesystem::remove(file);
}

TEST(InputSvg, MalformedXmlNamesTheFileAndLine) {
    const std::string head = "<svg viewBox=\"0 0 100 100\">\n  <g>\n    <path d=\"M0 0 L1 1\"/>\n";
    // An unclosed tag: the end tag that does not match it, or the end of the
    // file, with the element left open.
    EXPECT_EQ(errorOf(head + "</svg>\n"), "t.svg: line 4: end tag </svg> does not match <g>");
    EXPECT_EQ(errorOf(head), "t.svg: line 2: <g> is not closed before the end of the file");
    expectError(head + "</g></svg></g>", "line 4", "end tag </g> does not match any open element");
    // Start tags.
    expectError(head + "    <path d=\"M0 0 L1 1\"\n</g></svg>", "line 5",
                "malformed start tag <path>");
    expectError(head + "    <path d=\"M0 0 L1 1/>\n</g></svg>\n", "line 4",
                "unterminated value of attribute d");
    expectError(head + "    <path d=M0/>\n</g></svg>", "line 4",
                "attribute value of d must be quoted");
    expectError(head + "    <path d=\"M0 0 L1 1\"id=\"p\"/>\n</g></svg>", "line 4",
                "expected whitespace before attribute id in <path>");
    expectError(head + "    <path d\n\"M0 0\"/></g></svg>", "line 5",
                "expected '=' after attribute d");
    expectError(head + "    <path d=\"M0 0 L1 1\"/ >\n</g></svg>", "line 4",
                "expected '/>' in <path>");
    expectError(head + "    <path d=\"M0 0 L1 1\"", "line 4",
                "unexpected end of file inside <path>");
    expectError(head + "    <path\n", "line 4", "unexpected end of file inside <path>");
    // Constructs left open are named where they start.
    expectError(head + "  <!-- a\n  b -- >\n</g></svg>", "line 4", "unterminated comment");
    expectError(head + "  <![CDATA[ a\n</g></svg>", "line 4", "unterminated CDATA section");
    expectError(head + "  <?pi a\n</g></svg>", "line 4", "unterminated processing instruction");
    // Declarations other than one DOCTYPE before the root.
    expectError(head + "  <!ELEMENT g ANY>\n</g></svg>", "line 4", "unknown declaration <!ELEMENT");
    expectError(head + "  <!DOCTYPE svg>\n</g></svg>", "line 4", "misplaced <!DOCTYPE>");
    // NUL is not an XML character.
    expectError(head + std::string(1, '\0') + "</g></svg>", "line 4", "NUL byte");
    // Lines count '\n' after a byte order mark and with CRLF line ends.
    expectError("\xEF\xBB\xBF<svg viewBox=\"0 0 100 100\">\r\n<g>\r\n</svg>", "line 3",
                "end tag </svg> does not match <g>");
}

struct Icon {
    const char* file;
    std::size_t curves;
    int closed;
};

TEST(InputSvg, EveryLucideIconLoads) {
    // Curve counts and closed curves read off the files (closed = the
    // subpath returns exactly to its start, with or without Z; see
    // data/svg/README.md); lucide draws inside 24 x 24.
    const Icon icons[] = {
        {"carrot.svg", 3, 1},      {"chart-spline.svg", 2, 0},
        {"flag.svg", 1, 0},        {"flame.svg", 1, 1},
        {"infinity.svg", 1, 1},    {"line-squiggle.svg", 1, 0},
        {"mountain.svg", 1, 1},    {"paw-print.svg", 4, 4},
        {"trending-up.svg", 2, 0}, {"waves-horizontal.svg", 3, 0},
    };
    std::size_t loaded = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dataDir() + "/svg")) {
        if (entry.path().extension() == ".svg") ++loaded;
    }
    EXPECT_EQ(loaded, std::size(icons)) << "an icon was added or removed: update this table";
    for (const Icon& icon : icons) {
        SCOPED_TRACE(icon.file);
        const CurveNetwork net = loadSvg(dataDir() + "/svg/" + icon.file);
        EXPECT_EQ(net.curves.size(), icon.curves);
        int closed = 0;
        for (const auto& c : net.curves) closed += c.closed;
        EXPECT_EQ(closed, icon.closed);
        EXPECT_GE(net.segments.size(), net.curves.size());
        EXPECT_LE(net.segments.size(), 400u); // 1e-4 relative tolerance: a few pieces per cubic/arc
        glm::dvec2 lo, hi;
        net.bounds(lo, hi);
        EXPECT_GE(lo.x, 0.0);
        EXPECT_GE(lo.y, 0.0);
        EXPECT_LE(hi.x, 24.0);
        EXPECT_LE(hi.y, 24.0);
        EXPECT_GT(std::max(hi.x - lo.x, hi.y - lo.y), 10.0);
        EXPECT_NO_THROW(checkNetwork(net));
        std::printf("%-22s curves %zu segments %zu\n", icon.file, net.curves.size(),
                    net.segments.size());
    }
}

TEST(InputSvg, LucideFlameKnownSegments) {
    // flame.svg starts "M12 3q1 4 4 6.5t3 5.5": flipped with y' = 24 - y.
    const CurveNetwork net = loadSvg(dataDir() + "/svg/flame.svg");
    ASSERT_GE(net.segments.size(), 2u);
    expectQuad(net.segments[0], V(12, 21), V(13, 17), V(16, 14.5));
    expectQuad(net.segments[1], V(16, 14.5), V(19, 12),
               V(19, 9)); // T reflects (13,7) about (16,9.5)
}

} // namespace
} // namespace sg::features::test
