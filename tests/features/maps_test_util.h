// Helpers of the feature-map tests: networks built in texel space, and an
// exact-distance oracle in double that shares no code with the bake (dense
// sampling of each segment, then golden-section refinement around the best
// samples).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "surfgrad/features/feature_maps.h"

namespace sgtest {

using glm::dvec2;
using sg::features::CurveNetwork;
using sg::features::Segment;

inline dvec2 bez(const Segment& s, double t) {
    double u = 1.0 - t;
    return u * u * s.p0 + 2.0 * t * u * s.p1 + t * t * s.p2;
}
inline dvec2 bezTangent(const Segment& s, double t) {
    return 2.0 * (1.0 - t) * (s.p1 - s.p0) + 2.0 * t * (s.p2 - s.p1);
}

// Builds networks curve by curve.
struct NetBuilder {
    CurveNetwork net;
    int curve = -1;
    void begin(bool closed = false) {
        net.curves.push_back({});
        net.curves.back().closed = closed;
        curve = int(net.curves.size()) - 1;
    }
    void line(dvec2 a, dvec2 b) {
        Segment s;
        s.kind = Segment::Kind::Line;
        s.p0 = a;
        s.p2 = b;
        s.p1 = 0.5 * (a + b);
        s.curve = curve;
        net.segments.push_back(s);
    }
    void quad(dvec2 a, dvec2 c, dvec2 b) {
        Segment s;
        s.kind = Segment::Kind::Quadratic;
        s.p0 = a;
        s.p1 = c;
        s.p2 = b;
        s.curve = curve;
        net.segments.push_back(s);
    }
    // Polyline as one curve.
    void polyline(const std::vector<dvec2>& pts, bool closed = false) {
        begin(closed);
        for (size_t k = 0; k + 1 < pts.size(); ++k) line(pts[k], pts[k + 1]);
        if (closed) line(pts.back(), pts.front());
    }
    // Circle of n quadratic arcs (control point at the tangent intersection).
    void circle(dvec2 c, double r, int n = 12, double phase = 0.1) {
        begin(true);
        for (int k = 0; k < n; ++k) {
            double a0 = phase + 2 * M_PI * k / n, a1 = phase + 2 * M_PI * (k + 1) / n,
                   am = 0.5 * (a0 + a1);
            dvec2 p0 = c + r * dvec2(std::cos(a0), std::sin(a0));
            dvec2 p2 = c + r * dvec2(std::cos(a1), std::sin(a1));
            if (k + 1 == n) p2 = c + r * dvec2(std::cos(phase), std::sin(phase));
            quad(p0, c + r / std::cos(M_PI / n) * dvec2(std::cos(am), std::sin(am)), p2);
        }
    }
};

// Exact distance from p to segment s (double): dense samples, then
// golden-section refinement of |B(t) - p|^2 around the three best samples.
inline double segDistance(const Segment& s, dvec2 p, double* tOut = nullptr) {
    const int n = 64;
    std::vector<double> d2(n + 1);
    for (int i = 0; i <= n; ++i) {
        dvec2 q = bez(s, double(i) / n) - p;
        d2[size_t(i)] = glm::dot(q, q);
    }
    double best = 1e300, bestT = 0;
    for (int i = 0; i <= n; ++i) {
        bool localMin = (i == 0 || d2[size_t(i)] <= d2[size_t(i - 1)]) &&
                        (i == n || d2[size_t(i)] <= d2[size_t(i + 1)]);
        if (!localMin) continue;
        double a = std::max(0.0, double(i - 1) / n), b = std::min(1.0, double(i + 1) / n);
        const double g = 0.5 * (std::sqrt(5.0) - 1.0);
        auto f = [&](double t) {
            dvec2 q = bez(s, t) - p;
            return glm::dot(q, q);
        };
        double x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = f(x1), f2 = f(x2);
        for (int it = 0; it < 80; ++it) {
            if (f1 < f2) {
                b = x2;
                x2 = x1;
                f2 = f1;
                x1 = b - g * (b - a);
                f1 = f(x1);
            } else {
                a = x1;
                x1 = x2;
                f1 = f2;
                x2 = a + g * (b - a);
                f2 = f(x2);
            }
        }
        for (double t : {a, b, 0.5 * (a + b), double(i) / n}) {
            double v = f(t);
            if (v < best) {
                best = v;
                bestT = t;
            }
        }
    }
    if (tOut) *tOut = bestT;
    return std::sqrt(best);
}

struct Closest {
    double dist = 1e300;
    dvec2 point{0.0};
    dvec2 tangent{1.0, 0.0};
    size_t segment = 0;
    double t = 0.0;
};

// Lower bound of the distance from p to segment s: the distance to the box
// of its control points (the curve lies in their convex hull).
inline double segBoxDistance(const Segment& s, dvec2 p) {
    dvec2 lo = glm::min(glm::min(s.p0, s.p1), s.p2), hi = glm::max(glm::max(s.p0, s.p1), s.p2);
    return glm::length(glm::max(glm::max(lo - p, p - hi), dvec2(0.0)));
}

inline Closest closest(const CurveNetwork& net, dvec2 p) {
    Closest c;
    for (size_t k = 0; k < net.segments.size(); ++k) {
        if (segBoxDistance(net.segments[k], p) > c.dist) continue; // cannot be closer
        double t;
        double d = segDistance(net.segments[k], p, &t);
        if (d < c.dist) {
            c.dist = d;
            c.segment = k;
            c.t = t;
            c.point = bez(net.segments[k], t);
            c.tangent = glm::normalize(bezTangent(net.segments[k], t));
        }
    }
    return c;
}

// Half the gap between p's nearest curve point (on curve `curve`, at
// distance d1) and the nearest point of any OTHER curve (dense sampling):
// a lower bound of p's distance to the medial axis between different
// curves. The maps smooth the gradient across medial axes (TOG 2008
// sec. 4), so gradient checks keep away from them; networks in the gradient
// tests are convex or gently curved, so a curve's own medial axis is far.
inline double otherCurveClearance(const CurveNetwork& net, dvec2 p, int curve, double d1) {
    double d2 = 1e300;
    for (const auto& s : net.segments) {
        if (s.curve == curve) continue;
        for (int i = 0; i <= 96; ++i) d2 = std::min(d2, glm::length(bez(s, i / 96.0) - p));
    }
    return 0.5 * (d2 - d1);
}

inline sg::features::BakeOptions texelSpace(int size, sg::features::BakeMode mode) {
    sg::features::BakeOptions o;
    o.size = size;
    o.mode = mode;
    o.fit = false;
    return o;
}

inline bool finite(const sg::glsl::SgFeatResult& r) {
    return std::isfinite(r.dist) && std::isfinite(r.grad.x) && std::isfinite(r.grad.y) &&
           std::isfinite(r.side);
}

// Samples the whole map on a grid (including texel borders, corners and a
// margin outside the map) and fails on any non-finite result, negative
// distance or gradient that is neither unit nor zero.
inline void expectAllFinite(const sg::features::GpuFeatureMaps& g, int perTexel = 4) {
    const int n = g.size;
    int bad = 0;
    for (int j = -perTexel; j <= n * perTexel + perTexel; ++j) {
        for (int i = -perTexel; i <= n * perTexel + perTexel; ++i) {
            glm::vec2 p(float(i) / float(perTexel), float(j) / float(perTexel));
            auto r = sg::features::sample(g, p);
            float gl = std::sqrt(r.grad.x * r.grad.x + r.grad.y * r.grad.y);
            // Unit gradient up to binary32 normalization (a few ulps), or 0.
            bool ok = finite(r) && r.dist >= 0.0f && (gl == 0.0f || std::fabs(gl - 1.0f) < 1e-5f) &&
                      (r.side == 1.0f || r.side == -1.0f);
            if (!ok && bad++ < 5)
                ADD_FAILURE() << "bad sample at " << p.x << ", " << p.y << ": d " << r.dist;
        }
    }
    EXPECT_EQ(bad, 0);
}

// Points along every input curve, skipping `skip(p)` ones.
inline void forCurvePoints(const CurveNetwork& net, int perSegment,
                           const std::function<void(dvec2 p, dvec2 unitTangent, size_t seg)>& fn) {
    for (size_t k = 0; k < net.segments.size(); ++k) {
        for (int i = 0; i <= perSegment; ++i) {
            double t = double(i) / perSegment;
            fn(bez(net.segments[k], t), glm::normalize(bezTangent(net.segments[k], t)), k);
        }
    }
}

// Distance from p to the nearest "special point": an end of an open curve,
// a junction of valence != 2, or a kink (segments meeting at an angle above
// 1e-4 radians). The maps cannot reproduce these exactly: curves end on texel
// boundaries, a texel holds at most two segments, and a segment spans a
// whole texel, so a corner inside a texel is cut (by at most the corner's
// distance from the chord of the texel's piece).
inline double distToSpecialPoint(const CurveNetwork& net, dvec2 p) {
    struct End {
        dvec2 pos;
        int valence;
        std::vector<dvec2> dirs; // unit directions leaving the point
    };
    std::vector<End> ends;
    auto add = [&](dvec2 q, dvec2 dir) {
        dir = glm::normalize(dir);
        for (auto& e : ends) {
            if (glm::length(e.pos - q) < 1e-9) {
                ++e.valence;
                e.dirs.push_back(dir);
                return;
            }
        }
        ends.push_back({q, 1, {dir}});
    };
    for (const auto& s : net.segments) {
        add(s.p0, bezTangent(s, 0.0));
        add(s.p2, -bezTangent(s, 1.0));
    }
    double best = 1e300;
    for (const auto& e : ends) {
        bool special = e.valence != 2 || glm::dot(e.dirs[0], e.dirs[1]) > -std::cos(1e-4);
        if (special) best = std::min(best, glm::length(e.pos - p));
    }
    return best;
}

} // namespace sgtest
