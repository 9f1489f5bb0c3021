// CPU/GPU parity harness (see parity.h).
#include "parity.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "surfgrad/shader_files.h"

namespace sg::parity {

namespace {

struct Gen {
    std::mt19937_64 rng;
    explicit Gen(uint64_t seed) : rng(seed) {}
    double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
    int pick(int n) { return int(std::uniform_int_distribution<int>(0, n - 1)(rng)); }
    bool chance(double p) { return uni(0, 1) < p; }
    // 10^U(lo, hi)
    double mag(double lo, double hi) { return std::pow(10.0, uni(lo, hi)); }
    void unitVec(float* v) {
        double x, y, z, l;
        do {
            x = uni(-1, 1);
            y = uni(-1, 1);
            z = uni(-1, 1);
            l = x * x + y * y + z * z;
        } while (l < 1e-6 || l > 1);
        l = std::sqrt(l);
        v[0] = float(x / l);
        v[1] = float(y / l);
        v[2] = float(z / l);
    }
    void vec(float* v, int n, double scale) {
        for (int i = 0; i < n; ++i) v[i] = float(uni(-1, 1) * scale);
    }
};

// One adversarial magnitude: tiny, huge or ordinary.
double advScale(Gen& g) {
    switch (g.pick(5)) {
    case 0: return g.mag(-18, -12);
    case 1: return g.mag(12, 18);
    case 2: return 0.0;
    default: return g.mag(-3, 3);
    }
}

// Fills one record. Cross-field adversarial relations (derivatives parallel
// to each other or to n, vectors at the horizon of n) are applied after the
// independent fill.
void fillRecord(Gen& g, const eval::Entry& e, float* rec, bool adversarial) {
    for (const auto& f : e.inputs) {
        float* v = rec + f.slot;
        const std::string& k = f.key;
        if (f.kind == eval::FieldKind::Bool) {
            v[0] = g.chance(0.5) ? 1.0f : 0.0f;
        } else if (k == "bface_mode") {
            v[0] = float(g.pick(3));
        } else if (k == "count") {
            v[0] = float(g.pick(5));
        } else if (k == "resolve_sign") {
            v[0] = g.chance(0.5) ? 1.0f : -1.0f;
        } else if (k == "n" || k == "resolved" || k == "axis_x" || k == "axis_y" || k == "dir") {
            g.unitVec(v);
            if (adversarial && g.chance(0.3)) {
                double s = advScale(g); // non-unit, zero, huge or tiny normals
                for (int i = 0; i < 3; ++i) v[i] = float(v[i] * s);
            } else if (adversarial && g.chance(0.3)) {
                // axis-aligned, possibly negative
                int a = g.pick(3);
                v[0] = v[1] = v[2] = 0.0f;
                v[a] = g.chance(0.5) ? 1.0f : -1.0f;
            }
        } else if (k == "m") {
            // normal-map xy: inside the disk, on the circle or outside
            double r = adversarial ? (g.chance(0.5) ? 1.0 : g.uni(0.99, 1.5)) : g.uni(0, 0.999);
            double a = g.uni(0, 2 * M_PI);
            v[0] = float(r * std::cos(a));
            v[1] = float(r * std::sin(a));
            if (adversarial && g.chance(0.2)) v[0] = v[1] = 0.0f;
        } else if (k == "k") {
            v[0] = float(adversarial ? g.mag(-2, 2.5) : g.uni(1, 8));
        } else if (k == "dim") {
            v[0] = float(1 << g.pick(13));
            v[1] = float(1 << g.pick(13));
        } else if (k == "tangent") {
            g.vec(v, 3, adversarial ? advScale(g) : g.mag(-1, 1));
            v[3] = g.chance(0.5) ? 1.0f : -1.0f;
        } else if (k == "inv_view_proj_scr") {
            // A perspective camera's inverse: built below from a random view.
            for (int i = 0; i < 16; ++i) v[i] = float(g.uni(-1, 1));
            v[15] = float(1.0 + g.uni(0, 1));
        } else if (k == "x" || k == "y") {
            v[0] = float(g.uni(0, 1024)) + 0.5f;
        } else if (k == "h" || k == "h1" || k == "h2" || k == "hc" || k == "hll" || k == "hlr" ||
                   k == "hul" || k == "u") {
            v[0] = float(g.uni(-1, 1) * (adversarial ? advScale(g) : 1.0));
        } else if (k == "p") {
            v[0] = float(adversarial ? advScale(g) : g.mag(0, 3));
        } else {
            // generic vector or scalar (sg, d, t, b, dpdx, dpdy, dstdx, dstdy,
            // deriv, grad, dx/dy/dz, offset, dhdxy, scale, alpha, w*, ...)
            double s = adversarial ? advScale(g) : g.mag(-3, 3);
            g.vec(v, f.width, s);
        }
    }
    if (!adversarial) return;
    auto slotOf = [&](const char* key) -> float* {
        for (const auto& f : e.inputs) {
            if (f.key == key) return rec + f.slot;
        }
        return nullptr;
    };
    float* n = slotOf("n");
    float* dpdx = slotOf("dpdx");
    float* dpdy = slotOf("dpdy");
    float* dstdx = slotOf("dstdx");
    float* dstdy = slotOf("dstdy");
    int rel = g.pick(6);
    if (rel == 0 && dpdx && dpdy) {
        // parallel screen derivatives: the surface is seen edge-on
        double c = g.uni(-2, 2);
        for (int i = 0; i < 3; ++i) dpdy[i] = float(dpdx[i] * c);
    } else if (rel == 1 && dstdx && dstdy) {
        // zero-determinant UV Jacobian (degenerate UVs)
        double c = g.uni(-2, 2);
        for (int i = 0; i < 2; ++i) dstdy[i] = float(dstdx[i] * c);
    } else if (rel == 2 && n && dpdx) {
        // dpdx along the normal: sigma_x vanishes
        double c = g.uni(-2, 2);
        for (int i = 0; i < 3; ++i) dpdx[i] = float(n[i] * c);
    } else if (rel == 3 && n) {
        // a vector field at the horizon of n (v, grad, sg, dir, t...) : make
        // every other 3-vector input perpendicular to n
        for (const auto& f : e.inputs) {
            if (f.width != 3 || f.key == "n") continue;
            float* v = rec + f.slot;
            double nn = double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2];
            if (nn <= 0) continue;
            double d = (double(v[0]) * n[0] + double(v[1]) * n[1] + double(v[2]) * n[2]) / nn;
            for (int i = 0; i < 3; ++i) v[i] = float(v[i] - d * n[i]);
        }
    }
}

} // namespace

std::vector<float> generateInputs(const eval::Entry& e, size_t count, uint64_t seed) {
    const int stride = eval::inStride();
    std::vector<float> data(count * size_t(stride), 0.0f);
    Gen g(seed ^ (uint64_t(e.kernel) * 0x9E3779B97F4A7C15ull));
    for (size_t r = 0; r < count; ++r) {
        float* rec = data.data() + r * size_t(stride);
        for (const auto& f : e.inputs) {
            for (int i = 0; i < f.width; ++i) rec[f.slot + i] = f.defaultValue;
        }
        fillRecord(g, e, rec, g.chance(0.4));
    }
    return data;
}

std::vector<float> evalCpuAll(const eval::Entry& e, const std::vector<float>& inputs) {
    const size_t in = size_t(eval::inStride()), out = size_t(eval::outStride());
    const size_t count = inputs.size() / in;
    std::vector<float> result(count * out);
    for (size_t r = 0; r < count; ++r) eval::evalCpu(e, &inputs[r * in], &result[r * out]);
    return result;
}

std::vector<float> GpuEvaluator::evalAll(const eval::Entry& e, const std::vector<float>& inputs) {
    ctx_.makeCurrent();
    auto it = programs_.find(e.kernel);
    if (it == programs_.end()) {
        auto src = shaders::assemble(eval::evalGpuBody(), "eval[" + e.name + "]",
                                     eval::evalGpuDefines(e));
        it = programs_.emplace(e.kernel, gl::Program({{gl::Stage::Compute, src}})).first;
    }
    const size_t in = size_t(eval::inStride());
    return gl::runCompute(it->second, inputs, eval::inStride(), eval::outStride(),
                          inputs.size() / in);
}

Row compare(GpuEvaluator& gpuEval, const eval::Entry& e, const std::vector<float>& inputs) {
    const size_t out = size_t(eval::outStride());
    const auto cpu = evalCpuAll(e, inputs);
    const auto gpu = gpuEval.evalAll(e, inputs);
    Row row;
    row.entry = e.name;
    row.records = inputs.size() / size_t(eval::inStride());
    for (size_t r = 0; r < row.records; ++r) {
        const float* c = &cpu[r * out];
        const float* q = &gpu[r * out];
        bool cpuBad = false, gpuBad = false;
        for (const auto& f : e.outputs) {
            double diffInf = 0, cInf = 0;
            for (int i = f.slot; i < f.slot + f.width; ++i) {
                cpuBad |= !std::isfinite(c[i]);
                gpuBad |= !std::isfinite(q[i]);
                double d = std::fabs(double(q[i]) - double(c[i]));
                diffInf = std::max(diffInf, d);
                cInf = std::max(cInf, std::fabs(double(c[i])));
                row.maxAbsErr = std::max(row.maxAbsErr, d);
                if (std::fabs(c[i]) >= 1e-6) row.maxRelErr = std::max(row.maxRelErr, d / std::fabs(c[i]));
            }
            double mixed = diffInf / std::max(1.0, cInf);
            if (mixed > row.maxMixedErr || std::isnan(mixed)) {
                row.maxMixedErr = std::isnan(mixed) ? INFINITY : mixed;
                row.worstRecord = r;
            }
        }
        row.nonFiniteCpu += cpuBad;
        row.nonFiniteGpu += gpuBad;
    }
    return row;
}

} // namespace sg::parity
