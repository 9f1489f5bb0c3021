// bench_bump: CPU cost of every shared bump function (shaders/sg/*.glsl
// compiled as C++ through GLM, surfgrad/bump/core.h), in ns per call.
// Each benchmark cycles through 1024 precomputed random inputs (so nothing
// is constant-folded) and keeps every result alive with DoNotOptimize.
// The baseline row "baseline/load3" reads the same inputs and returns one
// of them: the cost of the loop and the loads, to subtract mentally.
// Run: build/bin/bench_bump [--benchmark_repetitions=5
//      --benchmark_report_aggregates_only=true] (see bench/README.md).
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "surfgrad/bump/core.h"

namespace {

namespace g = sg::glsl;

struct Inputs {
    std::vector<g::vec3> n, a, b, c;
    std::vector<g::vec2> d, e, f;
    std::vector<g::vec4> t4;
    std::vector<g::mat4> m;
    std::vector<float> s;
    std::vector<g::SgFrame> frame;
    Inputs() {
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> U(-1, 1);
        auto v3 = [&] { return g::vec3(U(rng), U(rng), U(rng)); };
        for (int i = 0; i < 1024; ++i) {
            g::vec3 nn = g::normalize(v3() + g::vec3(0, 0, 2));
            n.push_back(nn);
            a.push_back(v3() * 0.01f);
            b.push_back(v3() * 0.01f);
            c.push_back(v3());
            d.push_back(g::vec2(U(rng), U(rng)) * 0.7f);
            e.push_back(g::vec2(0.002f + 0.001f * U(rng), 0.0005f * U(rng)));
            f.push_back(g::vec2(0.0005f * U(rng), 0.002f + 0.001f * U(rng)));
            t4.push_back(g::vec4(v3(), U(rng) < 0 ? -1.0f : 1.0f));
            g::mat4 mm(1.0f);
            for (int k = 0; k < 4; ++k) mm[k] += g::vec4(v3() * 0.1f, 0.0f);
            mm[3][3] = 1.0f;
            m.push_back(mm);
            s.push_back(1.0f + U(rng));
            frame.push_back(g::sgPrologue(nn * 1.3f, a.back(), b.back(), true, SG_BFACE_NONE));
        }
    }
};
const Inputs& in() {
    static const Inputs x;
    return x;
}

template <class F>
void run(benchmark::State& state, F&& fn) {
    const Inputs& x = in();
    size_t i = 0;
    for (auto _ : state) {
        auto r = fn(x, i & 1023);
        benchmark::DoNotOptimize(r);
        ++i;
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}

#define SG_BENCH(name, expr)                                                                       \
    void BM_##name(benchmark::State& state) {                                                      \
        run(state, [](const Inputs& x, size_t i) { return expr; });                                \
    }                                                                                              \
    BENCHMARK(BM_##name)->Name(#name)

SG_BENCH(baseline_load3, x.c[i]);
SG_BENCH(resolve_L1, g::sgResolve(x.frame[i], x.c[i] * 0.3f));
SG_BENCH(bump_scale_L2, g::sgBumpScale(x.s[i], x.c[i]));
SG_BENCH(tspace_to_deriv_L4, g::sgTspaceNormalToDeriv(x.d[i], false));
SG_BENCH(tbn_L5, g::sgSurfgradFromTBN(x.d[i], x.a[i], x.b[i]));
SG_BENCH(gen_basis_tb_L6, ([&] {
             g::vec3 t, b;
             g::sgGenBasisTB(x.frame[i], x.d[i], x.e[i], x.f[i], t, b);
             return t + b;
         }()));
SG_BENCH(perturbed_L7, g::sgSurfgradFromPerturbedNormal(x.frame[i], x.c[i] + x.n[i] * 2.0f));
SG_BENCH(scale_dependent_L8,
         g::sgSurfgradScaleDependent(x.frame[i], x.d[i], x.e[i], x.f[i], g::vec2(1024.0f)));
SG_BENCH(screen_deriv_L8, g::sgSurfgradFromScreenDeriv(x.frame[i], x.d[i]));
SG_BENCH(height_3tap_L9, g::sgHeightDeriv3Tap(x.s[i], x.d[i].x, x.d[i].y));
SG_BENCH(parallax_project_L10, g::sgProjectVecToTextureSpace(x.frame[i], x.n[(i + 1) & 1023],
                                                             x.e[i], x.f[i], 0.05f, false));
SG_BENCH(texoffs_to_surface_L11, g::sgTexSpaceOffsToSurface(x.frame[i], x.e[i], x.f[i], x.d[i]));
SG_BENCH(volume_L12, g::sgSurfgradFromVolumeGradient(x.frame[i], x.c[i]));
SG_BENCH(triplanar_weights_L14, g::sgTriplanarWeights(x.n[i], 3.0f));
SG_BENCH(triplanar_L13_L14,
         g::sgSurfgradFromTriplanar(x.frame[i], g::sgTriplanarWeights(x.n[i], 3.0f), x.d[i], x.e[i],
                                    x.f[i], false, false));
SG_BENCH(decal_L15, g::sgSurfgradFromDecal(x.frame[i], x.d[i], x.a[i], x.b[i], false));
SG_BENCH(prologue_L16, g::sgPrologue(x.c[i], x.a[i], x.b[i], (i & 1) != 0, SG_BFACE_FLIP));
SG_BENCH(reprologue, g::sgReprologue(x.frame[i], x.n[(i + 3) & 1023], x.a[i], x.b[i]));
SG_BENCH(mikkts_basis, ([&] {
             g::vec3 t, b;
             g::sgMikktsBasis(x.c[i], x.t4[i], t, b);
             return t + b;
         }()));
SG_BENCH(screen_deriv_of_pos_L17, ([&] {
             g::vec3 dx, dy;
             g::sgScreenDerivOfPos(dx, dy, x.c[i], x.n[i], x.m[i], 100.5f, 200.5f);
             return dx + dy;
         }()));
SG_BENCH(deriv_to_tspace, g::sgDerivToTspaceNormal(x.d[i], false));
SG_BENCH(loviscach_scale, g::sgDerivScale(x.d[i], x.s[i]));
SG_BENCH(loviscach_add, g::sgDerivAdd(x.d[i], x.s[i], x.e[i], 0.5f));
SG_BENCH(loviscach_modulate, g::sgDerivModulate(x.d[i], x.s[i], x.e[i], 0.5f));
SG_BENCH(loviscach_curve, g::sgDerivCurve(x.d[i], g::sgCurveBoostSlope(x.s[i], 100.0f, 0.5f)));
SG_BENCH(loviscach_deform_sine,
         g::sgDerivDeform(x.d[i], g::sgSineWarpJacobian(x.s[i], 0.02f, 100.0f)));
SG_BENCH(bounded_scale, g::sgBoundedScale3(x.c[i], g::vec4(x.s[i], 1e10f, 1e-12f, 3.0f)));
// The per-pixel TBN chain of the llvmpipe benchmark, on the CPU:
// L16 + L6 + L4 + L5 + L1 against the vertex-tangent chain mikkts + L4 + L5 + L1.
SG_BENCH(chain_per_pixel_tbn, ([&] {
             g::SgFrame fr = g::sgPrologue(x.c[i], x.a[i], x.b[i], true, SG_BFACE_NONE);
             g::vec3 t, b;
             g::sgGenBasisTB(fr, x.d[i], x.e[i], x.f[i], t, b);
             return g::sgResolve(
                 fr, g::sgSurfgradFromTBN(g::sgTspaceNormalToDeriv(x.d[i], false), t, b));
         }()));
SG_BENCH(chain_vertex_tangent, ([&] {
             g::SgFrame fr;
             fr.nrmBase = g::sgSafeNormalize(x.c[i], g::vec3(0, 0, 1));
             fr.resolveSign = 1.0f;
             g::vec3 t, b;
             g::sgMikktsBasis(x.c[i], x.t4[i], t, b);
             return g::sgResolve(
                 fr, g::sgSurfgradFromTBN(g::sgTspaceNormalToDeriv(x.d[i], false), t, b));
         }()));

} // namespace

BENCHMARK_MAIN();
