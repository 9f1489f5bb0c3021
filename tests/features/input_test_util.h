// Helpers of the feature-curve input tests: exact curve evaluation and a
// sampled Hausdorff distance between an exact curve and the quadratic
// segments that approximate it.
#pragma once

#include "surfgrad/features/curves.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace sg::features::test {

using CurveFn = std::function<glm::dvec2(double)>;

inline glm::dvec2 evalSegment(const Segment& s, double t) {
    const double u = 1.0 - t;
    return u * u * s.p0 + 2.0 * t * u * s.p1 + t * t * s.p2;
}

inline glm::dvec2 evalCubic(const glm::dvec2 c[4], double t) {
    const double u = 1.0 - t;
    return u * u * u * c[0] + 3.0 * u * u * t * c[1] + 3.0 * u * t * t * c[2] + t * t * t * c[3];
}

// Distance from p to f([t0, t1]): `samples` uniform samples, then a
// golden-section search around every sampled local minimum (so the nearest
// branch of a self-intersecting curve is not missed). The result is the
// distance to an actual curve point, so it can only over-estimate the true
// distance: asserting "<= bound" on it is sound.
inline double distToCurve(glm::dvec2 p, const CurveFn& f, double t0, double t1, int samples = 64) {
    std::vector<double> d(std::size_t(samples) + 1);
    for (int i = 0; i <= samples; ++i)
        d[std::size_t(i)] = glm::length(f(t0 + (t1 - t0) * i / samples) - p);
    double best = *std::min_element(d.begin(), d.end());
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int i = 0; i <= samples; ++i) {
        const std::size_t k = std::size_t(i);
        if ((i > 0 && d[k] > d[k - 1]) || (i < samples && d[k] > d[k + 1])) continue;
        double a = t0 + (t1 - t0) * std::max(0, i - 1) / samples;
        double b = t0 + (t1 - t0) * std::min(samples, i + 1) / samples;
        for (int it = 0; it < 60; ++it) {
            const double m1 = b - g * (b - a), m2 = a + g * (b - a);
            if (glm::length(f(m1) - p) < glm::length(f(m2) - p))
                b = m2;
            else
                a = m1;
        }
        best = std::min(best, glm::length(f(0.5 * (a + b)) - p));
    }
    return best;
}

inline double distToSegments(glm::dvec2 p, const std::vector<Segment>& segs) {
    double best = INFINITY;
    for (const Segment& s : segs) {
        // Cheap reject: the segment lies in its control points' hull.
        glm::dvec2 lo = glm::min(s.p0, glm::min(s.p1, s.p2)),
                   hi = glm::max(s.p0, glm::max(s.p1, s.p2));
        const glm::dvec2 q = glm::clamp(p, lo, hi);
        if (glm::length(q - p) >= best) continue;
        best = std::min(best, distToCurve(
                                  p, [&](double t) { return evalSegment(s, t); }, 0.0, 1.0));
    }
    return best;
}

// Two-sided Hausdorff distance between f([0,1]) and the union of segs,
// sampled: `samples` points of f, 64 points of each segment. The maximum
// over samples may miss the exact maximiser by O(spacing^2 * curvature),
// negligible at these densities against the tolerances tested.
inline double hausdorff(const CurveFn& f, const std::vector<Segment>& segs, int samples = 1000) {
    double h = 0.0;
    for (int i = 0; i <= samples; ++i)
        h = std::max(h, distToSegments(f(double(i) / samples), segs));
    for (const Segment& s : segs) {
        for (int j = 0; j <= 64; ++j) {
            h = std::max(h, distToCurve(evalSegment(s, j / 64.0), f, 0.0, 1.0, 400));
        }
    }
    return h;
}

// gtest without gmock (FindGTest of CMake < 3.23 has no GTest::gmock).
#define SG_EXPECT_CONTAINS(haystack, needle)                                                       \
    EXPECT_NE(std::string(haystack).find(needle), std::string::npos)                               \
        << "\"" << (haystack) << "\" does not contain \"" << (needle) << "\""

// Runs fn, expects an InputError whose what() contains `needle`.
template <class Fn>
void expectThrowsWith(Fn&& fn, const std::string& needle) {
    try {
        fn();
        ADD_FAILURE() << "no error; expected one containing \"" << needle << "\"";
    } catch (const std::runtime_error& e) {
        SG_EXPECT_CONTAINS(e.what(), needle);
    }
}

// Segments of one curve.
inline std::vector<Segment> curveSegments(const CurveNetwork& net, int curve) {
    std::vector<Segment> out;
    for (const Segment& s : net.segments) {
        if (s.curve == curve) out.push_back(s);
    }
    return out;
}

inline std::string dataDir() {
    const char* env = std::getenv("SURFGRAD_DATA_DIR");
    return env && *env ? env : SURFGRAD_DATA_DIR;
}

inline std::string sourceDir() {
    return SURFGRAD_SOURCE_DIR;
}

// System font installed by scripts/setup-deps; the test fails (never skips)
// when it is missing.
inline std::string systemFont(const char* path) {
    EXPECT_TRUE(std::filesystem::exists(path)) << path << " missing: run scripts/setup-deps";
    return path;
}

} // namespace sg::features::test
