// Table 7, triplanar method (docs/accuracy-cost.md): the surface-gradient
// triplanar of Mikkelsen 2019 section 2.8 (listings 13, 14, 12, 1) against
// what engines ship (triplanar.glsl: naive swizzle blend, UDN, whiteout,
// RNM, and Perlin's volume gradient added to the normal), on curved
// surfaces, in both handedness/origin conventions, over the blend
// sharpness k.
//
// Ground truth, in double: one tiling height map h(s, t) = A sin(2 pi s)
// sin(2 pi t) projected on the three planes (s, t along the convention's
// axes, scale `kScale` repeats per unit) and blended with listing 14's
// weights of the exact surface normal: the height field
//   H(p) = sum_i w_i(n(p)) h(s_i(p), t_i(p)),
// whose perturbed normal is normalize(n - grad_s H) (Blinn; Mikkelsen 2019
// eq. 1), grad_s H the surface gradient of H: the 3D gradient of H over a
// smooth extension off the surface (n(p) constant along the normal lines:
// p/|p| on the sphere, the normal of the nearest point on the torus), by
// central differences in double, projected on the tangent plane. Every
// method gets the exact base normal and the map's exact tangent-space
// normals at the pixel (rounded to binary32, no texture filtering), so the
// error is the method's alone. Two truths: the blend with the weights held
// constant, sum_i w_i grad_s h_i (what every method here approximates: none
// differentiates the weights), and the blended height H itself, whose
// gradient adds sum_i h_i grad_s w_i (what a surface displaced by H would
// show; large where the weights change fast, i.e. at high k).
//
// Cost: a ray-traced sphere filling the view (one full-screen triangle),
// three fetches of an RGBA32F tangent-space normal map, listing 14's
// weights and the method; the methods interleaved frame by frame, ratio to
// the surface-gradient row.
#include <epoxy/gl.h>

#include <array>
#include <cmath>
#include <string>

#include "tables.h"
#include "torus.h"
#include "triplanar.h"
#include "triplanar_glsl.h"

namespace study {

namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kScale = 3.0; // map repeats per unit length

struct Convention {
    bool rightHanded, upperLeft;
    const char* name;
};

glm::dvec3 axisS(int p, bool rh) {
    return p == 0 ? glm::dvec3(0, 0, rh ? -1 : 1) : glm::dvec3(1, 0, 0);
}
glm::dvec3 axisT(int p, bool rh, bool ul) {
    const double v = ul ? -1 : 1;
    return p == 1 ? glm::dvec3(0, 0, v * (rh ? -1 : 1)) : glm::dvec3(0, v, 0);
}

// Listing 14 in double (the truth's weights).
glm::dvec3 weights(const glm::dvec3& n, double k) {
    glm::dvec3 b = glm::max(glm::abs(n) - glm::dvec3(0.2), glm::dvec3(0.0));
    const double m = std::max(b.x, std::max(b.y, b.z));
    if (!(m > 0)) return glm::dvec3(1.0 / 3.0);
    glm::dvec3 w(std::pow(b.x / m, k), std::pow(b.y / m, k), std::pow(b.z / m, k));
    return w / (w.x + w.y + w.z);
}

struct Field {
    double amp; // A: steepest slope of a plane's height = A 2 pi kScale
    Convention c;
    double k;
    double h(double s, double t) const { return amp * std::sin(kTwoPi * s) * std::sin(kTwoPi * t); }
    glm::dvec2 dh(double s, double t) const { // d/ds, d/dt in map units
        return amp * kTwoPi *
               glm::dvec2(std::cos(kTwoPi * s) * std::sin(kTwoPi * t),
                          std::sin(kTwoPi * s) * std::cos(kTwoPi * t));
    }
    glm::dvec2 st(int p, const glm::dvec3& pos) const {
        return kScale * glm::dvec2(glm::dot(pos, axisS(p, c.rightHanded)),
                                   glm::dot(pos, axisT(p, c.rightHanded, c.upperLeft)));
    }
    // The map's tangent-space normal of plane p at pos (unit, z up): the
    // slope per unit of length on the surface, as normal maps store it.
    glm::dvec3 sample(int p, const glm::dvec3& pos) const {
        const glm::dvec2 q = st(p, pos), d = kScale * dh(q.x, q.y);
        return glm::normalize(glm::dvec3(-d.x, -d.y, 1.0));
    }
    double blended(const glm::dvec3& pos, const glm::dvec3& n, bool frozen,
                   const glm::dvec3& w0) const {
        const glm::dvec3 w = frozen ? w0 : weights(n, k);
        double sum = 0;
        for (int p = 0; p < 3; ++p) {
            const glm::dvec2 q = st(p, pos);
            sum += w[p] * h(q.x, q.y);
        }
        return sum;
    }
};

// A closed surface: the point of a sample and the normal field around it.
// Three kinds: a sphere, an analytic torus, and a subdivision surface, the
// Catmull-Clark limit of table 1's torus cage (16 x 8 quads, valence 4
// everywhere: a periodic bicubic B-spline evaluated in closed form in
// double, torus.h), whose normal field off the surface is the limit normal
// at the nearest point (found by Gauss-Newton on the closed form).
struct Surface {
    enum Kind { Sphere, Torus, Subdivision };
    const char* name;
    Kind kind;
    TorusCage cage; // Subdivision

    // The nearest point's parameters on the limit surface, from (s, t).
    glm::dvec2 footParams(const glm::dvec3& p, glm::dvec2 st) const {
        for (int it = 0; it < 40; ++it) {
            const SurfacePoint sp = cage.limit(st.x, st.y);
            const glm::dvec3 r = p - sp.pos;
            const double a = glm::dot(sp.dPds, sp.dPds), b = glm::dot(sp.dPds, sp.dPdt),
                         c = glm::dot(sp.dPdt, sp.dPdt);
            const double gs = glm::dot(sp.dPds, r), gt = glm::dot(sp.dPdt, r);
            const double det = a * c - b * b;
            const glm::dvec2 step((c * gs - b * gt) / det, (a * gt - b * gs) / det);
            st += step;
            if (std::abs(step.x) + std::abs(step.y) < 1e-15) break;
        }
        return st;
    }
    // The parameters of the torus angles of p (a start for footParams).
    static glm::dvec2 angleParams(const glm::dvec3& p) {
        const double u = std::atan2(p.y, p.x), ring = std::sqrt(p.x * p.x + p.y * p.y);
        const double v = std::atan2(p.z, ring - 1.0);
        return {u / kTwoPi, v / kTwoPi};
    }
    glm::dvec3 normalAt(const glm::dvec3& p) const {
        if (kind == Sphere) return glm::normalize(p);
        if (kind == Torus) {
            const glm::dvec3 ring = glm::normalize(glm::dvec3(p.x, p.y, 0.0)); // major radius 1
            return glm::normalize(p - ring);
        }
        const glm::dvec2 st = footParams(p, angleParams(p));
        return cage.limit(st.x, st.y).normal;
    }
    // Sample i of count: area-uniform on the sphere (Fibonacci), a uniform
    // (u, v) grid on the torus (major radius 1, minor 0.45) and on the
    // subdivision surface's (s, t), tilted so no symmetry plane of the
    // surface is a projection plane.
    glm::dvec3 point(int i, int count) const {
        if (kind == Sphere) {
            const double z = 1.0 - (2.0 * i + 1.0) / count;
            const double phi = i * 2.399963229728653, r = std::sqrt(1.0 - z * z);
            return glm::dvec3(r * std::cos(phi), r * std::sin(phi), z);
        }
        const int nu = int(std::sqrt(double(count) * 2.2)), nv = std::max(1, count / nu);
        const double s = ((i % nu) + 0.5) / nu, t = ((i / nu % nv) + 0.5) / nv;
        if (kind == Subdivision) return cage.limit(s, t).pos;
        const double u = kTwoPi * s, v = kTwoPi * t;
        return glm::dvec3((1.0 + 0.45 * std::cos(v)) * std::cos(u),
                          (1.0 + 0.45 * std::cos(v)) * std::sin(u), 0.45 * std::sin(v));
    }
};

// Rotation applied to the surfaces (both the point and the normal field):
// 20 degrees about x, then 35 about z.
glm::dvec3 rotate(const glm::dvec3& p, bool inverse) {
    const double a = 20.0 * M_PI / 180, b = 35.0 * M_PI / 180;
    if (!inverse) {
        const glm::dvec3 q(p.x, std::cos(a) * p.y - std::sin(a) * p.z,
                           std::sin(a) * p.y + std::cos(a) * p.z);
        return {std::cos(b) * q.x - std::sin(b) * q.y, std::sin(b) * q.x + std::cos(b) * q.y, q.z};
    }
    const glm::dvec3 q(std::cos(b) * p.x + std::sin(b) * p.y,
                       -std::sin(b) * p.x + std::cos(b) * p.y, p.z);
    return {q.x, std::cos(a) * q.y + std::sin(a) * q.z, -std::sin(a) * q.y + std::cos(a) * q.z};
}

struct Errors {
    std::vector<std::vector<double>> method; // [method][sample], vs the blend (frozen weights)
    std::vector<std::vector<double>> full;   // [method][sample], vs the blended height
};

Errors measure(const Surface& surf, const Field& f, int count) {
    Errors e;
    e.method.assign(STUDY_TRI_COUNT, {});
    e.full.assign(STUDY_TRI_COUNT, {});
    auto normalField = [&](const glm::dvec3& p) {
        return rotate(surf.normalAt(rotate(p, true)), false);
    };
    const double eps = 1e-5;
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 pos = rotate(surf.point(i, count), false);
        const glm::dvec3 n = normalField(pos);
        const glm::dvec3 w0 = weights(n, f.k);
        glm::dvec3 g(0.0), gFrozen(0.0);
        for (int a = 0; a < 3; ++a) {
            glm::dvec3 d(0.0);
            d[a] = eps;
            g[a] = (f.blended(pos + d, normalField(pos + d), false, w0) -
                    f.blended(pos - d, normalField(pos - d), false, w0)) /
                   (2 * eps);
            gFrozen[a] =
                (f.blended(pos + d, n, true, w0) - f.blended(pos - d, n, true, w0)) / (2 * eps);
        }
        const glm::dvec3 truth = glm::normalize(n - (g - glm::dot(n, g) * n));
        const glm::dvec3 frozen = glm::normalize(n - (gFrozen - glm::dot(n, gFrozen) * n));
        const glm::vec3 nf(n);
        const glm::vec3 wf = sg::glsl::sgTriplanarWeights(nf, float(f.k));
        const glm::vec3 tx(f.sample(0, pos)), ty(f.sample(1, pos)), tz(f.sample(2, pos));
        for (int m = 0; m < STUDY_TRI_COUNT; ++m) {
            const glm::vec3 r =
                sg::glsl::studyTriplanar(m, nf, wf, tx, ty, tz, f.c.rightHanded, f.c.upperLeft);
            e.method[size_t(m)].push_back(angleDeg(glm::dvec3(r), frozen));
            e.full[size_t(m)].push_back(angleDeg(glm::dvec3(r), truth));
        }
    }
    return e;
}

const char* kFragment = R"(
uniform sampler2D uMap; // tangent-space normal of h per texel, RGBA32F, one period
uniform vec2 uSize;     // viewport
uniform float uK;       // blend sharpness
uniform float uScale;   // map repeats per unit
out vec4 oColor;
vec3 fetch(int p, vec3 q) {
    vec2 st = vec2(dot(q, studyTriAxisS(p, RH)), dot(q, studyTriAxisT(p, RH, UL)));
    return texture(uMap, st).xyz;
}
void main() {
    // Orthographic view of the unit sphere filling the viewport.
    vec2 xy = (gl_FragCoord.xy / uSize) * 2.0 - 1.0;
    float r2 = dot(xy, xy);
    vec3 n = normalize(vec3(xy, sqrt(max(1.0 - r2, 0.0))));
    vec3 w = sgTriplanarWeights(n, uK);
    vec3 q = uScale * n;
    vec3 r = studyTriplanar(METHOD, n, w, fetch(0, q), fetch(1, q), fetch(2, q), RH, UL);
    oColor = vec4(r * 0.5 + 0.5, 1.0);
}
)";

const char* kMethodNames[STUDY_TRI_COUNT] = {"surface gradient (L13 + L14)",
                                             "volume gradient added (Perlin 1985)",
                                             "naive swizzle blend",
                                             "UDN",
                                             "whiteout",
                                             "RNM"};

} // namespace

void tableTriplanar(const Options& o) {
    const int count = o.quick ? 20000 : 200000;
    const double slope = 1.0; // steepest slope of each plane's height: 45 degrees
    const double amp = slope / (kTwoPi * kScale);
    const Convention lh{false, false, "left-handed, lower-left origin"};
    const Convention rh{true, true, "right-handed, upper-left origin"};
    const Surface sphere{"sphere", Surface::Sphere, {}}, torus{"torus", Surface::Torus, {}};
    const Surface subd{"subdivision", Surface::Subdivision, TorusCage{}};
    const double kDefault = 4.0;
    const double ks[] = {1.0, 2.0, 8.0, 32.0};

    const Errors sph = measure(sphere, {amp, lh, kDefault}, count);
    const Errors tor = measure(torus, {amp, lh, kDefault}, count);
    const Errors torRh = measure(torus, {amp, rh, kDefault}, count);
    const Errors sub = measure(subd, {amp, lh, kDefault}, count);
    std::vector<Errors> sweep;
    for (double k : ks) sweep.push_back(measure(torus, {amp, lh, k}, count));

    // Cost.
    const FullscreenTriangle fullscreen;
    const int tw = 64;
    std::vector<float> texels(size_t(tw) * size_t(tw) * 4);
    const Field f{amp, lh, kDefault};
    for (int j = 0; j < tw; ++j) {
        for (int i = 0; i < tw; ++i) {
            const glm::dvec2 d = kScale * f.dh((i + 0.5) / tw, (j + 0.5) / tw);
            const glm::dvec3 m = glm::normalize(glm::dvec3(-d.x, -d.y, 1.0));
            for (int c = 0; c < 3; ++c)
                texels[(size_t(j) * size_t(tw) + size_t(i)) * 4 + size_t(c)] = float(m[c]);
        }
    }
    const unsigned tex = makeFloatTexture(tw, tw, 4, texels, true, true);
    std::vector<sg::gl::Program> progs;
    const std::string fs = std::string(kTriplanarGlsl) + kFragment;
    for (int m = 0; m < STUDY_TRI_COUNT; ++m) {
        progs.push_back(makeProgram(fullscreenVertexShader(), fs, "triplanar",
                                    {"METHOD " + std::to_string(m), "RH false", "UL false"}));
    }
    const int size = o.size;
    Target target(size, size, 1, false);
    glDisable(GL_DEPTH_TEST);
    glBindTextureUnit(0, tex);
    for (const auto& p : progs) {
        glUseProgram(p.id());
        glUniform1i(p.uniform("uMap"), 0);
        glUniform2f(p.uniform("uSize"), float(size), float(size));
        glUniform1f(p.uniform("uK"), float(kDefault));
        glUniform1f(p.uniform("uScale"), float(kScale));
    }
    const auto ms = timeVariants(
        progs.size(),
        [&](size_t v) {
            target.bind();
            target.clear();
            glUseProgram(progs[v].id());
            fullscreen.draw();
        },
        o);
    deleteTexture(tex);

    Table t;
    t.title = "Table 7: triplanar method (one height map projected on 3 planes, slopes up to 45 "
              "deg, blended by listing 14 at k = 4 unless stated; truth in double)";
    t.header = {"method",    "sphere p50", "sphere p99", "torus p50", "torus p99", "torus max",
                "subd p50",  "subd p99",   "k=1 p99",    "k=2 p99",   "k=8 p99",   "k=32 p99",
                "RH+UL p99", "height p50", "height p99", "frame ms",  "ratio"};
    for (size_t m = 0; m < size_t(STUDY_TRI_COUNT); ++m) {
        const ErrorStats a = errorStats(sph.method[m]), b = errorStats(tor.method[m]),
                         c = errorStats(torRh.method[m]), h = errorStats(tor.full[m]);
        std::vector<std::string> r = {kMethodNames[m], fmtErr(a.p50), fmtErr(a.p99),
                                      fmtErr(b.p50),   fmtErr(b.p99), fmtErr(b.max)};
        const ErrorStats sd = errorStats(sub.method[m]);
        r.push_back(fmtErr(sd.p50));
        r.push_back(fmtErr(sd.p99));
        for (const Errors& e : sweep) r.push_back(fmtErr(errorStats(e.method[m]).p99));
        r.push_back(fmtErr(c.p99));
        r.push_back(fmtErr(h.p50));
        r.push_back(fmtErr(h.p99));
        r.push_back(fmt(ms[m], 2));
        r.push_back(fmtRatio(ms[m] / ms[0]));
        t.add(r);
    }
    t.notes.push_back(
        "Degrees; " + std::to_string(count) +
        " samples per surface (sphere: area-uniform; torus R = 1, r = 0.45: uniform in its "
        "angles; subd: the Catmull-Clark limit of table 1's torus cage, 16 x 8 quads, "
        "closed-form B-spline, uniform in its (s, t)), all rotated (20 deg about x, 35 about z) "
        "off the projection planes. "
        "Map: h = A sin(2 pi s) sin(2 pi t), " +
        fmt(kScale, 0) + " repeats per unit, A = " + fmtErr(amp) +
        ". Truth: the normal of the blend sum_i w_i h_i with the weights held constant "
        "(what every method approximates); 'height': of the blended height including the "
        "weights' own gradient (a displaced surface would show it; no method has it). "
        "Up to 'torus max' and 'height' at k = 4, left-handed, lower-left origin; k "
        "columns: torus, same convention; RH+UL: torus, right-handed, upper-left origin.");
    t.notes.push_back(
        "Every method gets the exact base normal and exact map normals (binary32), no "
        "filtering; the C++ build of triplanar.glsl, the code the GPU pass runs.");
    t.notes.push_back("Cost: " + std::to_string(size) + "^2 pass on " + o.renderer +
                      " (ray-traced unit sphere, 3 fetches of a 64^2 RGBA32F map, k = 4), " +
                      std::to_string(o.runs) + " runs x " + std::to_string(o.frames) +
                      " frames, medians; ratio to the surface-gradient row.");
    t.plot = {"triplanar",
              16,
              4,
              -1,
              {0},
              false,
              true,
              "frame time, ratio to surface gradient (same run)",
              "normal error p99 on the torus (k = 4), degrees"};
    t.print(o);
}

} // namespace study
