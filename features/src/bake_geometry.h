// Double-precision quadratic Bezier geometry for the feature-map bake
// (internal to features/src): evaluation, roots, exact point-curve
// distance. Texel-space positions (surfgrad/features/feature_maps.h).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace sg::features::detail {

using dvec2 = glm::dvec2;

inline double cross2(dvec2 a, dvec2 b) {
    return a.x * b.y - a.y * b.x;
}

// B(u) = (1-u)^2 p0 + 2u(1-u) p1 + u^2 p2 = p0 + b u + a u^2.
struct Quad {
    dvec2 p0{0.0}, p1{0.0}, p2{0.0};
    dvec2 a() const { return p0 - 2.0 * p1 + p2; }
    dvec2 b() const { return 2.0 * (p1 - p0); }
    // Power form p0 + u (b + u a): exact for a coordinate that is constant
    // along the curve (a and b vanish there), which the Bernstein form is
    // not; the scan conversion relies on it for curves along grid lines.
    dvec2 at(double u) const { return p0 + u * (b() + u * a()); }
    dvec2 tangent(double u) const { return b() + 2.0 * u * a(); } // B'(u)
    Quad reversed() const { return {p2, p1, p0}; }
    // Restriction to [u0, u1] (blossoming).
    Quad sub(double u0, double u1) const {
        dvec2 mid = (1 - u0) * (1 - u1) * p0 + ((1 - u0) * u1 + u0 * (1 - u1)) * p1 + u0 * u1 * p2;
        return {at(u0), mid, at(u1)};
    }
};

// Real roots of A x^2 + B x + C = 0 (numerically stable); returns the count
// (0..2). A degenerate (A == 0) equation gives its linear root; an identity
// (all zero) gives none.
inline int quadRoots(double A, double B, double C, double r[2]) {
    double scale = std::max({std::fabs(A), std::fabs(B), std::fabs(C)});
    if (scale == 0.0) return 0;
    if (std::fabs(A) <= 1e-14 * scale) {
        if (std::fabs(B) <= 1e-14 * scale) return 0;
        r[0] = -C / B;
        return 1;
    }
    double disc = B * B - 4.0 * A * C;
    if (disc < 0.0) return 0;
    double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
    if (q == 0.0) {
        r[0] = 0.0;
        return 1;
    }
    r[0] = q / A;
    r[1] = C / q;
    if (r[0] > r[1]) std::swap(r[0], r[1]);
    return 2;
}

// Real roots of c3 x^3 + c2 x^2 + c1 x + c0 in [0, 1], polished by Newton.
inline int cubicRootsUnit(double c3, double c2, double c1, double c0, double r[3]) {
    int n = 0;
    double scale = std::max({std::fabs(c3), std::fabs(c2), std::fabs(c1), std::fabs(c0)});
    if (scale == 0.0) return 0;
    auto push = [&](double x) {
        if (!(x >= -1e-9 && x <= 1.0 + 1e-9)) return;
        x = std::clamp(x, 0.0, 1.0);
        for (int it = 0; it < 3; ++it) {
            double f = ((c3 * x + c2) * x + c1) * x + c0;
            double df = (3 * c3 * x + 2 * c2) * x + c1;
            if (df == 0.0) break;
            double nx = std::clamp(x - f / df, 0.0, 1.0);
            if (nx == x) break;
            x = nx;
        }
        r[n++] = x;
    };
    if (std::fabs(c3) <= 1e-12 * scale) {
        double q[2];
        int k = quadRoots(c2, c1, c0, q);
        for (int i = 0; i < k; ++i) push(q[i]);
        return n;
    }
    // Depressed cubic t^3 + p t + q with x = t - b/3.
    double b = c2 / c3, c = c1 / c3, d = c0 / c3;
    double p = c - b * b / 3.0;
    double q = 2.0 * b * b * b / 27.0 - b * c / 3.0 + d;
    double off = -b / 3.0;
    double disc = q * q / 4.0 + p * p * p / 27.0;
    if (disc > 0.0) {
        double s = std::sqrt(disc);
        push(std::cbrt(-q / 2.0 + s) + std::cbrt(-q / 2.0 - s) + off);
    } else if (p == 0.0) {
        push(off);
    } else {
        double m = 2.0 * std::sqrt(-p / 3.0);
        double arg = std::clamp(3.0 * q / (p * m), -1.0, 1.0);
        double th = std::acos(arg) / 3.0;
        for (int k = 0; k < 3; ++k) push(m * std::cos(th - 2.0 * M_PI * k / 3.0) + off);
    }
    return n;
}

// Closest point of the curve (straight when `line`) to p: returns the
// squared distance and the parameter.
inline double closestParam(const Quad& c, bool line, dvec2 p, double& uBest) {
    dvec2 d0 = c.p0 - p;
    if (line) {
        dvec2 e = c.p2 - c.p0;
        double ee = glm::dot(e, e);
        double u = ee > 0.0 ? std::clamp(-glm::dot(d0, e) / ee, 0.0, 1.0) : 0.0;
        dvec2 x = d0 + u * e;
        uBest = u;
        return glm::dot(x, x);
    }
    dvec2 a = c.a(), b = c.b();
    // d/du |B(u) - p|^2 / 2 = (d0 + b u + a u^2) . (b + 2 a u)
    double c3 = 2.0 * glm::dot(a, a);
    double c2 = 3.0 * glm::dot(a, b);
    double c1 = glm::dot(b, b) + 2.0 * glm::dot(a, d0);
    double c0 = glm::dot(b, d0);
    double roots[3];
    int n = cubicRootsUnit(c3, c2, c1, c0, roots);
    double best = glm::dot(d0, d0);
    uBest = 0.0;
    dvec2 e1 = c.p2 - p;
    if (glm::dot(e1, e1) < best) {
        best = glm::dot(e1, e1);
        uBest = 1.0;
    }
    for (int i = 0; i < n; ++i) {
        dvec2 x = c.at(roots[i]) - p;
        double dd = glm::dot(x, x);
        if (dd < best) {
            best = dd;
            uBest = roots[i];
        }
    }
    return best;
}

inline double wrapAngle(double theta) {
    // Line direction: reduce to [-pi/2, pi/2].
    while (theta > M_PI / 2) theta -= M_PI;
    while (theta < -M_PI / 2) theta += M_PI;
    return theta;
}

} // namespace sg::features::detail
