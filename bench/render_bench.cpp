// Renderer benchmarks on llvmpipe (bench/README.md, "Renderer"): frame
// times at 1280x720, medians over several frames, each frame finished with
// glFinish (llvmpipe skips draws a later opaque draw covers, so unfinished
// frames under-report: docs/platform.md). Ratios are to a baseline
// measured in the same run.
//  1. Effects on demand: a one-layer scene through its assembled program vs
//     the same scene through an uber-shader with every layer kind compiled
//     in and switched off by uniforms (goal: >= 1.5x faster).
//  2. Cost per layer kind: a sphere with no layer (prologue + resolve +
//     shading only) vs the same sphere with one layer of each kind.
//  3. Frame time of the built-in default scene and every examples/*/scene.json.
// Cases compared with each other are timed with their frames interleaved.
// GL_TIME_ELAPSED queries are not used here: llvmpipe rasterises at the
// flush, outside the query, so they read near 0 (the viewer shows them for
// real GPUs).
// Usage: render_bench [--frames N] [--width W --height H]
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "surfgrad/gl/context.h"
#include "surfgrad/render.h"

using namespace sg::render;
namespace fs = std::filesystem;

namespace {

int gFrames = 15, gWidth = 1280, gHeight = 720;

struct Timing {
    double wallMs = 0;  // median wall time of render + glFinish
    double firstMs = 0; // first frame (program compile, JIT, uploads)
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

struct Case {
    const Scene* scene;
    const SceneAssets* assets;
    bool uber;
};

double frameMs(GlRenderer& gl, const Case& c, const View& view) {
    gl.setUber(c.uber);
    auto a = std::chrono::steady_clock::now();
    gl.renderToTexture(*c.scene, *c.assets, view);
    glFinish();
    gl.setUber(false);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a).count();
}

// Times several cases with their frames interleaved (A B C A B C ...), so
// load from other processes on the machine hits every case alike.
std::vector<Timing> timeInterleaved(GlRenderer& gl, const std::vector<Case>& cases) {
    std::vector<Timing> t(cases.size());
    std::vector<View> views;
    for (size_t i = 0; i < cases.size(); ++i) {
        views.push_back(makeView(*cases[i].scene, *cases[i].assets, gWidth, gHeight, Aov::Color));
        t[i].firstMs = frameMs(gl, cases[i], views[i]);
        frameMs(gl, cases[i], views[i]); // warm: the JIT may finish lazily
    }
    std::vector<std::vector<double>> ms(cases.size());
    for (int f = 0; f < gFrames; ++f)
        for (size_t i = 0; i < cases.size(); ++i) ms[i].push_back(frameMs(gl, cases[i], views[i]));
    for (size_t i = 0; i < cases.size(); ++i) t[i].wallMs = median(ms[i]);
    return t;
}

std::string sphereScene(const std::string& layers) {
    return R"({"camera": {"position": [0, 0, 2.6], "target": [0, 0, 0], "fov_deg": 40},
      "materials": [{"name": "m", "layers": [)" +
           layers +
           R"(]}], "meshes": [{"procedural": {"type": "sphere", "size": 1, "segments": 96}}]})";
}

struct KindCase {
    const char* name;
    std::string layer;
};

std::vector<KindCase> kinds() {
    std::string data = std::string(SURFGRAD_DATA_DIR);
    return {
        {"uv_normal", R"({"type": "uv_normal", "map": {"procedural": "bricks", "size": 512}})"},
        {"uv_normal + modifiers",
         R"({"type": "uv_normal", "map": {"procedural": "bumps", "size": 512}, "height": {"channel": "a"},
           "modifiers": [{"type": "deform", "amplitude": 0.02, "frequency": 20}, {"type": "curve", "boost": 100}]})"},
        {"object_normal",
         R"({"type": "object_normal", "strength": 0.2, "map": {"procedural": "bumps", "size": 512}})"},
        {"height (3 taps)",
         R"({"type": "height", "scale": 0.01, "map": {"procedural": "bumps", "output": "height", "size": 512}})"},
        {"deriv_map",
         R"({"type": "deriv_map", "map": {"procedural": "weave", "output": "derivative", "size": 512}})"},
        {"triplanar (3 planes)",
         R"({"type": "triplanar", "scale": 2, "map": {"procedural": "tiles", "size": 512}})"},
        {"decal",
         R"({"type": "decal", "position": [0, 0, 1], "size": [1.5, 1.5, 1], "map": {"procedural": "scratches", "size": 512}})"},
        {"noise perlin",
         R"({"type": "noise", "noise": "perlin", "amplitude": 0.02, "frequency": 6})"},
        {"noise turbulence 5 oct + x^3",
         R"({"type": "noise", "noise": "turbulence", "amplitude": 0.01, "frequency": 6, "octaves": 5, "exponent": 3})"},
        {"feature curves (linear)",
         R"({"type": "feature", "curves": {"svg": ")" + data +
             R"(/svg/flame.svg", "size": 256}, "profile": "crease", "depth": 2, "width": 4})"},
        {"post_resolve (noise)",
         R"({"type": "post_resolve", "layers": [{"type": "noise", "amplitude": 0.01, "frequency": 8}]})"},
    };
}

void row(const std::string& what, const Timing& t, double baseline) {
    std::printf("| %-34s | %9.2f | %9.2f | %8.2f | %6.2fx |\n", what.c_str(), t.wallMs, baseline,
                t.firstMs, baseline > 0 ? t.wallMs / baseline : 1.0);
}

void rule() {
    std::printf("|%s|%s|%s|%s|%s|\n", std::string(36, '-').c_str(), std::string(11, '-').c_str(),
                std::string(11, '-').c_str(), std::string(10, '-').c_str(),
                std::string(9, '-').c_str());
}

} // namespace

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--frames") && i + 1 < argc)
            gFrames = std::max(3, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--width") && i + 1 < argc)
            gWidth = std::max(16, std::atoi(argv[++i]));
        else if (!std::strcmp(argv[i], "--height") && i + 1 < argc)
            gHeight = std::max(16, std::atoi(argv[++i]));
        else {
            std::fprintf(stderr, "usage: render_bench [--frames N] [--width W] [--height H]\n");
            return 2;
        }
    }
    sg::gl::HeadlessContext ctx;
    GlRenderer gl;
    std::printf("renderer benchmarks: %s, %s, %dx%d, median of %d frames (render + glFinish)\n\n",
                ctx.renderer().c_str(), ctx.version().c_str(), gWidth, gHeight, gFrames);
    const char* header = "| %-34s | %9s | %9s | %8s | %7s |\n";

    // 1. Assembled vs uber-shader.
    std::printf("## 1. One-layer scene: assembled program vs uber-shader (every kind compiled in, "
                "off by uniforms)\n\n");
    std::printf(header, "program", "frame ms", "base ms", "1st ms", "ratio");
    rule();
    {
        Scene s = parseScene(sphereScene(kinds()[0].layer), "one-layer", ".");
        SceneAssets a = loadAssets(s);
        auto t = timeInterleaved(gl, {{&s, &a, false}, {&s, &a, true}});
        row("assembled (uv_normal only)", t[0], t[0].wallMs);
        row("uber-shader (same scene)", t[1], t[0].wallMs);
        std::printf("\nassembled is %.2fx faster than the uber-shader (goal >= 1.5x)\n\n",
                    t[1].wallMs / t[0].wallMs);
    }

    // 2. Cost per layer kind, each timed interleaved with the no-layer sphere.
    std::printf("## 2. Cost per layer kind (sphere filling most of the frame; base = no layer, "
                "same run)\n\n");
    std::printf(header, "layers", "frame ms", "base ms", "1st ms", "vs base");
    rule();
    Scene s0 = parseScene(sphereScene(""), "no-layer", ".");
    SceneAssets a0 = loadAssets(s0);
    std::vector<std::string> all;
    for (const auto& k : kinds()) {
        Scene s = parseScene(sphereScene(k.layer), k.name, ".");
        SceneAssets a = loadAssets(s);
        auto t = timeInterleaved(gl, {{&s0, &a0, false}, {&s, &a, false}});
        row(k.name, t[1], t[0].wallMs);
        if (std::string(k.name).find("post_resolve") == std::string::npos) all.push_back(k.layer);
    }
    {
        std::string joined;
        for (const auto& l : all) joined += (joined.empty() ? "" : ", ") + l;
        Scene s = parseScene(
            sphereScene(joined + R"(, {"type": "post_resolve", "layers": [{"type": "noise"}]})"),
            "all", ".");
        SceneAssets a = loadAssets(s);
        auto t = timeInterleaved(gl, {{&s0, &a0, false}, {&s, &a, false}});
        row("all of the above together", t[1], t[0].wallMs);
    }

    // 3. Default scene and examples, interleaved with the default scene.
    std::printf("\n## 3. Scenes at %dx%d (base = the built-in default scene, same run)\n\n", gWidth,
                gHeight);
    std::printf(header, "scene", "frame ms", "base ms", "1st ms", "vs def.");
    rule();
    Scene def = defaultScene();
    SceneAssets defA = loadAssets(def);
    fs::path examples = fs::path(SURFGRAD_SOURCE_DIR) / "examples";
    std::vector<fs::path> scenes;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(examples, ec)) {
        if (fs::exists(e.path() / "scene.json")) scenes.push_back(e.path() / "scene.json");
    }
    std::sort(scenes.begin(), scenes.end());
    {
        auto t = timeInterleaved(gl, {{&def, &defA, false}});
        row("built-in default scene", t[0], t[0].wallMs);
    }
    for (const auto& p : scenes) {
        try {
            Scene s = loadScene(p);
            SceneAssets a = loadAssets(s);
            auto t = timeInterleaved(gl, {{&def, &defA, false}, {&s, &a, false}});
            row(p.parent_path().filename().string(), t[1], t[0].wallMs);
        } catch (const std::exception& e) {
            std::printf("| %-34s | failed: %s\n", p.parent_path().filename().string().c_str(),
                        e.what());
        }
    }
    return 0;
}
