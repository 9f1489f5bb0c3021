// Height <-> slopes (Loviscach 2008, "Birth"): central differences against
// exact slopes, and the Poisson solve of to-height: exact inverse of
// from-height on tiling (DFT) and non-tiling (DCT, Neumann) grids of
// power-of-two and other sizes, a least-squares projection on real maps
// (idempotent), and how far the naive path integration is.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "analytic_fields.h"
#include "hardcase.h"

namespace {

using namespace sg::normalmap;
using namespace sg::normalmap::test;

// Largest |a - b| over all texels.
double maxDiff(const ScalarField& a, const ScalarField& b) {
    double m = 0;
    for (size_t k = 0; k < a.size(); ++k) m = std::max(m, std::abs(double(a.v[k]) - b.v[k]));
    return m;
}
double maxDiff(const DerivField& a, const DerivField& b) {
    double m = 0;
    for (size_t k = 0; k < a.size(); ++k) {
        m = std::max(
            {m, std::abs(double(a.v[k].x) - b.v[k].x), std::abs(double(a.v[k].y) - b.v[k].y)});
    }
    return m;
}
double range(const ScalarField& s) {
    auto [lo, hi] = std::minmax_element(s.v.begin(), s.v.end());
    return double(*hi - *lo);
}

// A smooth field that does not tile (a tilted paraboloid plus waves whose
// periods do not divide the size).
Field nonTiling(int W) {
    Field f;
    f.h = [=](double u, double v) {
        return 0.002 * (u - 0.3 * W) * (u - 0.3 * W) - 0.03 * v + 4 * std::sin(u / 13.0 + v / 29.0);
    };
    f.grad = [=](double u, double v) {
        const double c = 4 * std::cos(u / 13.0 + v / 29.0);
        return glm::dvec2(0.004 * (u - 0.3 * W) + c / 13.0, -0.03 + c / 29.0);
    };
    return f;
}

TEST(Poisson, ToHeightInvertsFromHeight) {
    struct Case {
        const char* name;
        int w, h;
        Wrap wrap;
    };
    for (const Case& c : {Case{"256x256 repeat", 256, 256, Wrap::Repeat},
                          Case{"96x160 repeat", 96, 160, Wrap::Repeat},
                          Case{"255x97 repeat", 255, 97, Wrap::Repeat},
                          Case{"256x256 clamp", 256, 256, Wrap::Clamp},
                          Case{"100x77 clamp", 100, 77, Wrap::Clamp}}) {
        const Field f = c.wrap == Wrap::Repeat ? sines(c.w, c.h, 9.0) : nonTiling(c.w);
        const ScalarField h = heightsFromMin(f, c.w, c.h);
        const DerivField d = fromHeight(h, 1.0f, c.wrap);
        const ScalarField back = toHeight(d, c.wrap);
        const double err = maxDiff(back, h);
        // Round trip of the map: slopes of the recovered height.
        const double errSlope = maxDiff(fromHeight(back, 1.0f, c.wrap), d);
        std::printf("[ measure  ] %-16s to-height(from-height(h)): max |dh| %.2e texels of %.1f; "
                    "slopes %.2e\n",
                    c.name, err, range(h), errSlope);
        // Exact in exact arithmetic; binary32 heights (1e-7 relative of the
        // range, ~3e-6 texels) through double transforms: 1e-4 texels.
        EXPECT_LT(err, 1e-4) << c.name;
        EXPECT_LT(errSlope, 1e-5) << c.name;
    }
}

TEST(Poisson, ToHeightIsALeastSquaresProjectionOnRealMaps) {
    // A real map's slopes are not exactly integrable: to-height then
    // from-height gives the nearest integrable slopes, and doing it again
    // changes nothing.
    const Image img = readImage(std::string(SURFGRAD_DATA_DIR) + "/textures/wicker_normal.png");
    const DerivField d = decodeSlopes(img, MapFormat{}, "wicker");
    const DerivField p1 = fromHeight(toHeight(d, Wrap::Repeat), 1.0f, Wrap::Repeat);
    const DerivField p2 = fromHeight(toHeight(p1, Wrap::Repeat), 1.0f, Wrap::Repeat);
    double rmsResidual = 0;
    for (size_t k = 0; k < d.size(); ++k)
        rmsResidual += glm::dot(d.v[k] - p1.v[k], d.v[k] - p1.v[k]);
    rmsResidual = std::sqrt(rmsResidual / double(d.size()));
    std::printf("[ measure  ] wicker 512^2: rms non-integrable slope part %.4f; projection "
                "repeated: max change %.2e\n",
                rmsResidual, maxDiff(p1, p2));
    // Idempotent up to binary32 storage of the heights (slopes ~1, heights
    // ~100 texels: 1e-5 relative of a height difference).
    EXPECT_LT(maxDiff(p1, p2), 1e-3);
    for (const auto& v : p1.v) ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y));
}

TEST(Poisson, FromExactAndNoisySlopesVersusNaivePathIntegration) {
    const int W = 256, H = 256;
    for (Wrap wrap : {Wrap::Repeat, Wrap::Clamp}) {
        const Field f = wrap == Wrap::Repeat ? sines(W, H, 9.0) : nonTiling(W);
        const ScalarField truth = heightsFromMin(f, W, H);
        const DerivField d = slopes(f, W, H);
        // The same slopes with a little non-integrable noise (+-0.05 per
        // texel, e.g. 8-bit quantisation and baking noise).
        DerivField noisy = d;
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> U(-0.05f, 0.05f);
        for (auto& v : noisy.v) v += glm::vec2(U(rng), U(rng));
        const char* name = wrap == Wrap::Repeat ? "repeat" : "clamp";
        const double errOk = maxDiff(toHeight(d, wrap), truth);
        const double errNaive = maxDiff(naive::toHeight(d), truth);
        const double errOkNoisy = maxDiff(toHeight(noisy, wrap), truth);
        const double errNaiveNoisy = maxDiff(naive::toHeight(noisy), truth);
        std::printf("[ measure  ] to-height (%s, range %.1f texels): exact slopes max |dh| %.3f "
                    "(naive path %.3f); noisy slopes %.3f (naive path %.3f)\n",
                    name, range(truth), errOk, errNaive, errOkNoisy, errNaiveNoisy);
        // The central difference sees a wave of frequency w as sin(w): the
        // solve returns w / sin(w) of it, 0.3% too high for the 4-per-tile
        // waves; the non-tiling field's waves are longer. 0.5% of the range.
        EXPECT_LT(errOk, 0.005 * range(truth)) << name;
        // Noise averages out in the least-squares height and accumulates
        // along the integration path.
        EXPECT_LT(errOkNoisy, 0.01 * range(truth)) << name;
        EXPECT_GT(errNaiveNoisy, 3 * errOkNoisy) << name;
    }
}

TEST(Poisson, CentralDifferencesVersusForwardDifferences) {
    const int W = 256, H = 256;
    const Field f = sines(W, H, 9.0);
    const ScalarField h = heights(f, W, H);
    const auto want = exact(W, H, f.grad);
    const AngleError ok = compare(fromHeight(h, 1.0f, Wrap::Repeat), want);
    const AngleError nv = compare(naive::fromHeight(h, 1.0f, Wrap::Repeat), want);
    std::printf("[ measure  ] from-height: central max %.4f deg, forward (naive) max %.3f deg\n",
                ok.maxDeg, nv.maxDeg);
    // Central differences: omega^2 / 6 relative (0.3% of a 1-slope: 0.2
    // degrees); forward differences are half a texel off: omega / 2.
    EXPECT_LT(ok.maxDeg, 0.2);
    EXPECT_GT(nv.maxDeg, 5 * ok.maxDeg);
}

TEST(Poisson, DegenerateSizesAndFlatFields) {
    for (auto [w, h] : {std::pair{1, 1}, std::pair{1, 7}, std::pair{5, 1}, std::pair{2, 2}}) {
        for (Wrap wrap : {Wrap::Repeat, Wrap::Clamp}) {
            DerivField d(w, h, glm::vec2(0.3f, -0.2f));
            const ScalarField s = toHeight(d, wrap);
            ASSERT_EQ(s.size(), size_t(w) * size_t(h));
            for (float x : s.v) ASSERT_TRUE(std::isfinite(x) && x >= 0.0f) << w << "x" << h;
        }
    }
    // A flat map integrates to a flat height.
    const ScalarField flat = toHeight(DerivField(64, 48, glm::vec2(0.0f)), Wrap::Clamp);
    EXPECT_EQ(range(flat), 0.0);
    sg::test::reportHardCaseHolds("normal-map-images",
                                  "to-height of 1x1, 1x7, 5x1, 2x2 maps, repeat and clamp",
                                  "heights", "finite, >= 0", "holds");
    sg::test::reportHardCase({"normal-map-images", "to-height of a flat 64x48 map", "height range",
                              "0", sg::test::hardCaseNumber(range(flat))});
}

} // namespace
