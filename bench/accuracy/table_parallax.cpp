// Table 9: parallax. Offset mapping vs parallax occlusion mapping (POM) with
// N steps vs the exact hit (Mikkelsen 2019, section 2.6, listings 10, 11;
// shaders/sg/render/layer_parallax.glsl through its C++ build), and the
// re-prologue's derivative method on the virtual surface (section 3:
// listing 17 vs dFdx) at POM's discontinuities.
//  a. Error: analytic height fields (sines, a step, a hemisphere) carved
//     below a plane; the view ray of each sample traced against the field
//     in double is the truth; the shared functions see a 256^2 map of the
//     field. Error of the corrected coordinate in texels and of the field's
//     analytic normal there, in degrees (tests/render/parallax_test.cpp
//     asserts bounds on the same measure).
//  b. Cost: a plane filling the view with the layer through the renderer
//     (assembled program, llvmpipe), frames interleaved, ratio to a
//     `height` layer on the same map (3 taps, no correction).
//  c. Re-prologue derivatives: a camera over a terrace relief; per pixel the
//     virtual surface's position from POM (256 steps); dPdx from the 2x2
//     quad difference of the virtual positions (what dFdxFine gives) and
//     from listing 17 at the virtual position with the plateau's normal,
//     against the exact derivative of the level of the relief the pixel shows
//     (double). Quads whose two pixels show different levels of the relief
//     are the discontinuities.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "surfgrad/render.h"
#include "surfgrad/render/render_shaders.h"
#include "tables.h"

namespace study {

namespace {

namespace G = sg::glsl;
using sg::render::TextureImage;

constexpr double kPi = 3.14159265358979323846;
constexpr int kTexels = 256;

struct Field {
    const char* name;
    double scale;
    std::function<double(double, double)> h;
    std::function<glm::dvec2(double, double)> grad; // nullptr: no normal everywhere
};

std::vector<Field> fields() {
    const double w = 2.0 * kPi * 3.0, r = 0.15;
    return {
        {"sines", 0.04,
         [w](double s, double t) { return 0.5 + 0.5 * std::sin(w * s) * std::sin(w * t); },
         [w](double s, double t) {
             return glm::dvec2(0.5 * w * std::cos(w * s) * std::sin(w * t),
                               0.5 * w * std::sin(w * s) * std::cos(w * t));
         }},
        {"step", 0.04, [](double s, double) { return s < 0.5 ? 1.0 : 0.25; }, nullptr},
        {"hemisphere", r,
         [r](double s, double t) {
             double d2 = (s - 0.5) * (s - 0.5) + (t - 0.5) * (t - 0.5);
             return d2 < r * r ? std::sqrt(r * r - d2) / r : 0.0;
         },
         [r](double s, double t) {
             double ds = s - 0.5, dt = t - 0.5, d2 = ds * ds + dt * dt;
             double z = std::sqrt(std::max(r * r - d2, 1e-12));
             return d2 < r * r ? glm::dvec2(-ds / (z * r), -dt / (z * r)) : glm::dvec2(0.0);
         }},
    };
}

TextureImage fieldTexture(const Field& f) {
    std::vector<glm::vec4> texels(size_t(kTexels) * kTexels);
    for (int j = 0; j < kTexels; ++j)
        for (int i = 0; i < kTexels; ++i) {
            float v = float(f.h((i + 0.5) / kTexels, (j + 0.5) / kTexels));
            texels[size_t(j) * kTexels + size_t(i)] = glm::vec4(v, v, v, 1.0f);
        }
    return sg::render::makeTexture(kTexels, kTexels, std::move(texels), sg::render::Wrap::Repeat);
}

// The first crossing of the ray p + t v (t >= 0) with z = scale (H - 1).
glm::dvec3 traceRelief(const Field& f, glm::dvec3 p, glm::dvec3 v) {
    auto below = [&](double t) {
        glm::dvec3 q = p + t * v;
        return q.z <= f.scale * (f.h(q.x, q.y) - 1.0);
    };
    const double tEnd = (f.scale - p.z) / -v.z;
    const int n = 8000;
    double t0 = 0.0;
    for (int i = 1; i <= n; ++i) {
        double t1 = tEnd * i / n;
        if (below(t1)) {
            for (int k = 0; k < 60; ++k) {
                double tm = 0.5 * (t0 + t1);
                (below(tm) ? t1 : t0) = tm;
            }
            return p + t1 * v;
        }
        t0 = t1;
    }
    return p + tEnd * v;
}

// One pixel of the plane z = 0 (st = world xy) with a half-texel footprint:
// the corrected st and the virtual surface's offset. steps 0: offset mapping.
void shadeSample(const G::sampler2D& tex, float scale, glm::dvec2 st, glm::dvec3 toEye,
                 glm::vec3 dPdx, glm::vec3 dPdy, int steps, glm::dvec2& stOut, glm::dvec3& offOut) {
    G::SgFrame fr = G::sgPrologue(glm::vec3(0, 0, 1), dPdx, dPdy, true, 0);
    G::SgUvFrame uv = G::sgUvFramePixel(fr, glm::vec2(st), glm::vec2(dPdx), glm::vec2(dPdy));
    const G::SgParallaxSearch sv = G::sgParallaxSearch(fr, uv, glm::vec3(toEye), scale, steps == 0);
    const float d = steps == 0 ? G::sgParallaxOffsetDepth(uv, tex, 0)
                               : G::sgParallaxOcclusionDepth(uv, sv.st, tex, 0, steps);
    stOut = st - double(d) * glm::dvec2(sv.st);
    offOut = glm::dvec3(G::sgParallaxSurfaceOffset(fr, uv, sv, d, scale, tex, 0));
}

const int kSteps[] = {0, 4, 8, 16, 32, 64};

std::string methodName(int steps) {
    return steps ? "POM " + std::to_string(steps) + " steps" : "offset mapping (Welsh)";
}

// a. error per field and method; returns the first field's texel p99 per
// method (kSteps order), which table 9b plots against cost.
std::vector<double> errorRows(Table& t, int samples) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> pos(0.4, 0.6), az(0.0, 2.0 * kPi), el(20.0, 80.0);
    std::vector<std::pair<glm::dvec2, glm::dvec3>> px;
    for (int i = 0; i < samples; ++i) {
        double a = az(rng), e = glm::radians(el(rng));
        px.push_back(
            {glm::dvec2(pos(rng), pos(rng)),
             glm::dvec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e))});
    }
    const float foot = 0.5f / float(kTexels);
    std::vector<double> firstFieldP99;
    const std::vector<Field> all = fields();
    for (const Field& f : all) {
        TextureImage img = fieldTexture(f);
        G::sampler2D tex{&img};
        std::vector<glm::dvec3> hits;
        for (const auto& [st, e] : px) hits.push_back(traceRelief(f, glm::dvec3(st, 0.0), -e));
        for (int n : kSteps) {
            std::vector<double> texel, deg;
            for (size_t i = 0; i < px.size(); ++i) {
                glm::dvec2 st;
                glm::dvec3 off;
                shadeSample(tex, float(f.scale), px[i].first, px[i].second, glm::vec3(foot, 0, 0),
                            glm::vec3(0, foot, 0), n, st, off);
                texel.push_back(glm::length(st - glm::dvec2(hits[i])) * kTexels);
                if (f.grad) {
                    auto nrm = [&](glm::dvec2 q) {
                        glm::dvec2 g = f.grad(q.x, q.y) * f.scale;
                        return glm::dvec3(-g.x, -g.y, 1.0);
                    };
                    deg.push_back(angleDeg(nrm(st), nrm(glm::dvec2(hits[i]))));
                }
            }
            ErrorStats a = errorStats(texel), b = errorStats(deg);
            if (&f == &all.front()) firstFieldP99.push_back(a.p99);
            t.add({f.name, methodName(n), fmtErr(a.p50), fmtErr(a.p90), fmtErr(a.p99),
                   f.grad ? fmtErr(b.p50) : "-", f.grad ? fmtErr(b.p99) : "-"});
        }
    }
    return firstFieldP99;
}

// b. cost through the renderer
std::vector<double> costs(const Options& o) {
    using namespace sg::render;
    auto scene = [](const std::string& layer) {
        return parseScene(
            R"({"camera": {"position": [0, 1.1, 0.55], "target": [0, 0, 0.05], "fov_deg": 50},
                "materials": [{"name": "m", "layers": [)" +
                layer +
                R"(]}], "meshes": [{"procedural": {"type": "plane", "size": 2, "segments": 4},
                                    "uv_sets": [{"from": 0, "scale": [4, 4]}]}]})",
            "parallax-bench.json", ".");
    };
    const std::string map =
        R"("uv_set": 1, "map": {"procedural": "bricks", "output": "height", "size": 512})";
    std::vector<std::string> layers = {R"({"type": "height", "scale": 0.04, )" + map + "}"};
    for (int n : kSteps) {
        layers.push_back(n ? R"({"type": "pom", "scale": 0.04, "steps": )" + std::to_string(n) +
                                 ", " + map + "}"
                           : R"({"type": "parallax", "scale": 0.04, )" + map + "}");
    }
    std::vector<Scene> scenes;
    std::vector<SceneAssets> assets;
    std::vector<View> views;
    for (const auto& l : layers) scenes.push_back(scene(l));
    for (const auto& s : scenes) {
        assets.push_back(loadAssets(s));
        views.push_back(makeView(s, assets.back(), o.size, o.size, Aov::Color));
    }
    GlRenderer gl;
    return timeVariants(
        layers.size(), [&](size_t i) { gl.renderToTexture(scenes[i], assets[i], views[i]); }, o);
}

// c. derivative of the virtual position: L17 vs the quad difference
void derivativeRows(Table& t, const Options& o) {
    // A terrace: the mesh surface is above both levels, so a ray starting
    // over the upper level (s < 0.5) either lands on it or passes over its
    // edge and falls to the lower one: the virtual position jumps there.
    const Field f{"terrace", 0.04, [](double s, double) { return s < 0.5 ? 0.6 : 0.0; }, nullptr};
    TextureImage img = fieldTexture(f);
    G::sampler2D tex{&img};
    const int W = o.quick ? 128 : 256, H = W;
    // Above the upper level (s < 0.5), looking across its edge at s = 0.5:
    // the edge hides the lower level next to the wall (occlusion).
    // The view is turned so the edge crosses the screen diagonally (quads
    // straddle it in both directions).
    const glm::dvec3 eye(0.2, 0.35, 0.3);
    glm::dmat4 view = glm::lookAt(eye, glm::dvec3(0.6, 0.55, 0.0), glm::dvec3(0, 0, 1));
    glm::dmat4 proj = glm::perspective(glm::radians(40.0), 1.0, 0.01, 10.0);
    glm::dmat4 vp(1.0);
    vp[0][0] = 0.5 * W;
    vp[1][1] = 0.5 * H;
    vp[2][2] = 0.5;
    vp[3] = glm::dvec4(0.5 * W, 0.5 * H, 0.5, 1.0);
    const glm::dmat4 inv = glm::inverse(vp * proj * view);
    auto ray = [&](double x, double y) {
        glm::dvec4 a = inv * glm::dvec4(x, y, 0.0, 1.0), b = inv * glm::dvec4(x, y, 1.0, 1.0);
        glm::dvec3 p0 = glm::dvec3(a) / a.w, p1 = glm::dvec3(b) / b.w;
        return std::make_pair(p0, glm::normalize(p1 - p0));
    };
    // Derivatives in double of the ray's intersection with plane (q, n).
    auto planeDeriv = [&](double x, double y, glm::dvec3 q, glm::dvec3 n, bool alongY) {
        auto hit = [&](double xx, double yy) {
            auto [p, d] = ray(xx, yy);
            return p + d * (glm::dot(n, q - p) / glm::dot(n, d));
        };
        const double h = 1e-3;
        return alongY ? (hit(x, y + h) - hit(x, y - h)) / (2.0 * h)
                      : (hit(x + h, y) - hit(x - h, y)) / (2.0 * h);
    };
    struct Px {
        bool ok = false;
        glm::dvec3 virt, trueD[2], l17D[2]; // d/dx, d/dy
        int face = 0;                       // 0 upper level, 1 lower level
    };
    std::vector<Px> px(size_t(W) * size_t(H));
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            double cx = x + 0.5, cy = y + 0.5;
            auto [p0, d] = ray(cx, cy);
            if (!(d.z < -1e-3)) continue;
            glm::dvec3 p = p0 + d * (-p0.z / d.z);
            if (p.x < 0.1 || p.x > 0.9 || p.y < 0.1 || p.y > 0.9) continue;
            const glm::dvec3 o0(0.0), up(0, 0, 1);
            glm::dvec3 dPdx = planeDeriv(cx, cy, o0, up, false);
            glm::dvec3 dPdy = planeDeriv(cx, cy, o0, up, true);
            Px& r = px[size_t(y) * size_t(W) + size_t(x)];
            glm::dvec2 st;
            glm::dvec3 off;
            shadeSample(tex, float(f.scale), glm::dvec2(p), -d, glm::vec3(dPdx), glm::vec3(dPdy),
                        256, st, off);
            r.virt = p + off;
            // The face the pixel shows: the level nearest to the virtual
            // position (where POM and the exact ray disagree, near the
            // edge, is table 7a's error, not the derivative method's).
            const double zTop = f.scale * (0.6 - 1.0), zBottom = -f.scale;
            const bool top = std::abs(r.virt.z - zTop) < std::abs(r.virt.z - zBottom);
            r.face = top ? 0 : 1;
            const glm::dvec3 q(0, 0, top ? zTop : zBottom), n(0, 0, 1);
            r.trueD[0] = planeDeriv(cx, cy, q, n, false);
            r.trueD[1] = planeDeriv(cx, cy, q, n, true);
            // Listing 17 at the virtual position (camera-relative) with the
            // plateau's normal, as the re-prologue gets it from the resolve.
            glm::vec3 l17x, l17y;
            G::sgScreenDerivOfPos(l17x, l17y, glm::vec3(r.virt - eye), glm::vec3(0, 0, 1),
                                  glm::mat4(glm::translate(glm::dmat4(1.0), -eye) * inv), float(cx),
                                  float(cy));
            r.l17D[0] = glm::dvec3(l17x);
            r.l17D[1] = glm::dvec3(l17y);
            r.ok = true;
        }
    std::vector<double> eQuadAll, eL17All, eQuadDisc, eL17Disc;
    // dFdxFine / dFdyFine: the difference across the pixel's 2x2 quad.
    for (int dir = 0; dir < 2; ++dir)
        for (int y = 0; y + dir < H; y += 1 + dir)
            for (int x = 0; x + 1 - dir < W; x += 2 - dir) {
                const Px& a = px[size_t(y) * size_t(W) + size_t(x)];
                const Px& b = px[size_t(y + dir) * size_t(W) + size_t(x + 1 - dir)];
                if (!a.ok || !b.ok) continue;
                glm::dvec3 quad = b.virt - a.virt;
                bool disc = a.face != b.face;
                for (const Px* p : {&a, &b}) {
                    double len = glm::length(p->trueD[dir]);
                    double eq = glm::length(quad - p->trueD[dir]) / len;
                    double el = glm::length(p->l17D[dir] - p->trueD[dir]) / len;
                    (disc ? eQuadDisc : eQuadAll).push_back(eq);
                    (disc ? eL17Disc : eL17All).push_back(el);
                }
            }
    ErrorStats qa = errorStats(eQuadAll), la = errorStats(eL17All), qd = errorStats(eQuadDisc),
               ld = errorStats(eL17Disc);
    t.add({"dFdx of the virtual position (2x2 quad)", fmtErr(qa.p50), fmtErr(qa.p99),
           fmtErr(qd.p50), fmtErr(qd.p99), fmtErr(qd.max), std::to_string(qd.count)});
    t.add({"listing 17 analytic (virtual position, resolved normal)", fmtErr(la.p50),
           fmtErr(la.p99), fmtErr(ld.p50), fmtErr(ld.p99), fmtErr(ld.max),
           std::to_string(ld.count)});
}

} // namespace

void tableParallax(const Options& o) {
    Table t;
    t.title = "Table 9a: parallax, offset mapping vs POM vs the exact hit (analytic fields, "
              "ray-traced in double; 256^2 map; views 20-80 degrees above the plane)";
    t.header = {"field",     "method",         "texel p50",     "texel p90",
                "texel p99", "normal p50 deg", "normal p99 deg"};
    const std::vector<double> sinesP99 = errorRows(t, o.quick ? 100 : 400);
    t.notes.push_back("Texels: distance of the corrected coordinate to the true hit's. Normal: "
                      "angle between the field's analytic normals at the two (the step has none).");
    t.print(o.markdown);

    const std::vector<double> ms = costs(o);
    Table c;
    c.title = "Table 9b: parallax cost (plane filling the view, bricks relief 0.04 deep, " +
              std::to_string(o.size) + "^2)";
    c.header = {"layer", "ms", "ratio to height", "texel p99 (sines, table 9a)"};
    c.add({"height (3 taps, no correction)", fmt(ms[0], 2), fmtRatio(1.0), ""});
    for (size_t i = 0; i < std::size(kSteps); ++i)
        c.add({methodName(kSteps[i]), fmt(ms[i + 1], 2), fmtRatio(ms[i + 1] / ms[0]),
               fmtErr(sinesP99[i])});
    // The frontier: how far the corrected coordinate lands from the true hit
    // against what the correction costs (the height layer has no correction:
    // no point).
    c.plot.id = "parallax";
    c.plot.xColumn = 2;
    c.plot.yColumn = 3;
    c.plot.labelColumns = {0};
    c.plot.xLabel = "cost (ratio to a height layer, same run)";
    c.plot.yLabel = "distance to the true hit, p99 (texels, sines field)";
    c.notes.push_back("Frames interleaved; median over runs of the per-run median; renderer " +
                      o.renderer + ".");
    c.print(o);

    Table d;
    d.title = "Table 9c: re-prologue derivatives on the virtual surface (terrace relief, POM 256 "
              "steps): relative error of dPdx and dPdy";
    d.header = {"method",
                "smooth p50",
                "smooth p99",
                "discontinuity p50",
                "discontinuity p99",
                "discontinuity max",
                "discontinuity px"};
    derivativeRows(d, o);
    d.notes.push_back(
        "Truth: derivative in double of the ray's intersection with the level of the "
        "relief the pixel shows (nearest to its virtual position). Discontinuity: the "
        "quad's two pixels show different levels.");
    d.print(o.markdown);
}

} // namespace study
