// Benchmark: every `surfgrad normalmap` operation (surfgrad/normalmap/operations.h) on a
// 4096 x 4096 map, height-field-correct vs naive, on 1 thread and on all
// threads, in the same run. Input: an analytic tileable map (sums of sines
// plus a Gaussian bump, slopes up to ~1) built in memory, so no file I/O is
// timed; heights for the ops that need them are computed once and passed in
// (their cost is the to-height row).
//
//   bench/normalmap_bench [--size N] [--runs K] [--only NAME]
//
// Each row times the op K times per thread setting (interleaving correct
// and naive, so load hits both alike) and prints the median as Mpixel/s
// (output texels per second). Ratios: correct / naive time on one thread
// (the price of being correct) and one thread / all threads (the speed-up).
// On a shared machine only the ratios mean much.
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <tuple>
#include <vector>

#include "surfgrad/normalmap/operations.h"

namespace {

using namespace sg::normalmap;
using Clock = std::chrono::steady_clock;
constexpr double kPi = 3.14159265358979323846;

// Exact slopes of h = sum_k A_k sin(2 pi (p_k u + q_k v) / n) (tileable
// waves with slope amplitudes 0.5 and 0.4) plus a Gaussian bump (sigma =
// n / 12, steepest slope 0.3).
DerivField makeSlopes(int n) {
    DerivField d(n, n);
    const double s = n / 12.0, peak = 0.3 * s / std::exp(-0.5);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double u = i + 0.5, v = j + 0.5;
            glm::dvec2 g(0.0);
            for (auto [amp, p, q] : {std::tuple{0.5, 8.0, 3.0}, std::tuple{0.4, -5.0, 11.0}}) {
                const double c = std::cos(2 * kPi * (p * u + q * v) / n);
                g += amp * c * glm::normalize(glm::dvec2(p, q));
            }
            const double du = u - n / 2.0, dv = v - n / 2.0;
            const double e = peak * std::exp(-(du * du + dv * dv) / (2 * s * s)) / (s * s);
            g -= e * glm::dvec2(du, dv);
            d.at(i, j) = glm::vec2(float(g.x), float(g.y));
        }
    return d;
}

double medianMs(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

struct Row {
    std::string name;
    std::function<void()> correct, naive; // naive may be empty
};

struct Timing {
    double correct1 = 0, correctAll = 0, naive1 = 0, naiveAll = 0; // ms
};

template <class F>
double timeMs(F&& f) {
    const auto t0 = Clock::now();
    f();
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

Timing measure(const Row& r, int runs) {
    Timing t;
    for (int threads : {1, 0}) {
        std::vector<double> c, n;
        tbb::global_control gc(tbb::global_control::max_allowed_parallelism,
                               threads ? size_t(threads)
                                       : size_t(tbb::info::default_concurrency()));
        for (int k = 0; k < runs; ++k) {
            c.push_back(timeMs(r.correct));
            if (r.naive) n.push_back(timeMs(r.naive));
        }
        (threads ? t.correct1 : t.correctAll) = medianMs(c);
        if (r.naive) (threads ? t.naive1 : t.naiveAll) = medianMs(n);
    }
    return t;
}

} // namespace

int main(int argc, char** argv) {
    int n = 4096, runs = 5;
    std::string only;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--size") && i + 1 < argc)
            n = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc)
            runs = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--only") && i + 1 < argc)
            only = argv[++i];
        else {
            std::fprintf(stderr, "usage: normalmap_bench [--size N] [--runs K] [--only NAME]\n");
            return 2;
        }
    }
    n = std::clamp(n, 16, 16384);
    runs = std::max(runs, 1);
    std::printf("normalmap_bench: %dx%d map, median of %d runs, %d threads available\n", n, n, runs,
                tbb::info::default_concurrency());

    const DerivField d = makeSlopes(n), d2 = scale(makeSlopes(n), -0.5f);
    const NormalField nf = normalsFromSlopes(d), nf2 = normalsFromSlopes(d2);
    const Image rgb = encodeSlopes(d, MapFormat{}, false);
    const ScalarField h = toHeight(d, Wrap::Repeat), h2 = toHeight(d2, Wrap::Repeat);
    ScalarField mask(n, n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            mask.at(i, j) = 0.5f + 0.45f * std::sin(float(2 * kPi * (i + 2 * j)) / float(n));
    const Curve boost = boostCurve(100.0f, 0.5f);
    const Warp sine{Warp::Kind::Sine, 0.02f, float(8 * kPi)};
    const Wrap R = Wrap::Repeat;
    // Results go to a sink so nothing is optimised away.
    volatile float sink = 0.0f;
    auto keep = [&](const auto& grid) { sink = sink + float(grid.v[grid.v.size() / 2][0]); };
    auto keepS = [&](const ScalarField& s) { sink = sink + s.v[s.v.size() / 2]; };
    auto keepI = [&](const Image& img) { sink = sink + img.samples[img.samples.size() / 2]; };

    const std::vector<Row> rows = {
        {"decode rgb8 to slopes (L4) / to normals",
         [&] { keep(decodeSlopes(rgb, MapFormat{}, "b")); },
         [&] { keep(decodeNormals(rgb, MapFormat{}, "b")); }},
        {"scale 2", [&] { keep(scale(d, 2.0f)); }, [&] { keep(naive::scale(nf, 2.0f)); }},
        {"add A B", [&] { keep(add(d, 1.0f, d2, 1.0f)); },
         [&] { keep(naive::add(nf, 1.0f, nf2, 1.0f)); }},
        {"blend A B --mask (heights given)", [&] { keep(blend(d, h, d2, h2, mask, R)); },
         [&] { keep(naive::blend(nf, nf2, mask)); }},
        {"modulate (heights given)", [&] { keep(modulate(d, h, mask, R)); },
         [&] { keep(naive::modulate(nf, mask)); }},
        {"curves boost (heights given)", [&] { keep(applyCurve(d, h, boost)); },
         [&] { keep(naive::applyCurve(nf, h, boost)); }},
        {"deform sine", [&] { keep(deform(d, sine, R)); },
         [&] { keep(naive::deform(nf, sine, R)); }},
        {"from-height (central / forward differences)", [&] { keep(fromHeight(h, 1.0f, R)); },
         [&] { keep(naive::fromHeight(h, 1.0f, R)); }},
        {"to-height --wrap (DFT / path integration)", [&] { keepS(toHeight(d, R)); },
         [&] { keepS(naive::toHeight(d)); }},
        {"to-height, no wrap (DCT / path integration)", [&] { keepS(toHeight(d, Wrap::Clamp)); },
         [&] { keepS(naive::toHeight(d)); }},
        {"mips --lean / --naive", [&] { keepI(mipChain(leanLevel0(d)).back()); },
         [&] {
             auto l = mipChain(naiveMipLevel0(nf));
             finishNaiveMips(l);
             keepI(l.back());
         }},
        {"mips --toksvig",
         [&] {
             auto l = mipChain(toksvigLevel0(nf));
             finishToksvig(l);
             keepI(l.back());
         },
         {}},
        {"encode slopes / normals to rgb8", [&] { keepI(encodeSlopes(d, MapFormat{}, false)); },
         [&] { keepI(encodeNormals(nf, MapFormat{}, false)); }},
    };
    const double mpx = double(n) * double(n) / 1e6;
    std::printf(
        "\n| op | correct 1T Mpx/s | correct all Mpx/s | naive 1T Mpx/s | naive all Mpx/s | "
        "correct/naive time (1T) | speed-up all/1T (correct) |\n|---|---|---|---|---|---|---|\n");
    for (const Row& r : rows) {
        if (!only.empty() && r.name.find(only) == std::string::npos) continue;
        const Timing t = measure(r, runs);
        auto rate = [&](double ms) { return ms > 0 ? mpx / (ms / 1e3) : 0.0; };
        if (r.naive) {
            std::printf("| %s | %.1f | %.1f | %.1f | %.1f | %.2f | %.2f |\n", r.name.c_str(),
                        rate(t.correct1), rate(t.correctAll), rate(t.naive1), rate(t.naiveAll),
                        t.correct1 / t.naive1, t.correct1 / t.correctAll);
        } else {
            std::printf("| %s | %.1f | %.1f | - | - | - | %.2f |\n", r.name.c_str(),
                        rate(t.correct1), rate(t.correctAll), t.correct1 / t.correctAll);
        }
        std::fflush(stdout);
    }
    return sink == 12345.0f ? 1 : 0;
}
