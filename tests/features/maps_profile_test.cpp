// Feature profiles and the two compositions (shaders/sg/features/
// profile.glsl): slopes are the derivatives of the heights, blends are 0/1
// outside [w0, w], the paper's Eq. 1 and the surfgrad composition agree
// wherever the blend is 0 or 1 and differ (by a measured amount) between.
#include "maps_test_util.h"
#include "surfgrad/base/io.h"

using namespace sg::features;
using namespace sg::glsl;

namespace {

SgFeatResult at(float d, float side = 1.0f, float angle = 0.3f) {
    SgFeatResult r;
    r.dist = d;
    r.grad = vec2(std::cos(angle), std::sin(angle));
    r.side = side;
    r.profile = -1;
    r.width = 0.0f;
    return r;
}

const char* kNames[] = {"vgroove", "crease", "ridge",
                        "step",    "seam",   "table:0,-0.2,-0.9,-1,-0.5,0.3"};

} // namespace

// h'(d) is the derivative of h(d): central differences (step 1e-3 texels,
// error O(step^2 h''') < 1e-4 for these profiles of width >= 1) away from
// the kinks at d = 0 and d = w.
TEST(FeatureProfiles, SlopeIsDerivativeOfHeight) {
    for (const char* name : kNames) {
        for (float w : {1.0f, 3.5f}) {
            SgFeatProfile p = makeProfile(name, 1.7f, 0.0f, w);
            for (float side : {-1.0f, 1.0f}) {
                for (int k = 1; k < 40; ++k) {
                    // Offset from the table's nodes (every 1/5 of w), where
                    // Catmull-Rom's second derivative jumps.
                    float d = w * (float(k) + 0.37f) / 40.5f;
                    if (std::fabs(d - w) < 0.01f) continue;
                    float h = 1e-3f;
                    float fd = (sgFeatProfileHeightSlope(p, d + h, side).x -
                                sgFeatProfileHeightSlope(p, d - h, side).x) /
                               (2.0f * h);
                    EXPECT_NEAR(sgFeatProfileHeightSlope(p, d, side).y, fd, 2e-3f)
                        << name << " d " << d;
                }
                // Flat beyond the width.
                EXPECT_EQ(sgFeatProfileHeightSlope(p, 1.01f * w, side).y, 0.0f) << name;
                EXPECT_EQ(sgFeatProfileHeightSlope(p, 5.0f * w, side).y, 0.0f) << name;
            }
        }
    }
}

TEST(FeatureProfiles, ShapesAndSides) {
    SgFeatProfile v = makeProfile("vgroove", 2.0f, 0.0f, 4.0f);
    EXPECT_FLOAT_EQ(sgFeatProfileHeightSlope(v, 0.0f, 1.0f).x, -2.0f);
    EXPECT_FLOAT_EQ(sgFeatProfileHeightSlope(v, 2.0f, 1.0f).y, 0.5f);
    SgFeatProfile st = makeProfile("step", 2.0f, 0.0f, 4.0f);
    EXPECT_EQ(sgFeatProfileHeightSlope(st, 1.0f, -1.0f).x, 0.0f);      // right side stays flat
    EXPECT_FLOAT_EQ(sgFeatProfileHeightSlope(st, 4.0f, 1.0f).x, 2.0f); // left side rises to depth
    SgFeatProfile t = makeProfile("table:0,-0.5,-1,-0.5,0", 2.0f, 0.0f, 4.0f);
    for (int i = 0; i < 5; ++i) {
        // Catmull-Rom interpolates its nodes.
        EXPECT_NEAR(sgFeatProfileHeightSlope(t, float(i), 1.0f).x, 2.0f * t.table[i], 1e-6f);
    }
    // Slope continuous across a table node (Catmull-Rom is C1).
    EXPECT_NEAR(sgFeatProfileHeightSlope(t, 2.0f - 1e-4f, 1.0f).y,
                sgFeatProfileHeightSlope(t, 2.0f + 1e-4f, 1.0f).y, 1e-3f);
}

TEST(FeatureProfiles, Blend) {
    SgFeatProfile p = makeProfile("crease", 1.0f, 0.5f, 3.0f);
    EXPECT_EQ(sgFeatBlend(p, 0.0f), 0.0f);
    EXPECT_EQ(sgFeatBlend(p, 0.5f), 0.0f);
    EXPECT_EQ(sgFeatBlend(p, 3.0f), 1.0f);
    EXPECT_EQ(sgFeatBlend(p, 30.0f), 1.0f);
    float prev = 0.0f;
    for (int k = 0; k <= 100; ++k) {
        float b = sgFeatBlend(p, 0.5f + 2.5f * float(k) / 100.0f);
        EXPECT_GE(b, prev);
        prev = b;
    }
    SgFeatProfile hard = makeProfile("crease", 1.0f, 2.0f, 2.0f); // w0 == w: a step at w
    EXPECT_EQ(sgFeatBlend(hard, 1.99f), 0.0f);
    EXPECT_EQ(sgFeatBlend(hard, 2.01f), 1.0f);
}

// Where b = 0 (d <= w0) both compositions are the profile's normal; where
// b = 1 (d >= w) both are the base normal. Between, Eq. 1 interpolates unit
// normals while surfgrad interpolates slopes; the largest angle between the
// two over profiles, depths and base normals is measured and bounded.
TEST(FeatureProfiles, CompositionsAgreeOutsideTheBlendBand) {
    double maxInside = 0.0, maxOutside = 0.0;
    for (const char* name : kNames) {
        for (float depth : {0.25f, 1.0f, 3.0f}) {
            SgFeatProfile p = makeProfile(name, depth, 0.75f, 3.0f);
            for (float bx : {0.0f, 0.3f, -0.6f}) {
                vec3 base = normalize(vec3(bx, 0.25f, 1.0f));
                vec2 baseDeriv = vec2(-base.x / base.z, -base.y / base.z);
                for (int k = 0; k <= 80; ++k) {
                    float d = 4.0f * float(k) / 80.0f;
                    for (float side : {-1.0f, 1.0f}) {
                        vec3 paper = sgFeatNormalPaper(at(d, side), p, base);
                        vec3 sg = sgFeatNormalFromDeriv(sgFeatDeriv(at(d, side), p, baseDeriv));
                        double ang =
                            std::acos(std::clamp(double(dot(paper, sg)), -1.0, 1.0)) * 180.0 / M_PI;
                        bool band = d > p.w0 && d < p.w;
                        (band ? maxInside : maxOutside) =
                            std::max(band ? maxInside : maxOutside, ang);
                    }
                }
            }
        }
    }
    std::printf(
        "paper vs surfgrad composition: max %.4f deg outside the blend band, %.2f deg inside\n",
        maxOutside, maxInside);
    // Outside the band both are the same unit vector up to binary32 (a few
    // 1e-3 degrees from acos near 1).
    EXPECT_LT(maxOutside, 0.05);
    // Inside, they differ: slopes blend linearly, directions do not. The
    // largest gap occurs for steep profiles (depth 3 over 3 texels) against
    // a tilted base: measured 28.7 degrees; bound 40.
    EXPECT_GT(maxInside, 1.0);
    EXPECT_LT(maxInside, 40.0);
}

TEST(FeatureProfiles, NamesAndErrors) {
    for (const auto& n : {"vgroove", "crease", "ridge", "step", "seam"})
        EXPECT_NO_THROW(makeProfile(n, 1, 0, 2));
    EXPECT_THROW(makeProfile("bevel", 1, 0, 2), sg::io::InputError);
    EXPECT_THROW(makeProfile("vgroove", 1, 0, 0), sg::io::InputError);
    EXPECT_THROW(makeProfile("vgroove", 1, -1, 2), sg::io::InputError);
    EXPECT_THROW(makeProfile("vgroove", std::nanf(""), 0, 2), sg::io::InputError);
    EXPECT_THROW(makeProfile("table:1", 1, 0, 2), sg::io::InputError);
    EXPECT_THROW(makeProfile("table:1,x", 1, 0, 2), sg::io::InputError);
    EXPECT_THROW(makeProfile("table:1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17", 1, 0, 2),
                 sg::io::InputError);
    EXPECT_THROW(makeProfile("table:1,inf", 1, 0, 2), sg::io::InputError);
    EXPECT_EQ(makeProfile("table:0,1,0", 1, 0, 2).tableCount, 3);
}
