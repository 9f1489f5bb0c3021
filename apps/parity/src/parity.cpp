// CPU/GPU parity harness (see parity.h).
#include "surfgrad/parity.h"

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <sstream>

#include "surfgrad/shader_files.h"

namespace sg::parity {

namespace {

// SG_BIG of shaders/sg/compat.glsl: the documented input magnitude domain
// and the bound on outputs of the dividing functions.
constexpr double kBig = 1e18;
// Kernel id of listing 17 (SG_K_SCREEN_DERIV_OF_POS in kernels.glsl).
const int SG_K_SCREEN_DERIV_OF_POS_ID = eval::findEntry("screen-deriv-of-pos")->kernel;

struct Gen {
    std::mt19937_64 rng;
    explicit Gen(uint64_t seed) : rng(seed) {}
    double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
    int pick(int n) { return int(std::uniform_int_distribution<int>(0, n - 1)(rng)); }
    bool chance(double p) { return uni(0, 1) < p; }
    // 10^U(lo, hi)
    double mag(double lo, double hi) { return std::pow(10.0, uni(lo, hi)); }
    glm::dvec3 unitVec() {
        glm::dvec3 v;
        double l;
        do {
            v = {uni(-1, 1), uni(-1, 1), uni(-1, 1)};
            l = glm::dot(v, v);
        } while (l < 1e-6 || l > 1);
        return v / std::sqrt(l);
    }
    void unitVec(float* v) {
        glm::dvec3 u = unitVec();
        for (int i = 0; i < 3; ++i) v[i] = float(u[i]);
    }
    void vec(float* v, int n, double scale) {
        for (int i = 0; i < n; ++i) v[i] = float(uni(-1, 1) * scale);
    }
};

// One adversarial magnitude: denormal, tiny, huge (up to the SG_BIG domain
// bound), zero or ordinary.
double advScale(Gen& g) {
    switch (g.pick(6)) {
    case 0:
        return g.mag(-18, -12);
    case 1:
        return g.mag(12, 18);
    case 2:
        return 0.0;
    case 3:
        return g.mag(-44, -38); // binary32 denormals: GPUs flush them
    default:
        return g.mag(-3, 3);
    }
}

// A real camera for listing 17: invViewProjScr = inverse(viewport * proj *
// view), the pixel (x, y) inside the viewport and `pos` on that pixel's
// view ray, n facing the camera (adversarial: edge-on, back-facing, far
// cameras, huge or tiny world scales).
void fillCamera(Gen& g, float* rec, bool adversarial) {
    const double w = double(64 << g.pick(7)), h = double(64 << g.pick(7));
    double worldScale = adversarial && g.chance(0.5) ? g.mag(-4, 4) : g.mag(-1, 1);
    // Camera-relative world space (listing 16's relative position): the eye
    // stays within a few scene sizes of the origin; adversarially up to 1000.
    // The eye is at the origin (camera-relative space, as listing 16 asks);
    // adversarially it is up to 1000 scene sizes away, which costs
    // |eye| / near digits (the probe flags those records).
    glm::dvec3 eye(0.0);
    if (adversarial && g.chance(0.2)) eye = g.unitVec() * (worldScale * g.mag(-1, 3));
    const double dist = worldScale * g.uni(0.5, 20);
    glm::dvec3 fwd = g.unitVec();
    glm::dvec3 up = g.unitVec();
    if (std::fabs(glm::dot(up, fwd)) > 0.99) up = glm::dvec3(fwd.y, fwd.z, fwd.x);
    const glm::dmat4 view = glm::lookAt(eye, eye + fwd * dist, up);
    const double fovy = glm::radians(g.uni(10, 120));
    const double zNear = dist * g.mag(-3, -1), zFar = dist * g.mag(1, 3);
    const glm::dmat4 proj = glm::perspective(fovy, w / h, zNear, zFar);
    // NDC [-1,1]^3 -> screen [0,w] x [0,h] x [0,1].
    glm::dmat4 viewport(1.0);
    viewport[0][0] = w / 2;
    viewport[1][1] = h / 2;
    viewport[2][2] = 0.5;
    viewport[3] = glm::dvec4(w / 2, h / 2, 0.5, 1.0);
    const glm::dmat4 inv = glm::inverse(viewport * proj * view);
    const double x = std::floor(g.uni(0, w)) + 0.5, y = std::floor(g.uni(0, h)) + 0.5;
    // A point on the pixel's ray at a depth between near and far.
    const double zScr = g.uni(0.05, 0.999);
    glm::dvec4 p = inv * glm::dvec4(x, y, zScr, 1.0);
    glm::dvec3 pos = glm::dvec3(p) / p.w;
    glm::dvec3 toEye = glm::normalize(eye - pos);
    glm::dvec3 n = g.unitVec();
    if (glm::dot(n, toEye) < 0) n = -n;
    if (adversarial) {
        switch (g.pick(3)) {
        case 0:
            n = glm::normalize(n - glm::dot(n, toEye) * toEye);
            break; // edge-on
        case 1:
            n = -n;
            break; // back-facing
        default:
            n = glm::normalize(n + toEye * g.mag(-8, -2)); // nearly edge-on
        }
    }
    for (int i = 0; i < 3; ++i) {
        rec[0 + i] = float(pos[i]);
        rec[3 + i] = float(n[i]);
    }
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) rec[6 + 4 * c + r] = float(inv[c][r]);
    }
    rec[22] = float(x);
    rec[23] = float(y);
}

// Fills one record. Cross-field adversarial relations (derivatives parallel
// to each other or to n, vectors at the horizon of n) are applied after the
// independent fill.
void fillRecord(Gen& g, const eval::Entry& e, float* rec, bool adversarial) {
    if (e.name == "screen-deriv-of-pos") {
        fillCamera(g, rec, adversarial);
        return;
    }
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
        } else if (k == "h" || k == "h1" || k == "h2" || k == "hc" || k == "hll" || k == "hlr" ||
                   k == "hul" || k == "u") {
            v[0] = float(g.uni(-1, 1) * (adversarial ? advScale(g) : 1.0));
        } else if (k == "p") {
            v[0] = float(adversarial ? advScale(g) : g.mag(0, 3));
        } else {
            // generic vector or scalar (sg, d, t, b, dpdx, dpdy, dstdx, dstdy,
            // deriv, grad, dx/dy/dz, offset, dhdxy, scale, alpha, w*, a, b...)
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
        auto src =
            shaders::assemble(eval::evalGpuBody(), "eval[" + e.name + "]", eval::evalGpuDefines(e));
        it = programs_.emplace(e.kernel, gl::Program({{gl::Stage::Compute, src}})).first;
    }
    const size_t in = size_t(eval::inStride());
    return gl::runCompute(it->second, inputs, eval::inStride(), eval::outStride(),
                          inputs.size() / in);
}

double mixedError(const eval::Entry& e, const double* a, const double* ref) {
    // Position derivatives (world units per pixel) have no natural unit
    // scale: their error is purely relative.
    const double floor = e.kernel == SG_K_SCREEN_DERIV_OF_POS_ID ? 1e-30 : 1.0;
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
        // Both unit (a valid UV Jacobian) or both zero (degenerate).
        if (unit("t", true) && unit("b", true) && (norm3(out) == 0) != (norm3(out + 3) == 0)) {
            why << "exactly one of t, b is zero";
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
