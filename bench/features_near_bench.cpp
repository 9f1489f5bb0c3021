// features_near_bench: accuracy and memory of the exact near field
// (shaders/sg/features/near.glsl) against the papers' interpolation
// (Parilov, Zorin 2008 sec. 5), on glyphs of several fonts (Latin TrueType,
// Latin CFF, CJK), SVG icons with sharp corners, stars and T-junctions.
//
// Truth: the exact distance to the input curves, in double, from dense
// sampling of each segment refined by golden-section search (written here,
// no code shared with the bake or the evaluator); its gradient is the unit
// vector from the nearest point. Evaluated: the C++ build of the shader
// (sg::features::sample, the same source the GPU compiles; CPU/GPU parity is
// tested in tests/features).
//
//  1. Distance error and gradient angle at points 0.01 / 0.05 / 0.2 / 0.5 /
//     1 / 2 texels from the curves (both sides, along the curve's normal,
//     every 0.5 texel along each segment), leaving out points within 0.25
//     texel of a junction point (curve ends and points where other than two
//     segment ends meet) and points with two equally near feet (a medial
//     axis: two gradients).
//  2. Rendered normal error at 16x and 64x magnification: pixel centres of
//     2 x 2-texel windows around 24 points of each input's curves, the
//     crease profile (D = 1, w = 3 texels, surfgrad composition) from the
//     evaluated d and gradient against the same profile from the exact ones
//     (pixels within 1e-4 texel of a curve, where the crease's normal flips,
//     are left out). The error is a function of position: magnification
//     changes how many pixels sample it, and how large a texel-sized error
//     looks (16 or 64 pixels per texel).
//  3. Memory: near-field lists and pieces per map texel, list statistics,
//     the time to build the lists (packGpu); bytes per texel and in total
//     for the example maps (examples/feature-curves, feature-profiles) in
//     both modes, next to an RGBA8 normal map of the same resolution.
//  4. Cost on the CPU reference (one core, the C++ build of the shader):
//     nanoseconds per sample of sgFeatSample (paper) and sgFeatSampleNear
//     (exact) against a plain bilinear fetch of an RGBA8 normal map
//     decoded to a derivative (the baseline), each timed in the same run,
//     interleaved, median of --runs runs; over every point of a 4 x 4 grid
//     per texel of the whole map and over those in the near-field band.
//     The GPU ratios are bench/features_llvmpipe_bench's.
//
// Run: build/bin/features_near_bench [--size N] [--runs N] (default 256, 7)
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <ctime>

#include "surfgrad/features/curves.h"
#include "surfgrad/features/feature_maps.h"

using namespace sg::features;
using glm::dvec2;

namespace {

dvec2 bez(const Segment& s, double t) {
    double u = 1.0 - t;
    return u * u * s.p0 + 2.0 * t * u * s.p1 + t * t * s.p2;
}
dvec2 bezTan(const Segment& s, double t) {
    return 2.0 * (1.0 - t) * (s.p1 - s.p0) + 2.0 * t * (s.p2 - s.p1);
}

// The oracle: nearest point of one segment (dense samples, then golden
// section around every sampled local minimum).
double segDist(const Segment& s, dvec2 p, dvec2& foot) {
    const int n = 48;
    double d2[n + 1];
    for (int i = 0; i <= n; ++i) {
        dvec2 q = bez(s, double(i) / n) - p;
        d2[i] = glm::dot(q, q);
    }
    double best = 1e300;
    for (int i = 0; i <= n; ++i) {
        if ((i > 0 && d2[i] > d2[i - 1]) || (i < n && d2[i] > d2[i + 1])) continue;
        double a = std::max(0.0, double(i - 1) / n), b = std::min(1.0, double(i + 1) / n);
        const double g = 0.5 * (std::sqrt(5.0) - 1.0);
        auto f = [&](double t) {
            dvec2 q = bez(s, t) - p;
            return glm::dot(q, q);
        };
        for (int it = 0; it < 70; ++it) {
            double x1 = b - g * (b - a), x2 = a + g * (b - a);
            (f(x1) < f(x2) ? b : a) = f(x1) < f(x2) ? x2 : x1;
        }
        for (double t : {a, b, double(i) / n}) {
            double v = f(t);
            if (v < best) {
                best = v;
                foot = bez(s, t);
            }
        }
    }
    return std::sqrt(best);
}

double boxDist(const Segment& s, dvec2 p) {
    dvec2 lo = glm::min(glm::min(s.p0, s.p1), s.p2), hi = glm::max(glm::max(s.p0, s.p1), s.p2);
    return glm::length(glm::max(glm::max(lo - p, p - hi), dvec2(0.0)));
}

struct Truth {
    double dist = 1e300;
    dvec2 grad{0.0};
    bool ambiguous = false;
};

Truth truth(const CurveNetwork& net, dvec2 p) {
    Truth t;
    double second = 1e300;
    dvec2 foot(0.0), secondFoot(0.0);
    for (const Segment& s : net.segments) {
        if (boxDist(s, p) > second) continue;
        dvec2 f;
        double d = segDist(s, p, f);
        if (d < t.dist) {
            second = t.dist;
            secondFoot = foot;
            t.dist = d;
            foot = f;
        } else if (d < second) {
            second = d;
            secondFoot = f;
        }
    }
    t.grad = t.dist > 0 ? (p - foot) / t.dist : dvec2(0.0);
    t.ambiguous = second - t.dist < 1e-6 && glm::length(secondFoot - foot) > 1e-3;
    return t;
}

std::vector<dvec2> junctions(const CurveNetwork& net) {
    std::vector<std::pair<dvec2, int>> ends;
    for (const Segment& s : net.segments) {
        for (dvec2 q : {s.p0, s.p2}) {
            bool found = false;
            for (auto& e : ends)
                if (glm::length(e.first - q) < 1e-9) {
                    ++e.second;
                    found = true;
                }
            if (!found) ends.push_back({q, 1});
        }
    }
    std::vector<dvec2> out;
    for (auto& e : ends)
        if (e.second != 2) out.push_back(e.first);
    return out;
}

double pct(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

const double kOffsets[6] = {0.01, 0.05, 0.2, 0.5, 1.0, 2.0};

struct Errors {
    std::vector<double> dist[6], angle[6];
    std::vector<double> render16, render64;
    void add(const Errors& o) {
        for (int k = 0; k < 6; ++k) {
            dist[k].insert(dist[k].end(), o.dist[k].begin(), o.dist[k].end());
            angle[k].insert(angle[k].end(), o.angle[k].begin(), o.angle[k].end());
        }
        render16.insert(render16.end(), o.render16.begin(), o.render16.end());
        render64.insert(render64.end(), o.render64.begin(), o.render64.end());
    }
    std::vector<double> all(const std::vector<double> (&v)[6], int from = 0) const {
        std::vector<double> out;
        for (int k = from; k < 6; ++k) out.insert(out.end(), v[k].begin(), v[k].end());
        return out;
    }
};

double angleDeg(dvec2 a, glm::vec2 b) {
    return std::acos(std::clamp(a.x * b.x + a.y * b.y, -1.0, 1.0)) * 180.0 / M_PI;
}

glm::dvec3 creaseNormal(double d, dvec2 g, const sg::glsl::SgFeatProfile& prof) {
    sg::glsl::SgFeatResult r;
    r.dist = float(d);
    r.grad = glm::vec2(g);
    r.side = 1.0f;
    r.profile = -1;
    r.width = 0.0f;
    return glm::dvec3(
        sg::glsl::sgFeatNormalFromDeriv(sg::glsl::sgFeatDeriv(r, prof, glm::vec2(0.0f))));
}

// Accuracy of one map in one mode.
void measure(const CurveNetwork& texelNet, const GpuFeatureMaps& g, NearMode mode, Errors& e) {
    const std::vector<dvec2> jp = junctions(texelNet);
    auto nearJunction = [&](dvec2 p) {
        for (const dvec2& j : jp)
            if (glm::length(p - j) < 0.25) return true;
        return false;
    };
    const double n = g.size;
    for (const Segment& s : texelNet.segments) {
        double len = glm::length(s.p1 - s.p0) + glm::length(s.p2 - s.p1);
        int count = std::max(2, int(std::ceil(len * 2.0)));
        for (int i = 0; i <= count; ++i) {
            double t = double(i) / count;
            dvec2 q = bez(s, t), tan = glm::normalize(bezTan(s, t)), nrm(-tan.y, tan.x);
            for (int k = 0; k < 6; ++k) {
                for (double sd : {-1.0, 1.0}) {
                    dvec2 p = dvec2(glm::vec2(q + sd * kOffsets[k] * nrm));
                    if (p.x < 0 || p.y < 0 || p.x > n || p.y > n || nearJunction(p)) continue;
                    Truth tr = truth(texelNet, p);
                    auto r = sample(g, glm::vec2(p), mode);
                    e.dist[k].push_back(std::fabs(double(r.dist) - tr.dist));
                    if (!tr.ambiguous && tr.dist > 1e-4)
                        e.angle[k].push_back(angleDeg(tr.grad, r.grad));
                }
            }
        }
    }
    // Rendered normals at 16x and 64x in 2 x 2-texel windows.
    const sg::glsl::SgFeatProfile prof = makeProfile("crease", 1.0f, 0.0f, 3.0f);
    const size_t segs = texelNet.segments.size();
    for (int w = 0; w < 24; ++w) {
        const Segment& s = texelNet.segments[(size_t(w) * 7919u) % segs];
        dvec2 c = bez(s, 0.37 + 0.013 * w);
        for (int zoom : {16, 64}) {
            const int px = 2 * zoom;
            const int step = zoom == 64 ? 4 : 1; // every 4th pixel row/column at 64x
            for (int y = 0; y < px; y += step) {
                for (int x = 0; x < px; x += step) {
                    dvec2 p = c + (dvec2(x, y) + 0.5) / double(zoom) - 1.0;
                    p = dvec2(glm::vec2(p));
                    if (p.x < 0 || p.y < 0 || p.x > n || p.y > n || nearJunction(p)) continue;
                    Truth tr = truth(texelNet, p);
                    // On a medial axis, or within 1e-4 texel of a curve where
                    // the crease's normal flips (both sides are right).
                    if (tr.ambiguous || tr.dist < 1e-4) continue;
                    auto r = sample(g, glm::vec2(p), mode);
                    glm::dvec3 a = creaseNormal(r.dist, dvec2(r.grad), prof);
                    glm::dvec3 b = creaseNormal(tr.dist, tr.grad, prof);
                    double ang = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * 180.0 / M_PI;
                    (zoom == 16 ? e.render16 : e.render64).push_back(ang);
                }
            }
        }
    }
}

struct Input {
    std::string group, name;
    CurveNetwork net;
    bool fit = true;
    int size = 0; // 0: --size
};

CurveNetwork star(int rays) {
    CurveNetwork net;
    dvec2 c(32.37 + 0.03 * rays, 32.61 - 0.02 * rays);
    for (int k = 0; k < rays; ++k) {
        double a = 0.3 + 2 * M_PI * k / rays + 0.1 * std::sin(3.0 * k);
        Segment s;
        s.p0 = c;
        s.p2 = c + 20.0 * dvec2(std::cos(a), std::sin(a));
        s.p1 = 0.5 * (s.p0 + s.p2);
        s.curve = k;
        net.curves.push_back({});
        net.segments.push_back(s);
    }
    return net;
}

double threadSeconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// The baseline: an RGBA8 normal map of (N+1)^2 samples at texel corners,
// bilinear, decoded to a surface derivative (-n.xy / n.z), as a plain
// normal-map layer does.
struct Rgba8Map {
    int n = 0;
    std::vector<uint32_t> texels;
    glm::vec2 deriv(glm::vec2 p) const {
        int i = std::clamp(int(std::floor(p.x)), 0, n - 1),
            j = std::clamp(int(std::floor(p.y)), 0, n - 1);
        float fx = p.x - float(i), fy = p.y - float(j);
        auto at = [&](int a, int b) {
            uint32_t v = texels[size_t(b) * size_t(n + 1) + size_t(a)];
            return glm::vec3(float(v & 255u), float((v >> 8) & 255u), float((v >> 16) & 255u)) *
                       (2.0f / 255.0f) -
                   1.0f;
        };
        glm::vec3 m = glm::mix(glm::mix(at(i, j), at(i + 1, j), fx),
                               glm::mix(at(i, j + 1), at(i + 1, j + 1), fx), fy);
        return -glm::vec2(m) / std::max(m.z, 1e-3f);
    }
};

Rgba8Map normalMapOf(const GpuFeatureMaps& g) {
    Rgba8Map m;
    m.n = g.size;
    m.texels.resize(size_t(g.size + 1) * size_t(g.size + 1));
    for (int j = 0; j <= g.size; ++j) {
        for (int i = 0; i <= g.size; ++i) {
            auto r = sample(g, glm::vec2(float(i), float(j)), NearMode::Paper);
            float d = std::clamp(r.dist, -3.0f, 3.0f);
            glm::vec3 nrm =
                glm::normalize(glm::vec3(-0.3f * r.grad * (d >= 0 ? 1.0f : -1.0f), 1.0f));
            glm::uvec3 q =
                glm::uvec3(glm::clamp((nrm * 0.5f + 0.5f) * 255.0f + 0.5f, 0.0f, 255.0f));
            m.texels[size_t(j) * size_t(g.size + 1) + size_t(i)] =
                q.x | (q.y << 8) | (q.z << 16) | (255u << 24);
        }
    }
    return m;
}

// Bytes per texel of the papers' two textures (corner pairs N x (N+1),
// edges N x N, RGBA32UI).
double paperBytesPerTexel(const GpuFeatureMaps& g) {
    return 4.0 * double(g.cornerPairs.size() + g.edges.size()) / (double(g.size) * g.size);
}

struct CostRow {
    double baseNs = 0, paperNs = 0, exactNs = 0;
};

// ns per sample of the three evaluators over pts, median of runs, timed
// interleaved so load on the machine hits all three alike.
CostRow timeCost(const GpuFeatureMaps& g, const Rgba8Map& nm, const std::vector<glm::vec2>& pts,
                 int runs) {
    std::vector<double> tb, tp, te;
    volatile float sink = 0.0f;
    for (int r = 0; r < runs; ++r) {
        double t0 = threadSeconds();
        float acc = 0.0f;
        for (const glm::vec2& p : pts) acc += nm.deriv(p).x;
        double t1 = threadSeconds();
        for (const glm::vec2& p : pts) acc += sample(g, p, NearMode::Paper).grad.x;
        double t2 = threadSeconds();
        for (const glm::vec2& p : pts) acc += sample(g, p, NearMode::Exact).grad.x;
        double t3 = threadSeconds();
        sink = sink + acc;
        const double k = 1e9 / double(std::max<size_t>(pts.size(), 1));
        tb.push_back((t1 - t0) * k);
        tp.push_back((t2 - t1) * k);
        te.push_back((t3 - t2) * k);
    }
    (void)sink;
    auto med = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    };
    return {med(tb), med(tp), med(te)};
}

// Two rows of the cost table (whole map, band) for one map.
std::string costTable(const std::string& name, const GpuFeatureMaps& g, int runs) {
    const Rgba8Map nm = normalMapOf(g);
    std::vector<glm::vec2> all, band;
    for (int j = 0; j < 4 * g.size; ++j) {
        for (int i = 0; i < 4 * g.size; ++i) {
            glm::vec2 p((float(i) + 0.5f) / 4.0f, (float(j) + 0.5f) / 4.0f);
            all.push_back(p);
            const uint32_t* h = &g.nearLists[4 * (size_t(j / 4) * size_t(g.size) + size_t(i / 4))];
            if (h[0] | h[1] | h[2] | h[3]) band.push_back(p);
        }
    }
    std::string out;
    for (int k = 0; k < 2; ++k) {
        const std::vector<glm::vec2>& pts = k ? band : all;
        CostRow c = timeCost(g, nm, pts, runs);
        char b[256];
        std::snprintf(b, sizeof b,
                      "| %s | %s | %zu | %.1f | %.1f | %.1f | %.2fx | %.2fx | %.2fx |\n",
                      name.c_str(), k ? "band" : "whole map", pts.size(), c.baseNs, c.paperNs,
                      c.exactNs, c.paperNs / c.baseNs, c.exactNs / c.baseNs, c.exactNs / c.paperNs);
        out += b;
    }
    return out;
}

// Memory of one example map in both modes.
void exampleMemory(const char* name, const CurveNetwork& net, BakeOptions o) {
    o.nearField = true;
    GpuFeatureMaps g = bake(net, o).packGpu();
    const double texels = double(g.size) * g.size;
    const double paper = paperBytesPerTexel(g), nearB = g.nearBytesPerTexel();
    std::printf("| %s | %d^2 | %.1f | %.1f | %.0f | %.1f | %.1f | %.0f | %.0f (%.1fx) |\n", name,
                g.size, 4.0 * double((g.size + 1) * (g.size + 1)) / texels, paper,
                paper * texels / 1024.0, nearB, paper + nearB, (paper + nearB) * texels / 1024.0,
                nearB * texels / 1024.0, (paper + nearB) / paper);
}

} // namespace

int main(int argc, char** argv) {
    int size = 256, runs = 7;
    for (int i = 1; i + 1 < argc; ++i) {
        if (!std::strcmp(argv[i], "--size"))
            size = std::max(16, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--runs"))
            runs = std::max(1, std::atoi(argv[++i]));
    }
    std::vector<Input> inputs;
    const std::string data = SURFGRAD_DATA_DIR;
    auto font = [&](const char* group, const char* name, const char* file, const char* text) {
        try {
            inputs.push_back({group, name, loadFont(file, text)});
        } catch (const std::exception& ex) {
            std::printf("(skipped %s: %s)\n", name, ex.what());
        }
    };
    font("Latin glyphs", "DejaVu Sans 'Rg'", "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
         "Rg");
    font("Latin glyphs", "DejaVu Serif Bold 'Sg'",
         "/usr/share/fonts/truetype/dejavu/DejaVuSerif-Bold.ttf", "Sg");
    font("Latin glyphs", "Inconsolata 'Q&' (CFF)",
         "/usr/share/fonts/truetype/inconsolata/Inconsolata.otf", "Q&");
    font("CJK glyphs", "WenQuanYi '\xe5\xbf\x83'", "/usr/share/fonts/truetype/wqy/wqy-microhei.ttc",
         "\xe5\xbf\x83");
    font("CJK glyphs", "WenQuanYi '\xe7\xb9\x81'", "/usr/share/fonts/truetype/wqy/wqy-microhei.ttc",
         "\xe7\xb9\x81");
    for (const char* icon : {"flame", "carrot", "paw-print", "chart-spline", "mountain"})
        inputs.push_back(
            {"icons", std::string("lucide ") + icon, loadSvg(data + "/svg/" + icon + ".svg")});
    for (int rays : {3, 6, 12})
        inputs.push_back({"stars", "star of " + std::to_string(rays), star(rays), false, 64});

    std::printf("Exact near field vs the papers' interpolation, quadratic maps; d error texels, "
                "gradient angle degrees, p95 (max) over points 0.01-2 texels from the curves, "
                "0.25 texel clear of junction points\n\n");
    std::printf("| input | map | pieces | band tx | pieces / band texel (mean / max) | overflow "
                "texels | near field B / texel | lists ms | d error exact | d error paper | "
                "gradient exact | gradient paper | gradient 0.2-2 tx exact / paper |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    std::vector<std::string> groups;
    std::vector<Errors> groupExact, groupPaper;
    std::vector<std::string> costRows;
    for (Input& in : inputs) {
        BakeOptions o;
        o.size = in.size ? in.size : size;
        o.mode = BakeMode::Quadratic;
        o.nearField = true;
        o.nearWidthTexels = 3.0;
        o.fit = in.fit;
        o.marginTexels = 6.0;
        BakeStats st;
        FeatureMaps m = bake(in.net, o, &st);
        auto t0 = std::chrono::steady_clock::now();
        GpuFeatureMaps g = m.packGpu();
        double packMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        CurveNetwork tn = in.net;
        for (Segment& s : tn.segments) {
            s.p0 = st.inputToTexel.apply(s.p0);
            s.p1 = st.inputToTexel.apply(s.p1);
            s.p2 = st.inputToTexel.apply(s.p2);
        }
        Errors ex, pa;
        measure(tn, g, NearMode::Exact, ex);
        measure(tn, g, NearMode::Paper, pa);
        auto cell = [](const std::vector<double>& v, const char* f) {
            char b[64];
            std::snprintf(b, sizeof b, f, pct(v, 0.95), pct(v, 1.0));
            return std::string(b);
        };
        std::printf("| %s | %d^2 | %d | %.1f | %.2f / %d | %d | %.1f | %.1f | %s | %s | %s | %s | "
                    "%.3f / %.1f |\n",
                    in.name.c_str(), o.size, st.nearPieces, st.nearBandTexels,
                    g.nearStats.meanPieces, g.nearStats.maxPieces, g.nearStats.overflowTexels,
                    g.nearBytesPerTexel(), packMs, cell(ex.all(ex.dist), "%.1e (%.1e)").c_str(),
                    cell(pa.all(pa.dist), "%.3f (%.2f)").c_str(),
                    cell(ex.all(ex.angle), "%.3f (%.2f)").c_str(),
                    cell(pa.all(pa.angle), "%.1f (%.0f)").c_str(), pct(ex.all(ex.angle, 2), 0.95),
                    pct(pa.all(pa.angle, 2), 0.95));
        auto it = std::find(groups.begin(), groups.end(), in.group);
        if (it == groups.end()) {
            groups.push_back(in.group);
            groupExact.emplace_back();
            groupPaper.emplace_back();
            it = groups.end() - 1;
        }
        groupExact[size_t(it - groups.begin())].add(ex);
        groupPaper[size_t(it - groups.begin())].add(pa);
        costRows.push_back(costTable(in.name, g, runs));
    }

    std::printf("\nBy distance from the curves (p95; exact / paper)\n\n| inputs | quantity |");
    for (double off : kOffsets) std::printf(" %.2g tx |", off);
    std::printf("\n|---|---|---|---|---|---|---|---|\n");
    for (size_t k = 0; k < groups.size(); ++k) {
        const Errors &ex = groupExact[k], &pa = groupPaper[k];
        std::printf("| %s | d error, texels |", groups[k].c_str());
        for (int o = 0; o < 6; ++o)
            std::printf(" %.1e / %.3f |", pct(ex.dist[o], 0.95), pct(pa.dist[o], 0.95));
        std::printf("\n| %s | gradient, degrees |", groups[k].c_str());
        for (int o = 0; o < 6; ++o)
            std::printf(" %.3f / %.1f |", pct(ex.angle[o], 0.95), pct(pa.angle[o], 0.95));
        std::printf("\n");
    }

    std::printf(
        "\nCPU reference cost, one core (C++ build of the shader), ns per sample, median of "
        "%d interleaved runs; baseline: bilinear RGBA8 normal map fetch decoded to a "
        "derivative\n\n| input | points | count | baseline ns | paper ns | exact ns | "
        "paper / baseline | exact / baseline | exact / paper |\n"
        "|---|---|---|---|---|---|---|---|---|\n",
        runs);
    for (const std::string& r : costRows) std::printf("%s", r.c_str());

    std::printf("\nMemory of the example maps (RGBA32UI textures; the RGBA8 normal map for "
                "scale)\n\n| example map | size | RGBA8 normal map B / texel | paper B / texel | "
                "paper KiB | near field B / texel | exact B / texel | exact KiB | near field KiB "
                "(exact / paper) |\n|---|---|---|---|---|---|---|---|---|\n");
    try {
        BakeOptions o;
        o.size = 128;
        o.mode = BakeMode::Quadratic;
        o.nearWidthTexels = 1.5; // the layer's width
        exampleMemory("feature-curves (DejaVu Serif Bold 'Sg')",
                      loadFont("/usr/share/fonts/truetype/dejavu/DejaVuSerif-Bold.ttf", "Sg"), o);
    } catch (const std::exception& ex) {
        std::printf("(skipped feature-curves: %s)\n", ex.what());
    }
    {
        BakeOptions o;
        o.size = 96;
        o.mode = BakeMode::Quadratic;
        o.marginTexels = 6.0;
        o.nearWidthTexels = 3.0; // the layer's width (curves may set their own)
        exampleMemory("feature-profiles (curves.json)",
                      loadCurvesJson(std::string(SURFGRAD_SOURCE_DIR) +
                                     "/examples/feature-profiles/curves.json"),
                      o);
    }

    std::printf("\nRendered normal error (crease D = 1, w = 3 texels, surfgrad composition) vs the "
                "exact-distance render, degrees, p95 / max\n\n| inputs | @16x exact | @16x paper "
                "| @64x exact | @64x paper |\n|---|---|---|---|---|\n");
    for (size_t k = 0; k < groups.size(); ++k) {
        const Errors &ex = groupExact[k], &pa = groupPaper[k];
        std::printf("| %s | %.3f / %.2f | %.1f / %.0f | %.3f / %.2f | %.1f / %.0f |\n",
                    groups[k].c_str(), pct(ex.render16, 0.95), pct(ex.render16, 1.0),
                    pct(pa.render16, 0.95), pct(pa.render16, 1.0), pct(ex.render64, 0.95),
                    pct(ex.render64, 1.0), pct(pa.render64, 0.95), pct(pa.render64, 1.0));
    }
    return 0;
}
