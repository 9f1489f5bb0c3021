// Parity-record generators of the feature-curve kernels (see kernel_inputs.h
// and the kernel list in shaders/sg/features/kernels.glsl). Deterministic
// for a seed; each returns whole records of kEvalInStride floats.
#include "kernel_inputs.h"

#include "bake_geometry.h"

#include <cmath>
#include <random>

namespace sg::features::detail {

namespace {

Segment makeSegment(dvec2 a, dvec2 c, dvec2 b, bool line, int curve) {
    Segment s;
    s.kind = line ? Segment::Kind::Line : Segment::Kind::Quadratic;
    s.p0 = a;
    s.p1 = line ? 0.5 * (a + b) : c;
    s.p2 = b;
    s.curve = curve;
    return s;
}

// A network exercising every configuration the bake produces: circles,
// polylines, an eight-ray star, tight arcs (Eq. 7 repairs), curves on grid
// lines; texel space of a 32^2 map.
CurveNetwork configurationNetwork(uint32_t seed) {
    CurveNetwork net;
    auto curve = [&]() {
        net.curves.push_back({});
        return int(net.curves.size()) - 1;
    };
    auto circle = [&](dvec2 c, double r, int n, double phase) {
        int id = curve();
        net.curves.back().closed = true;
        for (int k = 0; k < n; ++k) {
            double a0 = phase + 2 * M_PI * k / n, a1 = phase + 2 * M_PI * (k + 1) / n,
                   am = 0.5 * (a0 + a1);
            dvec2 p0 = c + r * dvec2(std::cos(a0), std::sin(a0));
            dvec2 p2 = c + r * dvec2(std::cos(a1), std::sin(a1));
            if (k + 1 == n) p2 = net.segments[net.segments.size() - size_t(k)].p0;
            net.segments.push_back(makeSegment(
                p0, c + r / std::cos(M_PI / n) * dvec2(std::cos(am), std::sin(am)), p2, false, id));
        }
    };
    circle({10.3, 11.7}, 6.2, 10, 0.1);
    circle({24.1, 22.6}, 3.1, 8, 0.4);
    net.segments.push_back(makeSegment({2.0, 2.0}, {}, {30.0, 30.0}, true, curve()));
    net.segments.push_back(makeSegment({1.5, 20.0}, {}, {30.5, 20.0}, true, curve()));
    dvec2 c(20.37, 8.61);
    for (int k = 0; k < 8; ++k) {
        double a = 0.3 + 0.785 * k;
        net.segments.push_back(
            makeSegment(c, {}, c + 6.0 * dvec2(std::cos(a), std::sin(a)), true, curve()));
    }
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 12; ++k) {
        dvec2 cc(4.0 + 24.0 * u(rng), 4.0 + 24.0 * u(rng));
        double r = 0.4 + u(rng), a0 = 6.28 * u(rng), sw = 0.6 + 1.8 * u(rng);
        net.segments.push_back(makeSegment(
            cc + r * dvec2(std::cos(a0), std::sin(a0)),
            cc + r / std::cos(sw / 2) * dvec2(std::cos(a0 + sw / 2), std::sin(a0 + sw / 2)),
            cc + r * dvec2(std::cos(a0 + sw), std::sin(a0 + sw)), false, curve()));
    }
    return net;
}

} // namespace

std::vector<float> kernelInputsEval(uint32_t seed) {
    CurveNetwork net = configurationNetwork(seed);
    std::vector<float> out;
    std::vector<float> rec(static_cast<size_t>(kEvalInStride)),
        res(static_cast<size_t>(kEvalOutStride));
    std::mt19937 rng(seed + 1);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (BakeMode mode : {BakeMode::Quadratic, BakeMode::Linear}) {
        BakeOptions o;
        o.size = 32;
        o.mode = mode;
        o.fit = false;
        const FeatureMaps m = bake(net, o);
        const GpuFeatureMaps g = m.packGpu();
        // Every texel with features at 9 boundary and 40 random points, and
        // every seventh plain texel at 4.
        for (int j = 0; j < m.size; ++j) {
            for (int i = 0; i < m.size; ++i) {
                bool feat = (m.configWord(i, j) & 0xFFFFu) != 0;
                if (!feat && (i + j) % 7) continue;
                for (int s = 0; s < (feat ? 49 : 4); ++s) {
                    glm::vec2 p = s < 9 ? glm::vec2(float(s % 3) * 0.5f, float(s / 3) * 0.5f)
                                        : glm::vec2(u(rng), u(rng));
                    packEvalRecord(g, i, j, p, rec.data());
                    // Within 1e-3 texels of a curve the side is decided by
                    // rounding (FMA contraction moves the point by ~1e-7).
                    evalKernelCpu(SG_FEAT_K_EVAL, rec.data(), res.data());
                    if (res[0] < 1e-3f) continue;
                    out.insert(out.end(), rec.begin(), rec.end());
                }
            }
        }
    }
    return out;
}

std::vector<float> kernelInputsProfile(uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const size_t n = 12000;
    std::vector<float> out(n * size_t(kEvalInStride));
    const auto& layout = kernels()[SG_FEAT_K_PROFILE].in;
    for (size_t k = 0; k < n; ++k) {
        RecordWriter r(layout, &out[k * size_t(kEvalInStride)]);
        float w = 0.5f + 6.0f * u(rng);
        r.set("dist", 1.3f * w * u(rng));
        float a = 6.2832f * u(rng);
        r.set("grad", glm::vec2(std::cos(a), std::sin(a)));
        r.set("side", u(rng) < 0.5f ? -1.0f : 1.0f);
        r.set("kind", float(k % SG_FEAT_PROFILE_COUNT));
        r.set("depth", 4.0f * u(rng) - 2.0f);
        r.set("w0", w * u(rng) * 0.8f);
        r.set("w", w);
        r.set("tableCount", float(2 + k % 15));
        for (const char* t : {"table0", "table1", "table2", "table3"}) {
            r.set(t, glm::vec4(2.0f * u(rng) - 1.0f, 2.0f * u(rng) - 1.0f, 2.0f * u(rng) - 1.0f,
                               2.0f * u(rng) - 1.0f));
        }
        r.set("baseDeriv", glm::vec2(u(rng) - 0.5f, u(rng) - 0.5f));
        r.set("baseNormal", glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, 1.0f)));
    }
    return out;
}

std::vector<float> kernelInputsNearPiece(uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const auto& layout = kernels()[SG_FEAT_K_NEAR_PIECE].in;
    std::vector<float> out;
    std::vector<float> rec(static_cast<size_t>(kEvalInStride));
    while (out.size() < 20000 * size_t(kEvalInStride)) {
        // Pieces from 0.05 to 30 texels, tight to nearly straight, some
        // straight, with points up to 3 texels around (texel-local frames).
        const double scale = std::pow(10.0, -1.3 + 2.8 * u(rng));
        const dvec2 p0(u(rng), u(rng));
        const dvec2 e = scale * dvec2(u(rng) - 0.5, u(rng) - 0.5);
        if (glm::length(e) < 1e-3) continue;
        const double bend = std::pow(10.0, -4.0 + 4.5 * u(rng)) * (u(rng) < 0.5 ? -1.0 : 1.0);
        const bool curved = u(rng) < 0.8;
        const dvec2 p2 = p0 + e;
        const dvec2 p1 = curved
                             ? 0.5 * (p0 + p2) + bend * dvec2(-e.y, e.x) + 0.2 * (u(rng) - 0.5) * e
                             : 0.5 * (p0 + p2);
        const glm::vec2 f0(p0), f1(p1), f2(p2);
        const glm::vec2 pt(float(u(rng) * 3.0 - 1.0), float(u(rng) * 3.0 - 1.0));
        // Conditioning, in binary64 on the binary32 data: the distance along
        // the piece sampled densely; skip points within 1e-3 texels of it,
        // with a second local minimum within 1e-3 of the first, or whose
        // distance is within 10% of the radius of curvature at the foot.
        const Quad q{dvec2(f0), curved ? dvec2(f1) : 0.5 * (dvec2(f0) + dvec2(f2)), dvec2(f2)};
        double best = 1e300, second = 1e300, bestU = 0.0;
        const int n = 512;
        std::vector<double> d(n + 1);
        for (int k = 0; k <= n; ++k) d[size_t(k)] = glm::length(q.at(double(k) / n) - dvec2(pt));
        for (int k = 0; k <= n; ++k) {
            bool localMin = (k == 0 || d[size_t(k)] <= d[size_t(k - 1)]) &&
                            (k == n || d[size_t(k)] <= d[size_t(k + 1)]);
            if (!localMin) continue;
            if (d[size_t(k)] < best) {
                second = best;
                best = d[size_t(k)];
                bestU = double(k) / n;
            } else {
                second = std::min(second, d[size_t(k)]);
            }
        }
        if (best < 1e-3 || second - best < 1e-3) continue;
        const dvec2 t = q.tangent(bestU), acc = 2.0 * q.a();
        const double curvature = std::fabs(cross2(t, acc)) / std::pow(glm::length(t), 3.0);
        if (curved && std::fabs(1.0 - best * curvature) < 0.1) continue;
        RecordWriter r(layout, rec.data());
        r.set("p0", f0);
        r.set("p1", curved ? f1 : 0.5f * (f0 + f2));
        r.set("p2", f2);
        r.set("curved", curved ? 1.0f : 0.0f);
        r.set("query", pt);
        out.insert(out.end(), rec.begin(), rec.end());
    }
    return out;
}

} // namespace sg::features::detail
