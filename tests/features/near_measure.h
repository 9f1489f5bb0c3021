// Accuracy of the reconstructed distance field against the exact distance
// to the input curves (maps_test_util.h's oracle), by distance from the
// curves: points on every segment, moved along the curve's normal by
// 0.01 / 0.05 / 0.2 / 0.5 / 1 / 2 texels to both sides. Used by the tests
// and shared with nothing in the library.
#pragma once

#include <algorithm>
#include <cstdio>
#include <functional>
#include <vector>

#include "maps_test_util.h"

namespace sgtest {

inline constexpr double kNearOffsets[6] = {0.01, 0.05, 0.2, 0.5, 1.0, 2.0};

struct NearAccuracy {
    std::vector<double> distErr[6];  // |d - exact| per offset
    std::vector<double> angleDeg[6]; // gradient angle to the exact one per offset
    int wrongSide = 0;               // gradients pointing back towards the curve

    size_t samples() const {
        size_t n = 0;
        for (const auto& v : distErr) n += v.size();
        return n;
    }
    static double pct(std::vector<double> v, double q) {
        if (v.empty()) return 0.0;
        std::sort(v.begin(), v.end());
        return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
    }
    std::vector<double> all(const std::vector<double> (&v)[6]) const {
        std::vector<double> out;
        for (const auto& x : v) out.insert(out.end(), x.begin(), x.end());
        return out;
    }
    double distP95() const { return pct(all(distErr), 0.95); }
    double angleP95() const { return pct(all(angleDeg), 0.95); }
    double distMax() const { return pct(all(distErr), 1.0); }
    double angleMax() const { return pct(all(angleDeg), 1.0); }
    void print(const char* name) const {
        std::printf("%s: %zu samples; p95 d error %.2e, gradient %.3f deg (max %.2e, %.2f deg); "
                    "per offset p95 d / deg:",
                    name, samples(), distP95(), angleP95(), distMax(), angleMax());
        for (int k = 0; k < 6; ++k)
            std::printf(" %.4f/%.2f", pct(distErr[k], 0.95), pct(angleDeg[k], 0.95));
        std::printf("; wrong side %d\n", wrongSide);
    }
};

// Junction points: ends of open curves and points where other than two
// segment ends meet (valence != 2).
inline std::vector<dvec2> junctionPoints(const CurveNetwork& net) {
    struct End {
        dvec2 pos;
        int valence;
    };
    std::vector<End> ends;
    auto add = [&](dvec2 q) {
        for (auto& e : ends) {
            if (glm::length(e.pos - q) < 1e-9) {
                ++e.valence;
                return;
            }
        }
        ends.push_back({q, 1});
    };
    for (const auto& s : net.segments) {
        add(s.p0);
        add(s.p2);
    }
    std::vector<dvec2> out;
    for (const auto& e : ends)
        if (e.valence != 2) out.push_back(e.pos);
    return out;
}

// Samples within `band` of the curves (the near field's band), skipping
// points within `junctionSkip` of a junction point and points where the
// nearest curve point is ambiguous (two feet more than 1e-3 apart at
// distances within 1e-6: the gradient has two values there).
inline NearAccuracy measureNear(const CurveNetwork& net, const sg::features::GpuFeatureMaps& g,
                                sg::features::NearMode mode, double junctionSkip, double perTexel,
                                double band = 3.0) {
    NearAccuracy a;
    const std::vector<dvec2> junctions = junctionPoints(net);
    auto nearJunction = [&](dvec2 p) {
        for (const dvec2& j : junctions)
            if (glm::length(p - j) < junctionSkip) return true;
        return false;
    };
    const double n = g.size;
    // Points every 1 / perTexel texels along each segment (by the length of
    // its control polygon, at least 4 per segment).
    auto visit = [&](const std::function<void(dvec2, dvec2)>& fn) {
        for (const Segment& s : net.segments) {
            double len = glm::length(s.p1 - s.p0) + glm::length(s.p2 - s.p1);
            int count = std::max(4, int(std::ceil(len * perTexel)));
            for (int i = 0; i <= count; ++i) {
                double t = double(i) / count;
                fn(bez(s, t), glm::normalize(bezTangent(s, t)));
            }
        }
    };
    visit([&](dvec2 q, dvec2 tan) {
        dvec2 nrm(-tan.y, tan.x);
        for (int k = 0; k < 6; ++k) {
            for (double sd : {-1.0, 1.0}) {
                dvec2 p = q + sd * kNearOffsets[k] * nrm;
                if (p.x < 0 || p.y < 0 || p.x > n || p.y > n) continue;
                if (nearJunction(p)) continue;
                Closest c = closest(net, p);
                if (c.dist > band) continue;
                // Ambiguity: the nearest point of the other segments.
                double second = 1e300;
                dvec2 secondPoint(0.0);
                for (size_t s = 0; s < net.segments.size(); ++s) {
                    if (s == c.segment || segBoxDistance(net.segments[s], p) > second) continue;
                    double t;
                    double d = segDistance(net.segments[s], p, &t);
                    if (d < second) {
                        second = d;
                        secondPoint = bez(net.segments[s], t);
                    }
                }
                bool ambiguous =
                    second - c.dist < 1e-6 && glm::length(secondPoint - c.point) > 1e-3;
                auto r = sg::features::sample(g, glm::vec2(p), mode);
                a.distErr[k].push_back(std::fabs(double(r.dist) - c.dist));
                if (ambiguous || c.dist < 1e-4) continue;
                dvec2 exactGrad = (p - c.point) / c.dist;
                double cosA =
                    std::clamp(exactGrad.x * r.grad.x + exactGrad.y * r.grad.y, -1.0, 1.0);
                a.angleDeg[k].push_back(std::acos(cosA) * 180.0 / M_PI);
                if (cosA <= 0.0) ++a.wrongSide;
            }
        }
    });
    return a;
}

} // namespace sgtest
