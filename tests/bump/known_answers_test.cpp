// Known answers for the shared bump math (shaders/sg/*.glsl as C++ through
// surfgrad/bump/core.h), each computed INDEPENDENTLY in double inside this file:
//  - Blinn 1978: the perturbed normal of a height h(u, v) on an analytic
//    surface is normalize(cross(P_u + h_u n, P_v + h_v n)); the framework
//    (Mikkelsen 2019 eq. 1 with listing 8's surface gradient) must match it
//    on a plane, a sphere and a torus;
//  - Mikkelsen 2019 appendix: a volume bump (L12) and a 2D bump (L8) of the
//    same height distribution give the same surface gradient, and two UV
//    parametrizations of the same heights give the same normal (L8 for
//    affine reparametrizations, L6 GenBasisTB + L5 for isometric ones);
//  - eq. 2-3 linearity (k layers = summed height), L7 round trip, section
//    2.2 mikktspace compliance, section 2.10 double-sided modes, listing 17
//    against finite differences of a real projection;
//  - Loviscach 2008 "Feeding": scale (alpha = -1 inverts, alpha = 2 never
//    turns inward), modulate (product rule), curves (chain rule), deform
//    (warp Jacobian), masked blend (product rule), each against finite
//    differences; central differences of a height, a curve through points
//    (cubic Hermite) against its closed form;
//  - "Care: Antialiasing": LEAN moments and covariance of a known set of
//    slopes, Toksvig's variance of a known average normal.
// Tolerances: the shared code runs in binary32; each comparison states the
// precision it expects and why.
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <functional>
#include <random>

#include "hardcase.h"
#include "surfgrad/bump/core.h"

namespace {

namespace g = sg::glsl;
using dvec2 = glm::dvec2;
using dvec3 = glm::dvec3;

g::vec3 f3(const dvec3& v) {
    return g::vec3(float(v.x), float(v.y), float(v.z));
}
g::vec2 f2(const dvec2& v) {
    return g::vec2(float(v.x), float(v.y));
}
dvec3 d3(const g::vec3& v) {
    return dvec3(v.x, v.y, v.z);
}

// Angle between two directions in radians (robust for tiny angles).
double angle(const dvec3& a, const dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// A binary32 unit vector is good to ~1e-7 rad per component; the framework
// path runs ~30 binary32 operations on inputs of magnitude ~1-10, so 5e-6 rad
// (about 40 ulps) bounds rounding with margin while any formula error (wrong
// sign, missing term, wrong metric) shows up at 1e-2 rad or more.
constexpr double kAngleTol = 5e-6;

// ---- analytic surfaces: P(u, v), P_u, P_v in double -------------------------
struct SurfacePoint {
    dvec3 p, pu, pv;
};
using Surface = std::function<SurfacePoint(double u, double v)>;

SurfacePoint plane(double u, double v) {
    // A tilted, sheared plane: P = o + u a + v b.
    const dvec3 a(1.0, 0.2, 0.1), b(-0.3, 0.8, 0.4);
    return {dvec3(0.5, -1, 2) + u * a + v * b, a, b};
}
SurfacePoint sphere(double u, double v) {
    // Longitude u, latitude v, radius 2.
    const double r = 2.0;
    dvec3 p(r * std::cos(v) * std::cos(u), r * std::cos(v) * std::sin(u), r * std::sin(v));
    dvec3 pu(-r * std::cos(v) * std::sin(u), r * std::cos(v) * std::cos(u), 0);
    dvec3 pv(-r * std::sin(v) * std::cos(u), -r * std::sin(v) * std::sin(u), r * std::cos(v));
    return {p, pu, pv};
}
SurfacePoint torus(double u, double v) {
    const double R = 3.0, r = 1.0;
    const double w = R + r * std::cos(v);
    dvec3 p(w * std::cos(u), w * std::sin(u), r * std::sin(v));
    dvec3 pu(-w * std::sin(u), w * std::cos(u), 0);
    dvec3 pv(-r * std::sin(v) * std::cos(u), -r * std::sin(v) * std::sin(u), r * std::cos(v));
    return {p, pu, pv};
}

// Height over (u, v) and its analytic partials.
struct Height {
    double a, fu, fv, phase;
    double h(double u, double v) const { return a * std::sin(fu * u + phase) * std::cos(fv * v); }
    dvec2 grad(double u, double v) const {
        return {a * fu * std::cos(fu * u + phase) * std::cos(fv * v),
                -a * fv * std::sin(fu * u + phase) * std::sin(fv * v)};
    }
};

// Blinn 1978, exact: the normal of the displaced surface P + h n with the
// h n_u, h n_v terms dropped (Blinn's approximation, which eq. 1 reproduces).
dvec3 blinnNormal(const SurfacePoint& s, const dvec2& hGrad) {
    dvec3 n = glm::normalize(glm::cross(s.pu, s.pv));
    return glm::normalize(glm::cross(s.pu + hGrad.x * n, s.pv + hGrad.y * n));
}

// The framework's 2D scale-dependent bump (listing 8) at a surface point
// whose (u, v) are a texture coordinate st = (u, v) / uvPeriod of a map of
// texDim texels, seen through a screen Jacobian J = d(u, v)/d(x, y).
g::vec3 frameworkSurfgrad2D(const SurfacePoint& s, const dvec2& hGrad, const glm::dmat2& J,
                            const dvec2& uvPeriod, const dvec2& texDim, g::SgFrame* outFrame) {
    const dvec3 dPdx = s.pu * J[0][0] + s.pv * J[0][1];
    const dvec3 dPdy = s.pu * J[1][0] + s.pv * J[1][1];
    g::SgFrame f =
        g::sgPrologue(f3(glm::cross(s.pu, s.pv)), f3(dPdx), f3(dPdy), true, SG_BFACE_NONE);
    // st = uv / period: dST/dx = J col 0 / period; dH/d(texel) = dH/du * period / texDim.
    const dvec2 dSTdx = dvec2(J[0][0], J[0][1]) / uvPeriod;
    const dvec2 dSTdy = dvec2(J[1][0], J[1][1]) / uvPeriod;
    const dvec2 derivPerTexel = hGrad * uvPeriod / texDim;
    if (outFrame) *outFrame = f;
    return g::sgSurfgradScaleDependent(f, f2(derivPerTexel), f2(dSTdx), f2(dSTdy), f2(texDim));
}

TEST(KnownAnswers, ResolvedNormalEqualsBlinnOnPlaneSphereTorus) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> U(-1, 1);
    const std::pair<const char*, Surface> surfaces[] = {
        {"plane", plane}, {"sphere", sphere}, {"torus", torus}};
    for (const auto& [name, surf] : surfaces) {
        double worst = 0;
        for (int i = 0; i < 2000; ++i) {
            const double u = U(rng) * 3, v = U(rng) * 1.4; // sphere: away from the poles
            const Height hgt{0.3 + 0.2 * U(rng), 2 + U(rng), 3 + U(rng), U(rng)};
            const SurfacePoint s = surf(u, v);
            const dvec2 hg = hgt.grad(u, v);
            // A screen Jacobian d(u, v)/d(x, y) with condition number <= 6:
            // a near-singular one (the surface seen edge-on) is a conditioning
            // question the parity suite covers, not a formula check.
            const glm::dmat2 J(0.01 * (1 + 0.5 * U(rng)), 0.003 * U(rng), 0.003 * U(rng),
                               0.01 * (1 + 0.5 * U(rng)));
            g::SgFrame f;
            const g::vec3 sgr = frameworkSurfgrad2D(s, hg, J, dvec2(2.0, 3.0), dvec2(512, 256), &f);
            const dvec3 n = d3(g::sgResolve(f, sgr));
            const double a = angle(n, blinnNormal(s, hg));
            worst = std::max(worst, a);
            ASSERT_LT(a, kAngleTol) << name << " u=" << u << " v=" << v;
        }
        RecordProperty(std::string(name) + "_max_angle_rad", std::to_string(worst));
    }
}

TEST(KnownAnswers, VolumeAndTwoDBumpGiveTheSameSurfaceGradient) {
    // H(x, y, z) on the sphere; the 2D map is its restriction h = H o P.
    auto H = [](const dvec3& p) {
        return 0.4 * std::sin(1.3 * p.x) * std::cos(0.7 * p.y) + 0.2 * p.z * p.z;
    };
    auto gradH = [](const dvec3& p) {
        return dvec3(0.4 * 1.3 * std::cos(1.3 * p.x) * std::cos(0.7 * p.y),
                     -0.4 * 0.7 * std::sin(1.3 * p.x) * std::sin(0.7 * p.y), 0.4 * p.z);
    };
    (void)H;
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int i = 0; i < 2000; ++i) {
        const double u = U(rng) * 3, v = U(rng) * 1.3;
        const SurfacePoint s = sphere(u, v);
        const dvec3 gH = gradH(s.p);
        const dvec2 hg(glm::dot(gH, s.pu), glm::dot(gH, s.pv)); // chain rule
        const dvec3 n = glm::normalize(glm::cross(s.pu, s.pv));
        const dvec3 oracle = gH - glm::dot(gH, n) * n; // surface gradient (projection)
        const glm::dmat2 J(0.02, 0.005, -0.004, 0.015);
        g::SgFrame f;
        const dvec3 sg2d = d3(frameworkSurfgrad2D(s, hg, J, dvec2(1, 1), dvec2(1024, 1024), &f));
        const dvec3 sgVol = d3(g::sgSurfgradFromVolumeGradient(f, f3(gH)));
        // Both are O(1) vectors computed from binary32 inputs: 1e-5 absolute
        // is ~100 ulps, far below the size of any formula error.
        const double scale = std::max(1.0, glm::length(oracle));
        ASSERT_LT(glm::length(sg2d - oracle) / scale, 1e-5) << i;
        ASSERT_LT(glm::length(sgVol - oracle) / scale, 1e-5) << i;
        ASSERT_LT(glm::length(sg2d - sgVol) / scale, 1e-5) << i;
    }
}

TEST(KnownAnswers, ParametrizationIndependenceScaleDependent) {
    // The same heights through two affine UV layouts (u2, v2) = A (u, v) + c
    // with a non-similar A (shear, anisotropic scale, mirror): listing 8 must
    // give the same normal.
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    sg::test::Worst worst;
    for (int i = 0; i < 1000; ++i) {
        const double u = U(rng) * 3, v = U(rng) * 1.2;
        const SurfacePoint s = torus(u, v);
        const Height hgt{0.5, 2.0, 3.0, 0.3};
        const dvec2 hg = hgt.grad(u, v);
        glm::dmat2 A(1.5 + 0.3 * U(rng), 0.4 * U(rng), 0.4 * U(rng),
                     -0.7 + 0.2 * U(rng)); // mirrored
        // Layout 2: P2(u2, v2) = P(A^-1 (u2 - c)): P2_u2 = [P_u P_v] A^-1 columns, and the
        // height gradient transforms with A^-T.
        const glm::dmat2 Ai = glm::inverse(A);
        SurfacePoint s2{s.p, s.pu * Ai[0][0] + s.pv * Ai[0][1], s.pu * Ai[1][0] + s.pv * Ai[1][1]};
        const dvec2 hg2 = glm::transpose(Ai) * hg;
        const glm::dmat2 J(0.01, 0.002, -0.003, 0.012); // d(u,v)/d(x,y)
        const glm::dmat2 J2 = A * J;                    // d(u2,v2)/d(x,y)
        g::SgFrame f1, f2f;
        const g::vec3 sg1 = frameworkSurfgrad2D(s, hg, J, dvec2(1.0, 2.0), dvec2(256, 512), &f1);
        const g::vec3 sg2 =
            frameworkSurfgrad2D(s2, hg2, J2, dvec2(3.0, 0.5), dvec2(2048, 64), &f2f);
        // Layout 2 is mirrored: its geometric normal flips, so resolve both
        // against the same base normal (the surface's).
        const dvec3 n1 = d3(g::sgResolve(f1, sg1));
        const dvec3 n2 = d3(g::sgResolve(f1, sg2));
        ASSERT_LT(angle(n1, n2), kAngleTol) << i;
        ASSERT_LT(angle(n1, blinnNormal(s, hg)), kAngleTol) << i;
        worst.add(angle(n1, n2));
    }
    sg::test::reportHardCase({"uv-mirrored",
                              "L8 on a torus, a second UV layout (u2, v2) = A (u, v) + c with a "
                              "mirroring, shearing, anisotropic A",
                              "angle between the two layouts' normals (rad)",
                              "<= " + sg::test::hardCaseNumber(kAngleTol),
                              sg::test::hardCaseNumber(worst.value)});
}

TEST(KnownAnswers, ParametrizationIndependenceGenBasisTB) {
    // TBN-style bump with the per-pixel basis (L6 + L5) on a plane whose UV
    // layout is isometric (st = rotation/reflection of plane coordinates, the
    // case where TBN-style and scale-dependent bump coincide). Two layouts
    // rotated and mirrored against each other give the same normal.
    const dvec3 e1 = glm::normalize(dvec3(1, 0.3, -0.2));
    const dvec3 e2 = glm::normalize(glm::cross(dvec3(0.1, 0.2, 1), e1));
    const dvec3 n = glm::cross(e1, e2);
    const Height hgt{0.4, 2.5, 1.5, 0.2}; // h over plane coordinates (a, b)
    std::mt19937_64 rng(4);
    std::uniform_real_distribution<double> U(-1, 1);
    sg::test::Worst worstRotated, worstMirrored;
    for (int i = 0; i < 1000; ++i) {
        const double pa = U(rng) * 4, pb = U(rng) * 4;
        const dvec2 hg = hgt.grad(pa, pb); // dh/d(a, b)
        // Screen Jacobian d(a, b)/d(x, y).
        const glm::dmat2 J(0.01 + 0.005 * U(rng), 0.004 * U(rng), 0.004 * U(rng),
                           0.01 + 0.005 * U(rng));
        const dvec3 dPdx = e1 * J[0][0] + e2 * J[0][1], dPdy = e1 * J[1][0] + e2 * J[1][1];
        g::SgFrame f = g::sgPrologue(f3(n), f3(dPdx), f3(dPdy), true, SG_BFACE_NONE);
        dvec3 normals[2];
        for (int layout = 0; layout < 2; ++layout) {
            // st = R (a, b): rotation by theta, mirrored for layout 1.
            const double th = layout ? 2.1 : -0.4;
            glm::dmat2 R(std::cos(th), std::sin(th), -std::sin(th), std::cos(th));
            if (layout) R = R * glm::dmat2(1, 0, 0, -1);
            const dvec2 dSTdx = R * dvec2(J[0][0], J[0][1]), dSTdy = R * dvec2(J[1][0], J[1][1]);
            const dvec2 dHdST = glm::transpose(glm::inverse(R)) * hg; // = R hg (orthogonal)
            g::vec3 t, b;
            g::sgGenBasisTB(f, g::vec2(0.5f), f2(dSTdx), f2(dSTdy), t, b);
            normals[layout] = d3(g::sgResolve(f, g::sgSurfgradFromTBN(f2(dHdST), t, b)));
        }
        const dvec3 oracle = glm::normalize(n - (hg.x * e1 + hg.y * e2));
        ASSERT_LT(angle(normals[0], oracle), kAngleTol) << i;
        ASSERT_LT(angle(normals[1], oracle), kAngleTol) << i;
        worstRotated.add(angle(normals[0], oracle));
        worstMirrored.add(angle(normals[1], oracle));
    }
    sg::test::reportHardCase({"uv-mirrored", "L6 + L5 on a plane, UVs rotated (not mirrored)",
                              "angle to the exact normal (rad)",
                              "<= " + sg::test::hardCaseNumber(kAngleTol),
                              sg::test::hardCaseNumber(worstRotated.value)});
    sg::test::reportHardCase({"uv-mirrored", "L6 + L5 on a plane, UVs rotated and mirrored",
                              "angle to the exact normal (rad)",
                              "<= " + sg::test::hardCaseNumber(kAngleTol),
                              sg::test::hardCaseNumber(worstMirrored.value)});
}

TEST(KnownAnswers, LayersAddLikeHeights) {
    // k = 4 layers with bump scales s_i: the resolve of sum s_i sg_i equals
    // Blinn's normal of the summed height sum s_i h_i.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int i = 0; i < 1000; ++i) {
        const double u = U(rng) * 3, v = U(rng) * 1.2;
        const SurfacePoint s = sphere(u, v);
        const glm::dmat2 J(0.01, 0.002, -0.003, 0.012);
        g::vec3 sum(0.0f);
        dvec2 sumGrad(0);
        g::SgFrame f;
        for (int k = 0; k < 4; ++k) {
            const Height hk{0.2 + 0.1 * k, 1.0 + k, 2.0 - 0.3 * k, 0.5 * k};
            const double scale = 1.5 * U(rng);
            const dvec2 gk = hk.grad(u, v);
            sumGrad += scale * gk;
            sum += g::sgBumpScale(float(scale),
                                  frameworkSurfgrad2D(s, gk, J, dvec2(1, 1), dvec2(256, 256), &f));
        }
        ASSERT_LT(angle(d3(g::sgResolve(f, sum)), blinnNormal(s, sumGrad)), kAngleTol) << i;
    }
}

TEST(KnownAnswers, PerturbedNormalRoundTrip) {
    // gradient -> resolve -> L7 -> the same gradient. The gradient is any
    // tangent vector with |sg| <= 10 (the resolved normal then stays >= 5.7
    // degrees above the horizon, where L7's 1/(n.v) amplifies rounding by
    // at most |sg|^2 ~ 100: tolerance 1e-5 relative to max(1, |sg|)^2).
    std::mt19937_64 rng(6);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int i = 0; i < 5000; ++i) {
        const dvec3 n = glm::normalize(dvec3(U(rng), U(rng), U(rng)));
        dvec3 t = glm::cross(n, dvec3(U(rng), U(rng), U(rng)));
        t = glm::normalize(t) * (10.0 * std::abs(U(rng)));
        g::SgFrame f = g::sgPrologue(f3(n), g::vec3(0.0f), g::vec3(0.0f), true, SG_BFACE_NONE);
        const g::vec3 resolved = g::sgResolve(f, f3(t));
        const dvec3 back = d3(g::sgSurfgradFromPerturbedNormal(f, resolved));
        const double s = std::max(1.0, glm::length(t));
        ASSERT_LT(glm::length(back - t) / (s * s), 1e-5) << i;
        // And the oracle resolve itself.
        ASSERT_LT(angle(d3(resolved), glm::normalize(n - t)), kAngleTol) << i;
    }
}

TEST(KnownAnswers, MikktspaceCompliantTbnEqualsClassicTbn) {
    // Section 2.2: with interpolated, UNNORMALIZED n, t and b = w cross(n, t)
    // (mikktspace), the classic perturbed normal is normalize(t mx + b my + n mz).
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int i = 0; i < 5000; ++i) {
        const dvec3 n = dvec3(U(rng), U(rng), U(rng)) + dvec3(0, 0, 2);         // |n| in ~[1, 3.5]
        const dvec3 t = glm::cross(n, dvec3(U(rng), U(rng), U(rng))) + 0.2 * n; // not orthogonal
        const double w = U(rng) < 0 ? -1.0 : 1.0;
        const dvec2 m(0.7 * U(rng), 0.7 * U(rng));
        const double mz = std::sqrt(1 - m.x * m.x - m.y * m.y);
        const dvec3 classic = glm::normalize(t * m.x + w * glm::cross(n, t) * m.y + n * mz);

        g::vec3 tb, bb;
        g::sgMikktsBasis(f3(n), g::vec4(float(t.x), float(t.y), float(t.z), float(w)), tb, bb);
        g::SgFrame f = g::sgPrologue(f3(n), g::vec3(0.0f), g::vec3(0.0f), true, SG_BFACE_NONE);
        const g::vec2 d = g::sgTspaceNormalToDeriv(f2(m), false);
        const dvec3 framework = d3(g::sgResolve(f, g::sgSurfgradFromTBN(d, tb, bb)));
        // |m| <= 0.99, so 1/mz <= 7: 2e-5 rad covers the amplified rounding.
        ASSERT_LT(angle(framework, classic), 2e-5) << i;
    }
}

TEST(KnownAnswers, DoubleSidedModes) {
    // Section 2.10 on a back face (gl_FrontFacing false), same interpolated
    // attributes as the front face:
    //   NONE   - the perturbed normal equals the front side's n';
    //   MIRROR - base normal flips, gradient unchanged: n' reflected through
    //            the tangent plane, n' - 2 (n'.n) n;
    //   FLIP   - the perturbed normal is flipped: -n'.
    // The generated tangent frame (L6) must be the same on both sides.
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> U(-1, 1);
    sg::test::Worst worst[3], frameChange;
    for (int i = 0; i < 2000; ++i) {
        const dvec3 n = glm::normalize(dvec3(U(rng), U(rng), U(rng)));
        const dvec3 dPdx = glm::cross(n, dvec3(U(rng), U(rng), U(rng)));
        const dvec3 dPdy = glm::cross(n, dvec3(U(rng), U(rng), U(rng)));
        const dvec2 dSTdx(U(rng), U(rng)), dSTdy(U(rng), U(rng));
        if (std::abs(dSTdx.x * dSTdy.y - dSTdx.y * dSTdy.x) < 0.05) continue;
        if (glm::length(glm::cross(dPdx, dPdy)) < 0.05) continue;
        const g::vec2 deriv(float(U(rng)), float(U(rng)));

        auto run = [&](bool front, int mode, g::vec3& t, g::vec3& b) {
            g::SgFrame f = g::sgPrologue(f3(n), f3(dPdx), f3(dPdy), front, mode);
            g::sgGenBasisTB(f, g::vec2(0.5f), f2(dSTdx), f2(dSTdy), t, b);
            return d3(g::sgResolve(f, g::sgSurfgradFromTBN(deriv, t, b)));
        };
        g::vec3 t0, b0;
        const dvec3 front = run(true, SG_BFACE_NONE, t0, b0);
        // Oracle of the front side from the frame vectors.
        const dvec3 sgFront = double(deriv.x) * d3(t0) + double(deriv.y) * d3(b0);
        ASSERT_LT(angle(front, glm::normalize(n - sgFront)), kAngleTol);
        for (int mode : {SG_BFACE_NONE, SG_BFACE_MIRROR, SG_BFACE_FLIP}) {
            g::vec3 t, b;
            const dvec3 back = run(false, mode, t, b);
            ASSERT_LT(glm::length(d3(t) - d3(t0)), 1e-6) << "tangent changed, mode " << mode;
            ASSERT_LT(glm::length(d3(b) - d3(b0)), 1e-6) << "bitangent changed, mode " << mode;
            dvec3 expect = front;
            if (mode == SG_BFACE_MIRROR) expect = front - 2.0 * glm::dot(front, n) * n;
            if (mode == SG_BFACE_FLIP) expect = -front;
            ASSERT_LT(angle(back, expect), kAngleTol) << "mode " << mode << " record " << i;
            worst[mode].add(angle(back, expect));
            frameChange.add(std::max(glm::length(d3(t) - d3(t0)), glm::length(d3(b) - d3(b0))));
        }
    }
    const char* names[3] = {"none: the front side's normal",
                            "mirror: reflected through the "
                            "tangent plane",
                            "flip: negated"};
    for (int mode : {SG_BFACE_NONE, SG_BFACE_MIRROR, SG_BFACE_FLIP}) {
        sg::test::reportHardCase(
            {"back-faces", std::string("L16 + L6 + L5 + L1 on a back face, mode ") + names[mode],
             "angle to the section 2.10 answer (rad)", "<= " + sg::test::hardCaseNumber(kAngleTol),
             sg::test::hardCaseNumber(worst[mode].value)});
    }
    sg::test::reportHardCase({"back-faces", "L6 on a back face, every mode",
                              "|vT - vT front|, |vB - vB front|", "<= 1e-06",
                              sg::test::hardCaseNumber(frameChange.value)});
}

TEST(KnownAnswers, AnalyticScreenDerivativesMatchFiniteDifferences) {
    // Listing 17 against central differences of the true ray/plane
    // intersection of a real perspective camera, all in double here.
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> U(-1, 1);
    int checked = 0;
    for (int i = 0; i < 500; ++i) {
        const double w = 1280, h = 720;
        const dvec3 fwd = glm::normalize(dvec3(U(rng), U(rng), U(rng)));
        const glm::dmat4 view = glm::lookAt(dvec3(0), fwd, dvec3(0, 0, 1));
        const glm::dmat4 proj =
            glm::perspective(glm::radians(30.0 + 60.0 * std::abs(U(rng))), w / h, 0.1, 100.0);
        glm::dmat4 vp(1.0);
        vp[0][0] = w / 2;
        vp[1][1] = h / 2;
        vp[2][2] = 0.5;
        vp[3] = glm::dvec4(w / 2, h / 2, 0.5, 1);
        const glm::dmat4 inv = glm::inverse(vp * proj * view);
        auto unproject = [&](double x, double y, double z) {
            glm::dvec4 p = inv * glm::dvec4(x, y, z, 1);
            return dvec3(p) / p.w;
        };
        const double x = 100 + 1080 * std::abs(U(rng)), y = 50 + 620 * std::abs(U(rng));
        const dvec3 pos = unproject(x, y, 0.9 + 0.09 * std::abs(U(rng)));
        dvec3 n = glm::normalize(dvec3(U(rng), U(rng), U(rng)));
        if (glm::dot(n, -pos) < 0) n = -n;
        if (glm::dot(n, glm::normalize(-pos)) < 0.2) continue; // keep away from edge-on
        auto hit = [&](double px, double py) {
            const dvec3 a = unproject(px, py, 0), b = unproject(px, py, 1);
            const double s = glm::dot(n, pos - a) / glm::dot(n, b - a);
            return a + s * (b - a);
        };
        const double e = 1e-3;
        const dvec3 fdX = (hit(x + e, y) - hit(x - e, y)) / (2 * e);
        const dvec3 fdY = (hit(x, y + e) - hit(x, y - e)) / (2 * e);
        g::mat4 m;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) m[c][r] = float(inv[c][r]);
        g::vec3 dx, dy;
        g::sgScreenDerivOfPos(dx, dy, f3(pos), f3(n), m, float(x), float(y));
        // Relative error: binary32 matrix and position (1e-7 each) amplified
        // by the depth ratio of the camera (far/near = 1000) and 1/(n.v) <= 5:
        // 2e-3 relative, while a wrong formula is off by O(1).
        ASSERT_LT(glm::length(d3(dx) - fdX) / glm::length(fdX), 2e-3) << i;
        ASSERT_LT(glm::length(d3(dy) - fdY) / glm::length(fdY), 2e-3) << i;
        ++checked;
    }
    EXPECT_GT(checked, 100);
}

// ---- Loviscach 2008, "Feeding" ------------------------------------------------

// The unit normal of a height field with derivative d (double oracle).
dvec3 heightNormal(const dvec2& d) {
    return glm::normalize(dvec3(-d.x, -d.y, 1));
}

TEST(KnownAnswers, LoviscachScaleInvertsAndNeverTurnsInward) {
    std::mt19937_64 rng(10);
    std::uniform_real_distribution<double> U(-1, 1);
    int naiveInward = 0;
    for (int i = 0; i < 20000; ++i) {
        // Normal-map xy anywhere in the unit disk, including the rim.
        const double r = std::sqrt(std::abs(U(rng))) * 0.9999, a = 3.14159265 * U(rng);
        const g::vec2 m(float(r * std::cos(a)), float(r * std::sin(a)));
        const g::vec2 d = g::sgTspaceNormalToDeriv(m, false);
        // alpha = -1: the normal of -h, i.e. x and y of the normal negated.
        const dvec3 n = d3(g::sgDerivToTspaceNormal(d, false));
        const dvec3 inv = d3(g::sgDerivToTspaceNormal(g::sgDerivScale(d, -1.0f), false));
        ASSERT_LT(angle(inv, dvec3(-n.x, -n.y, n.z)), kAngleTol) << i;
        ASSERT_LT(angle(inv, heightNormal(-dvec2(d.x, d.y))), kAngleTol) << i;
        // alpha = 2 keeps z > 0 (never inward) and equals the doubled height.
        const dvec3 twice = d3(g::sgDerivToTspaceNormal(g::sgDerivScale(d, 2.0f), false));
        ASSERT_GT(twice.z, 0.0) << i;
        ASSERT_LT(angle(twice, heightNormal(2.0 * dvec2(d.x, d.y))), kAngleTol) << i;
        // The naive lerp normalize(2 n - flat) does turn some inward: the
        // test's premise holds.
        naiveInward += (2 * n.z - 1) < 0;
    }
    EXPECT_GT(naiveInward, 100);
}

TEST(KnownAnswers, LoviscachModulateCurveDeformMatchFiniteDifferences) {
    auto h1 = [](double u, double v) {
        return 0.3 * std::sin(2 * u + 0.1) * std::cos(3 * v) + 0.5;
    };
    auto h2 = [](double u, double v) { return 0.2 * std::cos(1.5 * u - v) + 0.7; };
    auto grad = [](auto&& h, double u, double v) {
        const double e = 1e-5;
        return dvec2((h(u + e, v) - h(u - e, v)) / (2 * e), (h(u, v + e) - h(u, v - e)) / (2 * e));
    };
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int i = 0; i < 2000; ++i) {
        const double u = U(rng) * 3, v = U(rng) * 3;
        // Central differences with e = 1e-5 on O(1) smooth functions: error
        // ~e^2 f''' + 1e-16/e ~ 1e-10; binary32 evaluation ~1e-7 relative:
        // tolerance 2e-6 absolute on O(1) derivatives.
        const double tol = 2e-6;
        // Modulate: d(h1 h2) = d1 h2 + h1 d2.
        const dvec2 d1 = grad(h1, u, v), d2 = grad(h2, u, v);
        const dvec2 fdProd = grad([&](double a, double b) { return h1(a, b) * h2(a, b); }, u, v);
        const g::vec2 mod = g::sgDerivModulate(f2(d1), float(h1(u, v)), f2(d2), float(h2(u, v)));
        ASSERT_LT(glm::length(dvec2(mod.x, mod.y) - fdProd), tol) << i;

        // Curves: f(h) = atan(sqrt(P)(h - H)) / sqrt(P), f'(h) = 1/(1 + P (h - H)^2).
        const double P = 1 + 99 * std::abs(U(rng)), Hc = 0.5 + 0.3 * U(rng);
        auto f = [&](double hh) { return std::atan(std::sqrt(P) * (hh - Hc)) / std::sqrt(P); };
        const double hh = h1(u, v);
        const double fdSlope = (f(hh + 1e-6) - f(hh - 1e-6)) / 2e-6;
        const float slope = g::sgCurveBoostSlope(float(hh), float(P), float(Hc));
        ASSERT_LT(std::abs(slope - fdSlope), 1e-5 * std::max(1.0, std::abs(fdSlope))) << i;
        ASSERT_LT(std::abs(g::sgCurveBoostValue(float(hh), float(P), float(Hc)) - f(hh)), 1e-6)
            << i;
        const dvec2 fdCurved = grad([&](double a, double b) { return f(h1(a, b)); }, u, v);
        const g::vec2 curved = g::sgDerivCurve(f2(d1), slope);
        ASSERT_LT(glm::length(dvec2(curved.x, curved.y) - fdCurved), tol) << i;

        // Deform with the sine warp s = u, t = v + A sin(B u).
        const double A = 0.05 * U(rng), B = 10 * U(rng);
        auto warped = [&](double a, double b) { return h2(a, b + A * std::sin(B * a)); };
        const dvec2 dAt = grad(h2, u, v + A * std::sin(B * u));
        const g::vec2 def =
            g::sgDerivDeform(f2(dAt), g::sgSineWarpJacobian(float(u), float(A), float(B)));
        ASSERT_LT(glm::length(dvec2(def.x, def.y) - grad(warped, u, v)), tol) << i;
        // A general warp with an analytic Jacobian.
        auto sw = [](double a, double b) { return dvec2(a + 0.3 * b * b, b - 0.2 * std::sin(a)); };
        const glm::dmat2 Jw(1, -0.2 * std::cos(u), 0.6 * v, 1); // columns d/du, d/dv
        auto warped2 = [&](double a, double b) {
            dvec2 st = sw(a, b);
            return h1(st.x, st.y);
        };
        const dvec2 st = sw(u, v);
        const g::vec2 def2 =
            g::sgDerivDeform(f2(grad(h1, st.x, st.y)), g::mat2(float(Jw[0][0]), float(Jw[0][1]),
                                                               float(Jw[1][0]), float(Jw[1][1])));
        ASSERT_LT(glm::length(dvec2(def2.x, def2.y) - grad(warped2, u, v)), 1e-5) << i;
    }
}

TEST(KnownAnswers, LoviscachMaskedBlendMatchesFiniteDifferences) {
    auto hA = [](double u, double v) { return 0.4 * std::sin(1.3 * u) * std::cos(0.7 * v); };
    auto hB = [](double u, double v) { return 0.25 * std::cos(2.1 * u + v) + 0.3; };
    auto m = [](double u, double v) { return 0.5 + 0.45 * std::sin(0.9 * u - 1.7 * v); };
    auto grad = [](auto&& h, double u, double v) {
        const double e = 1e-5;
        return dvec2((h(u + e, v) - h(u - e, v)) / (2 * e), (h(u, v + e) - h(u, v - e)) / (2 * e));
    };
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> U(-3, 3);
    for (int i = 0; i < 2000; ++i) {
        const double u = U(rng), v = U(rng);
        auto blended = [&](double a, double b) {
            return (1 - m(a, b)) * hA(a, b) + m(a, b) * hB(a, b);
        };
        const g::vec2 d =
            g::sgDerivMaskBlend(f2(grad(hA, u, v)), float(hA(u, v)), f2(grad(hB, u, v)),
                                float(hB(u, v)), float(m(u, v)), f2(grad(m, u, v)));
        // Same budget as the modulate test: finite differences ~1e-10,
        // binary32 products of O(1) values ~1e-7.
        ASSERT_LT(glm::length(dvec2(d.x, d.y) - grad(blended, u, v)), 2e-6) << i;
    }
}

TEST(KnownAnswers, CentralDifferenceAndHermiteCurve) {
    // Central differences of a quadratic are exact: h = a u^2 + b v^2 + c u v.
    auto h = [](double u, double v) { return 0.25 * u * u - 0.5 * v * v + 0.125 * u * v; };
    for (double u : {-3.0, 0.0, 2.0, 7.0})
        for (double v : {-1.0, 0.0, 4.0}) {
            const g::vec2 d = g::sgHeightDerivCentral(float(h(u - 1, v)), float(h(u + 1, v)),
                                                      float(h(u, v - 1)), float(h(u, v + 1)));
            // Values are small integers / 8: binary32 exact.
            EXPECT_EQ(double(d.x), 0.5 * u + 0.125 * v);
            EXPECT_EQ(double(d.y), -1.0 * v + 0.125 * u);
        }
    // The Hermite segment reproduces every cubic: f(x) = x^3 - 2x^2 + 0.5x + 1
    // on [x0, x1] from its end values and end slopes.
    auto f = [](double x) { return x * x * x - 2 * x * x + 0.5 * x + 1; };
    auto fp = [](double x) { return 3 * x * x - 4 * x + 0.5; };
    const double x0 = 0.25, x1 = 1.75;
    const g::vec4 knots(float(x0), float(f(x0)), float(x1), float(f(x1)));
    const g::vec2 slopes(float(fp(x0)), float(fp(x1)));
    for (int i = 0; i <= 100; ++i) {
        const double x = x0 + (x1 - x0) * i / 100.0;
        const g::vec2 r = g::sgCurveHermite(float(x), knots, slopes);
        // O(1) values through ~20 binary32 operations: 1e-6.
        EXPECT_NEAR(r.x, f(x), 1e-6) << x;
        EXPECT_NEAR(r.y, fp(x), 1e-6) << x;
    }
    // Clamped beyond the ends; a zero-length segment has slope 0.
    EXPECT_NEAR(g::sgCurveHermite(5.0f, knots, slopes).y, fp(x1), 1e-6);
    EXPECT_EQ(g::sgCurveHermite(0.5f, g::vec4(0.5f, 0.2f, 0.5f, 0.9f), slopes),
              g::vec2(0.2f, 0.0f));
}

TEST(KnownAnswers, LeanCovarianceAndToksvigVariance) {
    // Slopes d_k = (c + a cos(phi_k), e + b sin(phi_k)) at 64 equally spaced
    // phases: mean (c, e), var x = a^2 / 2, var y = b^2 / 2, cov 0 exactly.
    const double a = 0.6, b = 0.3, c = 0.2, e = -0.1;
    dvec2 mean(0);
    glm::dvec3 second(0);
    const int n = 64;
    for (int k = 0; k < n; ++k) {
        const double phi = 2 * 3.14159265358979 * k / n;
        const g::vec2 d(float(c + a * std::cos(phi)), float(e + b * std::sin(phi)));
        const g::vec3 m2 = g::sgLeanSecondMoments(d);
        mean += dvec2(d.x, d.y) / double(n);
        second += glm::dvec3(m2.x, m2.y, m2.z) / double(n);
    }
    const g::vec3 cov =
        g::sgLeanCovariance(f2(mean), g::vec3(float(second.x), float(second.y), float(second.z)));
    // M - B B^T of O(0.1) binary32 values: 1e-6.
    EXPECT_NEAR(cov.x, a * a / 2, 1e-6);
    EXPECT_NEAR(cov.y, b * b / 2, 1e-6);
    EXPECT_NEAR(cov.z, 0.0, 1e-6);
    // Rounding that makes M - B B^T indefinite is clamped to a valid covariance.
    const g::vec3 clamped = g::sgLeanCovariance(g::vec2(1.0f, 1.0f), g::vec3(0.999f, 2.0f, 5.0f));
    EXPECT_EQ(clamped.x, 0.0f);
    EXPECT_EQ(clamped.z, 0.0f);
    // Toksvig: |N| = 1 / (1 + s2) gives s2 back; the factor is 1 / (1 + p s2).
    for (double s2 : {0.0, 0.01, 0.3, 4.0}) {
        const double len = 1 / (1 + s2);
        const g::vec3 avg(float(0.6 * len), 0.0f, float(0.8 * len));
        // (1 - |N|) / |N| with |N| good to 1e-7 relative: 1e-6 relative.
        EXPECT_NEAR(g::sgToksvigVariance(avg), s2, 1e-6 * (1 + s2)) << s2;
        EXPECT_NEAR(g::sgToksvigFactor(float(s2), 64.0f), 1 / (1 + 64 * s2), 1e-6) << s2;
    }
    // An average that cancels stays finite (fully rough), a unit one is 0.
    EXPECT_TRUE(std::isfinite(g::sgToksvigVariance(g::vec3(0.0f))));
    EXPECT_EQ(g::sgToksvigVariance(g::vec3(0.0f, 0.0f, 1.0f)), 0.0f);
}

} // namespace
