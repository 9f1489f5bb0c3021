// Font input (input_font.cpp): exact outlines of the tiny test fonts built
// by tests/features/data/make_test_fonts.py (TrueType conics with implied
// on-curve points at odd coordinates, kerning, CFF cubics within the
// tolerance), real fonts (DejaVu "O" / "A", a CJK glyph from a TrueType
// collection, a CFF .otf), and the error messages.
#include "input_test_util.h"

#include "surfgrad/base/io.h"

namespace sg::features::test {
namespace {

using V = glm::dvec2;

std::string tinyTT() {
    return sourceDir() + "/tests/features/data/tiny-tt.ttf";
}
std::string tinyCFF() {
    return sourceDir() + "/tests/features/data/tiny-cff.otf";
}
const char* kDejaVu = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
const char* kWqy = "/usr/share/fonts/truetype/wqy/wqy-microhei.ttc";
const char* kInconsolata = "/usr/share/fonts/truetype/inconsolata/Inconsolata.otf";

void expectError(const std::string& font, const std::string& text, const std::string& element,
                 const std::string& reason, int face = 0) {
    FontOptions opt;
    opt.faceIndex = face;
    try {
        loadFont(font, text, opt);
        ADD_FAILURE() << "accepted: " << text;
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.element(), element) << e.what();
        SG_EXPECT_CONTAINS(e.reason(), reason) << e.what();
    }
}

void expectLine(const Segment& s, V a, V b) {
    EXPECT_EQ(s.kind, Segment::Kind::Line);
    EXPECT_EQ(s.p0, a);
    EXPECT_EQ(s.p2, b);
}
void expectQuad(const Segment& s, V a, V c, V b) {
    EXPECT_EQ(s.kind, Segment::Kind::Quadratic);
    EXPECT_EQ(s.p0, a);
    EXPECT_EQ(s.p1, c);
    EXPECT_EQ(s.p2, b);
}

TEST(InputFont, TrueTypeLinesKnownAnswer) {
    const CurveNetwork net = loadFont(tinyTT(), "A");
    ASSERT_EQ(net.curves.size(), 2u);
    ASSERT_EQ(net.segments.size(), 6u);
    expectLine(net.segments[0], {0, 0}, {350, 700});
    expectLine(net.segments[1], {350, 700}, {700, 0});
    expectLine(net.segments[2], {700, 0}, {0, 0});
    expectLine(net.segments[5], {350, 300}, {250, 100});
    EXPECT_TRUE(net.curves[0].closed);
    EXPECT_TRUE(net.curves[1].closed);
    EXPECT_EQ(net.curves[1].name, "U+0041 'A' contour 1");
}

TEST(InputFont, ImpliedOnCurvePointsAreExactMidpoints) {
    // A contour of four off-curve points: it starts at the midpoint of the
    // last and first, and every on-curve point is implied (half-integers).
    CurveNetwork net = loadFont(tinyTT(), "O");
    ASSERT_EQ(net.segments.size(), 4u);
    expectQuad(net.segments[0], {150.5, 150.5}, {301, 0}, {451, 150.5});
    expectQuad(net.segments[1], {451, 150.5}, {601, 301}, {451, 451});
    expectQuad(net.segments[2], {451, 451}, {301, 601}, {150.5, 451});
    expectQuad(net.segments[3], {150.5, 451}, {0, 301}, {150.5, 150.5});
    EXPECT_TRUE(net.curves[0].closed);
    // Line, two conics with an implied point (350.5, 50.5), lines.
    net = loadFont(tinyTT(), "g");
    ASSERT_EQ(net.segments.size(), 5u);
    expectLine(net.segments[0], {0, 0}, {200, 0});
    expectQuad(net.segments[1], {200, 0}, {300, 0}, {350.5, 50.5});
    expectQuad(net.segments[2], {350.5, 50.5}, {401, 101}, {300, 200});
    expectLine(net.segments[3], {300, 200}, {0, 200});
    expectLine(net.segments[4], {0, 200}, {0, 0});
}

TEST(InputFont, LayoutByAdvancesKerningAndNewlines) {
    const CurveNetwork a = loadFont(tinyTT(), "A");
    const CurveNetwork o = loadFont(tinyTT(), "O");
    // "AO": the font's kern pair (A, O) = -50, advance of A = 700.
    const CurveNetwork ao = loadFont(tinyTT(), "AO");
    ASSERT_EQ(ao.segments.size(), a.segments.size() + o.segments.size());
    ASSERT_EQ(ao.curves.size(), 3u);
    for (std::size_t i = 0; i < o.segments.size(); ++i) {
        const Segment& s = ao.segments[a.segments.size() + i];
        EXPECT_EQ(s.p0, o.segments[i].p0 + V(650, 0));
        EXPECT_EQ(s.p1, o.segments[i].p1 + V(650, 0));
        EXPECT_EQ(s.curve, 2);
    }
    // "A A": no kerning across the space (advance 250).
    const CurveNetwork aa = loadFont(tinyTT(), "A A");
    EXPECT_EQ(aa.segments[6].p0, a.segments[0].p0 + V(950, 0));
    // A newline moves one face height (ascent 800 - descent -200) down.
    const CurveNetwork lines = loadFont(tinyTT(), "A\nA");
    EXPECT_EQ(lines.segments[6].p0, a.segments[0].p0 + V(0, -1000));
}

TEST(InputFont, CffCubicsWithinTolerance) {
    // tiny-cff.otf "O": four cubics around (300, 300) written in the
    // generator; "g": an S-shaped cubic with an inflection.
    for (double tol : {0.0, 1e-3, 1.0}) {
        FontOptions opt;
        opt.approx.tolerance = tol;
        const double effTol =
            tol > 0.0 ? tol : 1e-4 * 600.0; // default: 1e-4 of the 600-unit drawing
        const CurveNetwork net = loadFont(tinyCFF(), "O", opt);
        ASSERT_EQ(net.curves.size(), 1u);
        EXPECT_TRUE(net.curves[0].closed);
        const int k = 166;
        const V cubics[4][4] = {
            {{600, 300}, {600, 300 + k}, {300 + k, 600}, {300, 600}},
            {{300, 600}, {300 - k, 600}, {0, 300 + k}, {0, 300}},
            {{0, 300}, {0, 300 - k}, {300 - k, 0}, {300, 0}},
            {{300, 0}, {300 + k, 0}, {600, 300 - k}, {600, 300}},
        };
        std::size_t next = 0;
        for (const auto& c : cubics) {
            std::vector<Segment> run;
            ASSERT_LT(next, net.segments.size());
            EXPECT_EQ(net.segments[next].p0, c[0]);
            while (next < net.segments.size()) {
                run.push_back(net.segments[next++]);
                if (run.back().p2 == c[3]) break;
            }
            EXPECT_EQ(run.back().p2, c[3]);
            EXPECT_LE(hausdorff([&](double t) { return evalCubic(c, t); }, run), effTol + 1e-9);
        }
        EXPECT_EQ(next, net.segments.size());
    }
    const CurveNetwork g = loadFont(tinyCFF(), "g");
    const V s[4] = {{100, 0}, {400, 0}, {0, 400}, {400, 400}};
    std::vector<Segment> run;
    for (const Segment& seg : g.segments) {
        if (seg.kind == Segment::Kind::Quadratic) run.push_back(seg);
    }
    ASSERT_GE(run.size(), 2u);
    EXPECT_EQ(run.front().p0, s[0]);
    EXPECT_EQ(run.back().p2, s[3]);
    EXPECT_LE(hausdorff([&](double t) { return evalCubic(s, t); }, run), 1e-4 * 400.0 + 1e-9);
}

TEST(InputFont, DejaVuOAndA) {
    const std::string font = systemFont(kDejaVu);
    const CurveNetwork o = loadFont(font, "O");
    ASSERT_EQ(o.curves.size(), 2u); // outer and inner contour
    EXPECT_TRUE(o.curves[0].closed && o.curves[1].closed);
    EXPECT_EQ(o.segments.size(), 16u); // 2 x 12 points "on off off": 8 quadratics each
    for (const Segment& s : o.segments) EXPECT_EQ(s.kind, Segment::Kind::Quadratic);
    glm::dvec2 lo, hi;
    o.bounds(lo, hi);
    EXPECT_EQ(lo.x, 115.0); // left side bearing in hmtx
    EXPECT_LT(lo.y, 0.0);   // overshoot below the baseline
    EXPECT_GT(hi.y, 1400.0);
    EXPECT_LT(hi.x, 1612.0); // inside the advance
    const CurveNetwork a = loadFont(font, "A");
    ASSERT_EQ(a.curves.size(), 2u);
    EXPECT_EQ(a.segments.size(), 11u); // 3 + 8 on-curve points, all lines
    for (const Segment& s : a.segments) EXPECT_EQ(s.kind, Segment::Kind::Line);
    EXPECT_TRUE(a.curves[0].closed && a.curves[1].closed);
    EXPECT_NO_THROW(checkNetwork(loadFont(font, "Surface gradients, AV To\n0123")));
}

TEST(InputFont, CjkGlyphFromCollection) {
    const std::string font = systemFont(kWqy);
    for (int face : {0, 1}) {
        FontOptions opt;
        opt.faceIndex = face;
        const CurveNetwork net = loadFont(font, "中", opt);
        EXPECT_EQ(net.curves.size(), 3u);
        for (const auto& c : net.curves) EXPECT_TRUE(c.closed);
        SG_EXPECT_CONTAINS(net.curves[0].name, "U+4E2D");
        glm::dvec2 lo, hi;
        net.bounds(lo, hi);
        EXPECT_GT(hi.x - lo.x, 1000.0); // 2048 units per em, a wide glyph
    }
    const CurveNetwork many = loadFont(font, "特征曲线");
    EXPECT_GT(many.curves.size(), 10u);
    expectError(font, "中", "face 2", "face index out of range: the file has 2 face(s)", 2);
}

TEST(InputFont, CffOpenTypeFont) {
    const std::string font = systemFont(kInconsolata);
    const CurveNetwork net = loadFont(font, "S");
    EXPECT_EQ(net.curves.size(), 1u);
    EXPECT_TRUE(net.curves[0].closed);
    int quads = 0;
    for (const Segment& s : net.segments) quads += s.kind == Segment::Kind::Quadratic;
    EXPECT_GT(quads, 8); // the cubics of "S", split to meet the tolerance
}

TEST(InputFont, Errors) {
    const std::string font = systemFont(kDejaVu);
    expectError(font, "A中", "glyph U+4E2D", "not in font 'DejaVu Sans Book' (face 0)");
    expectError(font, "", "text", "the text is empty");
    expectError(font, "A\xC3", "text byte 1", "invalid UTF-8");
    expectError(font, "\xED\xA0\x80", "text byte 0", "surrogate"); // U+D800
    expectError(font, "\xC0\xAF", "text byte 0", "overlong");
    expectError(font, "   ", "", "no glyph outlines");
    expectError(font, "A", "face 1", "face index out of range: the file has 1 face(s)", 1);
    expectError(font, "A", "face -1", "face index must be 0..65535", -1);
    expectError(sourceDir() + "/tests/features/input_font_test.cpp", "A", "",
                "not a usable font file");
    expectError("/nonexistent.ttf", "A", "", "no such file");
    try {
        const std::string bytes = "OTTO junk";
        parseFont(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "A",
                  "mem.otf");
        ADD_FAILURE();
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.file(), "mem.otf");
        SG_EXPECT_CONTAINS(e.reason(), "not a usable font file");
    }
}

} // namespace
} // namespace sg::features::test
