// Property tests (rapidcheck) of the shared bump math through its C++ build
// (shaders/sg/*.glsl via surfgrad/bump/core.h and the evaluation table of
// shaders/sg/eval/kernels.glsl):
//  - finite outputs: every entry of the evaluation table on any record of
//    its documented domain (components 0 or 1e-45 to 1e18 in magnitude);
//  - unit-length resolve (Mikkelsen 2019, listing 1);
//  - linearity of the surface-gradient sum (eq. 2-3): listings 5, 8 and 12
//    are linear maps of the derivative or volume gradient;
//  - the TBN frame of listing 6: unit, tangent, orthogonal, along +s;
//  - parametrisation independence: a volume gradient (listing 12) ignores
//    the screen parametrisation, a decal's (listing 15) the rotation or
//    mirroring of its plane's axes, a triplanar projection's (listing 13,
//    section 2.8) its handedness and texture-origin conventions, a
//    scale-dependent bump's (listing 8) an affine change of UV layout;
//  - round trips: normal-map texel -> derivative -> normal (listing 4 and
//    its decoder), surface gradient -> normal -> surface gradient
//    (listings 1 and 7);
//  - the derivative edits of Loviscach 2008: scale, add/blend, modulate,
//    curves, deform (composition is the product of the warp Jacobians).
//
// Seeds: CI runs a fixed seed (kSeed below, set through RC_PARAMS when the
// environment does not set it) and 1000 cases per
// property. To run more, or another seed:
//   RC_PARAMS="max_success=100000 seed=1" build/bin/bump_property_test
// (rapidcheck prints the seed and a minimal failing case on a failure;
// RC_PARAMS="reproduce=..." replays it).
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "surfgrad/bump/core.h"
#include "surfgrad/bump/eval_kernels.h"

namespace {

namespace g = sg::glsl;
using dvec2 = glm::dvec2;
using dvec3 = glm::dvec3;

// The fixed seed of the CI run (rapidcheck reads RC_PARAMS once, at its
// first property).
constexpr const char* kDefaultParams = "seed=20261125 max_success=1000";
[[maybe_unused]] const bool kSeeded = [] {
    if (!std::getenv("RC_PARAMS")) setenv("RC_PARAMS", kDefaultParams, 0);
    return true;
}();

constexpr double kEps = 1.1920928955078125e-07; // FLT_EPSILON

// ---- generators -------------------------------------------------------------

// rapidcheck's inRange grows its range with the test's size (only `lo` at
// size 0); these draw from the whole range at every size (shrinking still
// goes toward `lo`).
int uniformInt(int lo, int hi) { // [lo, hi)
    return *rc::gen::resize(100, rc::gen::inRange(lo, hi));
}
bool coin() {
    return uniformInt(0, 2) == 1;
}
// Uniform in [lo, hi] on a grid of 2^24 steps.
double real(double lo, double hi) {
    const int i = uniformInt(0, (1 << 24) + 1);
    return lo + (hi - lo) * double(i) / double(1 << 24);
}
// Sign * 10^[e0, e1], or 0 one time in 16.
double anyMagnitude(double e0, double e1) {
    if (uniformInt(0, 16) == 0) return 0.0;
    const double m = std::pow(10.0, real(e0, e1));
    return coin() ? m : -m;
}
// Uniform on the unit sphere (z uniform, azimuth uniform).
dvec3 unitVec() {
    const double z = real(-1, 1), a = real(-M_PI, M_PI), r = std::sqrt(std::max(0.0, 1 - z * z));
    return dvec3(r * std::cos(a), r * std::sin(a), z);
}
// A unit vector perpendicular to the unit vector n, at a uniform angle.
dvec3 tangentTo(const dvec3& n) {
    const dvec3 axis = std::fabs(n.x) < 0.6 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
    const dvec3 e1 = glm::normalize(glm::cross(n, axis)), e2 = glm::cross(n, e1);
    const double a = real(-M_PI, M_PI);
    return std::cos(a) * e1 + std::sin(a) * e2;
}
dvec2 vec2In(double r) {
    return dvec2(real(-r, r), real(-r, r));
}

g::vec3 f3(const dvec3& v) {
    return g::vec3(float(v.x), float(v.y), float(v.z));
}
g::vec2 f2(const dvec2& v) {
    return g::vec2(float(v.x), float(v.y));
}
dvec3 d3(const g::vec3& v) {
    return dvec3(v.x, v.y, v.z);
}
dvec2 d2(const g::vec2& v) {
    return dvec2(v.x, v.y);
}
bool finite(double x) {
    return std::isfinite(x);
}
double angle(const dvec3& a, const dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

g::SgFrame frame(const dvec3& n, const dvec3& dPdx, const dvec3& dPdy) {
    return g::sgPrologue(f3(n), f3(dPdx), f3(dPdy), true, SG_BFACE_NONE);
}

// A well-conditioned pixel: unit n, screen derivatives in the tangent plane
// with condition number <= ~4, `scale` world units per pixel.
struct Pixel {
    dvec3 n, dPdx, dPdy;
};
Pixel wellConditionedPixel(double scale) {
    Pixel p;
    p.n = unitVec();
    const dvec3 e1 = tangentTo(p.n), e2 = glm::cross(p.n, e1);
    p.dPdx = scale * (e1 + real(-0.3, 0.3) * e2);
    p.dPdy = scale * (e2 + real(-0.3, 0.3) * e1) * (coin() ? 1.0 : -1.0);
    return p;
}

// ---- finite outputs over the evaluation table --------------------------------

// Every entry of the table, on any record of the documented domain: each
// float component 0 or +-10^[-45, 18] (denormals to SG_BIG), each bool 0/1,
// each int in its declared range. The shared functions promise finite
// results for all of them (shaders/sg/compat.glsl, SG_BIG).
RC_GTEST_PROP(BumpProperties, EveryTableEntryGivesFiniteOutputsOnItsDomain, ()) {
    const auto& table = sg::eval::entries();
    for (const sg::eval::Entry& e : table) {
        std::vector<float> in(size_t(sg::eval::inStride()), 0.0f),
            out(size_t(sg::eval::outStride()), 0.0f);
        for (const auto& f : e.inputs) {
            for (int i = 0; i < f.width; ++i) {
                float v = 0.0f;
                if (f.kind == sg::eval::FieldKind::Bool) {
                    v = float(uniformInt(0, 2));
                } else if (f.kind == sg::eval::FieldKind::Int) {
                    v = float(uniformInt(f.minValue, f.maxValue + 1));
                } else {
                    v = float(std::clamp(anyMagnitude(-45, 18), -1e18, 1e18));
                }
                in[size_t(f.slot + i)] = v;
            }
        }
        sg::eval::evalCpu(e, in.data(), out.data());
        for (const auto& f : e.outputs) {
            for (int i = 0; i < f.width; ++i) {
                RC_ASSERT(finite(out[size_t(f.slot + i)]));
            }
        }
    }
}

// ---- resolve ------------------------------------------------------------------

RC_GTEST_PROP(BumpProperties, ResolveIsUnitLength, ()) {
    const dvec3 n = unitVec() * std::pow(10.0, real(-30, 18)); // any length
    const dvec3 s(anyMagnitude(-45, 18), anyMagnitude(-45, 18), anyMagnitude(-45, 18));
    const int mode = *rc::gen::inRange(0, 3);
    const g::SgFrame f = g::sgPrologue(f3(n), g::vec3(0.0f), g::vec3(0.0f), coin(), mode);
    const dvec3 r = d3(g::sgResolve(f, f3(s)));
    RC_ASSERT(finite(r.x) && finite(r.y) && finite(r.z));
    // sgSafeNormalize: a normalization of a vector scaled to unit largest
    // component, within 2 ulps of unit length.
    RC_ASSERT(std::fabs(glm::length(r) - 1.0) <= 2.0 * kEps);
}

// ---- linearity of the surface-gradient sum (eq. 2-3) ------------------------

// Listing 5: sum_i a_i TBN(d_i) = TBN(sum_i a_i d_i), so layers add like
// heights. Rounding: a few ulps of the largest term.
RC_GTEST_PROP(BumpProperties, TbnSurfaceGradientIsLinear, ()) {
    const dvec3 t = unitVec() * real(0.1, 10), b = unitVec() * real(0.1, 10);
    const dvec2 d1 = vec2In(10), d2 = vec2In(10);
    const double a1 = real(-4, 4), a2 = real(-4, 4);
    const dvec3 lhs = d3(g::sgSurfgradFromTBN(f2(a1 * d1 + a2 * d2), f3(t), f3(b)));
    const dvec3 rhs = a1 * d3(g::sgSurfgradFromTBN(f2(d1), f3(t), f3(b))) +
                      a2 * d3(g::sgSurfgradFromTBN(f2(d2), f3(t), f3(b)));
    const double scale = (std::fabs(a1) * glm::length(d1) + std::fabs(a2) * glm::length(d2)) *
                         (glm::length(t) + glm::length(b));
    RC_ASSERT(glm::length(lhs - rhs) <= 8.0 * kEps * scale + 1e-30);
}

// Listing 12: the surface gradient of a sum of volume gradients is the sum.
RC_GTEST_PROP(BumpProperties, VolumeSurfaceGradientIsLinear, ()) {
    const g::SgFrame f = frame(unitVec(), dvec3(0), dvec3(0));
    const dvec3 g1 = unitVec() * real(0, 100), g2 = unitVec() * real(0, 100);
    const double a1 = real(-4, 4), a2 = real(-4, 4);
    const dvec3 lhs = d3(g::sgSurfgradFromVolumeGradient(f, f3(a1 * g1 + a2 * g2)));
    const dvec3 rhs = a1 * d3(g::sgSurfgradFromVolumeGradient(f, f3(g1))) +
                      a2 * d3(g::sgSurfgradFromVolumeGradient(f, f3(g2)));
    const double scale = std::fabs(a1) * glm::length(g1) + std::fabs(a2) * glm::length(g2);
    RC_ASSERT(glm::length(lhs - rhs) <= 8.0 * kEps * scale + 1e-30);
}

// Listing 8 is linear in the derivative on a well-conditioned pixel (its
// unit scalings and sgBoundedGain only change roundings there). The map
// d -> sg has norm at most |M| = max over the unit vectors; rounding is a
// few ulps of |M| |d| times the Jacobian's condition number (<= ~4).
RC_GTEST_PROP(BumpProperties, ScaleDependentSurfaceGradientIsLinear, ()) {
    const double scale = std::pow(10.0, real(-6, 6));
    const Pixel p = wellConditionedPixel(scale);
    const g::SgFrame f = frame(p.n, p.dPdx, p.dPdy);
    const dvec2 dSTdx(real(0.5, 2) * 1e-3, real(-0.3, 0.3) * 1e-3),
        dSTdy(real(-0.3, 0.3) * 1e-3, real(0.5, 2) * 1e-3);
    const dvec2 texDim(512, 256);
    auto L8 = [&](const dvec2& d) {
        return d3(g::sgSurfgradScaleDependent(f, f2(d), f2(dSTdx), f2(dSTdy), f2(texDim)));
    };
    const dvec2 d1 = vec2In(1), d2 = vec2In(1);
    const double a1 = real(-4, 4), a2 = real(-4, 4);
    const double norm = std::max(glm::length(L8(dvec2(1, 0))), glm::length(L8(dvec2(0, 1))));
    const dvec3 lhs = L8(a1 * d1 + a2 * d2), rhs = a1 * L8(d1) + a2 * L8(d2);
    const double bound =
        64.0 * kEps * norm * (std::fabs(a1) * glm::length(d1) + std::fabs(a2) * glm::length(d2));
    RC_ASSERT(glm::length(lhs - rhs) <= bound + 1e-30);
}

// ---- the TBN frame of listing 6 -----------------------------------------------

// On a well-conditioned pixel and UV Jacobian: vT, vB unit, tangent,
// orthogonal, vT along dP/ds and vB along +t (dP/dt's side), for mirrored
// (det < 0) and unmirrored UV layouts.
RC_GTEST_PROP(BumpProperties, GenBasisIsAnOrthonormalFrameAlongS, ()) {
    const Pixel p = wellConditionedPixel(std::pow(10.0, real(-6, 6)));
    const g::SgFrame f = frame(p.n, p.dPdx, p.dPdy);
    // UV Jacobian J = d(s,t)/d(x,y), condition number <= ~5, any sign of det.
    const double k = std::pow(10.0, real(-6, 3));
    const double th = real(-M_PI, M_PI);
    const glm::dmat2 R(std::cos(th), std::sin(th), -std::sin(th), std::cos(th));
    glm::dmat2 J = R * glm::dmat2(real(0.5, 2), 0.0, real(-0.5, 0.5), real(0.5, 2)) * k;
    if (coin()) J = glm::dmat2(1, 0, 0, -1) * J; // mirrored UVs
    const dvec2 dSTdx = J[0], dSTdy = J[1];
    g::vec3 vT, vB;
    g::sgGenBasisTB(f, g::vec2(0.0f), f2(dSTdx), f2(dSTdy), vT, vB);
    const dvec3 t = d3(vT), b = d3(vB), n = d3(f.nrmBase);
    RC_ASSERT(std::fabs(glm::length(t) - 1.0) <= 4.0 * kEps);
    RC_ASSERT(std::fabs(glm::length(b) - 1.0) <= 4.0 * kEps);
    RC_ASSERT(std::fabs(glm::dot(t, n)) <= 8.0 * kEps);
    RC_ASSERT(std::fabs(glm::dot(b, n)) <= 8.0 * kEps);
    RC_ASSERT(std::fabs(glm::dot(t, b)) <= 8.0 * kEps);
    // Exact dP/ds, dP/dt from the inverse of J (double): [dP/ds dP/dt] =
    // [dPdx dPdy] J^-1.
    const glm::dmat2 Ji = glm::inverse(J);
    const dvec3 dPds = p.dPdx * Ji[0][0] + p.dPdy * Ji[0][1];
    const dvec3 dPdt = p.dPdx * Ji[1][0] + p.dPdy * Ji[1][1];
    // A binary32 frame of a Jacobian with condition number <= ~25 (screen
    // times UV): a few hundred ulps.
    RC_ASSERT(angle(t, dPds) <= 1e-4);
    RC_ASSERT(glm::dot(b, dPdt) > 0.0);
}

// ---- parametrisation independence ---------------------------------------------

// Listing 12 uses only the base normal: the screen parametrisation (dPdx,
// dPdy, zero, parallel or anything) does not change it, bit for bit, and
// the result is tangent.
RC_GTEST_PROP(BumpProperties, VolumeGradientIgnoresTheScreenParametrisation, ()) {
    const dvec3 n = unitVec();
    const dvec3 grad = unitVec() * std::pow(10.0, real(-10, 10));
    const g::SgFrame a = frame(n, dvec3(0), dvec3(0));
    const g::SgFrame b =
        frame(n, unitVec() * anyMagnitude(-20, 15), unitVec() * anyMagnitude(-20, 15));
    const g::vec3 ga = g::sgSurfgradFromVolumeGradient(a, f3(grad));
    const g::vec3 gb = g::sgSurfgradFromVolumeGradient(b, f3(grad));
    RC_ASSERT(ga == gb);
    RC_ASSERT(std::fabs(glm::dot(d3(ga), n)) <= 8.0 * kEps * glm::length(grad));
}

// Listing 15: a decal is the 3D height field h(p) = map(p.axisX, p.axisY);
// rotating or mirroring its axes within their plane, with the map's
// derivative rotated back (the same height field), gives the same gradient.
RC_GTEST_PROP(BumpProperties, DecalGradientIgnoresTheAxesOfItsPlane, ()) {
    const dvec3 n = unitVec();
    const g::SgFrame f = frame(n, dvec3(0), dvec3(0));
    const dvec3 z = unitVec(), x = tangentTo(z), y = glm::cross(z, x);
    const double th = real(-M_PI, M_PI);
    glm::dmat2 M(std::cos(th), std::sin(th), -std::sin(th), std::cos(th));
    if (coin()) M = M * glm::dmat2(1, 0, 0, -1);
    // [x' y'] = [x y] M, d' = M^T d.
    const dvec3 x2 = x * M[0][0] + y * M[0][1], y2 = x * M[1][0] + y * M[1][1];
    const dvec2 d = vec2In(10);
    const dvec2 dd = glm::transpose(M) * d;
    const bool ul = coin();
    // An upper-left origin negates the map's second derivative component;
    // express the same height field in that convention.
    auto conv = [&](dvec2 v) { return ul ? dvec2(v.x, -v.y) : v; };
    const dvec3 a = d3(g::sgSurfgradFromDecal(f, f2(conv(d)), f3(x), f3(y), ul));
    const dvec3 b = d3(g::sgSurfgradFromDecal(f, f2(conv(dd)), f3(x2), f3(y2), ul));
    RC_ASSERT(glm::length(a - b) <= 16.0 * kEps * glm::length(d));
}

// Listing 13 (section 2.8): the handedness of the projections (x and y
// planes sampled at (-z, y), (x, -z)) and the texture origin (t flipped)
// are conventions of the maps: the same height fields expressed in either
// give the same gradient. Weights depend only on |n|.
RC_GTEST_PROP(BumpProperties, TriplanarGradientIgnoresItsConventions, ()) {
    const dvec3 n = unitVec();
    const double k = real(0.5, 16);
    const g::vec3 w = g::sgTriplanarWeights(f3(n), float(k));
    const g::vec3 wAbs = g::sgTriplanarWeights(f3(glm::abs(n)), float(k));
    RC_ASSERT(w == wAbs);
    // Derivatives of the three height fields in the left-handed, lower-left
    // convention of listing 13.
    const dvec2 dX = vec2In(5), dY = vec2In(5), dZ = vec2In(5);
    const bool rh = coin(), ul = coin();
    // The same fields in convention (rh, ul): sampling at -z negates the
    // derivative along that coordinate, sampling at 1 - t negates the second.
    dvec2 cX = dX, cY = dY, cZ = dZ;
    if (rh) {
        cX.x = -cX.x;
        cY.y = -cY.y;
    }
    if (ul) {
        cX.y = -cX.y;
        cY.y = -cY.y;
        cZ.y = -cZ.y;
    }
    const g::SgFrame f = frame(n, dvec3(0), dvec3(0));
    const dvec3 a = d3(g::sgSurfgradFromTriplanar(f, w, f2(dX), f2(dY), f2(dZ), false, false));
    const dvec3 b = d3(g::sgSurfgradFromTriplanar(f, w, f2(cX), f2(cY), f2(cZ), rh, ul));
    RC_ASSERT(glm::length(a - b) <=
              16.0 * kEps * (glm::length(dX) + glm::length(dY) + glm::length(dZ)));
}

// Listing 8: an affine change of UV layout st' = A st (any A with
// condition number <= ~10, mirrored or not), with the same heights
// (dH/dst' = A^-T dH/dst), gives the same normal.
RC_GTEST_PROP(BumpProperties, ScaleDependentBumpIgnoresTheUvLayout, ()) {
    const Pixel p = wellConditionedPixel(std::pow(10.0, real(-4, 4)));
    const g::SgFrame f = frame(p.n, p.dPdx, p.dPdy);
    const dvec2 dSTdx(real(0.5, 2) * 1e-3, real(-0.3, 0.3) * 1e-3),
        dSTdy(real(-0.3, 0.3) * 1e-3, real(0.5, 2) * 1e-3);
    // Slopes of order 1: dH/dP ~ dH/dst * 1e-3 / |dPdx|.
    const dvec2 dHdST = vec2In(2) * glm::length(p.dPdx) / 1e-3;
    glm::dmat2 A(real(0.5, 3), real(-1, 1), real(-1, 1), real(0.5, 3));
    if (coin()) A = A * glm::dmat2(-1, 0, 0, 1);
    RC_PRE(std::fabs(glm::determinant(A)) > 0.1);
    const dvec2 tex1(512, 512), tex2(64, 2048);
    const dvec2 dHdST2 = glm::transpose(glm::inverse(A)) * dHdST;
    const dvec3 n1 = d3(g::sgResolve(
        f, g::sgSurfgradScaleDependent(f, f2(dHdST / tex1), f2(dSTdx), f2(dSTdy), f2(tex1))));
    const dvec3 n2 =
        d3(g::sgResolve(f, g::sgSurfgradScaleDependent(f, f2(dHdST2 / tex2), f2(A * dSTdx),
                                                       f2(A * dSTdy), f2(tex2))));
    // Conditioning: the screen Jacobian (<= ~4) and A (<= ~60): 1e-4 rad is
    // ~800 ulps, a wrong metric is off by O(1).
    RC_ASSERT(angle(n1, n2) <= 1e-4);
}

// ---- round trips --------------------------------------------------------------

// Texel -> derivative -> normal: the xy of the decoded normal is the texel
// (|m| <= 0.99, away from listing 4's clamp). d = -m/m_z amplifies m's
// rounding by 1/m_z^2 <= 50.
RC_GTEST_PROP(BumpProperties, NormalMapTexelRoundTrip, ()) {
    const double r = real(0, 0.99), a = real(-M_PI, M_PI);
    const dvec2 m(r * std::cos(a), r * std::sin(a));
    const bool flipV = coin();
    const g::vec2 d = g::sgTspaceNormalToDeriv(f2(m), flipV);
    const g::vec3 back = g::sgDerivToTspaceNormal(d, flipV);
    const double mz2 = 1.0 - r * r;
    RC_ASSERT(glm::length(dvec2(back.x, back.y) - d2(f2(m))) <= 8.0 * kEps / mz2);
    // flipV only negates the t component.
    const g::vec2 other = g::sgTspaceNormalToDeriv(f2(m), !flipV);
    RC_ASSERT(other.x == d.x && other.y == -d.y);
}

// Derivative -> normal -> derivative for |d| <= 64 per component (inside
// the 128 clamp): m_z^2 = 1 - |m|^2 cancels, so the relative error grows
// as (1 + |d|^2).
RC_GTEST_PROP(BumpProperties, DerivativeRoundTrip, ()) {
    const dvec2 d = vec2In(real(0, 64));
    const bool flipV = coin();
    const g::vec3 m = g::sgDerivToTspaceNormal(f2(d), flipV);
    const dvec2 back = d2(g::sgTspaceNormalToDeriv(g::vec2(m.x, m.y), flipV));
    const double l2 = 1.0 + glm::dot(d, d);
    RC_ASSERT(glm::length(back - d) <= 8.0 * kEps * l2 * glm::length(d) + 1e-30);
}

// Surface gradient -> resolved normal -> listing 7 -> the same gradient,
// for |sg| <= 10 (the normal >= 5.7 deg above the horizon): n.v ~ 1/|sg|
// carries an absolute rounding of a few ulps, so 1/(n.v) is off by a few
// ulps times |sg|, and the gradient by that times |sg|.
RC_GTEST_PROP(BumpProperties, SurfaceGradientNormalRoundTrip, ()) {
    const dvec3 n = unitVec();
    const dvec3 s = tangentTo(n) * real(0, 10);
    const g::SgFrame f = frame(n, dvec3(0), dvec3(0));
    const dvec3 back = d3(g::sgSurfgradFromPerturbedNormal(f, g::sgResolve(f, f3(s))));
    const double m = std::max(1.0, glm::length(s));
    RC_ASSERT(glm::length(back - s) <= 64.0 * kEps * m * m);
}

// ---- derivative edits (Loviscach 2008) ------------------------------------------

RC_GTEST_PROP(BumpProperties, DerivativeEditsAreHeightEdits, ()) {
    const dvec2 da = vec2In(10), db = vec2In(10), dc = vec2In(10);
    const double a = real(-4, 4), b = real(-4, 4), c = real(-4, 4);
    const double h1 = real(-2, 2), h2 = real(-2, 2);
    // Scaling twice is scaling by the product (a few ulps).
    const dvec2 twice = d2(g::sgDerivScale(g::sgDerivScale(f2(da), float(a)), float(b)));
    const dvec2 once = d2(g::sgDerivScale(f2(da), float(a) * float(b)));
    RC_ASSERT(glm::length(twice - once) <= 4.0 * kEps * std::fabs(a * b) * glm::length(da) + 1e-30);
    // Blend of 2 layers is sgDerivAdd, bit for bit; of 3, the sum in order;
    // counts are clamped to [0, 8].
    g::vec2 layers[SG_DERIV_MAX_LAYERS];
    float weights[SG_DERIV_MAX_LAYERS];
    for (int i = 0; i < SG_DERIV_MAX_LAYERS; ++i) {
        layers[i] = f2(vec2In(10));
        weights[i] = float(real(-2, 2));
    }
    layers[0] = f2(da);
    layers[1] = f2(db);
    layers[2] = f2(dc);
    weights[0] = float(a);
    weights[1] = float(b);
    weights[2] = float(c);
    RC_ASSERT(g::sgDerivBlend(layers, weights, 2) ==
              g::sgDerivAdd(f2(da), float(a), f2(db), float(b)));
    RC_ASSERT(g::sgDerivBlend(layers, weights, 3) ==
              g::sgDerivAdd(f2(da), float(a), f2(db), float(b)) + float(c) * f2(dc));
    RC_ASSERT(g::sgDerivBlend(layers, weights, 0) == g::vec2(0.0f));
    RC_ASSERT(g::sgDerivBlend(layers, weights, -3) == g::vec2(0.0f));
    RC_ASSERT(g::sgDerivBlend(layers, weights, 99) ==
              g::sgDerivBlend(layers, weights, SG_DERIV_MAX_LAYERS));
    // Modulate: the product rule is symmetric, and a constant factor (d2 = 0)
    // scales.
    RC_ASSERT(g::sgDerivModulate(f2(da), float(h1), f2(db), float(h2)) ==
              g::sgDerivModulate(f2(db), float(h2), f2(da), float(h1)));
    RC_ASSERT(g::sgDerivModulate(f2(da), float(h1), g::vec2(0.0f), float(h2)) ==
              f2(da) * float(h2));
}

// Curves: f'(h) in (0, 1], 1 at the centre; f(H) = 0; f increasing.
RC_GTEST_PROP(BumpProperties, CurveBoostIsAMonotoneSlopeLimiter, ()) {
    const float P = float(std::pow(10.0, real(-8, 8))), H = float(real(-10, 10));
    const float h1 = float(real(-100, 100)), h2 = float(real(-100, 100));
    const float s1 = g::sgCurveBoostSlope(h1, P, H);
    RC_ASSERT(s1 > 0.0f && s1 <= 1.0f);
    RC_ASSERT(g::sgCurveBoostSlope(H, P, H) == 1.0f);
    RC_ASSERT(g::sgCurveBoostValue(H, P, H) == 0.0f);
    const float v1 = g::sgCurveBoostValue(h1, P, H), v2 = g::sgCurveBoostValue(h2, P, H);
    RC_ASSERT(std::isfinite(v1) && std::isfinite(v2));
    if (h1 < h2) RC_ASSERT(v1 <= v2);
}

// Deform: the chain rule composes. h(w1(w2(x))) has the derivative
// J2^T J1^T d = (J1 J2)^T d; the identity warp changes nothing; the sine
// warp is a unit-determinant shear.
RC_GTEST_PROP(BumpProperties, DeformationsCompose, ()) {
    const dvec2 d = vec2In(10);
    const glm::dmat2 J1(real(-2, 2), real(-2, 2), real(-2, 2), real(-2, 2));
    const glm::dmat2 J2(real(-2, 2), real(-2, 2), real(-2, 2), real(-2, 2));
    auto fm = [](const glm::dmat2& m) {
        return g::mat2(float(m[0][0]), float(m[0][1]), float(m[1][0]), float(m[1][1]));
    };
    const dvec2 step = d2(g::sgDerivDeform(g::sgDerivDeform(f2(d), fm(J1)), fm(J2)));
    const dvec2 prod = glm::transpose(J1 * J2) * d;
    // Two 2x2 products in binary32 on inputs rounded once: a few ulps of
    // |J1| |J2| |d| (Frobenius norms bound the operator norms).
    auto fro = [](const glm::dmat2& m) {
        return std::sqrt(m[0][0] * m[0][0] + m[0][1] * m[0][1] + m[1][0] * m[1][0] +
                         m[1][1] * m[1][1]);
    };
    RC_ASSERT(glm::length(step - prod) <= 16.0 * kEps * fro(J1) * fro(J2) * glm::length(d) + 1e-30);
    RC_ASSERT(g::sgDerivDeform(f2(d), g::mat2(1.0f)) == f2(d));
    const g::mat2 S = g::sgSineWarpJacobian(
        float(anyMagnitude(-10, 18)), float(anyMagnitude(-10, 18)), float(anyMagnitude(-10, 18)));
    RC_ASSERT(S[0][0] == 1.0f && S[1][0] == 0.0f && S[1][1] == 1.0f);
    RC_ASSERT(std::isfinite(S[0][1]) && std::fabs(S[0][1]) <= 1e18f);
}

} // namespace
