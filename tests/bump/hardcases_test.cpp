// Hard cases of the shared bump math (shaders/sg/*.glsl as C++ through
// surfgrad/bump/core.h), each reported as rows of docs/hard-cases.md
// (tests/common/hardcase.h):
//  - normals at and below the horizon: Mikkelsen 2019 listing 7 (perturbed
//    normal to surface gradient), listing 4 (normal-map texels on the rim),
//    listing 1 (resolve of huge gradients);
//  - grazing views: listing 17 (analytic dPdx/dPdy), listing 8
//    (scale-dependent bump) and listing 6 (per-pixel tangent frame) as the
//    view turns edge-on;
//  - huge and tiny world and texture scales: listings 8 and 6 + 5 give the
//    same normal for a scaled scene;
//  - collapsed screen footprints (a zero-area pixel: dPdx parallel to dPdy)
//    and degenerate UV Jacobians: listings 6, 8, 10, 11, 16;
//  - decals parallel to the surface (section 2.9, listing 15) and
//    triplanar at equal weights (listings 13, 14);
//  - listing 17 far from the origin, where the inputs are world positions
//    instead of camera-relative ones.
// Oracles are computed in double inside this file from the paper's
// definitions, never from the shared code. Every bound says why.
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "hardcase.h"
#include "surfgrad/bump/core.h"

namespace {

namespace g = sg::glsl;
using dvec2 = glm::dvec2;
using dvec3 = glm::dvec3;
using sg::test::hardCaseAtMost;
using sg::test::hardCaseNumber;
using sg::test::reportHardCase;
using sg::test::Worst;

constexpr double kEps = 1.1920928955078125e-07; // FLT_EPSILON, as SG_FLT_EPSILON

g::vec3 f3(const dvec3& v) {
    return g::vec3(float(v.x), float(v.y), float(v.z));
}
g::vec2 f2(const dvec2& v) {
    return g::vec2(float(v.x), float(v.y));
}
dvec3 d3(const g::vec3& v) {
    return dvec3(v.x, v.y, v.z);
}
double angle(const dvec3& a, const dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}
bool finite3(const g::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
bool finite2(const g::vec2& v) {
    return std::isfinite(v.x) && std::isfinite(v.y);
}
double maxAbs(const g::vec3& v) {
    return std::max({std::fabs(double(v.x)), std::fabs(double(v.y)), std::fabs(double(v.z))});
}
double maxAbs(const g::vec2& v) {
    return std::max(std::fabs(double(v.x)), std::fabs(double(v.y)));
}

struct Rng {
    std::mt19937_64 gen;
    explicit Rng(uint64_t seed) : gen(seed) {}
    double u(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(gen); }
    // 10^x for x uniform in [lo, hi].
    double logU(double lo, double hi) { return std::pow(10.0, u(lo, hi)); }
    dvec3 unit() {
        for (;;) {
            dvec3 v(u(-1, 1), u(-1, 1), u(-1, 1));
            double l = glm::length(v);
            if (l > 0.1 && l <= 1.0) return v / l;
        }
    }
    // A unit vector perpendicular to n.
    dvec3 tangent(const dvec3& n) {
        for (;;) {
            dvec3 t = glm::cross(n, unit());
            double l = glm::length(t);
            if (l > 0.1) return t / l;
        }
    }
};

g::SgFrame frontFrame(const g::vec3& n, const g::vec3& dPdx, const g::vec3& dPdy) {
    return g::sgPrologue(n, dPdx, dPdy, true, SG_BFACE_NONE);
}

// ---- normals at the horizon -------------------------------------------------

// Listing 7 turns a perturbed normal v into a surface gradient; the resolve
// (listing 1) of that gradient gives v back. Its 1/(n.v) is clamped at
// FLT_EPSILON (relative to v's largest component), so v on or below the
// horizon comes back at the horizon, within about FLT_EPSILON of it: the
// rounding of n.v (an absolute error of an ulp or two), amplified by the
// clamped 1/(n.v) = 1/FLT_EPSILON, tilts the result by up to about one
// FLT_EPSILON either way.
TEST(HardCasesBump, PerturbedNormalAtAndBelowTheHorizon) {
    Rng rng(101);
    Worst above, nearExcess, grad, unitErr;
    double lowest = 1.0;
    int bad = 0;
    for (int i = 0; i < 40000; ++i) {
        const dvec3 n = rng.unit(), t = rng.tangent(n);
        // Elevation of v: +-10^[-9, 0.2] rad, exactly 0 for 1 record in 16.
        double theta = (i % 16 == 0) ? 0.0 : rng.logU(-9, 0.2) * (i % 3 == 0 ? -1 : 1);
        const double len = rng.logU(-20, 18); // "v need not be unit length"
        const g::vec3 nF = f3(n), vF = f3(len * (std::cos(theta) * t + std::sin(theta) * n));
        const g::SgFrame f = frontFrame(nF, g::vec3(0.0f), g::vec3(0.0f));
        const g::vec3 sgr = g::sgSurfgradFromPerturbedNormal(f, vF);
        const g::vec3 r = g::sgResolve(f, sgr);
        if (!finite3(sgr) || !finite3(r)) {
            ++bad;
            continue;
        }
        grad.add(maxAbs(sgr));
        unitErr.add(std::fabs(glm::length(d3(r)) - 1.0));
        // The elevation of the binary32 inputs, in double: the truth the
        // function sees (rounding n and v moves it by ~1e-7).
        const dvec3 nd = glm::normalize(d3(nF)), vd = glm::normalize(d3(vF));
        const double thetaIn = std::asin(glm::clamp(glm::dot(nd, vd), -1.0, 1.0));
        const double elev = std::asin(glm::clamp(glm::dot(nd, d3(r)), -1.0, 1.0));
        lowest = std::min(lowest, elev);
        if (thetaIn >= 1e-6) {
            above.add(angle(d3(r), vd));
        } else if (std::fabs(thetaIn) < 1e-6) {
            nearExcess.add(elev - std::max(std::fabs(thetaIn), kEps));
        }
    }
    EXPECT_EQ(bad, 0) << "non-finite outputs";
    // Above the horizon the round trip is exact up to rounding of n.v: an
    // absolute error of a few FLT_EPSILON in the elevation (measured 1.6e-7
    // rad); 1e-6 rad is 8 FLT_EPSILON.
    hardCaseAtMost("horizon", "L7 then L1, v 1e-6 to 1.6 rad above the horizon, |v| 1e-20 to 1e18",
                   "angle between the resolved normal and v (rad)", above.value, 1e-6);
    // Within 1e-6 rad of the horizon (on it, or below it): the clamp puts
    // the result at most max(|elevation|, FLT_EPSILON) above the horizon;
    // n.v's rounding, amplified by the clamp's 1/FLT_EPSILON, moves it by
    // about one more FLT_EPSILON (measured 1.75e-7 = 1.5 FLT_EPSILON).
    hardCaseAtMost(
        "horizon", "L7 then L1, v within 1e-6 rad of the horizon, on it or below it",
        "elevation of the resolved normal minus max(|elevation of v|, FLT_EPSILON) (rad)",
        nearExcess.value, 3.0 * kEps);
    // ... and at most about one FLT_EPSILON below it (measured -3.4e-8).
    EXPECT_GE(lowest, -kEps);
    reportHardCase({"horizon", "L7 then L1, v at any elevation in [-1.6, 1.6] rad",
                    "lowest elevation of the resolved normal (rad)",
                    ">= -" + hardCaseNumber(kEps) + " (FLT_EPSILON)", hardCaseNumber(lowest)});
    // |sg| <= sqrt(3) / FLT_EPSILON = 1.45e7 (the clamped 1/(n.v) times the
    // tangential part of v scaled to unit largest component).
    hardCaseAtMost("horizon", "L7, v at any elevation, any length", "largest |sg| component",
                   grad.value, std::sqrt(3.0) / kEps);
    // Resolve normalizes with sgSafeNormalize: within 2 ulps of unit length.
    hardCaseAtMost("horizon", "L1 of the gradients above", "| |n'| - 1 |", unitErr.value, 2.4e-7);
}

// Listing 4 on normal-map texels on and outside the unit circle (|m| >= 1:
// m.z = 0 or imaginary): the derivative is clamped to 128 per component,
// and its normal stays above the horizon.
TEST(HardCasesBump, NormalMapTexelsOnTheRim) {
    Rng rng(102);
    Worst d, below;
    int bad = 0;
    for (int i = 0; i < 20000; ++i) {
        const double r = (i % 8 == 0) ? 1.0 : 0.999 + 0.5 * rng.u(0, 1), a = rng.u(-M_PI, M_PI);
        const g::vec2 m = f2(r * dvec2(std::cos(a), std::sin(a)));
        const bool flipV = i % 2;
        const g::vec2 dv = g::sgTspaceNormalToDeriv(m, flipV);
        const g::vec3 back = g::sgDerivToTspaceNormal(dv, flipV);
        if (!finite2(dv) || !finite3(back)) {
            ++bad;
            continue;
        }
        d.add(maxAbs(dv));
        // Lowest possible z: |d| = 128 sqrt(2), z = 1/sqrt(1 + 2 128^2).
        below.add(1.0 / std::sqrt(1.0 + 2.0 * 128.0 * 128.0) - double(back.z));
    }
    EXPECT_EQ(bad, 0);
    // The clamp of listing 4: m.z^2 >= max(m.x^2, m.y^2) / 128^2, so
    // |d| <= 128 per component (exactly, in binary32).
    hardCaseAtMost("horizon", "L4, normal-map xy on and outside the unit circle (|m| 0.999 to 1.5)",
                   "largest |d| component", d.value, 128.0);
    // The decoded normal's z is at least 1/sqrt(1 + 2 128^2) = 5.5e-3 (up to
    // one rounding of the normalization, 1e-9).
    hardCaseAtMost("horizon", "L4 then its decoder, the same texels",
                   "1/sqrt(1 + 2 128^2) minus the decoded normal's z", below.value, 1e-9);
}

// Listing 1 of gradients from 1e-30 to 1e18 (the domain, SG_BIG): unit
// normals in the direction of n - sg.
TEST(HardCasesBump, ResolveOfHugeAndTinyGradients) {
    Rng rng(103);
    Worst ang, unitErr;
    for (int i = 0; i < 20000; ++i) {
        const dvec3 n = rng.unit();
        const dvec3 s = rng.tangent(n) * rng.logU(-30, 18);
        const g::SgFrame f = frontFrame(f3(n), g::vec3(0.0f), g::vec3(0.0f));
        const g::vec3 r = g::sgResolve(f, f3(s));
        ASSERT_TRUE(finite3(r)) << i;
        unitErr.add(std::fabs(glm::length(d3(r)) - 1.0));
        // The oracle from the binary32 inputs, in double.
        ang.add(angle(d3(r), glm::normalize(d3(f.nrmBase) - d3(f3(s)))));
    }
    // A few roundings of an O(1) direction: 4e-7 rad is ~3 FLT_EPSILON.
    hardCaseAtMost("horizon", "L1, tangent gradients 1e-30 to 1e18 (the result 0 to 90 deg off n)",
                   "angle to normalize(n - sg) in double (rad)", ang.value, 4e-7);
    hardCaseAtMost("horizon", "L1, the same gradients", "| |n'| - 1 |", unitErr.value, 2.4e-7);
}

// ---- grazing views ----------------------------------------------------------

// A perspective camera looking at the plane z = 0 (normal +z) at elevation
// alpha; the analytic screen derivatives of the ray/plane intersection in
// double (an independent derivation: the near and far points of the pixel's
// ray, differentiated as rational functions of the window coordinate).
struct GrazingView {
    glm::dmat4 inv; // screen -> world
    dvec3 pos;      // the point seen at pixel (x, y)
    double x, y;
    double sinAlpha; // |n . ray direction|
    dvec3 dPdx, dPdy;
};

GrazingView grazingView(Rng& rng, double alpha) {
    const double w = 1280, h = 720;
    const double az = rng.u(-M_PI, M_PI);
    const dvec3 fwd(std::cos(alpha) * std::cos(az), std::cos(alpha) * std::sin(az),
                    -std::sin(alpha));
    const dvec3 target(rng.u(-1, 1), rng.u(-1, 1), 0.0);
    const dvec3 eye = target - 5.0 * fwd;
    const glm::dmat4 view = glm::lookAt(eye, target, dvec3(0, 0, 1));
    const glm::dmat4 proj = glm::perspective(glm::radians(60.0), w / h, 0.1, 1000.0);
    glm::dmat4 vp(1.0);
    vp[0][0] = w / 2;
    vp[1][1] = h / 2;
    vp[2][2] = 0.5;
    vp[3] = glm::dvec4(w / 2, h / 2, 0.5, 1);
    GrazingView gv;
    gv.inv = glm::inverse(vp * proj * view);
    gv.x = w / 2 + 0.5;
    gv.y = h / 2 + 0.5;
    const dvec3 n(0, 0, 1);
    // Near point a and far point b of the ray (homogeneous) and their
    // derivatives along x and y: columns 0 and 1 of inv.
    const glm::dvec4 a = gv.inv * glm::dvec4(gv.x, gv.y, 0, 1);
    const glm::dvec4 b = gv.inv * glm::dvec4(gv.x, gv.y, 1, 1);
    const dvec3 A = dvec3(a) / a.w, B = dvec3(b) / b.w;
    const double s = -glm::dot(n, A) / glm::dot(n, B - A);
    gv.pos = A + s * (B - A);
    gv.sinAlpha = std::fabs(glm::dot(n, glm::normalize(B - A)));
    auto deriv = [&](int col) {
        const glm::dvec4 c = gv.inv[col];
        const dvec3 dA = (dvec3(c) * a.w - dvec3(a) * c.w) / (a.w * a.w);
        const dvec3 dB = (dvec3(c) * b.w - dvec3(b) * c.w) / (b.w * b.w);
        const double den = glm::dot(n, B - A);
        const double ds =
            (-glm::dot(n, dA) * den + glm::dot(n, A) * glm::dot(n, dB - dA)) / (den * den);
        return dA + ds * (B - A) + s * (dB - dA);
    };
    gv.dPdx = deriv(0);
    gv.dPdy = deriv(1);
    return gv;
}

g::mat4 f44(const glm::dmat4& m) {
    g::mat4 r;
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) r[c][k] = float(m[c][k]);
    return r;
}

TEST(HardCasesBump, GrazingViews) {
    Rng rng(104);
    // Height on the plane: H = a sin(2 pi 3 s) cos(2 pi 2 t), st = P.xy / 2,
    // in world units; its derivative map has 512^2 texels.
    const double size = 2.0, amp = 0.01;
    const dvec2 texDim(512, 512);
    Worst l17Err, l17Big, l8Err, l8Big, l6Err;
    int bad = 0, l6Zero = 0, grazingRecords = 0;
    for (int i = 0; i < 6000; ++i) {
        // alpha: 10^[-8, 0.19] rad, and exactly 0 (edge-on) for 1 in 32.
        const double alpha = (i % 32 == 0) ? 0.0 : rng.logU(-8, 0.19);
        const GrazingView gv = grazingView(rng, alpha);
        const bool measured = gv.sinAlpha >= 1e-3;
        grazingRecords += !measured;
        // Listing 17 (binary32) against the analytic derivatives.
        g::vec3 dx, dy;
        g::sgScreenDerivOfPos(dx, dy, f3(gv.pos), g::vec3(0, 0, 1), f44(gv.inv), float(gv.x),
                              float(gv.y));
        if (!finite3(dx) || !finite3(dy)) {
            ++bad;
            continue;
        }
        if (measured) {
            l17Err.add(glm::length(d3(dx) - gv.dPdx) / glm::length(gv.dPdx));
            l17Err.add(glm::length(d3(dy) - gv.dPdy) / glm::length(gv.dPdy));
        } else {
            l17Big.add(std::max(maxAbs(dx), maxAbs(dy)));
        }
        // Listing 8 with the exact derivatives rounded to binary32: the
        // normal of the height field, which does not depend on the view.
        const dvec2 st = dvec2(gv.pos) / size;
        const double w1 = 2 * M_PI * 3, w2 = 2 * M_PI * 2;
        const dvec2 dHdST(amp * w1 * std::cos(w1 * st.x) * std::cos(w2 * st.y),
                          -amp * w2 * std::sin(w1 * st.x) * std::sin(w2 * st.y));
        const dvec3 exact = glm::normalize(dvec3(-dHdST.x / size, -dHdST.y / size, 1.0));
        const g::SgFrame f = frontFrame(g::vec3(0, 0, 1), f3(gv.dPdx), f3(gv.dPdy));
        const g::vec2 dSTdx = f2(dvec2(gv.dPdx) / size), dSTdy = f2(dvec2(gv.dPdy) / size);
        const g::vec3 sgr =
            g::sgSurfgradScaleDependent(f, f2(dHdST / texDim), dSTdx, dSTdy, f2(texDim));
        const g::vec3 r = g::sgResolve(f, sgr);
        g::vec3 vT, vB;
        g::sgGenBasisTB(f, f2(st), dSTdx, dSTdy, vT, vB);
        if (!finite3(sgr) || !finite3(r) || !finite3(vT) || !finite3(vB)) {
            ++bad;
            continue;
        }
        if (measured) {
            l8Err.add(angle(d3(r), exact));
            // The per-pixel frame is +x, +y (s = x / 2, t = y / 2).
            if (maxAbs(vT) == 0.0) {
                ++l6Zero;
            } else {
                l6Err.add(std::max(angle(d3(vT), dvec3(1, 0, 0)), angle(d3(vB), dvec3(0, 1, 0))));
            }
        } else {
            l8Big.add(maxAbs(sgr));
        }
    }
    EXPECT_EQ(bad, 0) << "non-finite outputs";
    EXPECT_EQ(l6Zero, 0) << "the frame turned off at a view it should handle";
    EXPECT_GT(grazingRecords, 1000);
    // Listing 17 divides by n.D, the ray's elevation over the plane: the
    // binary32 inputs' relative error (~1e-7) grows as 1/sin(alpha) and
    // with the depth range of the camera; measured 1.1e-4 at sin(alpha) >=
    // 1e-3 (a wrong formula is off by O(1)).
    hardCaseAtMost("grazing", "L17, view 1e-3 to 1.57 rad above a plane (sin)",
                   "relative error of dPdx, dPdy against the analytic derivative", l17Err.value,
                   1e-3);
    // Below that, to edge-on (the exact derivative is infinite there): the
    // clamp of n.D at FLT_EPSILON and sgBoundedScale3 keep them within SG_BIG.
    hardCaseAtMost("grazing", "L17, view 0 to 1e-3 rad above the plane, edge-on included",
                   "largest |dPdx|, |dPdy| component", l17Big.value, 1e18);
    // Listing 8's 1/det of the screen Jacobian, det ~ sin(alpha): the normal's
    // error may grow as FLT_EPSILON / sin(alpha), 1.2e-4 at sin(alpha) =
    // 1e-3; measured 2.4e-8 rad (the binary32 derivatives of one plane stay
    // consistent with each other).
    hardCaseAtMost("grazing", "L8 then L1, view 1e-3 to 1.57 rad above the plane",
                   "angle to the exact normal of the height field (rad)", l8Err.value, 2e-4);
    hardCaseAtMost("grazing", "L8, view 0 to 1e-3 rad above the plane, edge-on included",
                   "largest |sg| component", l8Big.value, 1e18);
    // Listing 6 inverts the UV Jacobian scaled to unit largest entry: the
    // same 1/sin(alpha) conditioning; measured 5.8e-8 rad.
    hardCaseAtMost("grazing", "L6, view 1e-3 to 1.57 rad above the plane",
                   "angle of the per-pixel tangent and bitangent to +s, +t (rad)", l6Err.value,
                   2e-4);
}

// ---- huge and tiny scales ---------------------------------------------------

// The same bumpy surface scaled in world units by s and in texture units by
// k (dPdx * s; dSTdx * k; the scale-dependent height in world units, so its
// derivative per texel is deriv * s / k): the resolved normal must not move.
// TBN-style bumps (listings 6 + 5) do not depend on the metric at all.
TEST(HardCasesBump, HugeAndTinyScales) {
    Rng rng(105);
    Worst l8, l6;
    int bad = 0;
    const double exps[] = {-15, -10, -5, -1, 0, 1, 5, 10, 15};
    for (int i = 0; i < 400; ++i) {
        const dvec3 n = rng.unit();
        const dvec3 e1 = rng.tangent(n), e2 = glm::cross(n, e1);
        // A screen Jacobian and a UV Jacobian with condition numbers below ~4.
        const dvec3 dPdx = 0.01 * (e1 + 0.3 * rng.u(-1, 1) * e2),
                    dPdy = 0.01 * (e2 + 0.3 * rng.u(-1, 1) * e1);
        const dvec2 dSTdx(0.002 * rng.u(0.5, 1.5), 0.0005 * rng.u(-1, 1)),
            dSTdy(0.0005 * rng.u(-1, 1), 0.002 * rng.u(0.5, 1.5));
        const dvec2 deriv(rng.u(-1, 1), rng.u(-1, 1)), texDim(256, 1024);
        auto l8Normal = [&](double s, double k) {
            const g::SgFrame f = frontFrame(f3(n), f3(s * dPdx), f3(s * dPdy));
            return d3(
                g::sgResolve(f, g::sgSurfgradScaleDependent(f, f2(deriv * (s / k)), f2(k * dSTdx),
                                                            f2(k * dSTdy), f2(texDim))));
        };
        auto l6Normal = [&](double s, double k) {
            const g::SgFrame f = frontFrame(f3(n), f3(s * dPdx), f3(s * dPdy));
            g::vec3 vT, vB;
            g::sgGenBasisTB(f, g::vec2(0.0f), f2(k * dSTdx), f2(k * dSTdy), vT, vB);
            return d3(g::sgResolve(f, g::sgSurfgradFromTBN(f2(deriv), vT, vB)));
        };
        const dvec3 ref8 = l8Normal(1, 1), ref6 = l6Normal(1, 1);
        for (double es : exps) {
            for (double ek : exps) {
                const double s = std::pow(10.0, es), k = std::pow(10.0, ek);
                const dvec3 a = l8Normal(s, k), b = l6Normal(s, k);
                if (!std::isfinite(a.x + a.y + a.z + b.x + b.y + b.z)) {
                    ++bad;
                    continue;
                }
                l8.add(angle(a, ref8));
                l6.add(angle(b, ref6));
            }
        }
    }
    EXPECT_EQ(bad, 0);
    // Both functions scale their inputs to unit largest component before
    // any product, so the scales only change roundings: measured 2.7e-7 and
    // 1.75e-7 rad (a wrong exponent anywhere would give O(1)).
    hardCaseAtMost("scales", "L8 then L1, world scale and texture scale each 1e-15 to 1e15",
                   "angle to the normal at scale 1 (rad)", l8.value, 1e-6);
    hardCaseAtMost("scales", "L6 + L5 then L1, world scale and texture scale each 1e-15 to 1e15",
                   "angle to the normal at scale 1 (rad)", l6.value, 1e-6);
    // Below ~1e-19 units per pixel the sigmas' squared length is under
    // FLT_MIN (a denormal a GPU flushes): listing 6 returns the zero frame
    // (documented), the layer adds nothing and nothing is NaN.
    const g::SgFrame tiny =
        frontFrame(g::vec3(0, 0, 1), g::vec3(1e-22f, 0, 0), g::vec3(0, 1e-22f, 0));
    g::vec3 vT, vB;
    g::sgGenBasisTB(tiny, g::vec2(0.5f), g::vec2(1e-3f, 0), g::vec2(0, 1e-3f), vT, vB);
    const double off = std::max(maxAbs(vT), maxAbs(vB));
    EXPECT_EQ(off, 0.0);
    reportHardCase({"scales", "L6 at 1e-22 world units per pixel",
                    "largest |vT|, |vB| component (the zero frame)", "= 0", hardCaseNumber(off)});
}

// ---- collapsed screen footprints and degenerate UVs -------------------------

// A zero-area pixel: dPdy = c dPdx (c in [-2, 2], 0 included), or both zero,
// optionally with a relative perturbation of 1e-9 to 1e-3. Every function
// that inverts the screen or UV Jacobian stays finite and within SG_BIG,
// and the frame's orientation sign is exactly +-1.
TEST(HardCasesBump, CollapsedScreenFootprints) {
    Rng rng(106);
    Worst big;
    int bad = 0;
    for (int i = 0; i < 20000; ++i) {
        const dvec3 n = rng.unit();
        const double scale = rng.logU(-20, 15);
        const dvec3 dx = (i % 10 == 0) ? dvec3(0) : rng.unit() * scale;
        const double c = (i % 7 == 0) ? 0.0 : rng.u(-2, 2);
        const double pert = (i % 3 == 0) ? 0.0 : rng.logU(-9, -3);
        const dvec3 dy = c * dx + pert * scale * rng.unit();
        const g::SgFrame f = frontFrame(f3(n), f3(dx), f3(dy));
        const dvec2 st(rng.u(-1, 1), rng.u(-1, 1));
        const g::vec2 dSTdx = f2(st * rng.logU(-6, 0)),
                      dSTdy = f2(dvec2(rng.u(-1, 1), rng.u(-1, 1)) * 1e-3);
        const g::vec3 a =
            g::sgSurfgradScaleDependent(f, g::vec2(0.3f, -0.7f), dSTdx, dSTdy, g::vec2(512, 512));
        const g::vec3 b = g::sgSurfgradFromScreenDeriv(f, g::vec2(0.2f, 0.1f));
        const g::vec2 p = g::sgProjectVecToTextureSpace(f, f3(glm::normalize(n + rng.unit())),
                                                        dSTdx, dSTdy, 0.05f, i % 2);
        const g::vec3 o = g::sgTexSpaceOffsToSurface(f, dSTdx, dSTdy, g::vec2(0.01f, -0.02f));
        g::vec3 vT, vB;
        g::sgGenBasisTB(f, f2(st), dSTdx, dSTdy, vT, vB);
        const g::vec3 r = g::sgResolve(f, a + b);
        const bool ok = finite3(a) && finite3(b) && finite2(p) && finite3(o) && finite3(vT) &&
                        finite3(vB) && finite3(r) && (f.flipSign == 1.0f || f.flipSign == -1.0f) &&
                        std::fabs(glm::length(d3(r)) - 1.0) <= 2.4e-7;
        bad += !ok;
        big.add(std::max({maxAbs(a), maxAbs(b), maxAbs(p), maxAbs(o)}));
    }
    EXPECT_EQ(bad, 0);
    reportHardCase({"zero-area",
                    "L16, L8, L8 screen-space, L10, L11, L6, L1 on a zero-area pixel "
                    "(dPdy = c dPdx or both zero, perturbed by 0 to 1e-3)",
                    "records with a non-finite output, a sign not +-1 or a non-unit resolve", "0",
                    std::to_string(bad)});
    // Listings 8, 10, 11 clamp 1/det at FLT_EPSILON relative to the scale and
    // keep results within SG_BIG (sgBoundedScale3).
    hardCaseAtMost("zero-area", "L8, L10, L11 on the same pixels", "largest output component",
                   big.value, 1e18);
}

// The chart weight of sgGenBasisTB (sg/surfgrad.glsl, sgChartWeight),
// evaluated here in double from the binary32 inputs: smoothstep from 4 to
// 32 of |det J| / (k * 2^-22 (max|st| + 16 k)) times smoothstep from 2^-10
// to 2^-7 of the chart's shape on the surface, 2 |det M| / |M|_F^2 for the
// map M from the triangle's plane to (s, t): M = J S^-1, S the position's
// screen derivatives in an orthonormal basis of their plane.
double chartWeight(const g::SgFrame& f, const g::vec2& st, const g::vec2& a, const g::vec2& b) {
    const double k = std::max({std::fabs(double(a.x)), std::fabs(double(a.y)),
                               std::fabs(double(b.x)), std::fabs(double(b.y))});
    if (!(k > 0.0)) return 0.0;
    const double det = (double(a.x) * b.y - double(a.y) * b.x) / (k * k);
    const double noise = std::ldexp(1.0, -22) *
                         (std::max(std::fabs(double(st.x)), std::fabs(double(st.y))) + 16 * k);
    auto smooth = [](double lo, double hi, double x) {
        const double u = std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
        return u * u * (3.0 - 2.0 * u);
    };
    const dvec3 sx = d3(f.dPdx), sy = d3(f.dPdy);
    const dvec3 e1 = glm::normalize(sx), e2 = glm::normalize(glm::cross(glm::cross(sx, sy), e1));
    const glm::dmat2 S(glm::dot(sx, e1), glm::dot(sx, e2), glm::dot(sy, e1), glm::dot(sy, e2));
    const glm::dmat2 J(double(a.x), double(a.y), double(b.x), double(b.y));
    const glm::dmat2 M = J * glm::inverse(S);
    const double frob =
        M[0][0] * M[0][0] + M[0][1] * M[0][1] + M[1][0] * M[1][0] + M[1][1] * M[1][1];
    const double shape = 2.0 * std::fabs(glm::determinant(M)) / frob;
    return smooth(4.0, 32.0, std::fabs(det) * k / noise) *
           smooth(std::ldexp(1.0, -10), std::ldexp(1.0, -7), shape);
}

// Listing 6 with parallel UV derivatives (dSTdy = c dSTdx (1 + delta)) at
// texture coordinates of magnitude 1e-3 to 1e4: the frame is orthogonal,
// tangent, and as long as the chart's weight (1 on charts whose determinant
// is well above its rounding, 0 where it is rounding noise, continuous
// between); exactly parallel derivatives give the zero frame.
TEST(HardCasesBump, DegenerateUvJacobians) {
    Rng rng(107);
    Worst weightErr, tangentErr, orthoErr;
    int parallelNonZero = 0, zeros = 0, partial = 0, full = 0;
    const double deltas[] = {0.0, 1e-9, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-1};
    for (int i = 0; i < 16000; ++i) {
        const dvec3 n = rng.unit(), e1 = rng.tangent(n), e2 = glm::cross(n, e1);
        const dvec3 dPdx = 0.01 * e1, dPdy = 0.01 * (e2 + 0.2 * e1);
        const g::SgFrame f = frontFrame(f3(n), f3(dPdx), f3(dPdy));
        const double delta = deltas[i % 8];
        const dvec2 a = dvec2(rng.u(-1, 1), rng.u(-1, 1)) * rng.logU(-8, 3);
        const double c = (i % 11 == 0) ? 0.0 : rng.u(-3, 3);
        const dvec2 b = c * a + delta * glm::length(a) * dvec2(rng.u(-1, 1), rng.u(-1, 1));
        const g::vec2 st = f2(dvec2(rng.u(-1, 1), rng.u(-1, 1)) * rng.logU(-3, 4));
        g::vec3 vT, vB;
        g::sgGenBasisTB(f, st, f2(a), f2(b), vT, vB);
        ASSERT_TRUE(finite3(vT) && finite3(vB)) << i;
        const double w = chartWeight(f, st, f2(a), f2(b));
        const double lt = glm::length(d3(vT)), lb = glm::length(d3(vB));
        // The weight in binary32 against double: the determinant of the
        // scaled Jacobian carries its rounding relative to its largest
        // product (2^-23 relative), which the weight amplifies by its
        // slope (at most 1.5 / 28 per unit, units ~ det * 2^18): up to ~3e-3
        // at the steepest point; measured below.
        weightErr.add(std::max(std::fabs(lt - w), std::fabs(lb - w)));
        if (lt > 0.0) {
            tangentErr.add(std::max(std::fabs(glm::dot(d3(vT), d3(f.nrmBase))),
                                    std::fabs(glm::dot(d3(vB), d3(f.nrmBase)))) /
                           lt);
            orthoErr.add(std::fabs(glm::dot(d3(vT), d3(vB))) / (lt * lb));
        }
        if (delta == 0.0 && lt > 0.0) ++parallelNonZero;
        zeros += lt == 0.0;
        full += w == 1.0;
        partial += w > 0.0 && w < 1.0;
    }
    EXPECT_GT(zeros, 1000);
    EXPECT_GT(full, 500);
    EXPECT_GT(partial, 100);
    EXPECT_EQ(parallelNonZero, 0);
    reportHardCase({"uv-degenerate",
                    "L6, dSTdy = c dSTdx exactly (c in [-3, 3]), |st| 1e-3 to 1e4, scales 1e-8 "
                    "to 1e3",
                    "frames that are not zero", "0", std::to_string(parallelNonZero)});
    hardCaseAtMost(
        "uv-degenerate", "L6, dSTdy = c dSTdx (1 + delta), delta 0 to 0.1, the same st and scales",
        "| |vT| - w |, | |vB| - w | (w: the chart weight in double)", weightErr.value, 4e-3);
    // One projection, then a scale by the weight: a few roundings of the
    // unit tangent (measured 1e-7 before the weight existed).
    hardCaseAtMost("uv-degenerate", "the same records, non-zero frames",
                   "|vT . n| / |vT|, |vB . n| / |vB|", tangentErr.value, 4.8e-7);
    hardCaseAtMost("uv-degenerate", "the same records, non-zero frames", "|vT . vB| / (|vT| |vB|)",
                   orthoErr.value, 4.8e-7);
}

// ---- decals parallel to the surface -----------------------------------------

// Section 2.9: a decal whose projector plane is parallel to the surface
// (axis z along +-n) is a TBN-style bump with T = axis x, B = axis y; one
// whose projection direction lies in the surface (axis z perpendicular to
// n) keeps only the tangential part of its volume gradient, which is never
// longer than the map's derivative.
TEST(HardCasesBump, DecalsParallelToTheSurface) {
    Rng rng(108);
    Worst tbnDiff, grow, normalPart;
    for (int i = 0; i < 20000; ++i) {
        const dvec3 n = rng.unit();
        const g::SgFrame f = frontFrame(f3(n), g::vec3(0.0f), g::vec3(0.0f));
        const dvec2 d(rng.u(-2, 2), rng.u(-2, 2));
        const bool upperLeft = i % 2;
        // Plane parallel: axis x, y in the tangent plane (any rotation),
        // axis z = +-n.
        const dvec3 x = rng.tangent(n), y = glm::cross(n, x) * (i % 3 == 0 ? -1.0 : 1.0);
        const g::vec3 dec = g::sgSurfgradFromDecal(f, f2(d), f3(x), f3(y), upperLeft);
        const g::vec3 tbn =
            g::sgSurfgradFromTBN(f2(dvec2(d.x, upperLeft ? -d.y : d.y)), f3(x), f3(y));
        tbnDiff.add(glm::length(d3(dec) - d3(tbn)) / std::max(1.0, glm::length(d)));
        // Projection direction in the surface: z tangent, so x or y (or a mix)
        // leaves the tangent plane.
        const dvec3 z = rng.tangent(n);
        const double rot = rng.u(-M_PI, M_PI);
        const dvec3 u = glm::cross(z, n); // tangent, perpendicular to z
        const dvec3 x2 = std::cos(rot) * n + std::sin(rot) * u, y2 = glm::cross(z, x2);
        const g::vec3 edge = g::sgSurfgradFromDecal(f, f2(d), f3(x2), f3(y2), upperLeft);
        grow.add(glm::length(d3(edge)) / glm::length(d) - 1.0);
        normalPart.add(std::fabs(glm::dot(d3(edge), n)) / glm::length(d));
    }
    // The same products and sums as listing 5 plus a projection that removes
    // a component of rounding size: measured 1.7e-7 relative.
    hardCaseAtMost("decals-parallel", "L15, projector plane parallel to the surface (axis z = +-n)",
                   "|decal sg - TBN sg (T = axis x, B = axis y)| / max(1, |d|)", tbnDiff.value,
                   1e-6);
    // Listing 12's projection is an orthogonal projection: it cannot grow
    // the gradient (up to roundings, 3e-7 relative).
    hardCaseAtMost("decals-parallel",
                   "L15, projection direction in the surface (axis z perpendicular to n)",
                   "|sg| / |d| - 1", grow.value, 1e-6);
    hardCaseAtMost("decals-parallel", "L15, the same projectors", "|sg . n| / |d|",
                   normalPart.value, 1e-6);
}

// ---- triplanar at equal weights ---------------------------------------------

// Listing 14 at the diagonals n = (+-1, +-1, +-1)/sqrt(3), where the three
// planes weigh the same, for sharpness 0.01 to 316, and listing 13's
// gradient there: the projection of the average of the three planar
// gradients (eq. 7 with w = 1/3), computed in double.
TEST(HardCasesBump, TriplanarAtEqualWeights) {
    Rng rng(109);
    Worst wErr, sumErr, gErr, jump;
    const double ks[] = {0.01, 1, 3, 8, 64, 316};
    for (int i = 0; i < 12000; ++i) {
        const dvec3 n = glm::normalize(dvec3(i & 1 ? -1 : 1, i & 2 ? -1 : 1, i & 4 ? -1 : 1));
        const double k = ks[(i / 8) % 6];
        const g::vec3 w = g::sgTriplanarWeights(f3(n), float(k));
        for (int c = 0; c < 3; ++c) wErr.add(std::fabs(double(w[c]) - 1.0 / 3.0));
        sumErr.add(std::fabs(double(w.x) + double(w.y) + double(w.z) - 1.0));
        // Continuity through the equal-weight point: a step of 1e-6 rad
        // changes each weight by at most ~k * 1e-6 (dw/dn is bounded by
        // k / (3 (|n_i| - 0.2)) near the diagonal).
        const dvec3 n2 = glm::normalize(n + 1e-6 * rng.unit());
        const g::vec3 w2 = g::sgTriplanarWeights(f3(n2), float(k));
        jump.add(maxAbs(w2 - w) / std::max(1.0, k));
        // The surface gradient at equal weights.
        const dvec2 dX(rng.u(-1, 1), rng.u(-1, 1)), dY(rng.u(-1, 1), rng.u(-1, 1)),
            dZ(rng.u(-1, 1), rng.u(-1, 1));
        const bool rh = i % 3 == 0, ul = i % 5 == 0;
        const g::SgFrame f = frontFrame(f3(n), g::vec3(0.0f), g::vec3(0.0f));
        const g::vec3 sgr = g::sgSurfgradFromTriplanar(f, w, f2(dX), f2(dY), f2(dZ), rh, ul);
        // Eq. 7 (section 2.8): x plane sampled at (z, y), y plane at (x, z),
        // z plane at (x, y); the second coordinate flips for an upper-left
        // origin, z flips for a right-handed frame.
        const double v = ul ? -1.0 : 1.0;
        dvec3 grad = (1.0 / 3.0) * dvec3(dZ.x + dY.x, v * (dZ.y + dX.y), dX.x + v * dY.y);
        if (rh) grad.z = -grad.z;
        const dvec3 oracle = grad - glm::dot(grad, n) * n;
        gErr.add(glm::length(d3(sgr) - oracle) / std::max(1.0, glm::length(oracle)));
    }
    // w = b^k / sum b^k with equal b: 1/3 in binary32 (the diagonal's three
    // components round alike; measured 9.9e-9, the rounding of 1/3).
    hardCaseAtMost("triplanar-equal", "L14 at n = (+-1, +-1, +-1)/sqrt(3), sharpness 0.01 to 316",
                   "|w_i - 1/3|", wErr.value, 1e-6);
    hardCaseAtMost("triplanar-equal", "L14, the same normals", "|w.x + w.y + w.z - 1|",
                   sumErr.value, 4.8e-7);
    hardCaseAtMost("triplanar-equal", "L14, a 1e-6 rad step through the equal-weight point",
                   "largest weight change / max(1, k)", jump.value, 1e-5);
    // A weighted sum and a projection: a few ulps (measured 1.25e-7).
    hardCaseAtMost("triplanar-equal", "L13 with L14 weights at the diagonals",
                   "|sg - projected average of the planar gradients| / max(1, |sg|)", gErr.value,
                   1e-6);
    // No component above 0.2 (a normal far from unit length): equal weights
    // by definition.
    const g::vec3 w0 = g::sgTriplanarWeights(g::vec3(0.1f, -0.15f, 0.05f), 4.0f);
    const double off = maxAbs(w0 - g::vec3(1.0f / 3.0f));
    EXPECT_EQ(off, 0.0);
    reportHardCase({"triplanar-equal", "L14, a normal with no component above 0.2",
                    "largest |w_i - 1/3|", "= 0", hardCaseNumber(off)});
}

// ---- far from the origin ----------------------------------------------------

// Listing 17 is defined on positions relative to the camera (listing 16's
// "relative world position"). Fed WORLD positions of geometry at distance D
// from the origin instead, its inputs carry binary32 rounding of size
// D * 6e-8: the derivatives degrade with D. This measures by how much, with
// the camera 5 units from the surface.
TEST(HardCasesBump, ScreenDerivativesFarFromTheOrigin) {
    Rng rng(110);
    const double distances[] = {1e2, 1e3, 1e4};
    Worst rel[3];
    for (int i = 0; i < 3000; ++i) {
        const double w = 1280, h = 720;
        const dvec3 fwd = rng.unit();
        const dvec3 dir = rng.unit();
        const dvec3 target = 5.0 * fwd; // relative to the eye
        dvec3 n = rng.unit();
        if (glm::dot(n, -fwd) < 0.3) n = glm::normalize(n - 2.0 * glm::dot(n, fwd) * fwd);
        if (glm::dot(n, -fwd) < 0.3) continue;
        const glm::dmat4 proj = glm::perspective(glm::radians(50.0), w / h, 0.1, 100.0);
        glm::dmat4 vp(1.0);
        vp[0][0] = w / 2;
        vp[1][1] = h / 2;
        vp[2][2] = 0.5;
        vp[3] = glm::dvec4(w / 2, h / 2, 0.5, 1);
        const dvec3 up = std::fabs(fwd.z) < 0.9 ? dvec3(0, 0, 1) : dvec3(1, 0, 0);
        const float x = float(w / 2 + 0.5), y = float(h / 2 + 0.5);
        // Camera-relative: eye at the origin of the space.
        const glm::dmat4 invRel = glm::inverse(vp * proj * glm::lookAt(dvec3(0), fwd, up));
        g::vec3 rx, ry;
        g::sgScreenDerivOfPos(rx, ry, f3(target), f3(n), f44(invRel), x, y);
        // The reference: the same in double (an analytic intersection is not
        // needed: the camera-relative binary32 result is the well-conditioned
        // one, checked against finite differences in known_answers_test).
        for (int k = 0; k < 3; ++k) {
            const dvec3 eye = distances[k] * dir;
            const glm::dmat4 inv = glm::inverse(vp * proj * glm::lookAt(eye, eye + fwd, up));
            g::vec3 dx, dy;
            g::sgScreenDerivOfPos(dx, dy, f3(eye + target), f3(n), f44(inv), x, y);
            ASSERT_TRUE(finite3(dx) && finite3(dy));
            rel[k].add(glm::length(d3(dx) - d3(rx)) / glm::length(d3(rx)));
        }
    }
    // Growth: the position's rounding D * 6e-8 relative to the 5 units to
    // the camera, amplified by the perspective (far/near 1000) and
    // 1/(n.v) <= 3.3; measured 7.7e-4, 0.0115 and 0.07 at D = 1e2, 1e3,
    // 1e4 (at 1e5 no digit is left: 2.05). The bounds are the measured
    // values times ~2.5: the renderer must give the shared functions
    // camera-relative positions.
    const double bounds[] = {2e-3, 3e-2, 0.2};
    for (int k = 0; k < 3; ++k) {
        hardCaseAtMost("far-from-origin",
                       "L17 with world positions " + hardCaseNumber(distances[k]) +
                           " from the origin, camera 5 away",
                       "relative difference of dPdx to the camera-relative result", rel[k].value,
                       bounds[k]);
    }
}

} // namespace
