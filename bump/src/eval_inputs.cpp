// Input records of the parity suite (surfgrad/bump/eval_kernels.h,
// generateInputs): the generators named by the kernel list of
// shaders/sg/eval/kernels.glsl.
#include "eval_inputs.h"

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace sg::eval {

double RecordRandom::mag(double lo, double hi) {
    return std::pow(10.0, uni(lo, hi));
}

glm::dvec3 RecordRandom::unitVec() {
    glm::dvec3 v;
    double l;
    do {
        v = {uni(-1, 1), uni(-1, 1), uni(-1, 1)};
        l = glm::dot(v, v);
    } while (l < 1e-6 || l > 1);
    return v / std::sqrt(l);
}

void RecordRandom::unitVec(float* v) {
    glm::dvec3 u = unitVec();
    for (int i = 0; i < 3; ++i) v[i] = float(u[i]);
}

void RecordRandom::vec(float* v, int n, double scale) {
    for (int i = 0; i < n; ++i) v[i] = float(uni(-1, 1) * scale);
}

namespace {

// One adversarial magnitude: denormal, tiny, huge (up to the SG_BIG domain
// bound), zero or ordinary.
double advScale(RecordRandom& g) {
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

// One field's values by its Generate option.
void fillField(RecordRandom& g, const Field& f, float* v, bool adversarial) {
    if (f.kind == FieldKind::Bool) {
        v[0] = g.chance(0.5) ? 1.0f : 0.0f;
        return;
    }
    if (f.kind == FieldKind::Int) {
        v[0] = float(f.minValue + g.pick(f.maxValue - f.minValue + 1));
        return;
    }
    switch (f.generate) {
    case Generate::Sign:
        v[0] = g.chance(0.5) ? 1.0f : -1.0f;
        return;
    case Generate::Normal:
    case Generate::Direction:
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
        return;
    case Generate::NormalMapXY: {
        // inside the disk, on the circle or outside
        double r = adversarial ? (g.chance(0.5) ? 1.0 : g.uni(0.99, 1.5)) : g.uni(0, 0.999);
        double a = g.uni(0, 2 * M_PI);
        v[0] = float(r * std::cos(a));
        v[1] = float(r * std::sin(a));
        if (adversarial && g.chance(0.2)) v[0] = v[1] = 0.0f;
        return;
    }
    case Generate::Exponent:
        v[0] = float(adversarial ? g.mag(-2, 2.5) : g.uni(1, 8));
        return;
    case Generate::TexSize:
        v[0] = float(1 << g.pick(13));
        v[1] = float(1 << g.pick(13));
        return;
    case Generate::Tangent:
        g.vec(v, 3, adversarial ? advScale(g) : g.mag(-1, 1));
        v[3] = g.chance(0.5) ? 1.0f : -1.0f;
        return;
    case Generate::Symmetric:
        v[0] = float(g.uni(-1, 1) * (adversarial ? advScale(g) : 1.0));
        return;
    case Generate::Positive:
        v[0] = float(adversarial ? advScale(g) : g.mag(0, 3));
        return;
    default: {
        // any vector or scalar (sg, d, t, b, dpdx, dpdy, dstdx, dstdy, deriv,
        // grad, dx/dy/dz, offset, dhdxy, scale, alpha, w*, a, b...)
        double s = adversarial ? advScale(g) : g.mag(-3, 3);
        g.vec(v, f.width, s);
    }
    }
}

float* fieldWith(const Entry& e, float* record, Generate generate) {
    for (const Field& f : e.inputs) {
        if (f.generate == generate) return record + f.slot;
    }
    return nullptr;
}

float* fieldNamed(const Entry& e, float* record, const char* key) {
    for (const Field& f : e.inputs) {
        if (f.key == key) return record + f.slot;
    }
    return nullptr;
}

} // namespace

void fieldInputs(const Entry& e, RecordRandom& g, float* rec, bool adversarial) {
    for (const Field& f : e.inputs) fillField(g, f, rec + f.slot, adversarial);
    if (!adversarial) return;
    // Cross-field adversarial relations, applied after the independent fill.
    float* n = fieldWith(e, rec, Generate::Normal);
    float* dpdx = fieldWith(e, rec, Generate::ScreenDerivX);
    float* dpdy = fieldWith(e, rec, Generate::ScreenDerivY);
    float* dstdx = fieldWith(e, rec, Generate::UvDerivX);
    float* dstdy = fieldWith(e, rec, Generate::UvDerivY);
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
        for (const Field& f : e.inputs) {
            if (f.width != 3 || f.generate == Generate::Normal) continue;
            float* v = rec + f.slot;
            double nn = double(n[0]) * n[0] + double(n[1]) * n[1] + double(n[2]) * n[2];
            if (nn <= 0) continue;
            double d = (double(v[0]) * n[0] + double(v[1]) * n[1] + double(v[2]) * n[2]) / nn;
            for (int i = 0; i < 3; ++i) v[i] = float(v[i] - d * n[i]);
        }
    }
}

void cameraInputs(const Entry& e, RecordRandom& g, float* rec, bool adversarial) {
    const double w = double(64 << g.pick(7)), h = double(64 << g.pick(7));
    double worldScale = adversarial && g.chance(0.5) ? g.mag(-4, 4) : g.mag(-1, 1);
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
    float* recPos = fieldNamed(e, rec, "pos");
    float* recN = fieldNamed(e, rec, "n");
    float* recInv = fieldNamed(e, rec, "inv_view_proj_scr");
    for (int i = 0; i < 3; ++i) {
        recPos[i] = float(pos[i]);
        recN[i] = float(n[i]);
    }
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) recInv[4 * c + r] = float(inv[c][r]);
    }
    *fieldNamed(e, rec, "x") = float(x);
    *fieldNamed(e, rec, "y") = float(y);
}

std::vector<float> generateInputs(const Entry& e, size_t count, uint64_t seed) {
    const int stride = inStride();
    std::vector<float> data(count * size_t(stride), 0.0f);
    RecordRandom g(seed ^ (uint64_t(e.kernel) * 0x9E3779B97F4A7C15ull));
    for (size_t r = 0; r < count; ++r) {
        float* rec = data.data() + r * size_t(stride);
        for (const auto& f : e.inputs) {
            for (int i = 0; i < f.width; ++i) rec[f.slot + i] = f.defaultValue;
        }
        e.generator(e, g, rec, g.chance(0.4));
    }
    return data;
}

} // namespace sg::eval
