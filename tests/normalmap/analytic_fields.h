// Analytic height fields for the normal-map toolkit's tests and benchmark:
// heights and exact slopes at texel centres, in texel units (the
// conventions of surfgrad/normalmap/operations.h), evaluated in double.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "surfgrad/normalmap/operations.h"

namespace sg::normalmap::test {

constexpr double kPi = 3.14159265358979323846;

// h(u, v) and its gradient (dh/du, dh/dv) at any point (texel units).
struct Field {
    std::function<double(double, double)> h;
    std::function<glm::dvec2(double, double)> grad;
};

// Sum of sines, one period of each over a W x H tile (tileable):
// h = sum a_k sin(2 pi (p_k u / W + q_k v / H) + phase_k).
inline Field sines(int W, int H, double amplitude) {
    struct Wave {
        double a, p, q, phase;
    };
    const std::vector<Wave> waves = {{1.0, 2, 1, 0.3}, {0.6, -1, 3, 1.1}, {0.35, 4, -3, 2.0}};
    Field f;
    f.h = [=](double u, double v) {
        double s = 0;
        for (const auto& w : waves) {
            s += amplitude * w.a * std::sin(2 * kPi * (w.p * u / W + w.q * v / H) + w.phase);
        }
        return s;
    };
    f.grad = [=](double u, double v) {
        glm::dvec2 g(0.0);
        for (const auto& w : waves) {
            const double c = amplitude * w.a * 2 * kPi *
                             std::cos(2 * kPi * (w.p * u / W + w.q * v / H) + w.phase);
            g += c * glm::dvec2(w.p / W, w.q / H);
        }
        return g;
    };
    return f;
}

// A Gaussian bump of height `amplitude` and width sigma = W / 12 at the
// centre (6 sigma from the borders: below 2e-8 of its peak there, so it
// tiles to that).
inline Field gaussian(int W, int H, double amplitude) {
    const double cx = 0.5 * W, cy = 0.5 * H, s = W / 12.0;
    Field f;
    f.h = [=](double u, double v) {
        const double r2 = (u - cx) * (u - cx) + (v - cy) * (v - cy);
        return amplitude * std::exp(-r2 / (2 * s * s));
    };
    f.grad = [=](double u, double v) {
        const double r2 = (u - cx) * (u - cx) + (v - cy) * (v - cy);
        const double e = amplitude * std::exp(-r2 / (2 * s * s));
        return glm::dvec2(-(u - cx) / (s * s) * e, -(v - cy) / (s * s) * e);
    };
    return f;
}

// A crease: a roof h = slope * (H / 4 - |v - H / 2|) across v, slope
// discontinuous at v = H / 2 (a ridge) and at the tile border (a valley);
// texel centres never sit on either, so the sampled slopes are +-slope.
inline Field crease(int H, double slope) {
    // Evaluated periodically (v wrapped into [0, H)): it tiles.
    auto wrapV = [H](double v) { return v - H * std::floor(v / H); };
    Field f;
    f.h = [=](double, double v) { return slope * (H / 4.0 - std::abs(wrapV(v) - H / 2.0)); };
    f.grad = [=](double, double v) { return glm::dvec2(0.0, wrapV(v) < H / 2.0 ? slope : -slope); };
    return f;
}

inline DerivField slopes(const Field& f, int W, int H) {
    DerivField d(W, H);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const glm::dvec2 g = f.grad(i + 0.5, j + 0.5);
            d.at(i, j) = glm::vec2(float(g.x), float(g.y));
        }
    return d;
}

inline ScalarField heights(const Field& f, int W, int H) {
    ScalarField s(W, H);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) s.at(i, j) = float(f.h(i + 0.5, j + 0.5));
    return s;
}

// Heights measured from their lowest texel (the library's convention).
inline ScalarField heightsFromMin(const Field& f, int W, int H) {
    ScalarField s = heights(f, W, H);
    const float lo = *std::min_element(s.v.begin(), s.v.end());
    for (float& x : s.v) x -= lo;
    return s;
}

// Angle in degrees between the normals normalize(-a, 1) and normalize(-b, 1).
inline double angleDeg(glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec3 na(-a.x, -a.y, 1.0), nb(-b.x, -b.y, 1.0);
    return std::atan2(glm::length(glm::cross(na, nb)), glm::dot(na, nb)) * 180.0 / kPi;
}
inline double angleDeg(glm::dvec3 a, glm::dvec3 b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * 180.0 / kPi;
}

struct AngleError {
    double maxDeg = 0.0, rmsDeg = 0.0;
};

// Angular error of slopes (or normals) against exact slopes, over texels
// at least `margin` texels from the border.
inline AngleError compare(const DerivField& got, const std::vector<glm::dvec2>& want,
                          int margin = 0) {
    AngleError e;
    double sum = 0;
    size_t n = 0;
    for (int j = margin; j < got.height - margin; ++j)
        for (int i = margin; i < got.width - margin; ++i) {
            const glm::vec2 g = got.at(i, j);
            const double a =
                angleDeg(glm::dvec2(g.x, g.y), want[size_t(j) * size_t(got.width) + size_t(i)]);
            e.maxDeg = std::max(e.maxDeg, a);
            sum += a * a;
            ++n;
        }
    e.rmsDeg = std::sqrt(sum / double(std::max<size_t>(n, 1)));
    return e;
}
inline AngleError compare(const NormalField& got, const std::vector<glm::dvec2>& want,
                          int margin = 0) {
    AngleError e;
    double sum = 0;
    size_t n = 0;
    for (int j = margin; j < got.height - margin; ++j)
        for (int i = margin; i < got.width - margin; ++i) {
            const glm::dvec2 w = want[size_t(j) * size_t(got.width) + size_t(i)];
            const glm::vec3 g = got.at(i, j);
            const double a = angleDeg(glm::dvec3(g.x, g.y, g.z), glm::dvec3(-w.x, -w.y, 1.0));
            e.maxDeg = std::max(e.maxDeg, a);
            sum += a * a;
            ++n;
        }
    e.rmsDeg = std::sqrt(sum / double(std::max<size_t>(n, 1)));
    return e;
}

// Exact slopes of a transformed height at every texel centre.
inline std::vector<glm::dvec2> exact(int W, int H,
                                     const std::function<glm::dvec2(double, double)>& g) {
    std::vector<glm::dvec2> out(size_t(W) * size_t(H));
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) out[size_t(j) * size_t(W) + size_t(i)] = g(i + 0.5, j + 0.5);
    return out;
}

} // namespace sg::normalmap::test
