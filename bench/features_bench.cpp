// features_bench: feature-curve maps (Parilov, Rosenberg, Zorin 2005;
// Parilov, Zorin 2008) on the CPU.
//
//  bake      preprocessing time at one thread: linear mode on a 512^2 map
//            with 2,000 segments (goal < 100 ms), quadratic mode on a CJK
//            glyph at 512^2 (goal < 2 s), plus the lucide SVGs. Medians of
//            CPU time over several runs, with the phase split; the
//            baseline is the bake's own distance pass (the brute-force
//            distance field every distance-based normal map needs), so the
//            ratio shows what the configurations, signatures, optimisation
//            and smoothing add.
//  threads   each stage of the bake (scan, optimise, distance, smooth) and
//            the GPU packing with the exact near field's lists, at 1 thread
//            and at all cores (BakeOptions::threads = 0) side by side,
//            interleaved, wall-clock medians, on 512^2 and 1024^2 maps
//            (1M texels): the random polylines (linear) and the CJK glyph
//            (quadratic, with the near field); speed-up and efficiency
//            (speed-up / threads). Then the serial cut-over: whole bakes of
//            the polylines at 32^2..256^2, serial against parallel loops.
//  accuracy  crease position and normal error at 16x-64x magnification,
//            per map resolution 64..1024, for a plain bilinear normal map of
//            the same resolution, linear maps and quadratic maps, against
//            the exact distance and gradient of the input curves.
//
// Run: build/bin/features_bench [bake|threads|accuracy] [--runs N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bake_internal.h"
#include "surfgrad/features/curves.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/base/threads.h"

using namespace sg::features;
using glm::dvec2;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

void addLine(CurveNetwork& n, dvec2 a, dvec2 b, int curve) {
    Segment s;
    s.kind = Segment::Kind::Line;
    s.p0 = a;
    s.p2 = b;
    s.p1 = 0.5 * (a + b);
    s.curve = curve;
    n.segments.push_back(s);
}

void addQuad(CurveNetwork& n, dvec2 a, dvec2 c, dvec2 b, int curve) {
    Segment s;
    s.kind = Segment::Kind::Quadratic;
    s.p0 = a;
    s.p1 = c;
    s.p2 = b;
    s.curve = curve;
    n.segments.push_back(s);
}

// 500 random polylines of 4 segments (4..12 texels each) in a 512^2 map:
// 2,000 segments with joints, crossings and near-parallel runs.
CurveNetwork polylineNetwork() {
    CurveNetwork n;
    std::mt19937 rng(2026);
    std::uniform_real_distribution<double> pos(16.0, 496.0), ang(0.0, 2.0 * M_PI), len(4.0, 12.0);
    for (int c = 0; c < 500; ++c) {
        n.curves.push_back({});
        dvec2 p(pos(rng), pos(rng));
        double a = ang(rng);
        for (int k = 0; k < 4; ++k) {
            a += 0.5 * (ang(rng) / M_PI - 1.0);
            dvec2 q = glm::clamp(p + len(rng) * dvec2(std::cos(a), std::sin(a)), dvec2(2.0),
                                 dvec2(510.0));
            addLine(n, p, q, c);
            p = q;
        }
    }
    return n;
}

struct BakeRow {
    std::string what, input;
    int segments = 0, size = 0;
    double cpu = 0, wall = 0, distance = 0, scan = 0, optimize = 0, smooth = 0, goal = 0;
    BakeStats st;
};

BakeRow timeBake(const std::string& what, const std::string& input, const CurveNetwork& net,
                 BakeOptions o, int runs, double goal) {
    BakeRow r;
    r.what = what;
    r.input = input;
    r.segments = int(net.segments.size());
    r.size = o.size;
    r.goal = goal;
    o.threads = 1; // the one-core table; the threads section compares counts
    std::vector<double> cpu, wall, dist, scan, opt, smooth;
    for (int k = 0; k < runs; ++k) {
        FeatureMaps m = bake(net, o, &r.st);
        wall.push_back(r.st.seconds);
        cpu.push_back(r.st.cpuSeconds);
        dist.push_back(r.st.secondsDistance);
        scan.push_back(r.st.secondsScan);
        opt.push_back(r.st.secondsOptimize);
        smooth.push_back(r.st.secondsSmooth);
    }
    r.cpu = median(cpu);
    r.wall = median(wall);
    r.distance = median(dist);
    r.scan = median(scan);
    r.optimize = median(opt);
    r.smooth = median(smooth);
    return r;
}

void benchBake(int runs) {
    std::vector<BakeRow> rows;
    {
        BakeOptions o;
        o.size = 512;
        o.fit = false;
        o.mode = BakeMode::Linear;
        rows.push_back(
            timeBake("linear", "500 random polylines", polylineNetwork(), o, runs, 0.100));
        o.mode = BakeMode::Quadratic;
        rows.push_back(
            timeBake("quadratic", "500 random polylines", polylineNetwork(), o, runs, 0.0));
    }
    const char* font = "/usr/share/fonts/truetype/wqy/wqy-microhei.ttc";
    // The glyph with the most curved segments among a few complex ones.
    CurveNetwork glyph;
    std::string glyphName;
    for (const char* ch :
         {"\xe9\xbe\x8d", "\xe9\xac\xb1", "\xe5\xbf\x83", "\xe6\x84\x9b", "\xe7\xb9\x81"}) {
        try {
            CurveNetwork g = loadFont(font, ch);
            int q = 0, gq = 0;
            for (const auto& s : g.segments) q += s.kind == Segment::Kind::Quadratic;
            for (const auto& s : glyph.segments) gq += s.kind == Segment::Kind::Quadratic;
            if (glyph.segments.empty() || q > gq) {
                glyph = g;
                glyphName = ch;
            }
        } catch (const std::exception& e) {
            std::printf("(font %s unavailable: %s)\n", font, e.what());
            break;
        }
    }
    if (!glyph.segments.empty()) {
        BakeOptions o;
        o.size = 512;
        o.mode = BakeMode::Quadratic;
        int q = 0;
        for (const auto& s : glyph.segments) q += s.kind == Segment::Kind::Quadratic;
        rows.push_back(timeBake(
            "quadratic", "WenQuanYi " + glyphName + " (" + std::to_string(q) + " quadratics)",
            glyph, o, runs, 2.0));
        o.mode = BakeMode::Linear;
        rows.push_back(timeBake("linear", "WenQuanYi " + glyphName, glyph, o, runs, 0.0));
    }
    for (const char* svg : {"flame", "paw-print", "infinity", "carrot"}) {
        std::string path = std::string(SURFGRAD_DATA_DIR) + "/svg/" + svg + ".svg";
        try {
            CurveNetwork n = loadSvg(path);
            BakeOptions o;
            o.size = 512;
            o.mode = BakeMode::Quadratic;
            rows.push_back(timeBake("quadratic", std::string(svg) + ".svg", n, o, runs, 0.0));
        } catch (const std::exception& e) {
            std::printf("(skipping %s: %s)\n", path.c_str(), e.what());
        }
    }
    std::printf("\nPreprocessing, one thread (median of %d runs; CPU = process time, wall includes "
                "waiting on a shared "
                "machine)\n",
                runs);
    std::printf("| mode | input | segments | map | CPU ms | wall ms | distance ms (baseline) | "
                "ratio to baseline | "
                "scan ms | optimise ms | smooth ms | feature texels | curved | "
                "invalid->opt/straight | goal |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (const auto& r : rows) {
        std::string goal = r.goal > 0 ? (r.cpu < r.goal ? "< " : ">= ") +
                                            std::to_string(int(r.goal * 1000)) + " ms " +
                                            (r.cpu < r.goal ? "met" : "MISSED")
                                      : "-";
        std::printf("| %s | %s | %d | %d^2 | %.1f | %.1f | %.1f | %.2fx | %.1f | %.1f | %.1f | %d "
                    "| %d | %d->%d/%d | %s |\n",
                    r.what.c_str(), r.input.c_str(), r.segments, r.size, r.cpu * 1e3, r.wall * 1e3,
                    r.distance * 1e3, r.cpu / std::max(r.distance, 1e-9), r.scan * 1e3,
                    r.optimize * 1e3, r.smooth * 1e3, r.st.texelsWithFeatures, r.st.curvedSegments,
                    r.st.invalidTexels, r.st.optimizedTexels, r.st.fallbackTexels, goal.c_str());
    }
}

// ---------------------------------------------------------------------------
// Threads.

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The CJK glyph with the most quadratic segments (empty without the font).
CurveNetwork cjkGlyph(std::string& name) {
    CurveNetwork glyph;
    for (const char* ch :
         {"\xe9\xbe\x8d", "\xe9\xac\xb1", "\xe5\xbf\x83", "\xe6\x84\x9b", "\xe7\xb9\x81"}) {
        try {
            CurveNetwork g = loadFont("/usr/share/fonts/truetype/wqy/wqy-microhei.ttc", ch);
            auto quads = [](const CurveNetwork& n) {
                int q = 0;
                for (const auto& s : n.segments) q += s.kind == Segment::Kind::Quadratic;
                return q;
            };
            if (glyph.segments.empty() || quads(g) > quads(glyph)) {
                glyph = g;
                name = ch;
            }
        } catch (const std::exception&) {
            break;
        }
    }
    return glyph;
}

// One stage's wall-clock medians at 1 thread and at all cores.
struct StageRow {
    std::string input, stage;
    int size = 0, threads = 1;
    std::vector<double> one, all;
};

void printStageRows(const std::vector<StageRow>& rows) {
    std::printf("| input | map | stage | 1 thread ms | %s ms | speed-up | efficiency |\n",
                rows.empty() ? "N threads"
                             : (std::to_string(rows[0].threads) + " threads").c_str());
    std::printf("|---|---|---|---|---|---|---|\n");
    for (const StageRow& r : rows) {
        const double a = median(r.one), b = median(r.all);
        const double speedUp = b > 0 ? a / b : 0.0;
        std::printf("| %s | %d^2 | %s | %.2f | %.2f | %.2fx | %.2f |\n", r.input.c_str(), r.size,
                    r.stage.c_str(), a * 1e3, b * 1e3, speedUp, speedUp / r.threads);
    }
}

void benchThreads(int runs) {
    std::string glyphName;
    const CurveNetwork glyph = cjkGlyph(glyphName);
    struct Input {
        std::string name;
        CurveNetwork net;
        BakeMode mode;
        bool near;
    };
    std::vector<Input> inputs{
        {"500 random polylines, linear", polylineNetwork(), BakeMode::Linear, false}};
    if (!glyph.segments.empty())
        inputs.push_back({"WenQuanYi " + glyphName + ", quadratic + near field", glyph,
                          BakeMode::Quadratic, true});
    std::vector<StageRow> rows;
    double cpuOne = 0.0, cpuAll = 0.0;
    for (const Input& in : inputs) {
        for (int size : {512, 1024}) {
            BakeOptions o;
            o.size = size;
            o.mode = in.mode;
            o.nearField = in.near;
            const char* stages[] = {
                "scan (serial)",         "optimise",         "distance", "smooth",
                "pack GPU + near lists", "whole bake + pack"};
            std::vector<StageRow> r(6);
            for (int k = 0; k < 6; ++k) r[size_t(k)] = {in.name, stages[k], size, 1, {}, {}};
            for (int run = 0; run < runs; ++run) {
                for (int threads : {1, 0}) {
                    o.threads = threads;
                    BakeStats st;
                    const auto t0 = std::chrono::steady_clock::now();
                    FeatureMaps m = bake(in.net, o, &st);
                    const auto t1 = std::chrono::steady_clock::now();
                    GpuFeatureMaps g = m.packGpu(threads);
                    const double pack = secondsSince(t1), total = secondsSince(t0);
                    (threads == 1 ? cpuOne : cpuAll) += st.cpuSeconds;
                    const double v[6] = {st.wallSecondsScan,
                                         st.wallSecondsOptimize,
                                         st.wallSecondsDistance,
                                         st.wallSecondsSmooth,
                                         pack,
                                         total};
                    for (int k = 0; k < 6; ++k) {
                        (threads == 1 ? r[size_t(k)].one : r[size_t(k)].all).push_back(v[k]);
                        if (threads == 0) r[size_t(k)].threads = st.threads;
                    }
                    (void)g;
                }
            }
            rows.insert(rows.end(), r.begin(), r.end());
        }
    }
    std::printf("\nStages at 1 thread and at all cores (BakeOptions::threads = 0), same run, "
                "interleaved; wall-clock medians of %d runs (a shared machine: not quiet "
                "timings). Bake CPU time (all threads), summed: %.0f ms at 1 thread, %.0f ms at "
                "all cores.\n",
                runs, cpuOne * 1e3, cpuAll * 1e3);
    printStageRows(rows);

    // Serial cut-over: the whole bake with serial loops against parallel
    // loops on all cores (detail::bakeSteps bypasses bake()'s cut-over).
    std::printf("\nSerial cut-over (bake() runs maps below kBakeSerialBelowSize = %d on the "
                "calling thread): whole bakes of the polylines fitted into the map, wall-clock "
                "medians of %d runs\n",
                kBakeSerialBelowSize, runs * 3);
    std::vector<StageRow> cut;
    const CurveNetwork net = polylineNetwork();
    for (int size : {16, 24, 32, 64, 128, 256}) {
        BakeOptions o;
        o.size = size;
        o.marginTexels = 2.0;
        StageRow r{"500 random polylines, linear", "whole bake", size, 1, {}, {}};
        for (int run = 0; run < runs * 3; ++run) {
            BakeStats st;
            auto t0 = std::chrono::steady_clock::now();
            (void)sg::features::detail::bakeSteps(net, o, {false}, st);
            r.one.push_back(secondsSince(t0));
            t0 = std::chrono::steady_clock::now();
            sg::runWithThreads(0, [&] {
                r.threads = tbb::this_task_arena::max_concurrency();
                (void)sg::features::detail::bakeSteps(net, o, {true}, st);
            });
            r.all.push_back(secondsSince(t0));
        }
        cut.push_back(r);
    }
    printStageRows(cut);
}

// ---------------------------------------------------------------------------
// Accuracy.

dvec2 bez(const Segment& s, double t) {
    double u = 1.0 - t;
    return u * u * s.p0 + 2.0 * t * u * s.p1 + t * t * s.p2;
}
dvec2 bezTan(const Segment& s, double t) {
    return 2.0 * (1.0 - t) * (s.p1 - s.p0) + 2.0 * t * (s.p2 - s.p1);
}

// The test drawing in a unit square: a circle of radius 0.28 (8 quadratic
// arcs), an S curve of two quadratics and a straight line at 17 degrees.
CurveNetwork drawing() {
    CurveNetwork n;
    n.curves.resize(3);
    dvec2 c(0.36, 0.62);
    const double r = 0.28;
    for (int k = 0; k < 8; ++k) {
        double a0 = 0.3 + M_PI / 4 * k, a1 = a0 + M_PI / 4, am = 0.5 * (a0 + a1);
        addQuad(n, c + r * dvec2(std::cos(a0), std::sin(a0)),
                c + r / std::cos(M_PI / 8) * dvec2(std::cos(am), std::sin(am)),
                c + r * dvec2(std::cos(a1), std::sin(a1)), 0);
    }
    n.segments.back().p2 = n.segments.front().p0;
    addQuad(n, {0.08, 0.12}, {0.30, 0.45}, {0.52, 0.22}, 1);
    addQuad(n, {0.52, 0.22}, {0.74, -0.01}, {0.95, 0.30}, 1);
    addLine(n, {0.72, 0.40}, {0.92, 0.97}, 2);
    return n;
}

struct Probe {
    dvec2 point, normal; // texel space
};

struct ErrorStats {
    std::vector<double> crease; // texels
    std::vector<double> normalDeg;
};

void benchAccuracy() {
    const CurveNetwork base = drawing();
    const float depth = 1.0f, width = 2.0f; // V-groove, texels
    std::printf("\nAccuracy: V-groove (depth %.0f, half-width %.0f texels), probes across the "
                "curves at 64 samples per "
                "texel; crease = where the normal's component across the curve changes sign; "
                "normal error vs the "
                "exact profile normal within the groove\n",
                double(depth), double(width));
    std::printf("| map | method | crease error texels (mean / max) | crease px @16x (max) | crease "
                "px @64x (max) | "
                "normal error deg (mean / p95 / max) |\n|---|---|---|---|---|---|\n");
    glm::vec3 flat(0.0f, 0.0f, 1.0f);
    for (int n : {64, 128, 256, 512, 1024}) {
        TexelTransform xf;
        xf.scale = dvec2(0.8 * n);
        xf.offset = dvec2(0.1 * n);
        CurveNetwork net = base;
        for (auto& s : net.segments) {
            s.p0 = xf.apply(s.p0);
            s.p1 = xf.apply(s.p1);
            s.p2 = xf.apply(s.p2);
        }
        BakeOptions o;
        o.size = n;
        o.fit = false;
        o.mode = BakeMode::Linear;
        GpuFeatureMaps lin = bake(net, o).packGpu();
        o.mode = BakeMode::Quadratic;
        GpuFeatureMaps quad = bake(net, o).packGpu();
        // The bilinear reference: the profile's normal at the grid samples
        // from the exact (unsmoothed) distance and gradient.
        o.smoothIterations = 0;
        FeatureMaps exact = bake(net, o);
        sg::glsl::SgFeatProfile prof = makeProfile("vgroove", depth, 0.0f, width);
        auto profileNormal = [&](float d, glm::vec2 g) {
            sg::glsl::SgFeatResult r;
            r.dist = d;
            r.grad = g;
            r.side = 1.0f;
            r.profile = -1;
            r.width = 0.0f;
            return sg::glsl::sgFeatNormalFromDeriv(sg::glsl::sgFeatDeriv(r, prof, glm::vec2(0.0f)));
        };
        std::vector<glm::vec3> samples(size_t(n + 1) * size_t(n + 1));
        for (size_t k = 0; k < samples.size(); ++k) {
            samples[k] = profileNormal(exact.dist[k], glm::vec2(exact.gradX[k], exact.gradY[k]));
        }
        auto bilinear = [&](glm::vec2 p) {
            int i = std::clamp(int(std::floor(p.x)), 0, n - 1),
                j = std::clamp(int(std::floor(p.y)), 0, n - 1);
            float fx = p.x - float(i), fy = p.y - float(j);
            auto at = [&](int a, int b) { return samples[size_t(b) * size_t(n + 1) + size_t(a)]; };
            glm::vec3 v = glm::mix(glm::mix(at(i, j), at(i + 1, j), fx),
                                   glm::mix(at(i, j + 1), at(i + 1, j + 1), fx), fy);
            return glm::normalize(v);
        };
        auto featureNormal = [&](const GpuFeatureMaps& g, glm::vec2 p) {
            sg::glsl::SgFeatResult r = sample(g, p);
            return profileNormal(r.dist, r.grad);
        };
        // Probes: points along the curves, 3 texels clear of ends, joints and
        // other curves (so the exact nearest point is the probe's own).
        std::vector<Probe> probes;
        for (size_t k = 0; k < net.segments.size(); ++k) {
            const Segment& s = net.segments[k];
            int per = std::max(8, int(glm::length(s.p2 - s.p0) / 0.37));
            for (int i = 1; i < per; ++i) {
                double t = double(i) / per;
                dvec2 q = bez(s, t);
                dvec2 tan = glm::normalize(bezTan(s, t));
                bool ok = glm::length(q - s.p0) > 3.0 && glm::length(q - s.p2) > 3.0;
                for (size_t m = 0; m < net.segments.size() && ok; ++m) {
                    if (net.segments[m].curve == s.curve) continue;
                    for (int z = 0; z <= 200 && ok; ++z)
                        ok = glm::length(bez(net.segments[m], z / 200.0) - q) > 6.0;
                }
                if (ok) probes.push_back({q, dvec2(-tan.y, tan.x)});
            }
        }
        // Joints of the circle and the S curve are smooth (tangent
        // continuous) except the line's ends, which the 3-texel rule skips.
        ErrorStats stats[3];
        const char* names[3] = {"bilinear normal map", "linear maps", "quadratic maps"};
        const int steps = int(2.0f * width * 64.0f);
        for (const Probe& pr : probes) {
            for (int mth = 0; mth < 3; ++mth) {
                double prevC = 0.0, prevT = 0.0, cross = 1e9;
                bool havePrev = false;
                for (int s = 0; s < steps; ++s) {
                    double t = -double(width) + 2.0 * double(width) * (s + 0.5) / steps;
                    dvec2 p = pr.point + t * pr.normal;
                    glm::vec2 pf(p);
                    glm::vec3 nrm =
                        mth == 0 ? bilinear(pf) : featureNormal(mth == 1 ? lin : quad, pf);
                    double c = nrm.x * pr.normal.x + nrm.y * pr.normal.y;
                    if (havePrev && prevC > 0.0 && c <= 0.0 && cross > 1e8) {
                        // Bisect the sign change (the normal flips
                        // discontinuously at a sharp crease).
                        double lo = prevT, hi = t;
                        for (int it = 0; it < 24; ++it) {
                            double mid = 0.5 * (lo + hi);
                            glm::vec2 pm(pr.point + mid * pr.normal);
                            glm::vec3 nm =
                                mth == 0 ? bilinear(pm) : featureNormal(mth == 1 ? lin : quad, pm);
                            ((nm.x * pr.normal.x + nm.y * pr.normal.y) > 0.0 ? lo : hi) = mid;
                        }
                        cross = 0.5 * (lo + hi);
                    }
                    prevC = c;
                    prevT = t;
                    havePrev = true;
                    // Exact normal: distance |t| along the probe's normal.
                    glm::vec2 g = glm::vec2(float(t >= 0 ? pr.normal.x : -pr.normal.x),
                                            float(t >= 0 ? pr.normal.y : -pr.normal.y));
                    glm::vec3 ex = profileNormal(float(std::fabs(t)), g);
                    if (std::fabs(t) > 1.0 / 64.0 && std::fabs(t) < width - 1.0 / 64.0) {
                        stats[mth].normalDeg.push_back(
                            std::acos(std::clamp(double(glm::dot(ex, nrm)), -1.0, 1.0)) * 180.0 /
                            M_PI);
                    }
                }
                stats[mth].crease.push_back(cross > 1e8 ? double(width) : std::fabs(cross));
            }
        }
        for (int mth = 0; mth < 3; ++mth) {
            const ErrorStats& e = stats[mth];
            double meanC = 0, meanN = 0;
            for (double v : e.crease) meanC += v;
            for (double v : e.normalDeg) meanN += v;
            meanC /= std::max<size_t>(1, e.crease.size());
            meanN /= std::max<size_t>(1, e.normalDeg.size());
            double maxC = *std::max_element(e.crease.begin(), e.crease.end());
            double maxN = *std::max_element(e.normalDeg.begin(), e.normalDeg.end());
            std::printf("| %d^2 | %s | %.4f / %.4f | %.2f | %.2f | %.2f / %.2f / %.2f |\n", n,
                        names[mth], meanC, maxC, maxC * 16.0, maxC * 64.0, meanN,
                        percentile(e.normalDeg, 0.95), maxN);
        }
    }
}

} // namespace

int main(int argc, char** argv) {
    std::string what = "all";
    int runs = 7;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--runs") && i + 1 < argc)
            runs = std::max(1, std::atoi(argv[++i]));
        else
            what = argv[i];
    }
    if (what == "all" || what == "bake") benchBake(runs);
    if (what == "all" || what == "threads") benchThreads(runs);
    if (what == "all" || what == "accuracy") benchAccuracy();
    return 0;
}
