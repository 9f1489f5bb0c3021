// CPU/GPU parity harness (see parity.h).
#include "surfgrad/parity/check.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <sstream>
#include <utility>

#include "surfgrad/shaders/shader_files.h"

namespace sg::parity {

namespace {

// SG_BIG of shaders/sg/compat.glsl: the documented input magnitude domain
// and the bound on outputs of the dividing functions.
constexpr double kBig = 1e18;

uint64_t hashRecord(const float* in, int n) {
    uint64_t h = 1469598103934665603ull;
    for (int i = 0; i < n; ++i) {
        uint32_t b;
        std::memcpy(&b, &in[i], 4);
        h = (h ^ b) * 1099511628211ull;
    }
    return h;
}

double norm3(const float* v) {
    return std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
}

const eval::Field* outField(const eval::Entry& e, const char* key) {
    for (const auto& f : e.outputs) {
        if (f.key == key) return &f;
    }
    return nullptr;
}

} // namespace

std::vector<float> evalCpuAll(const eval::Entry& e, const std::vector<float>& inputs) {
    const size_t in = size_t(eval::inStride()), out = size_t(eval::outStride());
    const size_t count = inputs.size() / in;
    std::vector<float> result(count * out);
    for (size_t r = 0; r < count; ++r) eval::evalCpu(e, &inputs[r * in], &result[r * out]);
    return result;
}

GpuEvaluator::GpuEvaluator(gl::HeadlessContext& ctx, ProgramFactory factory, shaders::Target source)
    : ctx_(ctx), vertexStage_(false), factory_(std::move(factory)), source_(source) {
    if (ctx.api() != gl::Api::Gl45Core) {
        throw gl::GlError("GpuEvaluator: a program factory makes compute programs, which need an "
                          "OpenGL 4.5 context");
    }
}

std::vector<float> GpuEvaluator::evalAll(const eval::Entry& e, const std::vector<float>& inputs) {
    ctx_.makeCurrent();
    const shaders::Target target = this->target();
    const std::string name = "eval[" + e.name + "]";
    auto it = programs_.find(e.kernel);
    if (it == programs_.end()) {
        const auto defines = eval::evalGpuDefines(e);
        if (factory_) {
            it = programs_.emplace(e.kernel, factory_(e)).first;
        } else if (!vertexStage_) {
            auto src = shaders::assemble(eval::evalGpuBody(), name, defines);
            it = programs_.emplace(e.kernel, gl::Program({{gl::Stage::Compute, src}})).first;
        } else {
            // No compute stage: the vertex entry under transform feedback.
            auto vs = shaders::assemble(eval::evalGpuVertexBody(), name, defines, target);
            it = programs_
                     .emplace(e.kernel, gl::feedbackProgram(vs, target, eval::evalGpuFeedback()))
                     .first;
        }
    }
    const size_t in = size_t(eval::inStride());
    if (!vertexStage_) {
        return gl::runCompute(it->second, inputs, eval::inStride(), eval::outStride(),
                              inputs.size() / in);
    }
    return gl::runTransformFeedback(it->second, inputs, eval::inStride(), eval::outStride(),
                                    inputs.size() / in);
}

shaders::Target GpuEvaluator::target() const {
    return factory_ ? source_ : gl::targetFor(ctx_.api());
}

double mixedError(const eval::Entry& e, const double* a, const double* ref) {
    // Mixed: absolute below magnitude 1, relative above; Relative (outputs
    // with no natural unit scale, e.g. position units per pixel): relative.
    const double floor = e.measure == eval::ErrorMeasure::Relative ? 1e-30 : 1.0;
    double worst = 0;
    for (const auto& f : e.outputs) {
        double diffInf = 0, refInf = 0;
        for (int i = f.slot; i < f.slot + f.width; ++i) {
            double d = std::fabs(a[i] - ref[i]);
            if (std::isnan(d)) return INFINITY;
            diffInf = std::max(diffInf, d);
            refInf = std::max(refInf, std::fabs(ref[i]));
        }
        worst = std::max(worst, diffInf / std::max(floor, refInf));
    }
    return worst;
}

double conditionProbe(const eval::Entry& e, const float* in, int perturbations) {
    const int nin = eval::inStride();
    const size_t nout = size_t(eval::outStride());
    std::vector<double> x(static_cast<size_t>(nin)), y(nout), xp, yp(nout);
    for (int i = 0; i < nin; ++i) x[size_t(i)] = in[i];
    eval::evalDouble(e, x.data(), y.data());
    std::mt19937_64 rng(hashRecord(in, nin));
    double worst = 0;
    for (int p = 0; p < perturbations; ++p) {
        xp = x;
        for (const auto& f : e.inputs) {
            if (f.kind != eval::FieldKind::Float) continue; // flags, modes, counts stay
            for (int i = f.slot; i < f.slot + f.width; ++i) {
                double s = (rng() & 1) ? 1.0 : -1.0;
                xp[size_t(i)] = x[size_t(i)] * (1.0 + s * kPerturbation);
            }
        }
        eval::evalDouble(e, xp.data(), yp.data());
        worst = std::max(worst, mixedError(e, yp.data(), y.data()));
    }
    return worst;
}

bool backwardExplained(const eval::Entry& e, const float* in, const double* cpu, const double* gpu,
                       double mixedTol) {
    const int nin = eval::inStride();
    const size_t nout = size_t(eval::outStride());
    std::vector<double> x(static_cast<size_t>(nin)), xp, yp(nout);
    for (int i = 0; i < nin; ++i) x[size_t(i)] = in[i];
    std::mt19937_64 rng(hashRecord(in, nin) ^ 0x5bd1e995u);
    bool cpuOk = false, gpuOk = false;
    for (int p = 0; p < kBackwardSearch && !(cpuOk && gpuOk); ++p) {
        xp = x;
        // Half the probes at the full radius, half at random radii inside it.
        // Radii log-uniform from 2^-24 (one ulp) to kBackwardRadius, so that
        // both sign flips of a rounding-level determinant and results of a
        // clamp at FLT_EPSILON are reachable.
        const double radius = kBackwardRadius * std::exp2(-6.0 * double(rng() % 1024) / 1023.0);
        for (const auto& f : e.inputs) {
            if (f.kind != eval::FieldKind::Float) continue;
            for (int i = f.slot; i < f.slot + f.width; ++i) {
                double s = (rng() & 1) ? 1.0 : -1.0;
                xp[size_t(i)] = x[size_t(i)] * (1.0 + s * radius);
            }
        }
        eval::evalDouble(e, xp.data(), yp.data());
        cpuOk = cpuOk || mixedError(e, cpu, yp.data()) <= mixedTol;
        gpuOk = gpuOk || mixedError(e, gpu, yp.data()) <= mixedTol;
    }
    return cpuOk && gpuOk;
}

std::string checkInvariants(const eval::Entry& e, const float* in, const float* out) {
    std::ostringstream why;
    for (const auto& f : e.outputs) {
        for (int i = f.slot; i < f.slot + f.width; ++i) {
            if (!std::isfinite(out[i])) {
                why << f.key << " is not finite";
                return why.str();
            }
        }
    }
    // Unit length: binary32 normalization is good to a few ulps.
    auto unit = [&](const char* key, bool zeroAllowed) -> bool {
        const eval::Field* f = outField(e, key);
        double l = norm3(out + f->slot);
        if (zeroAllowed && l == 0.0) return true;
        if (std::fabs(l - 1.0) > 1e-5) {
            why << key << " has length " << l << " (expected 1" << (zeroAllowed ? " or 0)" : ")");
            return false;
        }
        return true;
    };
    auto sign = [&](const char* key) -> bool {
        float v = out[outField(e, key)->slot];
        if (v != 1.0f && v != -1.0f) {
            why << key << " = " << v << " (expected +-1)";
            return false;
        }
        return true;
    };
    auto bounded = [&](const char* key, double bound) -> bool {
        const eval::Field* f = outField(e, key);
        for (int i = f->slot; i < f->slot + f->width; ++i) {
            if (std::fabs(double(out[i])) > bound) {
                why << key << "[" << i - f->slot << "] = " << out[i] << " exceeds " << bound;
                return false;
            }
        }
        return true;
    };
    const std::string& n = e.name;
    if (n == "resolve") {
        unit("n", false);
    } else if (n == "deriv-to-tspace") {
        if (unit("m", false) && !(out[2] > 0.0f)) why << "m.z = " << out[2] << " is not > 0";
    } else if (n == "basis") {
        // Both as long as the chart weight, in [0, 1] (1 for a valid UV
        // Jacobian, 0 for a degenerate one), up to a few ulps.
        const double lt = norm3(out + outField(e, "t")->slot),
                     lb = norm3(out + outField(e, "b")->slot);
        if (lt > 1.0 + 1e-5 || std::fabs(lt - lb) > 1e-5 * std::max(1.0, lt)) {
            why << "t, b have lengths " << lt << ", " << lb << " (expected equal, at most 1)";
        }
    } else if (n == "triplanar-weights") {
        double sum = double(out[0]) + out[1] + out[2];
        if (std::min({out[0], out[1], out[2]}) < 0.0f || std::fabs(sum - 1.0) > 1e-5) {
            why << "weights (" << out[0] << ", " << out[1] << ", " << out[2]
                << ") are not a partition of unity";
        }
    } else if (n == "prologue" || n == "reprologue") {
        unit("nrm_base", false) && sign("flip_sign") && sign("resolve_sign");
    } else if (n == "tspace-to-deriv") {
        // |d_i| <= 128 (listing 4's clamp) plus rounding.
        bounded("d", 128.0 * (1.0 + 1e-6));
    } else if (n == "perturbed") {
        // s <= 1/FLT_EPSILON and |n.v n - v| <= 2 for the scaled v.
        bounded("sg", 2.0 / 1.1920929e-7 * (1.0 + 1e-6));
    } else if (n == "scale-dependent" || n == "screen-deriv-surfgrad") {
        bounded("sg", 4 * kBig);
    } else if (n == "parallax-project") {
        bounded("offset", 4 * kBig);
    } else if (n == "texoffs-to-surface") {
        bounded("p", 4 * kBig);
    } else if (n == "screen-deriv-of-pos") {
        bounded("dpdx", 4 * kBig) && bounded("dpdy", 4 * kBig);
    } else if (n == "mikkts-basis") {
        // tang = min(1/|n|, SG_BIG) t and bino = sign cross(n/|n|, t): within
        // SG_BIG * |t| and |t| for inputs in the domain.
        bounded("t", 2 * kBig * kBig) && bounded("b", 2 * kBig);
    } else if (n == "lean-covariance") {
        // A valid covariance: variances >= 0, |cov| <= sqrt(var x var y)
        // (the clamp of lean.glsl), up to the rounding of the sqrt.
        if (!(out[0] >= 0.0f && out[1] >= 0.0f) ||
            std::fabs(double(out[2])) > std::sqrt(double(out[0]) * out[1]) * (1.0 + 1e-6)) {
            why << "cov = (" << out[0] << ", " << out[1] << ", " << out[2]
                << ") is not positive semi-definite";
        }
    } else if (n == "toksvig-variance") {
        // (1 - |N|) / |N| with |N| clamped to [2^-20, 1]: in [0, 2^20].
        if (!(out[0] >= 0.0f && out[0] <= 1048576.0f))
            why << "s2 = " << out[0] << " outside [0, 2^20]";
    } else if (n == "toksvig-factor") {
        if (!(out[0] > 0.0f && out[0] <= 1.0f)) why << "k = " << out[0] << " outside (0, 1]";
    }
    (void)in;
    return why.str();
}

std::string describeRecord(const eval::Entry& e, const float* in, const float* cpu,
                           const float* gpu, const double* ref) {
    std::ostringstream s;
    s.precision(9);
    s << "  in:";
    for (const auto& f : e.inputs) {
        s << " " << f.key << "=";
        if (f.width > 1) s << "[";
        for (int i = 0; i < f.width; ++i) s << (i ? "," : "") << in[f.slot + i];
        if (f.width > 1) s << "]";
    }
    auto outs = [&](const char* label, auto* v) {
        if (!v) return;
        s << "\n  " << label << ":";
        for (const auto& f : e.outputs) {
            s << " " << f.key << "=[";
            for (int i = 0; i < f.width; ++i) s << (i ? "," : "") << v[f.slot + i];
            s << "]";
        }
    };
    outs("cpu", cpu);
    outs("gpu", gpu);
    outs("f64", ref);
    return s.str();
}

Row compare(GpuEvaluator& gpuEval, const eval::Entry& e, const std::vector<float>& inputs,
            double mixedTol) {
    const size_t nin = size_t(eval::inStride()), nout = size_t(eval::outStride());
    const auto cpu = evalCpuAll(e, inputs);
    const auto gpu = gpuEval.evalAll(e, inputs);
    Row row;
    row.entry = e.name;
    row.records = inputs.size() / nin;
    std::vector<double> x(nin), ref(nout), c(nout), q(nout);
    for (size_t r = 0; r < row.records; ++r) {
        const float* in = &inputs[r * nin];
        const float* cf = &cpu[r * nout];
        const float* gf = &gpu[r * nout];
        bool cpuBad = false, gpuBad = false;
        for (size_t i = 0; i < nout; ++i) {
            c[i] = cf[i];
            q[i] = gf[i];
        }
        for (const auto& f : e.outputs) {
            for (int i = f.slot; i < f.slot + f.width; ++i) {
                cpuBad |= !std::isfinite(cf[i]);
                gpuBad |= !std::isfinite(gf[i]);
            }
        }
        row.nonFiniteCpu += cpuBad;
        row.nonFiniteGpu += gpuBad;
        for (const float* o : {cf, gf}) {
            std::string why = checkInvariants(e, in, o);
            if (!why.empty()) {
                if (row.invariantViolations++ == 0) {
                    row.firstViolation = (o == cf ? "cpu: " : "gpu: ") + why + "\n" +
                                         describeRecord(e, in, cf, gf, nullptr);
                }
                break;
            }
        }
        const double mixed = mixedError(e, q.data(), c.data());
        row.maxMixedErrAll = std::max(row.maxMixedErrAll, mixed);
        // The short probe on every record; a record whose builds disagree
        // gets the long one (a random direction misses a rounding-level
        // singularity with probability up to 1/2 per try).
        if (conditionProbe(e, in, kPerturbations) > mixedTol / 4 ||
            (mixed > mixedTol && conditionProbe(e, in, kPerturbationsLong) > mixedTol / 4)) {
            ++row.illConditioned;
            continue;
        }
        if (mixed > mixedTol && backwardExplained(e, in, c.data(), q.data(), mixedTol)) {
            ++row.backwardExplained;
            continue;
        }
        for (size_t i = 0; i < nin; ++i) x[i] = in[i];
        eval::evalDouble(e, x.data(), ref.data());
        // Accuracy vs binary64, leaving out results that are exact for a
        // nearby input (a rounding-level sign branch taken the other way).
        for (auto [out, maxErr] :
             {std::pair{&c, &row.maxCpuRefErr}, std::pair{&q, &row.maxGpuRefErr}}) {
            double err = mixedError(e, out->data(), ref.data());
            if (err > mixedTol && (conditionProbe(e, in, kPerturbationsLong) > mixedTol / 4 ||
                                   backwardExplained(e, in, out->data(), out->data(), mixedTol))) {
                continue;
            }
            *maxErr = std::max(*maxErr, err);
        }
        if (mixed > row.maxMixedErr) {
            row.maxMixedErr = mixed;
            row.worstRecord = r;
        }
        for (const auto& f : e.outputs) {
            double diffInf = 0, cInf = 0;
            for (int i = f.slot; i < f.slot + f.width; ++i) {
                double d = std::fabs(q[size_t(i)] - c[size_t(i)]);
                row.maxAbsErr = std::max(row.maxAbsErr, d);
                diffInf = std::max(diffInf, d);
                cInf = std::max(cInf, std::fabs(c[size_t(i)]));
            }
            if (cInf >= 1e-30) row.maxRelErr = std::max(row.maxRelErr, diffInf / cInf);
        }
    }
    return row;
}

} // namespace sg::parity
