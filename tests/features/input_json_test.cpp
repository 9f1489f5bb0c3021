// JSON curve networks (input_json.cpp): known answers, one test per kind of
// bad field with the element and message checked, 100k segments.
#include "input_test_util.h"

#include "surfgrad/base/io.h"

#include <sstream>

namespace sg::features::test {
namespace {

CurveNetwork parse(const std::string& text) {
    return parseCurvesJson(text, "net.json");
}

// Parses `text`, expects an InputError with exactly `element` and a reason
// containing `reason`.
void expectError(const std::string& text, const std::string& element, const std::string& reason) {
    try {
        parse(text);
        ADD_FAILURE() << "accepted: " << text;
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.file(), "net.json");
        EXPECT_EQ(e.element(), element) << e.what();
        SG_EXPECT_CONTAINS(e.reason(), reason) << e.what();
    }
}

std::string curve(const std::string& body) {
    return R"({"version": 1, "curves": [)" + body + "]}";
}

TEST(InputJson, PolylineAndSegmentsKnownAnswer) {
    const CurveNetwork net = parse(curve(R"(
        {"name": "groove", "profile": "v-groove", "width": 0.25, "points": [[0, 0], [1, 0], [1, 2]]},
        {"segments": [{"line": [[5, 5], [6, 5]]}, {"quad": [[6, 5], [7, 6], [6, 7]]}], "closed": true})"));
    ASSERT_EQ(net.curves.size(), 2u);
    ASSERT_EQ(net.segments.size(), 5u); // 2 + 2 + closing line
    EXPECT_EQ(net.source, "net.json");
    EXPECT_EQ(net.curves[0].name, "groove");
    EXPECT_EQ(net.curves[0].profile, "v-groove");
    EXPECT_EQ(net.curves[0].width, 0.25);
    EXPECT_FALSE(net.curves[0].closed);
    EXPECT_TRUE(net.curves[1].name.empty());
    EXPECT_LT(net.curves[1].width, 0.0); // layer default
    EXPECT_TRUE(net.curves[1].closed);
    const Segment& l = net.segments[1];
    EXPECT_EQ(l.kind, Segment::Kind::Line);
    EXPECT_EQ(l.p0, glm::dvec2(1, 0));
    EXPECT_EQ(l.p1, glm::dvec2(1, 1));
    EXPECT_EQ(l.p2, glm::dvec2(1, 2));
    const Segment& q = net.segments[3];
    EXPECT_EQ(q.kind, Segment::Kind::Quadratic);
    EXPECT_EQ(q.p1, glm::dvec2(7, 6));
    EXPECT_EQ(q.curve, 1);
    const Segment& closing = net.segments[4];
    EXPECT_EQ(closing.p0, glm::dvec2(6, 7));
    EXPECT_EQ(closing.p2, glm::dvec2(5, 5));
    // Valence: the polyline's ends are valence 1, its joint valence 2.
    for (const auto& j : findJunctions(net)) {
        if (j.pos == glm::dvec2(0, 0) || j.pos == glm::dvec2(1, 2))
            EXPECT_EQ(j.valence(), 1);
        else
            EXPECT_EQ(j.valence(), 2);
    }
}

TEST(InputJson, ClosedPolylineAlreadyAtStartAddsNothing) {
    const CurveNetwork net =
        parse(curve(R"({"points": [[0, 0], [1, 0], [1, 1], [0, 0]], "closed": true})"));
    EXPECT_EQ(net.segments.size(), 3u);
    EXPECT_TRUE(net.curves[0].closed);
    // closed is geometric: a loop is closed even when not asked.
    const CurveNetwork loop = parse(curve(R"({"points": [[0, 0], [1, 0], [1, 1], [0, 0]]})"));
    EXPECT_TRUE(loop.curves[0].closed);
}

TEST(InputJson, CommentKeysAreIgnored) {
    EXPECT_NO_THROW(parse(
        R"({"version": 1, "_about": "x", "curves": [{"_note": 1, "points": [[0,0],[1,1]]}]})"));
}

TEST(InputJson, SyntaxErrorNamesLineAndColumn) {
    expectError("{\"version\": 1,\n  \"curves\": [\n  {\"points\": [[0, 0], [1, 1]],}\n]}",
                "line 3 column 31", "JSON syntax error");
    expectError("", "line 1 column 1", "JSON syntax error");
}
TEST(InputJson, RootMustBeAnObject) {
    expectError("[1, 2]", "", "expected a JSON object at the top level, got array");
}
TEST(InputJson, VersionMissing) {
    expectError(R"({"curves": []})", "version", "missing");
}
TEST(InputJson, VersionUnsupported) {
    expectError(R"({"version": 2, "curves": []})", "version", "unsupported version 2");
}
TEST(InputJson, VersionWrongType) {
    expectError(R"({"version": "1", "curves": []})", "version", "expected an integer, got string");
}
TEST(InputJson, CurvesMissing) {
    expectError(R"({"version": 1})", "curves", "missing");
}
TEST(InputJson, CurvesNotArray) {
    expectError(R"({"version": 1, "curves": {}})", "curves", "expected an array, got object");
}
TEST(InputJson, EmptyNetwork) {
    expectError(R"({"version": 1, "curves": []})", "curves", "the network is empty");
}
TEST(InputJson, UnknownTopLevelKey) {
    expectError(R"({"version": 1, "curvs": [], "curves": []})", "curvs", "unknown key");
}
TEST(InputJson, CurveNotObject) {
    expectError(curve("[[0, 0], [1, 1]]"), "curves[0]", "expected an object, got array");
}
TEST(InputJson, UnknownCurveKey) {
    expectError(curve(R"({"points": [[0,0],[1,1]], "widht": 2})"), "curves[0].widht",
                "unknown key");
}
TEST(InputJson, BothPointsAndSegments) {
    expectError(curve(R"({"points": [[0,0],[1,1]], "segments": []})"), "curves[0]", "has both");
}
TEST(InputJson, NeitherPointsNorSegments) {
    expectError(curve(R"({"name": "a"})"), "curves[0]", "needs \"points\"");
}
TEST(InputJson, PointsNotArray) {
    expectError(curve(R"({"points": 3})"), "curves[0].points",
                "expected an array of points, got number");
}
TEST(InputJson, TooFewPoints) {
    expectError(curve(R"({"points": [[0,0]]})"), "curves[0].points", "at least 2 points, got 1");
}
TEST(InputJson, PointWithThreeNumbers) {
    expectError(curve(R"({"points": [[0,0],[1,1,1]]})"), "curves[0].points[1]",
                "with 2 numbers, got 3");
}
TEST(InputJson, PointNotArray) {
    expectError(curve(R"({"points": [[0,0], {"x": 1}]})"), "curves[0].points[1]",
                "expected a point [x, y], got object");
}
TEST(InputJson, CoordinateNotNumber) {
    expectError(curve(R"({"points": [[0,0],[1,"NaN"]]})"), "curves[0].points[1][1]",
                "expected a number, got string");
}
TEST(InputJson, CoordinateOverflowsToInfinity) {
    // nlohmann rejects the literal while parsing; the message locates it.
    expectError(curve(R"({"points": [[0,0],[1e400, 1]]})"), "line 1 column 46",
                "number overflow parsing '1e400'");
}
TEST(InputJson, CoordinateBeyondLimit) {
    expectError(curve(R"({"points": [[0,0],[1e13, 1]]})"), "curves[0].points[1][0]",
                "exceeds the coordinate limit");
}
TEST(InputJson, CoincidentPolylinePoints) {
    expectError(curve(R"({"points": [[0,0],[1,1],[1,1]]})"), "curves[0].points[2]",
                "zero-length line segment");
}
TEST(InputJson, SegmentsEmpty) {
    expectError(curve(R"({"segments": []})"), "curves[0].segments", "at least 1 segment");
}
TEST(InputJson, SegmentUnknownKind) {
    expectError(curve(R"({"segments": [{"cubic": [[0,0],[1,1],[2,2],[3,3]]}]})"),
                "curves[0].segments[0].cubic", "unknown key");
}
TEST(InputJson, SegmentWithoutKind) {
    expectError(curve(R"({"segments": [{}]})"), "curves[0].segments[0]",
                "needs \"line\" or \"quad\"");
}
TEST(InputJson, SegmentNotObject) {
    expectError(curve(R"({"segments": [[[0,0],[1,1]]]})"), "curves[0].segments[0]",
                "expected an object");
}
TEST(InputJson, QuadWrongPointCount) {
    expectError(curve(R"({"segments": [{"quad": [[0,0],[1,1]]}]})"), "curves[0].segments[0].quad",
                "expected 3 points, got 2 entries");
}
TEST(InputJson, ZeroLengthLine) {
    expectError(curve(R"({"segments": [{"line": [[2,3],[2,3]]}]})"), "curves[0].segments[0].line",
                "zero-length line segment");
}
TEST(InputJson, CoincidentQuadControlPoints) {
    expectError(curve(R"({"segments": [{"line": [[0,0],[2,3]]}, {"quad": [[2,3],[2,3],[2,3]]}]})"),
                "curves[0].segments[1].quad", "all three control points coincide");
}
TEST(InputJson, QuadWithTwoEqualPointsIsValid) {
    // p0 == p1 (a straight quadratic) and p0 == p2 (a hairpin) have length.
    const CurveNetwork net = parse(
        curve(R"({"segments": [{"quad": [[0,0],[0,0],[2,3]]}, {"quad": [[2,3],[5,5],[2,3]]}]})"));
    EXPECT_EQ(net.segments.size(), 2u);
}
TEST(InputJson, DisconnectedSegments) {
    expectError(curve(R"({"segments": [{"line": [[0,0],[1,0]]}, {"line": [[1,0.5],[2,0]]}]})"),
                "curves[0].segments[1].line[0]", "must connect exactly");
}
TEST(InputJson, WidthNotPositive) {
    expectError(curve(R"({"width": -1, "points": [[0,0],[1,1]]})"), "curves[0].width",
                "must be > 0");
}
TEST(InputJson, WidthNotNumber) {
    expectError(curve(R"({"width": "2", "points": [[0,0],[1,1]]})"), "curves[0].width",
                "expected a number");
}
// Per-vertex widths: one per point (polyline) or per segment start plus the
// last end, linear along each segment; a closing line runs back to the
// first vertex's width.
TEST(InputJson, PerVertexWidths) {
    CurveNetwork net = parse(curve(
        R"({"profile": "table:0,1,0.5", "width": [1, 2, 4], "closed": true, "points": [[0,0],[1,0],[1,1]]},
           {"width": 2.5, "segments": [{"line": [[5,0],[6,0]]}, {"quad": [[6,0],[7,1],[8,0]]}]},
           {"width": [3, 0.5, 1], "segments": [{"line": [[9,0],[10,0]]}, {"quad": [[10,0],[11,1],[12,0]]}]})"));
    ASSERT_EQ(net.segments.size(), 7u);
    EXPECT_EQ(net.curves[0].profile, "table:0,1,0.5");
    const double w[7][2] = {{1, 2}, {2, 4}, {4, 1}, {-1, -1}, {-1, -1}, {3, 0.5}, {0.5, 1}};
    for (size_t k = 0; k < 7; ++k) {
        EXPECT_EQ(net.segments[k].width0, w[k][0]) << k;
        EXPECT_EQ(net.segments[k].width1, w[k][1]) << k;
    }
    EXPECT_EQ(net.curves[1].width, 2.5);
    EXPECT_EQ(net.curves[2].width, -1.0);
}
TEST(InputJson, PerVertexWidthCountAndValues) {
    expectError(curve(R"({"width": [1, 2], "points": [[0,0],[1,1],[2,0]]})"), "curves[0].width",
                "one width per vertex (3)");
    expectError(curve(R"({"width": [1, 0], "points": [[0,0],[1,1]]})"), "curves[0].width[1]",
                "must be > 0");
    expectError(curve(R"({"width": [1, "a"], "points": [[0,0],[1,1]]})"), "curves[0].width[1]",
                "expected a number");
}
TEST(InputJson, ProfileBadCharacters) {
    expectError(curve(R"({"profile": "v groove", "points": [[0,0],[1,1]]})"), "curves[0].profile",
                "only letters");
}
TEST(InputJson, ProfileNotString) {
    expectError(curve(R"({"profile": 3, "points": [[0,0],[1,1]]})"), "curves[0].profile",
                "got number");
}
TEST(InputJson, ClosedNotBool) {
    expectError(curve(R"({"closed": 1, "points": [[0,0],[1,1]]})"), "curves[0].closed",
                "expected true or false");
}
TEST(InputJson, NameNotString) {
    expectError(curve(R"({"name": null, "points": [[0,0],[1,1]]})"), "curves[0].name",
                "expected a string, got null");
}
TEST(InputJson, DeepNestingRejectedBeforeParsing) {
    expectError(std::string(100000, '[') + std::string(100000, ']'), "line 1 column 17",
                "nesting deeper than 16");
}
TEST(InputJson, MissingFile) {
    expectThrowsWith([] { loadCurvesJson("/nonexistent/net.json"); }, "no such file");
}

TEST(InputJson, HundredThousandSegments) {
    // 1000 curves of 101 points: 100,000 line segments.
    std::ostringstream s;
    s << R"({"version": 1, "curves": [)";
    for (int c = 0; c < 1000; ++c) {
        s << (c ? "," : "") << R"({"points": [)";
        for (int i = 0; i <= 100; ++i)
            s << (i ? "," : "") << "[" << i * 0.01 << "," << c * 0.01 + (i % 2) * 0.003 << "]";
        s << "]}";
    }
    s << "]}";
    const CurveNetwork net = parse(s.str());
    EXPECT_EQ(net.segments.size(), 100000u);
    EXPECT_EQ(net.curves.size(), 1000u);
    glm::dvec2 lo, hi;
    net.bounds(lo, hi);
    EXPECT_EQ(lo, glm::dvec2(0.0, 0.0));
    EXPECT_NEAR(hi.x, 1.0, 1e-12);
    EXPECT_NEAR(hi.y, 9.993, 1e-12);
    EXPECT_EQ(findJunctions(net).size(), 101000u);
}

} // namespace
} // namespace sg::features::test
