// features_llvmpipe_bench: per-pixel cost of the feature-map evaluator
// (shaders/sg/features: sgFeatSample + sgFeatDeriv) in a fragment pass on
// Mesa llvmpipe, against a plain bilinear normal-map fetch measured in the
// same run. Goals: <= 3x the baseline for linear maps, <= 6x for
// quadratic maps, at full feature coverage.
//
// Every variant draws one full-screen triangle into a 1024x1024 RGBA8
// target; the fragment shader maps the pixel to a texel-space position in a
// window of the map, computes a tangent-space normal, shades it (Lambert)
// and writes it. Only the normal's source differs:
//   baseline   texture() of an RGBA8 normal map of the same resolution
//              (GL_LINEAR, hardware bilinear), decoded to a derivative;
//   features   sgFeatSample (3 texelFetch) + sgFeatDeriv (V-groove);
//   near       quadratic maps with the exact near field (SG_FEAT_NEAR 1):
//              sgFeatSampleNear (the list header, then in the band 2
//              fetches per listed piece and the exact closest points; the
//              interpolation outside it) + the curve's profile + sgFeatDeriv.
// Maps: "dense" is a network of random curves in which every texel of the
// viewed window has a discontinuity (feature coverage ratio, FCR, ~100%: the
// paper's worst case); "glyph" is a CJK glyph seen whole (FCR a few %).
// Each frame is one draw + glFinish (llvmpipe skips draws covered by a
// later one; docs/platform.md); the table shows medians over runs of 20 frames.
// Run: LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe EGL_PLATFORM=surfaceless
//      build/bin/features_llvmpipe_bench [--runs N] [--frames N] [--size N]
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <time.h>

#include "surfgrad/features/curves.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/shaders/shader_files.h"

using namespace sg::features;
using glm::dvec2;

namespace {

// One triangle covering the viewport; vScreenUv in [0, 1]^2 over it.
const char* kVertex = "#include \"sg/render/fullscreen_vs.glsl\"\n";

const char* kFragmentHead = R"(
in vec2 vScreenUv;
uniform vec2 uWindowMin;  // texel-space window shown by the viewport
uniform vec2 uWindowSize;
uniform float uMapSize;   // N
layout(location = 0) out vec4 oColor;
vec4 shade(vec3 n) {
    vec3 l = normalize(vec3(-0.55, 0.65, 0.52));
    return vec4(vec3(0.1 + 0.9 * max(dot(n, l), 0.0)), 1.0);
}
)";

const char* kFragmentBaseline = R"(
#include "sg/surfgrad.glsl"
uniform sampler2D uNormalMap;
void main() {
    vec2 texelPos = uWindowMin + vScreenUv * uWindowSize;
    vec2 m = texture(uNormalMap, texelPos / uMapSize).xy * 2.0 - 1.0;
    vec2 d = sgTspaceNormalToDeriv(m, false);
    oColor = shade(normalize(vec3(-d, 1.0)));
}
)";

// The three fetches alone (their results summed), for the cost split.
const char* kFragmentFetchOnly = R"(
#include "sg/features/fetch.glsl"
uniform usampler2D uFeatCorners;
uniform usampler2D uFeatEdges;
void main() {
    vec2 texelPos = uWindowMin + vScreenUv * uWindowSize;
    vec2 local;
    ivec2 ij = sgFeatTexelOf(textureSize(uFeatEdges, 0), texelPos, local);
    SgFeatTexel tx = sgFeatFetch(uFeatCorners, uFeatEdges, ij);
    vec4 a = tx.dist + vec4(tx.grad0, tx.grad1) + vec4(tx.grad2, tx.grad3) + vec4(tx.edges) * 1e-9 + float(tx.cfg);
    oColor = vec4(a.x + a.y, a.z, a.w + local.x, 1.0);
}
)";
const char* kFragmentFeatures = R"(
#include "sg/features/fetch.glsl"
#include "sg/features/profile.glsl"
uniform usampler2D uFeatCorners;
uniform usampler2D uFeatEdges;
uniform float uDepth;
uniform float uWidth;
void main() {
    vec2 texelPos = uWindowMin + vScreenUv * uWindowSize;
    SgFeatResult r = sgFeatSample(uFeatCorners, uFeatEdges, texelPos);
    SgFeatProfile p;
    p.kind = SG_FEAT_PROFILE_VGROOVE;
    p.depth = uDepth;
    p.w0 = 0.0;
    p.w = uWidth;
    p.tableCount = 0;
    for (int i = 0; i < SG_FEAT_TABLE_MAX; ++i) p.table[i] = 0.0;
    vec2 d = sgFeatDeriv(r, p, vec2(0.0));
    oColor = shade(normalize(vec3(-d, 1.0)));
}
)";

// The same with the exact near field (SG_FEAT_NEAR 1): in the band, the
// listed pieces' closest points and each curve's own profile; outside it,
// the interpolation above.
const char* kFragmentFeaturesNear = R"(
#include "sg/features/fetch.glsl"
#include "sg/features/profile.glsl"
uniform usampler2D uFeatCorners;
uniform usampler2D uFeatEdges;
uniform usampler2D uFeatNear;
uniform usampler2D uFeatPieces;
uniform float uDepth;
uniform float uWidth;
void main() {
    vec2 texelPos = uWindowMin + vScreenUv * uWindowSize;
    SgFeatResult r = sgFeatSampleNear(uFeatCorners, uFeatEdges, uFeatNear, uFeatPieces, texelPos);
    SgFeatProfile p;
    p.kind = SG_FEAT_PROFILE_VGROOVE;
    p.depth = uDepth;
    p.w0 = 0.0;
    p.w = uWidth;
    p.tableCount = 0;
    for (int i = 0; i < SG_FEAT_TABLE_MAX; ++i) p.table[i] = 0.0;
    p = sgFeatCurveProfile(uFeatPieces, p, r);
    vec2 d = sgFeatDeriv(r, p, vec2(0.0));
    oColor = shade(normalize(vec3(-d, 1.0)));
}
)";

// CPU time of the whole process (llvmpipe's rasterizer threads included):
// on a shared machine it measures the work, where wall time also measures
// the waiting.
double processCpuMs() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

struct MapSet {
    std::string name;
    FeatureMaps lin, quad, nearMaps; // nearMaps: quadratic with the exact near field
    glm::vec2 windowMin, windowSize;
    double fcr = 0; // fraction of pixels in texels with features
};

CurveNetwork denseNetwork(int n) {
    CurveNetwork net;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    // Arcs of radius 2..6 texels every ~3 texels: every texel of the middle
    // of the map is crossed.
    for (int k = 0; k < n * n / 4; ++k) {
        dvec2 c(n * u(rng), n * u(rng));
        double r = 2.0 + 4.0 * u(rng), a0 = 6.283 * u(rng), sw = 1.0 + 1.5 * u(rng);
        Segment s;
        s.kind = Segment::Kind::Quadratic;
        s.p0 = c + r * dvec2(std::cos(a0), std::sin(a0));
        s.p2 = c + r * dvec2(std::cos(a0 + sw), std::sin(a0 + sw));
        s.p1 = c + r / std::cos(sw / 2) * dvec2(std::cos(a0 + sw / 2), std::sin(a0 + sw / 2));
        s.curve = int(net.curves.size());
        net.curves.push_back({});
        net.segments.push_back(s);
    }
    return net;
}

GLuint makeTexture(GLenum internal, int w, int h, GLenum format, GLenum type, const void* data,
                   GLenum filter) {
    GLuint t;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, 1, internal, w, h);
    glTextureSubImage2D(t, 0, 0, 0, w, h, format, type, data);
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, filter);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, filter);
    glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return t;
}

} // namespace

int main(int argc, char** argv) {
    int runs = 7, frames = 20, size = 1024;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!std::strcmp(argv[i], "--runs")) runs = std::max(1, std::atoi(argv[i + 1]));
        if (!std::strcmp(argv[i], "--frames")) frames = std::max(1, std::atoi(argv[i + 1]));
        if (!std::strcmp(argv[i], "--size")) size = std::max(16, std::atoi(argv[i + 1]));
    }
    sg::gl::HeadlessContext ctx;
    std::printf("renderer: %s\n", ctx.renderer().c_str());

    std::vector<MapSet> sets;
    {
        MapSet s;
        s.name = "dense curves";
        CurveNetwork net = denseNetwork(128);
        BakeOptions o;
        o.size = 128;
        o.fit = false;
        o.mode = BakeMode::Linear;
        s.lin = bake(net, o);
        o.mode = BakeMode::Quadratic;
        s.quad = bake(net, o);
        o.nearField = true;
        o.nearWidthTexels = 2.0; // the V-groove's half-width below
        s.nearMaps = bake(net, o);
        s.windowMin = glm::vec2(40.0f);
        s.windowSize = glm::vec2(48.0f); // 21 pixels per texel
        sets.push_back(std::move(s));
    }
    try {
        CurveNetwork net =
            loadFont("/usr/share/fonts/truetype/wqy/wqy-microhei.ttc", "\xe7\xb9\x81");
        MapSet s;
        s.name = "glyph (whole)";
        BakeOptions o;
        o.size = 512;
        o.mode = BakeMode::Linear;
        s.lin = bake(net, o);
        o.mode = BakeMode::Quadratic;
        s.quad = bake(net, o);
        o.nearField = true;
        o.nearWidthTexels = 2.0;
        s.nearMaps = bake(net, o);
        s.windowMin = glm::vec2(0.0f);
        s.windowSize = glm::vec2(512.0f);
        sets.push_back(std::move(s));
    } catch (const std::exception& e) {
        std::printf("(no glyph: %s)\n", e.what());
    }

    GLuint fbo, color, vao;
    glCreateFramebuffers(1, &fbo);
    glCreateRenderbuffers(1, &color);
    glNamedRenderbufferStorage(color, GL_RGBA8, size, size);
    glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glCreateVertexArrays(1, &vao);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glBindVertexArray(vao);
    glViewport(0, 0, size, size);

    auto program = [&](const char* frag, const char* name, std::vector<std::string> defines = {}) {
        auto vs = sg::shaders::assemble(kVertex, std::string(name) + ".vert");
        auto fs = sg::shaders::assemble(std::string(kFragmentHead) + frag,
                                        std::string(name) + ".frag", defines);
        return sg::gl::Program({{sg::gl::Stage::Vertex, vs}, {sg::gl::Stage::Fragment, fs}});
    };
    sg::gl::Program base = program(kFragmentBaseline, "baseline");
    sg::gl::Program feat = program(kFragmentFeatures, "features");
    // Linear maps use the straight-segment evaluator (SG_FEAT_CURVED 0).
    sg::gl::Program featLinear =
        program(kFragmentFeatures, "features-linear", {"SG_FEAT_CURVED 0"});
    sg::gl::Program fetchOnly = program(kFragmentFetchOnly, "fetchonly");
    sg::gl::Program featNear = program(kFragmentFeaturesNear, "features-near", {"SG_FEAT_NEAR 1"});

    std::printf("\nShader cost, %dx%d fragments, llvmpipe (median frame over %d runs of %d frames, "
                "one draw + glFinish "
                "per frame; CPU = process CPU time, all llvmpipe threads)\n",
                size, size, runs, frames);
    std::printf("| map | FCR | variant | CPU ms / frame | wall ms / frame | CPU ns / pixel | ratio "
                "to baseline (CPU) | goal "
                "|\n|---|---|---|---|---|---|---|---|\n");
    for (MapSet& s : sets) {
        const int n = s.lin.size;
        // FCR: pixels whose texel has features.
        size_t inFeat = 0;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                glm::vec2 p = s.windowMin +
                              (glm::vec2(float(x), float(y)) + 0.5f) / float(size) * s.windowSize;
                int i = std::clamp(int(p.x), 0, n - 1), j = std::clamp(int(p.y), 0, n - 1);
                inFeat += (s.quad.configWord(i, j) & 0xFFFFu) != 0;
            }
        }
        s.fcr = double(inFeat) / (double(size) * size);
        // The baseline's normal map: the profile's normal at the grid samples.
        std::vector<uint8_t> nm(size_t(n + 1) * size_t(n + 1) * 4);
        for (size_t k = 0; k < size_t(n + 1) * size_t(n + 1); ++k) {
            float d = s.lin.dist[k];
            glm::vec2 g(s.lin.gradX[k], s.lin.gradY[k]);
            float slope = d < 2.0f ? 0.5f : 0.0f;
            glm::vec3 v = glm::normalize(glm::vec3(-slope * g, 1.0f));
            nm[4 * k] = uint8_t(std::lround((v.x * 0.5f + 0.5f) * 255.0f));
            nm[4 * k + 1] = uint8_t(std::lround((v.y * 0.5f + 0.5f) * 255.0f));
            nm[4 * k + 2] = uint8_t(std::lround((v.z * 0.5f + 0.5f) * 255.0f));
            nm[4 * k + 3] = 255;
        }
        GLuint normalTex =
            makeTexture(GL_RGBA8, n + 1, n + 1, GL_RGBA, GL_UNSIGNED_BYTE, nm.data(), GL_LINEAR);
        struct Variant {
            const char* name;
            const FeatureMaps* maps; // nullptr: baseline
            double goal;
        };
        double baseMs = 0.0;
        for (const Variant& v :
             {Variant{"bilinear normal map (baseline)", nullptr, 0.0},
              Variant{"(fetches only, no evaluation)", &s.lin, -1.0},
              Variant{"feature maps, linear", &s.lin, 3.0},
              Variant{"feature maps, quadratic", &s.quad, 6.0},
              Variant{"feature maps, quadratic + exact near field", &s.nearMaps, 0.0}}) {
            const sg::gl::Program& prog =
                v.maps
                    ? (v.goal < 0 ? fetchOnly
                                  : (v.maps == &s.lin ? featLinear
                                                      : (v.maps == &s.nearMaps ? featNear : feat)))
                    : base;
            GLuint tex[4] = {0, 0, 0, 0};
            glUseProgram(prog.id());
            // The normal map is sampled at uv = texelPos / N: its N+1
            // samples sit at texel corners only approximately, which does
            // not matter for cost.
            glUniform1f(prog.uniform("uMapSize"), float(n));
            glUniform2f(prog.uniform("uWindowMin"), s.windowMin.x, s.windowMin.y);
            glUniform2f(prog.uniform("uWindowSize"), s.windowSize.x, s.windowSize.y);
            if (v.maps) {
                GpuFeatureMaps g = v.maps->packGpu();
                tex[0] = makeTexture(GL_RGBA32UI, n, n + 1, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                                     g.cornerPairs.data(), GL_NEAREST);
                tex[1] = makeTexture(GL_RGBA32UI, n, n, GL_RGBA_INTEGER, GL_UNSIGNED_INT,
                                     g.edges.data(), GL_NEAREST);
                glBindTextureUnit(0, tex[0]);
                glBindTextureUnit(1, tex[1]);
                glUniform1i(prog.uniform("uFeatCorners"), 0);
                glUniform1i(prog.uniform("uFeatEdges"), 1);
                if (g.hasNearField()) {
                    tex[2] = makeTexture(GL_RGBA32UI, n, g.nearHeight, GL_RGBA_INTEGER,
                                         GL_UNSIGNED_INT, g.nearLists.data(), GL_NEAREST);
                    tex[3] =
                        makeTexture(GL_RGBA32UI, SG_FEAT_PIECES_WIDTH, g.piecesHeight,
                                    GL_RGBA_INTEGER, GL_UNSIGNED_INT, g.pieces.data(), GL_NEAREST);
                    glBindTextureUnit(2, tex[2]);
                    glBindTextureUnit(3, tex[3]);
                    glUniform1i(prog.uniform("uFeatNear"), 2);
                    glUniform1i(prog.uniform("uFeatPieces"), 3);
                }
                if (prog.uniform("uDepth") >= 0) glUniform1f(prog.uniform("uDepth"), 1.0f);
                if (prog.uniform("uWidth") >= 0) glUniform1f(prog.uniform("uWidth"), 2.0f);
            } else {
                glBindTextureUnit(0, normalTex);
                glUniform1i(prog.uniform("uNormalMap"), 0);
            }
            // Warm-up (shader compilation happens on first use in llvmpipe).
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glFinish();
            std::vector<double> perRun, perRunWall;
            for (int r = 0; r < runs; ++r) {
                std::vector<double> ts, tw;
                for (int f = 0; f < frames; ++f) {
                    auto t0 = std::chrono::steady_clock::now();
                    double c0 = processCpuMs();
                    glDrawArrays(GL_TRIANGLES, 0, 3);
                    glFinish();
                    ts.push_back(processCpuMs() - c0);
                    tw.push_back(std::chrono::duration<double, std::milli>(
                                     std::chrono::steady_clock::now() - t0)
                                     .count());
                }
                perRun.push_back(median(ts));
                perRunWall.push_back(median(tw));
            }
            double ms = median(perRun);
            double wallMs = median(perRunWall);
            if (!v.maps) baseMs = ms;
            std::string goal = v.goal > 0 ? (ms / baseMs <= v.goal ? "<= " : "> ") +
                                                std::to_string(int(v.goal)) + "x " +
                                                (ms / baseMs <= v.goal ? "met" : "MISSED")
                                          : "-";
            std::printf("| %s | %.1f%% | %s | %.2f | %.2f | %.1f | %.2fx | %s |\n", s.name.c_str(),
                        100.0 * s.fcr, v.name, ms, wallMs, ms * 1e6 / (double(size) * size),
                        ms / baseMs, goal.c_str());
            for (GLuint t : tex)
                if (t) glDeleteTextures(1, &t);
            sg::gl::checkError("features_llvmpipe_bench draw");
        }
        glDeleteTextures(1, &normalTex);
    }
    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(1, &color);
    glDeleteVertexArrays(1, &vao);
    return 0;
}
