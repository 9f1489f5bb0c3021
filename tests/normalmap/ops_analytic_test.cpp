// Every operation of the normal-map toolkit against the analytically
// transformed height field (Loviscach 2008, "Feeding": the operation is
// applied to h, the normal map follows): sums of sines, a Gaussian bump and
// a crease, given as their exact slopes at texel centres (a map baked from
// a true surface). Each op must match the normal of the transformed height
// within a stated bound; the naive image operation must not (the measured
// error is printed and a lower bound asserted, so the comparison in
// docs/normalmap.md stays true).
#include <gtest/gtest.h>

#include <cstdio>

#include "analytic_fields.h"

namespace {

using namespace sg::normalmap;
using namespace sg::normalmap::test;

constexpr int W = 256, H = 256;

void print(const char* what, AngleError ok, AngleError naive) {
    std::printf("[ measure  ] %-28s correct max %.4f rms %.4f deg | naive max %.3f rms %.3f deg\n",
                what, ok.maxDeg, ok.rmsDeg, naive.maxDeg, naive.rmsDeg);
}

// Amplitudes: slopes up to about 1 (45 degrees), where the naive
// operations' errors are plain to see and the map is still ordinary.
Field sinesField() {
    return sines(W, H, 9.0);
}
Field bumpField() {
    return gaussian(W, H, 16.0);
}
Field creaseField() {
    return crease(H, 0.8);
}

TEST(OpsAnalytic, ScaleInvertsAndDoublesExactly) {
    const std::pair<const char*, Field> fields[] = {
        {"sines", sinesField()}, {"bump", bumpField()}, {"crease", creaseField()}};
    for (const auto& [name, f] : fields) {
        const DerivField d = slopes(f, W, H);
        const NormalField n = normalsFromSlopes(d);
        for (float alpha : {-1.0f, 2.0f, 0.5f}) {
            const auto want =
                exact(W, H, [&](double u, double v) { return double(alpha) * f.grad(u, v); });
            const AngleError ok = compare(scale(d, alpha), want);
            const AngleError nv = compare(naive::scale(n, alpha), want);
            const std::string what = std::string(alpha < 0   ? "scale -1"
                                                 : alpha > 1 ? "scale 2"
                                                             : "scale 0.5") +
                                     " (" + name + ")";
            print(what.c_str(), ok, nv);
            // alpha d in binary32, then the normal: rounding only (1e-4 deg
            // is ~2e-6 rad, tens of ulps).
            EXPECT_LT(ok.maxDeg, 1e-4);
            // The naive lerp is off by degrees at 45-degree slopes, still
            // 0.5 degrees on the gentler bump at alpha = 0.5.
            EXPECT_GT(nv.maxDeg, 0.5);
        }
    }
}

TEST(OpsAnalytic, ScaleMinusOneTwiceIsIdentityAndAddSelfIsScaleTwo) {
    const DerivField d = slopes(sinesField(), W, H);
    const DerivField back = scale(scale(d, -1.0f), -1.0f);
    const DerivField twice = add(d, 1.0f, d, 1.0f), two = scale(d, 2.0f);
    for (size_t k = 0; k < d.size(); ++k) {
        // Negation and doubling are exact in binary32.
        ASSERT_EQ(back.v[k], d.v[k]) << k;
        ASSERT_EQ(twice.v[k], two.v[k]) << k;
    }
    // The naive versions are not: measure how far.
    const NormalField n = normalsFromSlopes(d);
    const auto want = exact(W, H, [&](double u, double v) { return sinesField().grad(u, v); });
    const auto want2 =
        exact(W, H, [&](double u, double v) { return 2.0 * sinesField().grad(u, v); });
    const AngleError nvBack = compare(naive::scale(naive::scale(n, -1.0f), -1.0f), want);
    const AngleError nvAdd = compare(naive::add(n, 1.0f, n, 1.0f), want2);
    std::printf(
        "[ measure  ] naive scale -1 twice: max %.3f deg; naive add(A, A) vs 2h: max %.3f deg\n",
        nvBack.maxDeg, nvAdd.maxDeg);
    EXPECT_GT(nvBack.maxDeg, 1.0);
}

TEST(OpsAnalytic, AddEqualsTheSummedHeights) {
    const Field a = sinesField(), b = bumpField();
    const DerivField da = slopes(a, W, H), db = slopes(b, W, H);
    const auto want =
        exact(W, H, [&](double u, double v) { return 0.7 * a.grad(u, v) + 1.3 * b.grad(u, v); });
    const AngleError ok = compare(add(da, 0.7f, db, 1.3f), want);
    const AngleError nv =
        compare(naive::add(normalsFromSlopes(da), 0.7f, normalsFromSlopes(db), 1.3f), want);
    print("add 0.7 A + 1.3 B", ok, nv);
    EXPECT_LT(ok.maxDeg, 1e-4); // binary32 rounding of two products and a sum
    EXPECT_GT(nv.maxDeg, 2.0);
}

float lowest(const Field& f) {
    const ScalarField s = heights(f, W, H);
    return *std::min_element(s.v.begin(), s.v.end());
}

// A smooth mask/gain in [0.05, 0.95], tileable.
Field maskField() {
    Field m = sines(W, H, 1.0);
    Field f;
    f.h = [m](double u, double v) { return 0.5 + 0.45 * std::sin(m.h(u, v)); };
    f.grad = [m](double u, double v) { return 0.45 * std::cos(m.h(u, v)) * m.grad(u, v); };
    return f;
}

// Heights from the map itself: the Poisson solve of the exact slopes
// differs from the true height by the central difference's symbol
// (omega / sin omega - 1 ~ omega^2 / 6: 0.3% of a wave 4 periods per tile
// long), which bounds the ops that need h.
TEST(OpsAnalytic, BlendWithMaskUsesTheProductRule) {
    const Field a = sinesField(), b = bumpField(), m = maskField();
    const DerivField da = slopes(a, W, H), db = slopes(b, W, H);
    const ScalarField mask = heights(m, W, H);
    const ScalarField ha = toHeight(da, Wrap::Repeat), hb = toHeight(db, Wrap::Repeat);
    // The true heights are measured from their lowest texel (the convention).
    const float la = lowest(a), lb = lowest(b);
    const auto want = exact(W, H, [&](double u, double v) {
        const double mm = m.h(u, v);
        return (1 - mm) * a.grad(u, v) + mm * b.grad(u, v) +
               ((b.h(u, v) - lb) - (a.h(u, v) - la)) * m.grad(u, v);
    });
    const AngleError ok = compare(blend(da, ha, db, hb, mask, Wrap::Repeat), want);
    const AngleError nv =
        compare(naive::blend(normalsFromSlopes(da), normalsFromSlopes(db), mask), want);
    // Without the mask's slope term (sgDerivBlend with per-texel weights).
    DerivField lerp(W, H);
    for (size_t k = 0; k < da.size(); ++k)
        lerp.v[k] = (1 - mask.v[k]) * da.v[k] + mask.v[k] * db.v[k];
    const AngleError noMaskTerm = compare(lerp, want);
    print("blend A B --mask M", ok, nv);
    std::printf("[ measure  ] blend without the mask-slope term: max %.3f deg\n",
                noMaskTerm.maxDeg);
    // The mask's slope by central differences is off by omega^2 / 6
    // relative (0.3% for its 4-per-tile waves, more for the harmonics sin()
    // adds), and it is multiplied by hB - hA (up to ~35 texels); the
    // integrated heights add 0.3% of their range times |dm| (<= 0.06 per
    // texel). Together up to ~3e-3 in slope: 0.2 degrees.
    EXPECT_LT(ok.maxDeg, 0.2);
    EXPECT_GT(nv.maxDeg, 1.0);
    EXPECT_GT(noMaskTerm.maxDeg, 1.0);
}

TEST(OpsAnalytic, ModulateUsesTheProductRule) {
    const Field a = bumpField(), m = maskField();
    const DerivField da = slopes(a, W, H);
    const ScalarField gain = heights(m, W, H);
    const ScalarField ha = toHeight(da, Wrap::Repeat);
    const float la = lowest(a);
    const auto want = exact(W, H, [&](double u, double v) {
        return a.grad(u, v) * m.h(u, v) + (a.h(u, v) - la) * m.grad(u, v);
    });
    const AngleError ok = compare(modulate(da, ha, gain, Wrap::Repeat), want);
    const AngleError nv = compare(naive::modulate(normalsFromSlopes(da), gain), want);
    print("modulate --by M", ok, nv);
    // As for blend: heights to 0.3%, the gain's slopes to omega^2 / 6,
    // times a height of up to 16 texels: 0.1 degrees.
    EXPECT_LT(ok.maxDeg, 0.1);
    EXPECT_GT(nv.maxDeg, 1.0);
}

TEST(OpsAnalytic, CurvesScaleSlopesByTheCurvesDerivative) {
    const Field a = sinesField();
    const DerivField da = slopes(a, W, H);
    const ScalarField ha = toHeight(da, Wrap::Repeat);
    const ScalarField t = heights(a, W, H);
    const double lo = *std::min_element(t.v.begin(), t.v.end()),
                 hi = *std::max_element(t.v.begin(), t.v.end());
    for (const Curve& c : {boostCurve(100.0f, 0.5f), boostCurve(500.0f, 0.1f),
                           parseCurvePoints("0,0 0.3,0.1 0.6,0.8 1,1", "test")}) {
        const auto want = exact(W, H, [&](double u, double v) {
            const double x = (a.h(u, v) - lo) / (hi - lo);
            return double(c.slopeAt(float(x))) * a.grad(u, v);
        });
        const AngleError ok = compare(applyCurve(da, ha, c), want);
        const AngleError nv = compare(naive::applyCurve(normalsFromSlopes(da), ha, c), want);
        print(c.boost ? "curves boost" : "curves points", ok, nv);
        // The elevation x comes from the integrated height (0.3% of the
        // range) and the steepest curve (P = 500) has |f''| / f' up to
        // 2 sqrt(P) = 45 per unit x: 0.3% x 45 = 13% of a slope that is
        // itself small there; measured below 0.3 degrees.
        EXPECT_LT(ok.maxDeg, 0.3);
        EXPECT_GT(nv.maxDeg, 1.0);
    }
}

TEST(OpsAnalytic, DeformThroughTheJacobian) {
    struct Case {
        const char* name;
        Field f;
        bool crease;
    };
    for (const Case& c : {Case{"deform sine (sines)", sinesField(), false},
                          Case{"deform sine (bump)", bumpField(), false},
                          Case{"deform sine (crease)", creaseField(), true}}) {
        const Field& f = c.f;
        // The paper's example t = v + A sin(B u), A = 0.02, B = 4 pi (two
        // waves per tile, so the warp tiles).
        const Warp sine{Warp::Kind::Sine, 0.02f, 4.0f * float(kPi)};
        const DerivField d = slopes(f, W, H);
        const auto want = exact(W, H, [&](double u, double v) {
            const double s = u, tt = v + H * 0.02 * std::sin(4 * kPi * u / W);
            const glm::dvec2 g = f.grad(s, tt);
            const double dtdu = H * 0.02 * 4 * kPi / W * std::cos(4 * kPi * u / W);
            return glm::dvec2(g.x + g.y * dtdu, g.y);
        });
        // The crease's kinks (t = 0 and t = H/2 at the warped point) are
        // smeared over one texel by bilinear sampling: texels sampling
        // within 1.5 texels of them are left out (set to the exact value).
        const int margin = 0;
        DerivField got = deform(d, sine, Wrap::Repeat);
        NormalField gotNaive = naive::deform(normalsFromSlopes(d), sine, Wrap::Repeat);
        int skipped = 0;
        if (c.crease) {
            for (int j = 0; j < H; ++j)
                for (int i = 0; i < W; ++i) {
                    const double tt = j + 0.5 + H * 0.02 * std::sin(4 * kPi * (i + 0.5) / W);
                    const double m = std::fmod(tt + 2.0 * H, H / 2.0);
                    if (std::min(m, H / 2.0 - m) > 1.5) continue;
                    const glm::dvec2 w = want[size_t(j) * W + size_t(i)];
                    got.at(i, j) = glm::vec2(float(w.x), float(w.y));
                    gotNaive.at(i, j) = glm::normalize(glm::vec3(float(-w.x), float(-w.y), 1.0f));
                    ++skipped;
                }
            // Two bands of about 3 texels per column.
            EXPECT_LT(skipped, 8 * W);
        }
        const AngleError ok = compare(got, want, margin);
        const AngleError nv = compare(gotNaive, want, margin);
        print(c.name, ok, nv);
        // Bilinear interpolation of smooth slopes between texel centres:
        // |d''| / 8 per texel^2 ~ (2 pi 4 / 256)^2 / 8 relative = 1.2e-4:
        // 0.05 degrees bounds it with margin.
        EXPECT_LT(ok.maxDeg, 0.05) << c.name;
        EXPECT_GT(nv.maxDeg, 2.0) << c.name;
    }
    // Rotation by 90 degrees: the slopes turn with the content.
    const Field f = sinesField();
    const DerivField d = slopes(f, W, H);
    const auto want = exact(W, H, [&](double u, double v) {
        // Content turned +90 degrees: h'(p) = h(c + R(-90)(p - c)).
        const double x = u - W / 2.0, y = v - H / 2.0;
        const glm::dvec2 g = f.grad(W / 2.0 + y, H / 2.0 - x);
        return glm::dvec2(-g.y, g.x);
    });
    const Warp rot{Warp::Kind::Rotate, 90.0f, 0.0f};
    const AngleError ok = compare(deform(d, rot, Wrap::Repeat), want);
    const AngleError nv = compare(naive::deform(normalsFromSlopes(d), rot, Wrap::Repeat), want);
    print("deform rotate 90", ok, nv);
    EXPECT_LT(ok.maxDeg, 1e-3); // texel centres map to texel centres: rounding only
    EXPECT_GT(nv.maxDeg, 30.0); // the normals did not turn
}

} // namespace
