// Hard cases of the feature-map bake and evaluator, each a test:
// star junctions, curves through texel corners and along texel edges, two
// curves in one texel, tangential contact, tiny loops, nearly straight
// Beziers (theta_min), the Eq. 7 case, curves leaving the map, coincident
// control points, 100k segments. Every test also samples the whole map for
// NaN/Inf.
#include <cstdlib>
#include <random>

#include "hardcase.h"
#include "maps_test_util.h"
#include "surfgrad/base/io.h"

using namespace sg::features;
using namespace sgtest;
using sg::test::hardCaseNumber;
using sg::test::reportHardCase;
using sg::test::Worst;

namespace {

const BakeMode kModes[] = {BakeMode::Linear, BakeMode::Quadratic};

// max d over points along the given segments, skipping points within
// `skip` of a special point.
// Points where another curve passes within 2 * clearance texels are skipped
// too (curves sharing texels merge).
double maxOnCurve(const CurveNetwork& net, const GpuFeatureMaps& g, double skip, int per = 40,
                  double clearance = 0.0) {
    double m = 0;
    forCurvePoints(net, per, [&](dvec2 q, dvec2, size_t s) {
        if (distToSpecialPoint(net, q) < skip) return;
        if (clearance > 0 && otherCurveClearance(net, q, net.segments[s].curve, 0.0) < clearance)
            return;
        double d = sample(g, glm::vec2(q)).dist;
        if (std::getenv("SG_TEST_VERBOSE") && d > 1e-3)
            std::printf("  on-curve %.4f %.4f seg %zu: %.2e\n", q.x, q.y, s, d);
        m = std::max(m, d);
    });
    return m;
}

// The gradient at offset `off` on both sides of the curves points away from
// the curve (values never come from the other side); returns the number of
// violations.
int wrongSides(const CurveNetwork& net, const GpuFeatureMaps& g, double off, double skip,
               int per = 40) {
    int bad = 0;
    forCurvePoints(net, per, [&](dvec2 q, dvec2 tan, size_t) {
        if (distToSpecialPoint(net, q) < skip) return;
        dvec2 nrm(-tan.y, tan.x);
        for (double sd : {-1.0, 1.0}) {
            dvec2 p = q + sd * off * nrm;
            auto r = sample(g, glm::vec2(p));
            if (sd * (nrm.x * r.grad.x + nrm.y * r.grad.y) <= 0.0) {
                ++bad;
                if (std::getenv("SG_TEST_VERBOSE"))
                    std::printf("  wrong side at %.4f %.4f (d %.4f)\n", p.x, p.y, r.dist);
            }
        }
    });
    return bad;
}

} // namespace

// Eight straight rays meeting at one point: junction pairing makes four
// strokes through the centre texel, the transformation table keeps two of
// them there (an X), the others end on the centre texel's merged edge points
// (TOG 2008 Fig. 17).
TEST(FeatureMapsHardCases, StarOfEight) {
    for (BakeMode mode : kModes) {
        NetBuilder b;
        dvec2 c(16.37, 16.61);
        for (int k = 0; k < 8; ++k) {
            double a = 0.3 + 2 * M_PI * k / 8;
            b.polyline({c, c + 12.0 * dvec2(std::cos(a), std::sin(a))});
        }
        BakeStats st;
        FeatureMaps m = bake(b.net, texelSpace(32, mode), &st);
        GpuFeatureMaps g = m.packGpu();
        expectAllFinite(g);
        EXPECT_GT(st.segmentsDropped + st.edgePointsMerged, 0);
        // Rays two texels from the centre are exact (their texels hold one
        // segment): within quantization, 1e-4.
        const double rays = maxOnCurve(b.net, g, 2.5);
        EXPECT_LT(rays, 1e-3) << toString(mode);
        Worst centre;
        // Near the centre the rays are bent onto merged edge points: every
        // point of the star within 2.5 texels of the centre is within 0.75
        // texels of the zero set (measured 0.5: half a texel diagonal is the
        // most a merged edge point moves a ray).
        forCurvePoints(b.net, 80, [&](dvec2 q, dvec2, size_t) {
            if (glm::length(q - c) > 2.5) return;
            EXPECT_LT(sample(g, glm::vec2(q)).dist, 0.75)
                << toString(mode) << " at " << q.x << "," << q.y;
            centre.add(sample(g, glm::vec2(q)).dist);
        });
        const int wrong = wrongSides(b.net, g, 0.05, 2.5);
        EXPECT_EQ(wrong, 0) << toString(mode);
        const std::string name = std::string("star of 8 rays, ") + toString(mode) + " maps";
        reportHardCase({"feature-stars", name, "distance on the rays beyond 2.5 texels (texels)",
                        "< 0.001", hardCaseNumber(rays)});
        reportHardCase({"feature-stars", name, "distance on the rays within 2.5 texels (texels)",
                        "< 0.75", hardCaseNumber(centre.value)});
        reportHardCase({"feature-stars", name,
                        "gradients pointing to the wrong side at 0.05 texels", "0",
                        std::to_string(wrong)});
    }
}

// A diagonal through every texel corner, a horizontal line on a grid line,
// a vertical one on another, and a square with its corners on grid corners.
// Edge points stay 2^-10 texels off the corners, so the zero set moves by
// at most 2^-10 * sqrt(2) = 1.4e-3 texels.
TEST(FeatureMapsHardCases, CornersAndEdges) {
    for (BakeMode mode : kModes) {
        NetBuilder b;
        b.polyline({{2.0, 2.0}, {14.0, 14.0}});
        b.polyline({{1.5, 20.0}, {30.5, 20.0}});
        b.polyline({{25.0, 1.5}, {25.0, 18.0}});
        b.polyline({{4.0, 23.0}, {12.0, 23.0}, {12.0, 30.0}, {4.0, 30.0}}, true);
        FeatureMaps m = bake(b.net, texelSpace(32, mode));
        GpuFeatureMaps g = m.packGpu();
        expectAllFinite(g);
        // 2e-3: the 1.4e-3 corner margin plus the interpolation of d across
        // that sliver. (Skip 1.5: a curve ending on a corner loses the
        // texel it ends in, up to sqrt(2) of it.)
        const double on = maxOnCurve(b.net, g, 1.5);
        EXPECT_LT(on, 2e-3) << toString(mode);
        EXPECT_EQ(wrongSides(b.net, g, 0.01, 1.5), 0) << toString(mode);
        reportHardCase({"feature-other",
                        std::string("curves through texel corners and along texel edges, ") +
                            toString(mode) + " maps",
                        "distance on the curves (texels)", "< 0.002", hardCaseNumber(on)});
        // Points exactly on grid lines and corners evaluate in both
        // neighbouring texels without NaN: covered by expectAllFinite
        // (its grid includes every corner and edge).
    }
}

// Two parallel curves 0.3 texels apart cross the same texels: rule 1 merges
// their crossings, so one curve remains halfway between them.
TEST(FeatureMapsHardCases, TwoParallelCurvesInOneTexel) {
    for (BakeMode mode : kModes) {
        NetBuilder b;
        b.polyline({{2.3, 10.35}, {29.7, 10.35}});
        b.polyline({{2.3, 10.65}, {29.7, 10.65}});
        BakeStats st;
        FeatureMaps m = bake(b.net, texelSpace(32, mode), &st);
        GpuFeatureMaps g = m.packGpu();
        expectAllFinite(g);
        EXPECT_GT(st.edgePointsMerged, 20);
        // The merged curve at y = 10.5: each input is 0.15 away (+1e-3).
        const double on = maxOnCurve(b.net, g, 1.5);
        EXPECT_LT(on, 0.151) << toString(mode);
        EXPECT_LT(sample(g, glm::vec2(16.0f, 10.5f)).dist, 1e-3f);
        reportHardCase(
            {"feature-tangencies",
             std::string("two parallel curves 0.3 texels apart, ") + toString(mode) + " maps",
             "distance on each curve (texels; merged halfway)", "< 0.151", hardCaseNumber(on)});
    }
}

// A line tangent to a circle, and two circles touching: at the contact the
// two curves share texels (and their crossings merge); away from the
// contact both are exact.
TEST(FeatureMapsHardCases, TangentialContact) {
    for (BakeMode mode : kModes) {
        NetBuilder b;
        b.circle({16.2, 12.3}, 5.0, 12);
        b.polyline({{3.0, 17.3}, {29.0, 17.3}}); // tangent at the top
        b.circle({26.2, 12.3}, 5.0, 12, 0.3);    // touches the first at (21.2, 12.3)
        FeatureMaps m = bake(b.net, texelSpace(32, mode));
        GpuFeatureMaps g = m.packGpu();
        expectAllFinite(g);
        // Where the curves are more than a texel apart: the circles' pieces
        // are reproduced by quadratics within 0.01 (quadratic mode), by
        // chords within the sagitta 1.41^2 / (8 * 5) = 0.05 of a piece
        // crossing a texel diagonally (linear mode).
        double worst = maxOnCurve(b.net, g, 1.5, 60, 0.5);
        EXPECT_LT(worst, mode == BakeMode::Linear ? 0.06 : 0.01) << toString(mode);
        // At the contact: curves merge; the zero set stays within half a
        // texel.
        const float contact = sample(g, glm::vec2(16.2f, 17.3f)).dist;
        EXPECT_LT(contact, 0.5f);
        const std::string c = std::string("a line tangent to a circle, two circles touching, ") +
                              toString(mode) + " maps";
        reportHardCase({"feature-tangencies", c,
                        "distance on the curves away from the contact (texels)",
                        mode == BakeMode::Linear ? "< 0.06" : "< 0.01", hardCaseNumber(worst)});
        reportHardCase({"feature-tangencies", c, "distance at the contact point (texels)", "< 0.5",
                        hardCaseNumber(contact)});
    }
}

// A closed loop of radius 0.2 inside one texel never crosses an edge: it
// leaves no segment (curves must end on texel boundaries) and only the
// corner distances remember it, which interpolate bilinearly.
TEST(FeatureMapsHardCases, TinyLoopInsideTexel) {
    for (BakeMode mode : kModes) {
        NetBuilder b;
        b.circle({10.5, 7.5}, 0.2, 6);
        BakeStats st;
        FeatureMaps m = bake(b.net, texelSpace(16, mode), &st);
        GpuFeatureMaps g = m.packGpu();
        expectAllFinite(g);
        EXPECT_EQ(st.texelsWithFeatures, 0);
        // Corner samples are exact (0.507 from the loop); inside the texel d
        // is their bilinear mix, at least the true distance minus 0.2 and
        // at most the corner value.
        for (float y = 7.0f; y <= 8.0f; y += 0.125f) {
            for (float x = 10.0f; x <= 11.0f; x += 0.125f) {
                auto r = sample(g, glm::vec2(x, y));
                double exact = closest(b.net, {x, y}).dist;
                EXPECT_LE(r.dist, 0.5072f);
                EXPECT_GE(r.dist, exact - 0.21);
            }
        }
    }
    sg::test::reportHardCaseHolds("feature-other", "a loop of radius 0.2 inside one texel",
                                  "distance inside the texel",
                                  "between the true distance - 0.21 and 0.5072",
                                  "between the true distance - 0.21 and 0.5072");
}

// Nearly straight Beziers: the implicit form degenerates as the curve
// flattens, so segments whose deviation from their chord is below 1e-3
// texels become straight (exact to that deviation), and a curve crossing a
// texel edge at less than theta_min is straightened (TOG 2008 sec. 5.2).
TEST(FeatureMapsHardCases, NearlyStraightBeziers) {
    NetBuilder b;
    b.begin();
    b.quad({2.3, 5.2}, {16.0, 5.2 + 0.004}, {29.7, 5.2}); // sagitta 0.002 over 27 texels
    b.begin();
    // Crosses y = 20 at a grazing angle (tangent nearly horizontal there).
    b.quad({3.1, 19.93}, {16.0, 20.08}, {28.9, 19.93});
    // A circle of radius 2 whose top pokes 0.02 texels above y = 29: its
    // pieces there cross the grid line at 8 degrees, below theta_min of
    // their bulge.
    b.circle({8.3, 27.02}, 2.0, 12, 0.2);
    BakeStats st;
    FeatureMaps m = bake(b.net, texelSpace(32, BakeMode::Quadratic), &st);
    GpuFeatureMaps g = m.packGpu();
    expectAllFinite(g);
    EXPECT_GT(st.straightenedFlat, 20);
    EXPECT_GT(st.straightenedThetaMin, 0);
    // Flat pieces deviate from their chord by < 1e-3 (the rule), plus 1e-4
    // of quantization and interpolation.
    double worst = 0;
    forCurvePoints(b.net, 400, [&](dvec2 q, dvec2, size_t s) {
        if (s != 0 || distToSpecialPoint(b.net, q) < 1.5) return;
        worst = std::max(worst, double(sample(g, glm::vec2(q)).dist));
    });
    EXPECT_LT(worst, 1.1e-3);
    // Straightened pieces deviate by their sagitta: L^2 / (8 r) for a piece
    // of length L on radius r, 0.0625 for a one-texel piece of the circle
    // (r = 2); never a wrong side at 0.05.
    const double straightened = maxOnCurve(b.net, g, 1.5);
    EXPECT_LT(straightened, 0.07);
    EXPECT_EQ(wrongSides(b.net, g, 0.05, 1.5), 0);
    reportHardCase({"feature-other", "a quadratic with sagitta 0.002 over 27 texels",
                    "distance on the curve (texels)", "< 0.0011", hardCaseNumber(worst)});
    reportHardCase({"feature-other", "curves crossing texel edges below theta_min (straightened)",
                    "distance on the curves (texels)", "< 0.07", hardCaseNumber(straightened)});
}

// Highly curved segments (radius of curvature down to 0.3 texels) crossing
// texels: the natural signatures fail the Eq. 7 safety test, some fail the
// exact test too (the parabola re-enters the texel) and are repaired or
// straightened. Whatever the bake stores must pass the load-time validation
// (the same checks), and the side test must then classify correctly: the
// gradient points away from the STORED curve on both sides of it.
TEST(FeatureMapsHardCases, Eq7HighlyCurved) {
    NetBuilder b;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 40; ++k) {
        dvec2 c(4.0 + 24.0 * u(rng), 4.0 + 24.0 * u(rng));
        double r = 0.3 + 1.2 * u(rng), a0 = 2 * M_PI * u(rng), sweep = 0.6 + 1.8 * u(rng);
        dvec2 p0 = c + r * dvec2(std::cos(a0), std::sin(a0));
        dvec2 p2 = c + r * dvec2(std::cos(a0 + sweep), std::sin(a0 + sweep));
        dvec2 p1 =
            c + r / std::cos(sweep / 2) * dvec2(std::cos(a0 + sweep / 2), std::sin(a0 + sweep / 2));
        b.begin();
        b.quad(p0, p1, p2);
    }
    BakeStats st;
    FeatureMaps m = bake(b.net, texelSpace(32, BakeMode::Quadratic), &st);
    EXPECT_GT(st.eq7Failures, 10);
    EXPECT_GT(st.invalidTexels, 0);
    GpuFeatureMaps g = m.packGpu();
    expectAllFinite(g, 8);
    // Round trip through the validating loader: no stored signature is
    // invalid.
    auto dir = std::filesystem::temp_directory_path() / "sg_features_eq7";
    std::filesystem::create_directories(dir);
    save(m, dir / "m.exr");
    EXPECT_NO_THROW(load(dir / "m.exr"));
    std::filesystem::remove_all(dir);
    // Side classification against the STORED segments: rebuild each curved
    // segment from the maps (end points from the edge positions, middle
    // point from the tangent angles, appendix step 2) and probe 0.05 texels
    // to both sides of its midpoint: the gradient must point away from it.
    int checked = 0, bad = 0;
    auto edgeData = [&](int i, int j, int e, dvec2& q, double& theta) {
        size_t k = e == 0   ? m.index(i, j)
                   : e == 1 ? m.index(i + 1, j)
                   : e == 2 ? m.index(i, j + 1)
                            : m.index(i, j);
        bool h = e == 0 || e == 2;
        double t = h ? m.hPos[k] : m.vPos[k];
        theta = h ? m.hAngle[k] : m.vAngle[k];
        q = e == 0 ? dvec2(t, 0) : e == 1 ? dvec2(1, t) : e == 2 ? dvec2(t, 1) : dvec2(0, t);
    };
    for (int j = 0; j < 32; ++j) {
        for (int i = 0; i < 32; ++i) {
            uint32_t w = m.seg[m.index(i, j)];
            for (int s = 0; s < int(w & 3u); ++s) {
                if (!((w >> (6 + 5 * s)) & 1u)) continue;
                int ea = int((w >> (2 + 5 * s)) & 3u), eb = int((w >> (4 + 5 * s)) & 3u);
                dvec2 qa, qb;
                double ta, tb;
                edgeData(i, j, ea, qa, ta);
                edgeData(i, j, eb, qb, tb);
                dvec2 da(std::cos(ta), std::sin(ta)), db(std::cos(tb), std::sin(tb));
                double den = da.x * db.y - da.y * db.x;
                dvec2 b1 = qa + ((qb - qa).x * db.y - (qb - qa).y * db.x) / den * da;
                dvec2 mid = 0.25 * qa + 0.5 * b1 + 0.25 * qb, tan = glm::normalize(qb - qa);
                dvec2 nrm(-tan.y, tan.x);
                for (double sd : {-1.0, 1.0}) {
                    dvec2 pl = mid + sd * 0.05 * nrm;
                    if (pl.x < 0.02 || pl.y < 0.02 || pl.x > 0.98 || pl.y > 0.98) continue;
                    auto r = sample(g, glm::vec2(float(i + pl.x), float(j + pl.y)));
                    ++checked;
                    if (sd * (nrm.x * r.grad.x + nrm.y * r.grad.y) <= 0.0) ++bad;
                }
            }
        }
    }
    EXPECT_GT(checked, 40);
    EXPECT_EQ(bad, 0);
    reportHardCase({"feature-other",
                    "40 highly curved quadratics (radius of curvature 0.3 to 1.5 texels)",
                    "gradients pointing to the wrong side of the stored curve at 0.05 texels", "0",
                    std::to_string(bad)});
}

// Curves partly or wholly outside the map: crossings of the map border are
// edge points on the border, everything outside is ignored, corners within
// the band of an outside curve still get its distance.
TEST(FeatureMapsHardCases, CurvesLeavingTheMap) {
    for (BakeMode mode : kModes) {
        NetBuilder b;
        b.circle({0.3, 8.2}, 5.0, 12);            // half outside on the left
        b.polyline({{-40.0, 3.7}, {60.0, 13.1}}); // crosses the whole map
        b.polyline({{-9.0, -9.0}, {-3.0, -2.0}}); // entirely outside
        b.circle({16.0, 16.0}, 1e5, 12);          // huge, far outside the map
        FeatureMaps m = bake(b.net, texelSpace(16, mode));
        GpuFeatureMaps g = m.packGpu();
        expectAllFinite(g);
        double worst = 0;
        forCurvePoints(b.net, 200, [&](dvec2 q, dvec2, size_t s) {
            if (q.x < 0.5 || q.y < 0.5 || q.x > 15.5 || q.y > 15.5) return;
            if (distToSpecialPoint(b.net, q) < 1.5) return;
            // The line passes 0.2 texels from the circle: they share texels.
            if (otherCurveClearance(b.net, q, b.net.segments[s].curve, 0.0) < 0.75) return;
            double d = sample(g, glm::vec2(q)).dist;
            if (std::getenv("SG_TEST_VERBOSE") && d > 5e-3)
                std::printf("  on-curve %.4f %.4f: %.2e\n", q.x, q.y, d);
            worst = std::max(worst, d);
        });
        // Chords of a radius-5 circle (linear mode) deviate by up to the
        // sagitta of a diagonal piece, 0.05; quadratic pieces by < 0.01.
        EXPECT_LT(worst, mode == BakeMode::Linear ? 0.07 : 0.01) << toString(mode);
        // Corners get the exact distance to curves outside the map too
        // (binary32 storage: 1e-5).
        EXPECT_NEAR(m.dist[m.index(0, 0)], closest(b.net, {0.0, 0.0}).dist, 1e-5);
        reportHardCase({"feature-other",
                        std::string("curves leaving the map, one of radius 1e5 far outside, ") +
                            toString(mode) + " maps",
                        "distance on the curves inside the map (texels)",
                        mode == BakeMode::Linear ? "< 0.07" : "< 0.01", hardCaseNumber(worst)});
    }
}

// Coincident control points: a clear InputError naming the segment.
TEST(FeatureMapsHardCases, CoincidentControlPoints) {
    NetBuilder b;
    b.begin();
    b.quad({1.0, 1.0}, {2.0, 3.0}, {4.0, 1.0});
    b.quad({4.0, 1.0}, {4.0, 1.0}, {4.0, 1.0});
    try {
        bake(b.net, texelSpace(16, BakeMode::Quadratic));
        FAIL() << "no error";
    } catch (const sg::io::InputError& e) {
        EXPECT_EQ(e.element(), "segment 1");
        EXPECT_NE(std::string(e.reason()).find("coincident"), std::string::npos) << e.what();
    }
    NetBuilder c;
    c.begin();
    c.quad({1.0, 1.0}, {3.0, 3.0}, {1.0, 1.0}); // folds back: end points coincide
    EXPECT_THROW(bake(c.net, texelSpace(16, BakeMode::Quadratic)), sg::io::InputError);
    NetBuilder d;
    d.begin();
    d.quad({1.0, 1.0}, {5.0, 5.0}, {3.0, 3.0}); // collinear, middle point beyond the end
    EXPECT_THROW(bake(d.net, texelSpace(16, BakeMode::Quadratic)), sg::io::InputError);
    NetBuilder e;
    e.begin();
    e.quad({1.0, 1.0}, {1.0, 1.0}, {9.0, 4.0}); // middle point on an end: a straight line
    BakeStats st;
    FeatureMaps m = bake(e.net, texelSpace(16, BakeMode::Quadratic), &st);
    EXPECT_EQ(st.curvedSegments, 0);
    EXPECT_LT(maxOnCurve(e.net, m.packGpu(), 1.5), 1e-4);
    NetBuilder f;
    f.begin();
    f.line({1.0, std::nan("")}, {3.0, 3.0});
    EXPECT_THROW(bake(f.net, texelSpace(16, BakeMode::Linear)), sg::io::InputError);
    sg::test::reportHardCaseHolds("feature-other",
                                  "coincident, folded and collinear control points; a NaN point",
                                  "bake", "InputError naming the segment, or a straight line",
                                  "InputError naming the segment, or a straight line");
}

// 100k segments (short random lines, 1024^2, band 4): the bake completes,
// the statistics are consistent and sampled points are finite and exact on
// isolated pieces.
TEST(FeatureMapsHardCases, HundredThousandSegments) {
    NetBuilder b;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> pos(1.0, 1023.0), ang(0.0, 2 * M_PI);
    for (int k = 0; k < 100000; ++k) {
        dvec2 p(pos(rng), pos(rng));
        double a = ang(rng);
        b.polyline({p, p + 1.7 * dvec2(std::cos(a), std::sin(a))});
    }
    BakeOptions o = texelSpace(1024, BakeMode::Linear);
    o.bandTexels = 4.0;
    BakeStats st;
    FeatureMaps m = bake(b.net, o, &st);
    EXPECT_GT(st.texelsWithFeatures, 100000);
    EXPECT_LE(st.texelsWithSegments, st.texelsWithFeatures);
    GpuFeatureMaps g = m.packGpu();
    std::uniform_real_distribution<float> any(-1.0f, 1025.0f);
    for (int k = 0; k < 20000; ++k) {
        auto r = sample(g, glm::vec2(any(rng), any(rng)));
        ASSERT_TRUE(finite(r));
        ASSERT_GE(r.dist, 0.0f);
        ASSERT_LE(r.dist, 4.0f);
    }
    sg::test::reportHardCaseHolds("feature-other", "100,000 random segments on a 1024^2 map",
                                  "distance at 20,000 random points", "finite, in [0, band = 4]",
                                  "finite, in [0, band = 4]");
}
