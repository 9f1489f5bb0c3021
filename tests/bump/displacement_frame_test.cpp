// Mikkelsen 2019, section 2.5: a bump layer of the same height field as a
// displacement must take dPdx/dPdy of the surface BEFORE displacement (and
// the base normal before displacement). Measured here on a displaced
// cylinder with the shared prologue and listing 8's screen-space surface
// gradient (sg/frame.glsl, sg/surfgrad.glsl: what the fragment program
// runs), against the exact normal of the displaced surface:
//   (a) frame before displacement (what the renderer does: vRelPos is the
//       undisplaced position, sg/patch/patch_tes.glsl);
//   (b) dPdx/dPdy after displacement, base normal before;
//   (c) dPdx/dPdy and base normal after displacement: the bump is added a
//       second time on a surface that already has it.
// Finding: (a) carries bump mapping's usual approximation (it drops the
// height times the base curvature), (b) is exact, (c) is off by about the
// slope's angle: section 2.5's failure is (c), using the displaced surface
// for the bump of the height that displaced it.
// The same numbers are in docs/mesh.md ("Displacement").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "surfgrad/bump/core.h"

namespace {

namespace g = sg::glsl;

struct Errors {
    double p50 = 0, p99 = 0, max = 0;
};

Errors stats(std::vector<double> deg) {
    std::sort(deg.begin(), deg.end());
    Errors e;
    e.p50 = deg[deg.size() / 2];
    e.p99 = deg[size_t(0.99 * double(deg.size()))];
    e.max = deg.back();
    return e;
}

double angleDeg(glm::dvec3 a, glm::dvec3 b) {
    const double c = std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0);
    return std::acos(c) * 180.0 / M_PI;
}

// Cylinder of radius R about the y axis, P(u, v) = (R sin u, v, R cos u),
// displaced by s * h along its normal, h = sin(k u R) sin(k v) (a bump of
// wavelength 2 pi / k in both directions, amplitude s), seen orthographically
// along -z (screen x, y = world x, y of the displaced surface, one unit per
// pixel: only the ratios matter).
struct Study {
    double radius, amp, k;

    void at(double u, double v, std::vector<double> (&err)[3]) const {
        const glm::dvec3 N(std::sin(u), 0.0, std::cos(u));
        const glm::dvec3 Pu = radius * glm::dvec3(std::cos(u), 0.0, -std::sin(u)), Pv(0, 1, 0);
        const glm::dvec3 Nu = glm::dvec3(std::cos(u), 0.0, -std::sin(u));
        const double h = std::sin(k * u * radius) * std::sin(k * v);
        const double hu = k * radius * std::cos(k * u * radius) * std::sin(k * v);
        const double hv = k * std::sin(k * u * radius) * std::cos(k * v);
        const glm::dvec3 Du = Pu + amp * hu * N + amp * h * Nu, Dv = Pv + amp * hv * N;
        const glm::dvec3 truth = glm::normalize(glm::cross(Du, Dv));
        // Screen -> parameter Jacobian of the displaced surface.
        const double a = Du.x, b = Dv.x, c = Du.y, d = Dv.y, det = a * d - b * c;
        if (std::abs(det) < 1e-3 * glm::length(Du) * glm::length(Dv)) return; // silhouette
        const double uX = d / det, vX = -c / det, uY = -b / det, vY = a / det;
        const glm::dvec3 dPdxBase = Pu * uX + Pv * vX, dPdyBase = Pu * uY + Pv * vY;
        const glm::dvec3 dPdxDisp = Du * uX + Dv * vX, dPdyDisp = Du * uY + Dv * vY;
        const glm::dvec2 dHdxy(amp * (hu * uX + hv * vX), amp * (hu * uY + hv * vY));
        auto shade = [&](glm::dvec3 n, glm::dvec3 px, glm::dvec3 py) {
            const g::SgFrame f = g::sgPrologue(glm::vec3(n), glm::vec3(px), glm::vec3(py), true, 0);
            const glm::vec3 sgr = g::sgSurfgradFromScreenDeriv(f, glm::vec2(dHdxy));
            return glm::dvec3(g::sgResolve(f, sgr));
        };
        err[0].push_back(angleDeg(shade(N, dPdxBase, dPdyBase), truth));
        err[1].push_back(angleDeg(shade(N, dPdxDisp, dPdyDisp), truth));
        err[2].push_back(angleDeg(shade(truth, dPdxDisp, dPdyDisp), truth));
    }

    void run(Errors (&out)[3]) const {
        std::vector<double> err[3];
        const int n = 200;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                at(-1.2 + 2.4 * (i + 0.5) / n, -1.0 + 2.0 * (j + 0.5) / n, err);
        for (int c = 0; c < 3; ++c) out[c] = stats(err[c]);
    }
};

TEST(DisplacementFrame, BumpOfTheSameHeightNeedsTheFrameBeforeDisplacement) {
    // Amplitude relative to the radius (curvature 1/R) and the bump's slope
    // amp * k (the tilt of the displaced normal).
    struct Row {
        double radius, amp, k;
    };
    const Row rows[] = {{1.0, 0.01, 10.0},
                        {1.0, 0.02, 25.0},
                        {1.0, 0.05, 10.0},
                        {1.0, 0.05, 20.0},
                        {0.2, 0.02, 25.0}};
    std::printf("| R | amplitude | slope amp*k | (a) before: p50 / p99 / max deg | (b) dPdx "
                "after: p50 / p99 / max | (c) dPdx and normal after: p50 / p99 / max |\n");
    for (const Row& r : rows) {
        Errors e[3];
        Study{r.radius, r.amp, r.k}.run(e);
        std::printf("| %.1f | %.2f | %.2f | %.3f / %.3f / %.3f | %.3f / %.3f / %.3f | %.2f / "
                    "%.2f / %.2f |\n",
                    r.radius, r.amp, r.amp * r.k, e[0].p50, e[0].p99, e[0].max, e[1].p50, e[1].p99,
                    e[1].max, e[2].p50, e[2].p99, e[2].max);
        // (a): the bump normal differs from the displaced surface's by the
        // term bump mapping drops (s h dN/du, relative size amp / R) and
        // the ratios of metric it ignores: a fraction of the slope's angle
        // (bound: a fifth of atan(amp * k) at the 99th percentile).
        const double tilt = std::atan(r.amp * r.k) * 180.0 / M_PI;
        EXPECT_LE(e[0].p99, 0.2 * tilt);
        // (b) is exact up to rounding here: the displaced derivatives'
        // tangential parts sigma_x, sigma_y plus dH/dx, dH/dy along the base
        // normal are the displaced surface's derivatives exactly (N . dP'/dx
        // = dH/dx), so listing 8 rebuilds its normal (bound 1e-3 degrees:
        // binary32 rounding of unit vectors).
        EXPECT_LE(e[1].max, 1e-3);
        // (c) double-counts the slope: the error is about the tilt itself,
        // far above (a).
        EXPECT_GT(e[2].p50, 3.0 * e[0].p50);
        EXPECT_GT(e[2].p99, 0.5 * tilt);
    }
}

} // namespace
