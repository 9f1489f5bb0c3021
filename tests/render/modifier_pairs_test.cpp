// Known answers for every ordered pair of derivative-space modifiers of a
// UV layer (shaders/sg/render/deriv_mods.glsl; Loviscach 2008, "Feeding"):
// a tangent-space map with its height in alpha and a mask texture are made
// from analytic fields; the modifiers run exactly as the assembled program
// calls them (render/src/plan.cpp, modifierBlock: the warped lookup
// when DEFORM comes first, then one call per modifier), and the derivative
// must equal that of the analytically transformed height:
//   DEFORM   h(w(s, t)), w = (s, t + A sin(B s))
//   SCALE    alpha h
//   CURVE    atan(sqrt(P) (h - H)) / sqrt(P)
//   MODULATE h * gain * mask(lookup coordinate)
// DEFORM -> MODULATE checks that the mask's derivative is carried through
// the warp's Jacobian like the map's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "surfgrad/render/render_shaders.h"

namespace {

namespace G = sg::glsl;
constexpr double kPi = 3.14159265358979323846;
constexpr int kSize = 256;

// Height (per unit of st) and mask, periodic on [0, 1]^2.
double height(double s, double t) {
    return 0.02 * std::sin(2 * kPi * (3 * s + t)) + 0.012 * std::cos(2 * kPi * (2 * s - 3 * t)) +
           0.05;
}
double mask(double s, double t) {
    return 0.5 + 0.4 * std::sin(2 * kPi * (s + 2 * t) + 0.4);
}
glm::dvec2 grad(const std::function<double(double, double)>& f, double s, double t) {
    const double e = 1e-6;
    return glm::dvec2((f(s + e, t) - f(s - e, t)) / (2 * e), (f(s, t + e) - f(s, t - e)) / (2 * e));
}

// The map: signed normal (SG_ENC_FLOAT) of the height in rgb, the height
// in alpha; the mask in red.
sg::render::TextureImage mapTexture() {
    std::vector<glm::vec4> t(size_t(kSize) * kSize);
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            const double s = (i + 0.5) / kSize, tt = (j + 0.5) / kSize;
            const glm::dvec2 d = grad(height, s, tt);
            const glm::dvec3 n = glm::normalize(glm::dvec3(-d.x, -d.y, 1.0));
            t[size_t(j) * kSize + size_t(i)] =
                glm::vec4(float(n.x), float(n.y), float(n.z), float(height(s, tt)));
        }
    return sg::render::makeTexture(kSize, kSize, std::move(t), sg::render::Wrap::Repeat);
}
sg::render::TextureImage maskTexture() {
    std::vector<glm::vec4> t(size_t(kSize) * kSize);
    for (int j = 0; j < kSize; ++j)
        for (int i = 0; i < kSize; ++i) {
            const float m = float(mask((i + 0.5) / kSize, (j + 0.5) / kSize));
            t[size_t(j) * kSize + size_t(i)] = glm::vec4(m, m, m, 1.0f);
        }
    return sg::render::makeTexture(kSize, kSize, std::move(t), sg::render::Wrap::Repeat);
}

enum Kind { Scale = 1, Curve = 2, Modulate = 3, Deform = 4 };
const char* kNames[] = {"", "scale", "curve", "modulate", "deform"};

// Parameters: SCALE alpha; CURVE P, H; MODULATE mask channel 0, gain;
// DEFORM A, B.
glm::vec4 record(Kind k) {
    switch (k) {
    case Scale:
        return {1.0f, -1.7f, 0.0f, 0.0f};
    case Curve:
        return {2.0f, 400.0f, 0.05f, 0.0f};
    case Modulate:
        return {3.0f, 0.0f, 1.3f, 0.0f};
    default:
        return {4.0f, 0.03f, float(4 * kPi), 0.0f};
    }
}

// The analytic transformed height at (s, t).
double transformed(const std::vector<Kind>& mods, double s, double t) {
    double ls = s, lt = t; // lookup coordinate
    if (!mods.empty() && mods[0] == Deform) lt = t + 0.03 * std::sin(4 * kPi * s);
    double h = height(ls, lt);
    for (Kind k : mods) {
        const glm::vec4 r = record(k);
        if (k == Scale) h *= r.y;
        if (k == Curve) h = std::atan(std::sqrt(double(r.y)) * (h - r.z)) / std::sqrt(double(r.y));
        if (k == Modulate) h *= double(r.z) * mask(ls, lt);
    }
    return h;
}

// The modifier chain as derivModBlock() (render/src/layers/deriv_mods.cpp) emits it.
glm::vec2 chain(const std::vector<Kind>& mods, G::sampler2D map, G::sampler2D maskSmp,
                glm::vec2 st0) {
    G::SgUvNormalParams p;
    p.strength = 1.0f;
    p.encoding = SG_ENC_FLOAT;
    p.flipV = false;
    p.heightChannel = 3;
    p.heightScale = 1.0f;
    // Magnified: derivatives far below a texel, so level 0 is sampled.
    const glm::vec2 dx0(1e-5f, 0.0f), dy0(0.0f, 1e-5f);
    glm::mat2 jac(1.0f);
    glm::vec2 st = st0, dx = dx0, dy = dy0;
    if (mods[0] == Deform) {
        st = G::sgModWarp(record(Deform), st0, jac);
        dx = jac * dx0;
        dy = jac * dy0;
    }
    G::SgHeightDeriv hd = G::sgSampleUvNormalHD(map, st, dx, dy, p);
    for (Kind k : mods) {
        if (k == Deform) hd = G::sgModDeform(hd, jac);
        if (k == Scale) hd = G::sgModScale(hd, record(k));
        if (k == Curve) hd = G::sgModCurve(hd, record(k));
        if (k == Modulate) hd = G::sgModModulate(hd, record(k), maskSmp, st, dx, dy, jac);
    }
    return hd.d;
}

TEST(ModifierPairs, EveryOrderedPairMatchesTheTransformedHeight) {
    const auto mapImg = mapTexture(), maskImg = maskTexture();
    const G::sampler2D map{&mapImg}, maskSmp{&maskImg};
    std::vector<std::vector<Kind>> pairs;
    for (Kind a : {Scale, Curve, Modulate, Deform})
        for (Kind b : {Scale, Curve, Modulate}) pairs.push_back({a, b}); // DEFORM only first
    for (const auto& mods : pairs) {
        double worst = 0, scale = 0;
        for (int k = 0; k < 400; ++k) {
            // Points between texel centres too (bilinear interpolation).
            const double s = 0.0371 + 0.7431 * ((k * 37) % 400) / 400.0,
                         t = 0.0913 + 0.8017 * k / 400.0;
            const glm::dvec2 want =
                grad([&](double a, double b) { return transformed(mods, a, b); }, s, t);
            const glm::vec2 got = chain(mods, map, maskSmp, glm::vec2(float(s), float(t)));
            worst = std::max(worst, glm::length(glm::dvec2(got.x, got.y) - want));
            scale = std::max(scale, glm::length(want));
        }
        const std::string name = std::string(kNames[mods[0]]) + " -> " + kNames[mods[1]];
        std::printf("[ measure  ] %-20s max |d - exact| %.2e (largest |d| %.3f)\n", name.c_str(),
                    worst, scale);
        // Bilinear interpolation of 256^2 texels between centres: the
        // slopes' second derivative (2 pi 4)^2 |d| / 8 per (1/256)^2, 0.2%
        // of |d|; the mask's central differences one texel apart, omega^2 / 6
        // (0.1%); binary32 texels. 1% of the largest slope bounds them; a
        // missing Jacobian (DEFORM -> MODULATE) is off by |A B| |dm| h, tens
        // of percent.
        EXPECT_LT(worst, 0.01 * scale) << name;
    }
}

} // namespace
