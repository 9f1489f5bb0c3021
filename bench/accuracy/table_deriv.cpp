// Table 5, derivative method (docs/accuracy-cost.md): scale-dependent bump
// mapping (Mikkelsen 2019 section 2.5, listing 8) of a known height field
// on a sphere that the fragment shader ray-traces (one full-screen
// triangle, position, normal and lat-long UV exact per pixel in binary32),
// so the only approximations left are the derivatives under test:
//
//  position/UV derivatives (height derivative analytic, chain rule):
//    dFdxFine / dFdyFine of position and UV (the prologue, listing 16);
//    dFdxCoarse / dFdyCoarse (on llvmpipe the same values: docs/platform.md);
//    coarse derivatives emulated: the differences of the 2x2 quad's first
//      row and first column for all four pixels, what GPUs that compute
//      coarse derivatives once per quad return (and what dFdx gives in
//      GLSL 3.30 and ES 3.00, which have no dFdxFine, on such GPUs; the ray
//      is traced again at the quad's pixels, so no driver behaviour is
//      assumed; the same emulation of the fine differences reproduces
//      dFdxFine, checked in the notes);
//    analytic dPdx/dPdy of listing 17 (sgScreenDerivOfPos) with the UV
//      derivatives still from dFdxFine;
//    listing 17 plus analytic UV derivatives (the UV Jacobian of the sphere's
//      parametrization applied to dPdx): no screen differences at all;
//  height derivatives (position/UV derivatives from dFdxFine):
//    1-tap dFdxFine(h) of the analytic height, and of a height map;
//    3-tap forward differences of the height map (listing 9);
//    a texel-space derivative map (dh/du, dh/dv per texel, listing 8),
//  the maps at two resolutions: magnified (~3.5 pixels per texel at the
//  centre) and about one texel per pixel; bilinear, no mip maps.
//
// Ground truth, per pixel centre, in double on the CPU: the exact hit point,
// Blinn's perturbed normal of h on the exact sphere (torus.h, blinnNormal,
// with the analytic dP/ds, dP/dt) and the exact screen derivative of the hit
// point (central differences of the double ray-sphere intersection,
// 1e-3 pixel apart). Pixels: the sphere where |latitude| < 60 degrees
// (the lat-long chart's poles are its own problem, not the derivatives'),
// facing the camera by more than 15 degrees, and whose whole 2x2 quad hits
// the sphere (screen differences across the silhouette are meaningless).
// Cost: the same pass without the accuracy outputs, ratio to the first row.
#include <epoxy/gl.h>

#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "surfgrad/bump/core.h"
#include "tables.h"
#include "torus.h"

namespace study {

namespace {

const char* kFragment = R"(
#include "sg/surfgrad.glsl"
uniform mat4 uInvScr;    // screen (x, y, depth, 1) -> camera-relative world
uniform vec3 uCamPos;    // world position of the camera
uniform float uRadius;   // sphere at the world origin
uniform vec3 uHeightParams; // amplitude, frequency in s, frequency in t
uniform sampler2D uHeight;  // R32F height map
uniform sampler2D uDerivMap; // RG32F dh/du, dh/dv per texel
uniform vec2 uTexDim;
layout(location = 0) out vec4 oNormal; // perturbed normal, 1 where the ray hits
#ifdef ACCURACY
layout(location = 1) out vec4 oDpdx;   // the dPdx the pixel used
#endif
const float kTwoPi = 6.28318530718;

float heightAt(vec2 st) {
    return uHeightParams.x * sin(kTwoPi * uHeightParams.y * st.x) * sin(kTwoPi * uHeightParams.z * st.y);
}
vec2 heightGrad(vec2 st) {
    float as = kTwoPi * uHeightParams.y;
    float at = kTwoPi * uHeightParams.z;
    return uHeightParams.x * vec2(as * cos(as * st.x) * sin(at * st.y), at * sin(as * st.x) * cos(at * st.y));
}
// Lat-long chart: s = longitude / 2 pi + 0.5 (0 facing -y), t = latitude / pi + 0.5.
vec2 chart(vec3 n) {
    return vec2(atan(n.x, -n.y) / kTwoPi + 0.5, asin(clamp(n.z, -1.0, 1.0)) / 3.14159265359 + 0.5);
}

// The sphere seen through window position xy.
void traceSphere(vec2 xy, out vec3 relPos, out vec3 n, out vec2 st, out bool hit) {
    vec4 a = uInvScr * vec4(xy, 0.0, 1.0);
    vec4 b = uInvScr * vec4(xy, 1.0, 1.0);
    vec3 origin = a.xyz / a.w;
    vec3 dir = normalize(b.xyz / b.w - origin);
    vec3 oc = origin + uCamPos; // origin - centre, centre = -uCamPos in relative space
    float pb = dot(oc, dir);
    float disc = pb * pb - (dot(oc, oc) - uRadius * uRadius);
    hit = disc >= 0.0;
    // Misses (helper lanes of silhouette quads) take the closest point of the ray.
    float t = -pb - (hit ? sqrt(disc) : 0.0);
    relPos = origin + t * dir;
    n = normalize(relPos + uCamPos);
    st = chart(n);
}

void main() {
    vec2 xy = gl_FragCoord.xy;
    vec3 relPos;
    vec3 n;
    vec2 st;
    bool hit;
    traceSphere(xy, relPos, n, st, hit);

#if defined(POS_QUAD_EMU_COARSE) || defined(POS_QUAD_EMU_FINE)
    // The quad's pixel centres: (q0.x, row) and (q0.x + 1, row) for the x
    // difference, (column, q0.y) and (column, q0.y + 1) for y; coarse takes
    // the quad's first row and column for every pixel, fine the pixel's own.
    vec2 q0 = floor(xy * 0.5) * 2.0 + vec2(0.5);
#if defined(POS_QUAD_EMU_COARSE)
    vec2 rowCol = q0;
#else
    vec2 rowCol = xy;
#endif
    vec3 p0;
    vec3 p1;
    vec3 nq;
    vec2 s0;
    vec2 s1;
    bool hq;
    traceSphere(vec2(q0.x, rowCol.y), p0, nq, s0, hq);
    traceSphere(vec2(q0.x + 1.0, rowCol.y), p1, nq, s1, hq);
    vec3 dPdx = p1 - p0;
    vec2 dSTdx = s1 - s0;
    traceSphere(vec2(rowCol.x, q0.y), p0, nq, s0, hq);
    traceSphere(vec2(rowCol.x, q0.y + 1.0), p1, nq, s1, hq);
    vec3 dPdy = p1 - p0;
    vec2 dSTdy = s1 - s0;
#elif defined(POS_COARSE)
    vec3 dPdx = dFdxCoarse(relPos);
    vec3 dPdy = dFdyCoarse(relPos);
    vec2 dSTdx = dFdxCoarse(st);
    vec2 dSTdy = dFdyCoarse(st);
#elif defined(POS_L17) || defined(POS_L17_ST)
    vec3 dPdx;
    vec3 dPdy;
    sgScreenDerivOfPos(dPdx, dPdy, relPos, n, uInvScr, xy.x, xy.y);
#if defined(POS_L17_ST)
    // UV Jacobian of the chart on the sphere, applied to dPdx/dPdy.
    vec3 w = relPos + uCamPos;
    float rho2 = w.x * w.x + w.y * w.y;
    vec3 gradS = vec3(-w.y, w.x, 0.0) / (kTwoPi * rho2);
    vec3 gradT = vec3(0.0, 0.0, 1.0) / (3.14159265359 * sqrt(rho2));
    vec2 dSTdx = vec2(dot(gradS, dPdx), dot(gradT, dPdx));
    vec2 dSTdy = vec2(dot(gradS, dPdy), dot(gradT, dPdy));
#else
    vec2 dSTdx = dFdxFine(st);
    vec2 dSTdy = dFdyFine(st);
#endif
#else
    vec3 dPdx = dFdxFine(relPos);
    vec3 dPdy = dFdyFine(relPos);
    vec2 dSTdx = dFdxFine(st);
    vec2 dSTdy = dFdyFine(st);
#endif
    SgFrame f = sgPrologue(n, dPdx, dPdy, true, SG_BFACE_NONE);

#if defined(H_TAP1_ANALYTIC)
    float h = heightAt(st);
    vec3 sg = sgSurfgradFromScreenDeriv(f, vec2(dFdxFine(h), dFdyFine(h)));
#elif defined(H_TAP1_MAP)
    float h = texture(uHeight, st).x;
    vec3 sg = sgSurfgradFromScreenDeriv(f, vec2(dFdxFine(h), dFdyFine(h)));
#elif defined(H_TAP3_MAP)
    float hll = texture(uHeight, st).x;
    float hlr = texture(uHeight, st + dSTdx).x;
    float hul = texture(uHeight, st + dSTdy).x;
    vec3 sg = sgSurfgradFromScreenDeriv(f, sgHeightDeriv3Tap(hll, hlr, hul));
#elif defined(H_DERIV_MAP)
    vec3 sg = sgSurfgradScaleDependent(f, texture(uDerivMap, st).xy, dSTdx, dSTdy, uTexDim);
#else
    // Analytic dh/d(s,t): one "texel" per unit of st.
    vec3 sg = sgSurfgradScaleDependent(f, heightGrad(st), dSTdx, dSTdy, vec2(1.0));
#endif
    vec3 nb = sgResolve(f, sg);
    oNormal = vec4(nb, hit ? 1.0 : 0.0);
#ifdef ACCURACY
    oDpdx = vec4(dPdx, 0.0);
#endif
}
)";

struct Variant {
    std::string name;
    std::vector<std::string> defines;
    int map; // height/derivative map: 0 none, 1 magnified resolution, 2 about one texel per pixel
};

struct Sphere {
    double radius = 1.0;
    glm::dvec3 camPos{0.0, -3.2, 0.45};
    glm::dmat4 invScr{1.0}; // screen -> camera-relative world
    int size = 768;
    double amp = 0.03, fs = 12, ft = 6;
    Sphere(int sz) : size(sz) {
        const glm::dvec3 target(0.0, 0.0, 0.0);
        const glm::dmat4 viewRel =
            glm::lookAt(glm::dvec3(0.0), target - camPos, glm::dvec3(0, 0, 1));
        const glm::dmat4 proj = glm::perspective(glm::radians(42.0), 1.0, 0.5, 10.0);
        glm::dmat4 vp(1.0);
        vp = glm::translate(vp, glm::dvec3(size / 2.0, size / 2.0, 0.5));
        vp = glm::scale(vp, glm::dvec3(size / 2.0, size / 2.0, 0.5));
        invScr = glm::inverse(vp * proj * viewRel);
    }
    // Ray-sphere hit of window point (x, y) (pixel centre at .5), world space.
    bool hit(double x, double y, glm::dvec3& world) const {
        const glm::dvec4 a = invScr * glm::dvec4(x, y, 0.0, 1.0),
                         b = invScr * glm::dvec4(x, y, 1.0, 1.0);
        const glm::dvec3 o = glm::dvec3(a) / a.w;
        const glm::dvec3 d = glm::normalize(glm::dvec3(b) / b.w - o);
        const glm::dvec3 oc = o + camPos;
        const double pb = glm::dot(oc, d), disc = pb * pb - (glm::dot(oc, oc) - radius * radius);
        if (disc < 0) return false;
        world = o + (-pb - std::sqrt(disc)) * d + camPos;
        return true;
    }
    glm::dvec2 chart(const glm::dvec3& n) const {
        return {std::atan2(n.x, -n.y) / (2 * M_PI) + 0.5,
                std::asin(std::clamp(n.z, -1.0, 1.0)) / M_PI + 0.5};
    }
    SurfacePoint point(const glm::dvec2& st) const {
        const double ph = 2 * M_PI * (st.x - 0.5), th = M_PI * (st.y - 0.5);
        SurfacePoint p;
        p.pos = radius *
                glm::dvec3(std::cos(th) * std::sin(ph), -std::cos(th) * std::cos(ph), std::sin(th));
        p.dPds = 2 * M_PI * radius *
                 glm::dvec3(std::cos(th) * std::cos(ph), std::cos(th) * std::sin(ph), 0.0);
        p.dPdt =
            M_PI * radius *
            glm::dvec3(-std::sin(th) * std::sin(ph), std::sin(th) * std::cos(ph), std::cos(th));
        p.normal = glm::normalize(glm::cross(p.dPds, p.dPdt));
        return p;
    }
    glm::dvec2 heightGrad(const glm::dvec2& st) const {
        const double as = 2 * M_PI * fs, at = 2 * M_PI * ft;
        return amp * glm::dvec2(as * std::cos(as * st.x) * std::sin(at * st.y),
                                at * std::sin(as * st.x) * std::cos(at * st.y));
    }
    double height(const glm::dvec2& st) const {
        return amp * std::sin(2 * M_PI * fs * st.x) * std::sin(2 * M_PI * ft * st.y);
    }
};

} // namespace

void tableDerivatives(const Options& o) {
    const FullscreenTriangle fullscreen;
    const int size = o.quick ? 256 : 768;
    Sphere sph(size);
    const int mapW[3] = {0, o.quick ? 128 : 512, o.quick ? 512 : 2048};
    const std::string coarse = std::to_string(mapW[1]) + "x" + std::to_string(mapW[1] / 2);
    const std::string fine = std::to_string(mapW[2]) + "x" + std::to_string(mapW[2] / 2);
    const std::vector<Variant> variants = {
        {"dFdxFine P, st; analytic dh/dst (L8)", {}, 0},
        {"dFdxCoarse P, st; analytic dh/dst", {"POS_COARSE"}, 0},
        {"quad-coarse P, st (emulated); analytic dh/dst", {"POS_QUAD_EMU_COARSE"}, 0},
        {"L17 dPdx + dFdxFine st; analytic dh/dst", {"POS_L17"}, 0},
        {"L17 dPdx + analytic dst/dx; analytic dh/dst", {"POS_L17_ST"}, 0},
        {"1-tap dFdxFine(h), analytic h", {"H_TAP1_ANALYTIC"}, 0},
        {"1-tap dFdxFine(h), height map " + coarse, {"H_TAP1_MAP"}, 1},
        {"3-tap (L9), height map " + coarse, {"H_TAP3_MAP"}, 1},
        {"derivative map (L8) " + coarse, {"H_DERIV_MAP"}, 1},
        {"1-tap dFdxFine(h), height map " + fine, {"H_TAP1_MAP"}, 2},
        {"3-tap (L9), height map " + fine, {"H_TAP3_MAP"}, 2},
        {"derivative map (L8) " + fine, {"H_DERIV_MAP"}, 2},
    };
    // Height maps (R32F, h at texel centres) and texel-space derivative maps
    // (RG32F, exact dh/du, dh/dv in height per texel) at both resolutions;
    // s repeats, t clamps.
    unsigned heightTex[3] = {0, 0, 0}, derivTex[3] = {0, 0, 0};
    for (int m = 1; m <= 2; ++m) {
        const int w = mapW[m], h = w / 2;
        std::vector<float> ht(size_t(w) * size_t(h)), dt(size_t(w) * size_t(h) * 2);
        for (int j = 0; j < h; ++j) {
            for (int i = 0; i < w; ++i) {
                const glm::dvec2 st((i + 0.5) / w, (j + 0.5) / h);
                const size_t k = size_t(j) * size_t(w) + size_t(i);
                ht[k] = float(sph.height(st));
                const glm::dvec2 g = sph.heightGrad(st);
                dt[2 * k] = float(g.x / w);
                dt[2 * k + 1] = float(g.y / h);
            }
        }
        heightTex[m] = makeFloatTexture(w, h, 1, ht, true, false);
        derivTex[m] = makeFloatTexture(w, h, 2, dt, true, false);
    }
    const std::string fs = kFragment;
    std::vector<sg::gl::Program> acc, tim;
    for (const Variant& v : variants) {
        tim.push_back(makeProgram(fullscreenVertexShader(), fs, "deriv", v.defines));
        auto d = v.defines;
        d.push_back("ACCURACY");
        acc.push_back(makeProgram(fullscreenVertexShader(), fs, "deriv_acc", d));
    }
    // The emulation checked: its fine form must give dFdxFine's normals.
    const sg::gl::Program fineEmu =
        makeProgram(fullscreenVertexShader(), fs, "deriv_acc", {"POS_QUAD_EMU_FINE", "ACCURACY"});
    const glm::mat4 invScr(sph.invScr);
    auto use = [&](size_t k, const sg::gl::Program& p) {
        glUseProgram(p.id());
        glUniformMatrix4fv(p.uniform("uInvScr"), 1, GL_FALSE, &invScr[0][0]);
        glUniform3f(p.uniform("uCamPos"), float(sph.camPos.x), float(sph.camPos.y),
                    float(sph.camPos.z));
        glUniform1f(p.uniform("uRadius"), float(sph.radius));
        glUniform3f(p.uniform("uHeightParams"), float(sph.amp), float(sph.fs), float(sph.ft));
        const int m = variants[k].map;
        glUniform2f(p.uniform("uTexDim"), float(mapW[m]), float(mapW[m] / 2));
        glUniform1i(p.uniform("uHeight"), 0);
        glUniform1i(p.uniform("uDerivMap"), 1);
        glBindTextureUnit(0, heightTex[m == 0 ? 1 : m]);
        glBindTextureUnit(1, derivTex[m == 0 ? 1 : m]);
    };
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);

    // Ground truth per pixel and the mask.
    const size_t px = size_t(size) * size_t(size);
    std::vector<glm::dvec3> truthN(px), truthDpdx(px);
    std::vector<uint8_t> hitMask(px, 0), counted(px, 0);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            glm::dvec3 w;
            if (sph.hit(x + 0.5, y + 0.5, w)) hitMask[size_t(y) * size_t(size) + size_t(x)] = 1;
        }
    }
    const double eps = 1e-3;
    std::vector<double> tilt; // bump tilt of the truth: how strong the bumps are
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const size_t k = size_t(y) * size_t(size) + size_t(x);
            // Whole 2x2 quad on the sphere.
            const int qx = x & ~1, qy = y & ~1;
            bool quad = true;
            for (int dy = 0; dy < 2; ++dy) {
                for (int dx = 0; dx < 2; ++dx)
                    quad = quad && hitMask[size_t(qy + dy) * size_t(size) + size_t(qx + dx)];
            }
            glm::dvec3 w, wl, wr;
            if (!quad || !sph.hit(x + 0.5, y + 0.5, w) || !sph.hit(x + 0.5 - eps, y + 0.5, wl) ||
                !sph.hit(x + 0.5 + eps, y + 0.5, wr)) {
                continue;
            }
            const glm::dvec3 n = glm::normalize(w);
            const glm::dvec3 view = glm::normalize(sph.camPos - w);
            if (std::fabs(n.z) > std::sin(M_PI / 3) || glm::dot(n, view) < std::sin(M_PI / 12))
                continue;
            counted[k] = 1;
            const glm::dvec2 st = sph.chart(n);
            const glm::dvec2 g = sph.heightGrad(st);
            truthN[k] = blinnNormal(sph.point(st), g.x, g.y);
            tilt.push_back(angleDeg(truthN[k], n));
            truthDpdx[k] = (wr - wl) / (2 * eps);
        }
    }

    Target target(size, size, 2);
    std::vector<ErrorStats> nStats, dStats;
    std::vector<glm::vec4> fineNormals;
    double coarseVsFine = 0, fineEmuVsFine = 0;
    size_t used = 0;
    for (size_t k = 0; k < variants.size(); ++k) {
        target.clear();
        use(k, acc[k]);
        fullscreen.draw();
        const auto nrm = target.read(0), dpdx = target.read(1);
        std::vector<double> ne, de;
        for (size_t i = 0; i < px; ++i) {
            if (!counted[i]) continue;
            ne.push_back(angleDeg(glm::dvec3(nrm[i]), truthN[i]));
            de.push_back(glm::length(glm::dvec3(dpdx[i]) - truthDpdx[i]) /
                         glm::length(truthDpdx[i]));
            if (k == 1)
                coarseVsFine = std::max(coarseVsFine,
                                        angleDeg(glm::dvec3(nrm[i]), glm::dvec3(fineNormals[i])));
        }
        if (k == 0) {
            fineNormals = nrm;
            used = ne.size();
        }
        nStats.push_back(errorStats(ne));
        dStats.push_back(errorStats(de));
    }

    {
        target.clear();
        use(0, fineEmu); // the first row's uniforms (analytic height, no map)
        fullscreen.draw();
        const auto nrm = target.read(0);
        for (size_t i = 0; i < px; ++i) {
            if (counted[i])
                fineEmuVsFine = std::max(fineEmuVsFine,
                                         angleDeg(glm::dvec3(nrm[i]), glm::dvec3(fineNormals[i])));
        }
    }

    Target timTarget(size, size, 1, false);
    const auto ms = timeVariants(
        variants.size(),
        [&](size_t k) {
            timTarget.clear();
            use(k, tim[k]);
            fullscreen.draw();
        },
        o);
    for (int m = 1; m <= 2; ++m) {
        deleteTexture(heightTex[m]);
        deleteTexture(derivTex[m]);
    }

    Table t;
    t.title = "Table 5: derivative method (ray-traced sphere, scale-dependent bump of a known "
              "height, truth in double)";
    t.header = {"method",           "p50 deg",          "p90 deg",  "p99 deg", "max deg",
                "dPdx rel err p50", "dPdx rel err max", "frame ms", "ratio"};
    for (size_t k = 0; k < variants.size(); ++k) {
        const bool posRow = k < 5;
        t.add({variants[k].name, fmtErr(nStats[k].p50), fmtErr(nStats[k].p90),
               fmtErr(nStats[k].p99), fmtErr(nStats[k].max), posRow ? fmtErr(dStats[k].p50) : "",
               posRow ? fmtErr(dStats[k].max) : "", fmt(ms[k], 2), fmtRatio(ms[k] / ms[0])});
    }
    // Texels per pixel at the centre of the view, for the map rows.
    glm::dvec3 wc, wx;
    sph.hit(size / 2.0, size / 2.0, wc);
    sph.hit(size / 2.0 + 1.0, size / 2.0, wx);
    const double dsPerPixel =
        std::fabs(sph.chart(glm::normalize(wx)).x - sph.chart(glm::normalize(wc)).x);
    t.notes.push_back(
        std::to_string(used) + " pixels of a " + std::to_string(size) + "^2 view; h = " +
        fmt(sph.amp, 3) + " sin(2 pi 12 s) sin(2 pi 6 t) on the unit sphere (bump tilt p50 " +
        fmt(errorStats(tilt).p50, 1) + ", max " + fmt(errorStats(tilt).max, 1) +
        " degrees). Maps at the view centre: " + fmt(1.0 / (dsPerPixel * mapW[1]), 2) + " and " +
        fmt(1.0 / (dsPerPixel * mapW[2]), 2) + " pixels per texel.");
    t.notes.push_back(
        "dFdxCoarse vs dFdxFine on this driver: largest normal difference " + fmtErr(coarseVsFine) +
        " degrees (llvmpipe computes coarse derivatives like fine ones: docs/platform.md). "
        "The quad emulation with each pixel's own row and column against dFdxFine: " +
        fmtErr(fineEmuVsFine) +
        " degrees, so the emulated coarse row is what a GPU whose "
        "dFdxCoarse uses the quad's first row and column (and dFdx in GLSL 3.30 and ES 3.00 "
        "on such a GPU) gives.");
    t.notes.push_back("The emulated row's time is the emulation's (four more rays per pixel), "
                      "not a GPU's: there a coarse derivative costs no more than a fine one.");
    t.notes.push_back("Cost: " + std::to_string(size) + "^2 pass on " + o.renderer +
                      " (ray-sphere in every "
                      "variant), " +
                      std::to_string(o.runs) + " runs x " + std::to_string(o.frames) +
                      " frames, medians; ratio to the first row.");
    t.plot = {"deriv",
              8,
              3,
              -1,
              {0},
              false,
              true,
              "frame time, ratio to dFdxFine",
              "normal error p99, degrees"};
    t.print(o);
}

} // namespace study
