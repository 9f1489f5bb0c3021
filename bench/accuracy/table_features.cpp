// Table 4, feature-curve mode (docs/accuracy-cost.md): one 128^2 map of a
// drawing (a closed curve of quadratic arcs, an S curve, a straight line)
// with a "crease" profile (h = -D (1 - d/w)^2, sharp at the curve; D = 1,
// w0 = 0.5, w = 3 texels), reconstructed by
//   a plain bilinear normal map of the same resolution (the exact normals at
//     texel centres, GL_LINEAR),
//   linear feature maps (Parilov, Rosenberg, Zorin 2005) and quadratic
//     feature maps (Parilov, Zorin 2008), through the shared evaluator (the
//     C++ build of shaders/sg/features; the GPU build is the same source,
//     parity-tested in tests/features),
// composed with the base as the papers do (Eq. 1: "paper", the profile's
// normal blended with the base normal, the base masked near the curve) or as
// surface gradients ("surfgrad": the profile's slope h'(d) grad d added to the
// base's derivative; with the base map inside the layer the slopes are
// blended instead, "masked"); and quadratic maps with the exact near field
// (shaders/sg/features/near.glsl: within the band of the profile's width the
// distance to the input's pieces themselves; --near exact), surfgrad.
//
// Error, measured on probe lines across the curves (points 0.5 texel apart
// along every curve, 3 texels clear of ends and other curves; 64 samples per
// texel along each line: the view at 64x magnification):
//   crease position - where the normal's component across the curve changes
//     sign, against the curve (texels; x64 = pixels at 64x);
//   normal, flat base - angle to the same composition evaluated with the
//     exact distance and gradient of the input curves (double distance);
//   normal, bumpy base - angle to the normal of the carved surface: the
//     profile's height added to a base height field (0.5 texel sine bumps,
//     slopes up to ~0.4), i.e. Mikkelsen 2019 eq. 2-3 applied to the
//     feature and the base. Masked compositions drop the base near the curve
//     by design; this column shows how much that changes the normal.
// The accuracy per map resolution (64..1024) is features_bench's table
// (bench/README.md, "Features"); this table compares the modes at one
// resolution with their cost measured in the same run.
// Cost: a 512^2 full-screen pass over a 32x32-texel window of the map (16x
// magnification), flat base; ratio to the bilinear map. The profile kind is
// a compile-time constant (as in features_llvmpipe_bench) and, in one more
// row, a uniform (as the renderer's layer records pass it).
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "surfgrad/features/feature_maps.h"
#include "tables.h"

namespace study {

namespace {

using glm::dvec2;
using sg::features::CurveNetwork;
using sg::features::Segment;

dvec2 bezier(const Segment& s, double t) {
    const double u = 1.0 - t;
    return u * u * s.p0 + 2.0 * t * u * s.p1 + t * t * s.p2;
}
dvec2 bezierTangent(const Segment& s, double t) {
    return 2.0 * (1.0 - t) * (s.p1 - s.p0) + 2.0 * t * (s.p2 - s.p1);
}

void addSegment(CurveNetwork& n, dvec2 a, dvec2 c, dvec2 b, int curve, bool line) {
    Segment s;
    s.kind = line ? Segment::Kind::Line : Segment::Kind::Quadratic;
    s.p0 = a;
    s.p1 = line ? 0.5 * (a + b) : c;
    s.p2 = b;
    s.curve = curve;
    n.segments.push_back(s);
}

// The drawing, in texel space of a 128^2 map.
CurveNetwork drawing() {
    CurveNetwork n;
    n.curves.resize(3);
    n.curves[0].closed = true;
    const dvec2 c(46.0, 82.0);
    const double r = 27.0;
    for (int k = 0; k < 8; ++k) {
        const double a0 = 0.2 + M_PI / 4 * k, a1 = a0 + M_PI / 4, am = 0.5 * (a0 + a1);
        addSegment(n, c + r * dvec2(std::cos(a0), std::sin(a0)),
                   c + r / std::cos(M_PI / 8) * dvec2(std::cos(am), std::sin(am)),
                   c + r * dvec2(std::cos(a1), std::sin(a1)), 0, false);
    }
    n.segments.back().p2 = n.segments.front().p0;
    addSegment(n, {12.0, 18.0}, {38.0, 52.0}, {66.0, 30.0}, 1, false);
    addSegment(n, {66.0, 30.0}, {94.0, 8.0}, {117.0, 38.0}, 1, false);
    addSegment(n, {86.0, 54.0}, {}, {113.0, 117.0}, 2, true);
    return n;
}

// Exact distance from p to a segment (double): dense samples, then
// golden-section refinement of |B(t) - p| around the best sample.
double segmentDistance(const Segment& s, dvec2 p, dvec2& closest) {
    const int n = 48;
    int best = 0;
    double bestD = 1e300;
    for (int i = 0; i <= n; ++i) {
        const double d = glm::length(bezier(s, double(i) / n) - p);
        if (d < bestD) {
            bestD = d;
            best = i;
        }
    }
    double lo = std::max(0.0, (best - 1.0) / n), hi = std::min(1.0, (best + 1.0) / n);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 60; ++it) {
        const double a = hi - g * (hi - lo), b = lo + g * (hi - lo);
        if (glm::length(bezier(s, a) - p) < glm::length(bezier(s, b) - p))
            hi = b;
        else
            lo = a;
    }
    closest = bezier(s, 0.5 * (lo + hi));
    return glm::length(closest - p);
}

struct Exact {
    double dist;
    dvec2 grad; // unit, away from the nearest curve point
};

Exact exactDistance(const CurveNetwork& net, dvec2 p) {
    Exact e{1e300, {0.0, 0.0}};
    for (const Segment& s : net.segments) {
        dvec2 q;
        const double d = segmentDistance(s, p, q);
        if (d < e.dist) {
            e.dist = d;
            e.grad = d > 0 ? (p - q) / d : dvec2(0.0);
        }
    }
    return e;
}

struct Probe {
    dvec2 point, normal;
};

// Base height field (texel units) and its gradient.
struct Base {
    double amp = 0.5, lx = 9.7, ly = 13.1;
    dvec2 grad(dvec2 p) const {
        const double ax = 2 * M_PI / lx, ay = 2 * M_PI / ly;
        return amp * dvec2(ax * std::cos(ax * p.x) * std::sin(ay * p.y),
                           ay * std::sin(ax * p.x) * std::cos(ay * p.y));
    }
};

glm::dvec3 normalOfDeriv(dvec2 d) {
    return glm::normalize(glm::dvec3(-d.x, -d.y, 1.0));
}

enum Mode { Bilinear, LinearSurfgrad, QuadSurfgrad, QuadPaper, QuadMasked, QuadNear, ModeCount };
const char* kModeNames[ModeCount] = {"bilinear normal map 128^2",
                                     "linear maps, surfgrad",
                                     "quadratic maps, surfgrad",
                                     "quadratic maps, paper (Eq. 1)",
                                     "quadratic maps, surfgrad, base in layer (masked)",
                                     "quadratic maps + exact near field, surfgrad"};

const char* kFragment = R"(
#include "sg/features/fetch.glsl"
#include "sg/features/profile.glsl"
uniform vec2 uWindowMin;
uniform vec2 uWindowSize;
uniform float uMapSize;
uniform vec4 uProfile; // kind, depth, w0, w
uniform sampler2D uNormalMap;
uniform usampler2D uFeatCorners;
uniform usampler2D uFeatEdges;
uniform usampler2D uFeatNear;
uniform usampler2D uFeatPieces;
layout(location = 0) out vec4 oColor;
void main() {
    vec2 texelPos = uWindowMin + gl_FragCoord.xy * (uWindowSize / UVIEW);
    vec3 n;
#ifdef BILINEAR
    vec3 m = texture(uNormalMap, texelPos / uMapSize).xyz * 2.0 - 1.0;
    n = normalize(m);
#else
#if SG_FEAT_NEAR
    SgFeatResult r = sgFeatSampleNear(uFeatCorners, uFeatEdges, uFeatNear, uFeatPieces, texelPos);
#else
    SgFeatResult r = sgFeatSample(uFeatCorners, uFeatEdges, texelPos);
#endif
    SgFeatProfile p;
#ifdef KIND_UNIFORM
    p.kind = int(uProfile.x); // as the renderer's records pass it
#else
    p.kind = SG_FEAT_PROFILE_CREASE; // compile-time constant (features_llvmpipe_bench does the same)
#endif
    p.depth = uProfile.y;
    p.w0 = uProfile.z;
    p.w = uProfile.w;
    p.tableCount = 0;
    for (int i = 0; i < SG_FEAT_TABLE_MAX; ++i) p.table[i] = 0.0;
#if SG_FEAT_NEAR
    p = sgFeatCurveProfile(uFeatPieces, p, r); // per-curve profiles, as the renderer does
#endif
#ifdef PAPER
    n = sgFeatNormalPaper(r, p, vec3(0.0, 0.0, 1.0));
#else
    n = sgFeatNormalFromDeriv(sgFeatDeriv(r, p, vec2(0.0)));
#endif
#endif
    vec3 l = normalize(vec3(-0.55, 0.65, 0.52));
    oColor = vec4(vec3(0.1 + 0.9 * max(dot(n, l), 0.0)), 1.0);
}
)";

} // namespace

void tableFeatures(const Options& o) {
    const FullscreenTriangle fullscreen;
    const int n = 128;
    const CurveNetwork net = drawing();
    sg::features::BakeOptions bo;
    bo.size = n;
    bo.fit = false;
    bo.mode = sg::features::BakeMode::Linear;
    const sg::features::FeatureMaps linMaps = sg::features::bake(net, bo);
    bo.mode = sg::features::BakeMode::Quadratic;
    const sg::features::FeatureMaps quadMaps = sg::features::bake(net, bo);
    const sg::features::GpuFeatureMaps lin = linMaps.packGpu(), quad = quadMaps.packGpu();
    const float depth = 1.0f, w0 = 0.5f, w = 3.0f;
    bo.nearField = true;
    bo.nearWidthTexels = w; // the band covers the profile
    const sg::features::GpuFeatureMaps nearMaps = sg::features::bake(net, bo).packGpu();
    const sg::glsl::SgFeatProfile prof = sg::features::makeProfile("crease", depth, w0, w);
    const Base base;

    auto result = [](float d, glm::vec2 g) {
        sg::glsl::SgFeatResult r;
        r.dist = d;
        r.grad = g;
        r.side = 1.0f;
        r.profile = -1;
        r.width = 0.0f;
        return r;
    };
    // The flat-base surfgrad normal of an exact (distance, gradient); used
    // for the bilinear map's texels (flat) and as the truth.
    auto surfgradNormal = [&](const sg::glsl::SgFeatResult& r, dvec2 baseDeriv) {
        return normalOfDeriv(dvec2(sg::glsl::sgFeatDeriv(r, prof, glm::vec2(0.0f))) + baseDeriv);
    };
    // Bilinear normal maps (texel centres) of the exact flat and carved normals.
    std::vector<glm::dvec3> flatMap(size_t(n) * size_t(n)), bumpyMap(flatMap.size());
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const dvec2 p(i + 0.5, j + 0.5);
            const Exact e = exactDistance(net, p);
            const auto r = result(float(e.dist), glm::vec2(e.grad));
            flatMap[size_t(j) * size_t(n) + size_t(i)] = surfgradNormal(r, dvec2(0.0));
            bumpyMap[size_t(j) * size_t(n) + size_t(i)] = surfgradNormal(r, base.grad(p));
        }
    }
    auto bilinear = [&](const std::vector<glm::dvec3>& map, dvec2 p) {
        const double x = std::clamp(p.x - 0.5, 0.0, n - 1.0),
                     y = std::clamp(p.y - 0.5, 0.0, n - 1.0);
        const int i = std::min(int(x), n - 2), j = std::min(int(y), n - 2);
        const double fx = x - i, fy = y - j;
        auto at = [&](int a, int b) { return map[size_t(b) * size_t(n) + size_t(a)]; };
        return glm::normalize((1 - fx) * (1 - fy) * at(i, j) + fx * (1 - fy) * at(i + 1, j) +
                              (1 - fx) * fy * at(i, j + 1) + fx * fy * at(i + 1, j + 1));
    };
    // Normal of a mode at p, flat or bumpy base.
    auto modeNormal = [&](int mode, dvec2 p, bool bumpy) -> glm::dvec3 {
        const dvec2 bd = bumpy ? base.grad(p) : dvec2(0.0);
        if (mode == Bilinear) return bilinear(bumpy ? bumpyMap : flatMap, p);
        const auto r =
            mode == QuadNear
                ? sg::features::sample(nearMaps, glm::vec2(p), sg::features::NearMode::Exact)
                : sg::features::sample(mode == LinearSurfgrad ? lin : quad, glm::vec2(p));
        if (mode == QuadPaper) {
            return glm::dvec3(sg::glsl::sgFeatNormalPaper(r, prof, glm::vec3(normalOfDeriv(bd))));
        }
        if (mode == QuadMasked)
            return normalOfDeriv(dvec2(sg::glsl::sgFeatDeriv(r, prof, glm::vec2(bd))));
        return surfgradNormal(r, bd);
    };
    // The same composition with the exact distance (flat base).
    auto exactFlat = [&](int mode, const Exact& e) -> glm::dvec3 {
        const auto r = result(float(e.dist), glm::vec2(e.grad));
        if (mode == QuadPaper)
            return glm::dvec3(sg::glsl::sgFeatNormalPaper(r, prof, glm::vec3(0, 0, 1)));
        return surfgradNormal(r, dvec2(0.0));
    };

    // Probes: 3 texels clear of the open curves' ends (joints inside a curve
    // are tangent continuous) and 6 texels clear of every other curve, so
    // the nearest curve point of a probe line is its own.
    std::vector<dvec2> openEnds;
    for (size_t c = 0; c < net.curves.size(); ++c) {
        if (net.curves[c].closed) continue;
        const Segment* first = nullptr;
        const Segment* last = nullptr;
        for (const Segment& s : net.segments) {
            if (s.curve != int(c)) continue;
            if (!first) first = &s;
            last = &s;
        }
        openEnds.push_back(first->p0);
        openEnds.push_back(last->p2);
    }
    std::vector<Probe> probes;
    for (const Segment& s : net.segments) {
        const int per = std::max(4, int(glm::length(s.p2 - s.p0) / 0.5));
        for (int i = 0; i < per; ++i) {
            const double t = double(i) / per;
            const dvec2 q = bezier(s, t), tan = glm::normalize(bezierTangent(s, t));
            bool ok = true;
            for (const dvec2& e : openEnds) ok = ok && glm::length(q - e) > 3.0;
            for (const Segment& other : net.segments) {
                if (other.curve == s.curve) continue;
                for (int z = 0; z <= 100 && ok; ++z)
                    ok = glm::length(bezier(other, z / 100.0) - q) > 6.0;
            }
            if (ok) probes.push_back({q, dvec2(-tan.y, tan.x)});
        }
    }
    if (o.quick && probes.size() > 60) {
        std::vector<Probe> fewer;
        for (size_t k = 0; k < probes.size(); k += probes.size() / 60) fewer.push_back(probes[k]);
        probes.swap(fewer);
    }

    std::vector<std::vector<double>> crease(ModeCount), flatErr(ModeCount), bumpyErr(ModeCount);
    double paperVsMaskedMax = 0, paperVsSurfgradFlatMax = 0;
    const int steps = int(2 * w * 64);
    for (const Probe& pr : probes) {
        std::vector<double> ts;
        std::vector<Exact> ex;
        for (int s = 0; s < steps; ++s) {
            const double t = -w + 2.0 * w * (s + 0.5) / steps;
            ts.push_back(t);
            ex.push_back(exactDistance(net, pr.point + t * pr.normal));
        }
        for (int m = 0; m < ModeCount; ++m) {
            double prevC = 0, prevT = 0, cross = 1e9;
            for (size_t s = 0; s < ts.size(); ++s) {
                const dvec2 p = pr.point + ts[s] * pr.normal;
                const glm::dvec3 nf = modeNormal(m, p, false);
                const double c = nf.x * pr.normal.x + nf.y * pr.normal.y;
                if (s > 0 && prevC > 0.0 && c <= 0.0 && cross > 1e8) {
                    // Bisect the sign change (a discontinuity for feature maps).
                    double lo = prevT, hi = ts[s];
                    for (int it = 0; it < 30; ++it) {
                        const double mid = 0.5 * (lo + hi);
                        const glm::dvec3 nm = modeNormal(m, pr.point + mid * pr.normal, false);
                        ((nm.x * pr.normal.x + nm.y * pr.normal.y) > 0.0 ? lo : hi) = mid;
                    }
                    cross = 0.5 * (lo + hi);
                }
                prevC = c;
                prevT = ts[s];
                if (std::fabs(ts[s]) > 1.0 / 64.0) {
                    flatErr[size_t(m)].push_back(angleDeg(nf, exactFlat(m, ex[s])));
                    const auto r = result(float(ex[s].dist), glm::vec2(ex[s].grad));
                    const glm::dvec3 carved = surfgradNormal(r, base.grad(p));
                    const glm::dvec3 nb = modeNormal(m, p, true);
                    bumpyErr[size_t(m)].push_back(angleDeg(nb, carved));
                    if (m == QuadPaper) {
                        paperVsMaskedMax = std::max(paperVsMaskedMax,
                                                    angleDeg(nb, modeNormal(QuadMasked, p, true)));
                        paperVsSurfgradFlatMax = std::max(
                            paperVsSurfgradFlatMax,
                            angleDeg(exactFlat(QuadPaper, ex[s]), exactFlat(QuadSurfgrad, ex[s])));
                    }
                }
            }
            crease[size_t(m)].push_back(cross > 1e8 ? w : std::fabs(cross));
        }
    }

    // Cost.
    GLuint texCorners[3], texEdges[3], texNormal, texNear[2];
    const sg::features::GpuFeatureMaps* gm[3] = {&lin, &quad, &nearMaps};
    for (int k = 0; k < 3; ++k) {
        // Layout of surfgrad/features/feature_maps.h: corner pairs N x (N+1) and edge
        // words N x N, both RGBA32UI.
        glCreateTextures(GL_TEXTURE_2D, 1, &texCorners[k]);
        glTextureStorage2D(texCorners[k], 1, GL_RGBA32UI, gm[k]->cornerPairsWidth(),
                           gm[k]->cornerPairsHeight());
        glTextureSubImage2D(texCorners[k], 0, 0, 0, gm[k]->cornerPairsWidth(),
                            gm[k]->cornerPairsHeight(), GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                            gm[k]->cornerPairs.data());
        glCreateTextures(GL_TEXTURE_2D, 1, &texEdges[k]);
        glTextureStorage2D(texEdges[k], 1, GL_RGBA32UI, n, n);
        glTextureSubImage2D(texEdges[k], 0, 0, 0, n, n, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                            gm[k]->edges.data());
        for (GLuint t : {texCorners[k], texEdges[k]}) {
            glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        }
    }
    {
        // The near field's lists (N x nearHeight) and pieces, RGBA32UI.
        glCreateTextures(GL_TEXTURE_2D, 2, texNear);
        glTextureStorage2D(texNear[0], 1, GL_RGBA32UI, n, nearMaps.nearHeight);
        glTextureSubImage2D(texNear[0], 0, 0, 0, n, nearMaps.nearHeight, GL_RGBA_INTEGER,
                            GL_UNSIGNED_INT, nearMaps.nearLists.data());
        glTextureStorage2D(texNear[1], 1, GL_RGBA32UI, SG_FEAT_PIECES_WIDTH, nearMaps.piecesHeight);
        glTextureSubImage2D(texNear[1], 0, 0, 0, SG_FEAT_PIECES_WIDTH, nearMaps.piecesHeight,
                            GL_RGBA_INTEGER, GL_UNSIGNED_INT, nearMaps.pieces.data());
        for (GLuint t : texNear) {
            glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        }
    }
    {
        // RGBA8 normal map, as a plain normal map is stored.
        std::vector<unsigned char> px(size_t(n) * size_t(n) * 4);
        for (size_t k = 0; k < flatMap.size(); ++k) {
            for (int c = 0; c < 3; ++c)
                px[k * 4 + size_t(c)] =
                    (unsigned char)std::lround((flatMap[k][c] * 0.5 + 0.5) * 255);
            px[k * 4 + 3] = 255;
        }
        glCreateTextures(GL_TEXTURE_2D, 1, &texNormal);
        glTextureStorage2D(texNormal, 1, GL_RGBA8, n, n);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTextureSubImage2D(texNormal, 0, 0, 0, n, n, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
        glTextureParameteri(texNormal, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(texNormal, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(texNormal, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(texNormal, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    const int view = std::min(o.size, 512);
    const std::string uview = "UVIEW " + std::to_string(view) + ".0";
    // The fifth timed variant: quadratic surfgrad with the profile kind in a
    // uniform, as the renderer's layer records pass it; the sixth the exact
    // near field.
    const int timedModes[6] = {Bilinear,  LinearSurfgrad, QuadSurfgrad,
                               QuadPaper, QuadSurfgrad,   QuadNear};
    std::vector<sg::gl::Program> progs;
    progs.push_back(
        makeProgram(fullscreenVertexShader(), kFragment, "feat_bilinear", {uview, "BILINEAR"}));
    progs.push_back(makeProgram(fullscreenVertexShader(), kFragment, "feat_surfgrad", {uview}));
    progs.push_back(makeProgram(fullscreenVertexShader(), kFragment, "feat_surfgrad", {uview}));
    progs.push_back(
        makeProgram(fullscreenVertexShader(), kFragment, "feat_paper", {uview, "PAPER"}));
    progs.push_back(
        makeProgram(fullscreenVertexShader(), kFragment, "feat_uniform", {uview, "KIND_UNIFORM"}));
    progs.push_back(
        makeProgram(fullscreenVertexShader(), kFragment, "feat_near", {uview, "SG_FEAT_NEAR 1"}));
    // Window: 32x32 texels where the circle and the S curve pass.
    const glm::vec2 windowMin(22.0f, 40.0f), windowSize(32.0f);
    Target tim(view, view, 1, false);
    glDisable(GL_DEPTH_TEST);
    const auto ms = timeVariants(
        6,
        [&](size_t k) {
            tim.clear();
            const sg::gl::Program& p = progs[k];
            glUseProgram(p.id());
            glUniform2fv(p.uniform("uWindowMin"), 1, &windowMin[0]);
            glUniform2fv(p.uniform("uWindowSize"), 1, &windowSize[0]);
            glUniform1f(p.uniform("uMapSize"), float(n));
            glUniform4f(p.uniform("uProfile"), float(prof.kind), prof.depth, prof.w0, prof.w);
            glUniform1i(p.uniform("uNormalMap"), 0);
            glUniform1i(p.uniform("uFeatCorners"), 1);
            glUniform1i(p.uniform("uFeatEdges"), 2);
            glUniform1i(p.uniform("uFeatNear"), 3);
            glUniform1i(p.uniform("uFeatPieces"), 4);
            const int mapSet =
                timedModes[k] == LinearSurfgrad ? 0 : (timedModes[k] == QuadNear ? 2 : 1);
            glBindTextureUnit(0, texNormal);
            glBindTextureUnit(1, texCorners[mapSet]);
            glBindTextureUnit(2, texEdges[mapSet]);
            glBindTextureUnit(3, texNear[0]);
            glBindTextureUnit(4, texNear[1]);
            fullscreen.draw();
        },
        o);
    glDeleteTextures(3, texCorners);
    glDeleteTextures(3, texEdges);
    glDeleteTextures(2, texNear);
    glDeleteTextures(1, &texNormal);
    // Fraction of the window's texels with a discontinuity (the evaluator's
    // slow path).
    int featureTexels = 0;
    for (int j = 0; j < 32; ++j) {
        for (int i = 0; i < 32; ++i) {
            if (quadMaps.seg[quadMaps.index(int(windowMin.x) + i, int(windowMin.y) + j)] != 0)
                ++featureTexels;
        }
    }

    Table t;
    t.title =
        "Table 4: feature-curve mode (128^2 map, crease profile D = 1, w0 = 0.5, w = 3 texels)";
    t.header = {"mode",         "crease mean tx", "crease max tx", "max px @64x", "flat p50 deg",
                "flat p99 deg", "bumpy p50 deg",  "bumpy max deg", "frame ms",    "ratio"};
    for (int m = 0; m < ModeCount; ++m) {
        const ErrorStats c = errorStats(crease[size_t(m)]), f = errorStats(flatErr[size_t(m)]),
                         b = errorStats(bumpyErr[size_t(m)]);
        int timed = -1;
        for (int k : {5, 3, 2, 1, 0}) timed = timedModes[k] == m ? k : timed;
        t.add({kModeNames[m], fmtErr(c.mean), fmtErr(c.max), fmt(c.max * 64.0, 1), fmtErr(f.p50),
               fmtErr(f.p99), fmtErr(b.p50), fmtErr(b.max),
               timed >= 0 ? fmt(ms[size_t(timed)], 2) : "(as surfgrad)",
               timed >= 0 ? fmtRatio(ms[size_t(timed)] / ms[0]) : ""});
    }
    t.add({"quadratic maps, surfgrad, profile kind in a uniform", "(same)", "", "", "", "", "", "",
           fmt(ms[4], 2), fmtRatio(ms[4] / ms[0])});
    t.notes.push_back(
        std::to_string(probes.size()) + " probes x " + std::to_string(steps) +
        " samples. 'flat': against the same composition with the exact distance; 'bumpy': against "
        "the carved surface (profile height + base height). Paper vs surfgrad with exact "
        "distances, "
        "flat base: at most " +
        fmtErr(paperVsSurfgradFlatMax) +
        " degrees apart (inside the blend band "
        "w0 < d < w only); paper vs masked surfgrad on the bumpy base: at most " +
        fmtErr(paperVsMaskedMax) + " degrees.");
    t.notes.push_back(
        "Cost: " + std::to_string(view) + "^2 pass over a 32x32-texel window (" +
        std::to_string(featureTexels) + "/1024 texels with a discontinuity), " + o.renderer + ", " +
        std::to_string(o.runs) + " runs x " + std::to_string(o.frames) +
        " frames, medians; ratio to the bilinear map (RGBA8, GL_LINEAR). Accuracy per resolution "
        "64..1024: features_bench accuracy. Exact near field: band " +
        fmt(nearMaps.nearStats.bandTexels, 0) + " texels of the map, " +
        fmt(nearMaps.nearStats.meanPieces, 2) + " pieces per band texel (max " +
        std::to_string(nearMaps.nearStats.maxPieces) + "), " +
        fmt(nearMaps.nearBytesPerTexel(), 1) +
        " bytes per texel on top of the maps' 32; accuracy on glyphs, icons and stars: "
        "features_near_bench.");
    t.plot = {"features",
              9,
              2,
              -1,
              {0},
              true,
              true,
              "frame time, ratio to a bilinear normal map",
              "crease position error max, texels"};
    t.print(o);
}

} // namespace study
