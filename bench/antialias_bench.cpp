// Bump antialiasing against a supersampled ground truth (docs/accuracy-cost.md,
// table 8; bench/README.md, "Antialiasing"). A plane seen straight on, so
// every pixel covers the same number of texels (the minification m), lit by
// one directional light near the mirror direction, black base colour and no
// ambient: the image is the GGX highlight alone, the radiance that aliases.
//   truth    - the CPU reference renderer at 16 x 16 samples per pixel,
//              texture level 0 only (LodRule::Level0: no filtering), box
//              averaged: the radiance the pixel should show;
//   variants - the GPU at one sample per pixel with mip-mapped maps and the
//              layers' "antialias": none, Toksvig, LEAN; on the composed
//              scene also LEAN on the first layer only (what the covariance
//              sum adds over a single antialiased layer).
// Errors: RMSE and max of the pixel radiance (all channels equal), and the
// highlight energy (the image's total radiance / the truth's). Cost: frame
// time at 512 x 512 (m = 8), variants interleaved, medians of runs of
// frames, ratio to "none" in the same run.
// Usage: antialias_bench [--size W] [--runs N] [--frames N] [--image PNG] [--quick]
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "surfgrad/gl.h"
#include "surfgrad/render.h"

using namespace sg::render;

namespace {

constexpr int kSuper = 16;         // samples per pixel along each axis (truth)
constexpr double kFovDeg = 60.0;   // camera
constexpr double kHeight = 1.0;    // camera above the plane
constexpr double kPlaneSize = 1.3; // covers the view
constexpr int kMapTexels = 128;    // normal-map size

// A smooth tiling height field (sum of periodic sines, st units) written as
// a float tangent-space normal map: n = normalize(-dh/ds, -dh/dt, 1).
// `phase` varies the pattern between layers.
std::string writeSineMap(const std::string& path, double amplitude, double phase) {
    const int n = kMapTexels;
    const double tau = 6.283185307179586;
    Image img;
    img.width = img.height = n;
    img.pixels.resize(size_t(n) * size_t(n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double s = (i + 0.5) / n, t = (j + 0.5) / n;
            // h = sin(3 tau s) sin(5 tau t) + 0.5 sin(tau (7s + 4t) + phase)
            //     + 0.3 sin(tau (13s - 11t) + 2 phase), times amplitude.
            const double a = 3 * tau * s, b = 5 * tau * t;
            const double c = tau * (7 * s + 4 * t) + phase, e = tau * (13 * s - 11 * t) + 2 * phase;
            const double ds = 3 * tau * std::cos(a) * std::sin(b) + 0.5 * 7 * tau * std::cos(c) +
                              0.3 * 13 * tau * std::cos(e);
            const double dt = 5 * tau * std::sin(a) * std::cos(b) + 0.5 * 4 * tau * std::cos(c) -
                              0.3 * 11 * tau * std::cos(e);
            const glm::dvec3 m = glm::normalize(glm::dvec3(-amplitude * ds, -amplitude * dt, 1.0));
            img.pixels[size_t(j) * size_t(n) + size_t(i)] = glm::vec4(glm::vec3(m), 1.0f);
        }
    writeImage(path, img, Aov::Normal, 1.0f);
    return path;
}

struct LayerSpec {
    std::string map; // float normal-map file
    float strength;
    float scaleFactor; // of the UV tiling rate relative to the first layer
    float rotateDeg;
};

struct SceneSpec {
    const char* name;
    std::vector<LayerSpec> layers;
};

// UV repeats across the plane for a minification of m texels per pixel at
// width w: world units per pixel 2 H tan(fov/2) / w.
double uvScaleFor(double m, int w) {
    const double worldPerPixel = 2.0 * kHeight * std::tan(kFovDeg * 3.141592653589793 / 360.0) / w;
    return m * kPlaneSize / (kMapTexels * worldPerPixel);
}

// The scene at m texels per pixel of a w-pixel image, rendered at
// `renderWidth` pixels (w, or w * kSuper for the truth).
std::string sceneJson(const SceneSpec& spec, double m, int w, const std::vector<std::string>& aa,
                      int renderWidth = 0) {
    std::string layers, uvSets;
    for (size_t i = 0; i < spec.layers.size(); ++i) {
        const LayerSpec& L = spec.layers[i];
        const double s = uvScaleFor(m, w) * L.scaleFactor;
        uvSets += std::string(i ? ", " : "") + "{\"from\": 0, \"scale\": [" + std::to_string(s) +
                  ", " + std::to_string(s) + "], \"rotate_deg\": " + std::to_string(L.rotateDeg) +
                  "}";
        layers += std::string(i ? ", " : "") +
                  "{\"type\": \"uv_normal\", \"uv_set\": " + std::to_string(i + 1) +
                  ", \"strength\": " + std::to_string(L.strength) + ", \"antialias\": \"" + aa[i] +
                  "\", \"encoding\": \"float\", \"map\": {\"file\": \"" + L.map + "\"}}";
    }
    const int rw = renderWidth > 0 ? renderWidth : w;
    return R"({"output": {"width": )" + std::to_string(rw) + R"(, "height": )" +
           std::to_string(rw) +
           R"(}, "ambient": [0, 0, 0],
      "camera": {"position": [0, )" +
           std::to_string(kHeight) + R"(, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_deg": )" +
           std::to_string(kFovDeg) + R"(},
      "lights": [{"type": "directional", "direction": [-0.25, -1, -0.15], "intensity": 3}],
      "materials": [{"name": "m", "base_color": [0, 0, 0], "roughness": 0.2, "layers": [)" +
           layers + R"(]}],
      "meshes": [{"procedural": {"type": "plane", "size": )" +
           std::to_string(kPlaneSize) + R"(, "segments": 2, "uv_sets": 1},
                  "uv_sets": [)" +
           uvSets + "]}]}";
}

Scene parse(const std::string& json) {
    return parseScene(json, "antialias_bench.json", ".");
}

// The truth: 16 x 16 samples per pixel at level 0, box averaged.
Image truth(const SceneSpec& spec, double m, int w) {
    std::vector<std::string> none(spec.layers.size(), "none");
    Scene s = parse(sceneJson(spec, m, w, none, w * kSuper));
    SceneAssets a = loadAssets(s);
    View v = makeView(s, a, 0, 0, Aov::Color);
    CpuOptions o;
    o.textureLod = sg::glsl::LodRule::Level0;
    Image big = renderCpu(s, a, v, o);
    Image img;
    img.width = img.height = w;
    img.pixels.assign(size_t(w) * size_t(w), glm::vec4(0.0f));
    for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 sum(0.0);
            for (int j = 0; j < kSuper; ++j)
                for (int i = 0; i < kSuper; ++i)
                    sum += glm::dvec3(big.at(x * kSuper + i, y * kSuper + j));
            img.at(x, y) = glm::vec4(glm::vec3(sum / double(kSuper * kSuper)), 1.0f);
        }
    return img;
}

struct Errors {
    double rmse = 0, max = 0, energy = 0;
};

Errors compare(const Image& a, const Image& truth) {
    Errors e;
    double sumA = 0, sumT = 0, sq = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        const double va = a.pixels[i].y, vt = truth.pixels[i].y; // green: all channels equal
        sq += (va - vt) * (va - vt);
        e.max = std::max(e.max, std::abs(va - vt));
        sumA += va;
        sumT += vt;
    }
    e.rmse = std::sqrt(sq / double(a.pixels.size()));
    e.energy = sumT > 0 ? sumA / sumT : 0.0;
    return e;
}

struct Variant {
    const char* name;
    std::vector<std::string> aa; // per layer (the first entries used)
};

std::vector<Variant> variantsFor(const SceneSpec& spec) {
    const size_t n = spec.layers.size();
    std::vector<Variant> v = {{"no AA", std::vector<std::string>(n, "none")},
                              {"Toksvig", std::vector<std::string>(n, "toksvig")}};
    if (n > 1) {
        std::vector<std::string> first(n, "none");
        first[0] = "lean";
        v.push_back({"LEAN, first layer only", first});
    }
    v.push_back({n > 1 ? "LEAN per layer, covariances summed" : "LEAN",
                 std::vector<std::string>(n, "lean")});
    return v;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

void costTable(GlRenderer& gl, const SceneSpec& spec, int runs, int frames) {
    const int w = 512;
    std::vector<Variant> vars = variantsFor(spec);
    std::vector<Scene> scenes;
    for (const Variant& v : vars) scenes.push_back(parse(sceneJson(spec, 8.0, w, v.aa)));
    std::vector<SceneAssets> assets;
    for (const Scene& s : scenes) assets.push_back(loadAssets(s));
    std::vector<View> views;
    for (size_t i = 0; i < scenes.size(); ++i)
        views.push_back(makeView(scenes[i], assets[i], 0, 0, Aov::Color));
    for (size_t i = 0; i < scenes.size(); ++i) { // compile, upload
        gl.renderToTexture(scenes[i], assets[i], views[i]);
        glFinish();
    }
    std::vector<std::vector<double>> runMedians(vars.size());
    for (int r = 0; r < runs; ++r) {
        std::vector<std::vector<double>> t(vars.size());
        for (int f = 0; f < frames; ++f)
            for (size_t i = 0; i < vars.size(); ++i) {
                auto a = std::chrono::steady_clock::now();
                gl.renderToTexture(scenes[i], assets[i], views[i]);
                glFinish();
                t[i].push_back(
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - a)
                        .count());
            }
        for (size_t i = 0; i < vars.size(); ++i) runMedians[i].push_back(median(t[i]));
    }
    const double base = median(runMedians[0]);
    std::printf("\n#### Cost: %s, %dx%d, m = 8 (median of %d runs x %d frames)\n\n", spec.name, w,
                w, runs, frames);
    std::printf("| variant | frame ms | ratio |\n| :-- | --: | --: |\n");
    for (size_t i = 0; i < vars.size(); ++i) {
        const double ms = median(runMedians[i]);
        std::printf("| %s | %.2f | %.2fx |\n", vars[i].name, ms, ms / base);
    }
}

void accuracyTable(GlRenderer& gl, const SceneSpec& spec, int w, const std::vector<double>& ms) {
    std::vector<Variant> vars = variantsFor(spec);
    std::printf("\n#### Accuracy: %s, %dx%d pixels, truth %dx%d samples per pixel\n\n", spec.name,
                w, w, kSuper, kSuper);
    std::printf("| m | truth mean | variant | RMSE | max | energy |\n"
                "| --: | --: | :-- | --: | --: | --: |\n");
    for (double m : ms) {
        Image t = truth(spec, m, w);
        double mean = 0;
        for (const auto& p : t.pixels) mean += p.y;
        mean /= double(t.pixels.size());
        for (const Variant& v : vars) {
            Scene s = parse(sceneJson(spec, m, w, v.aa));
            SceneAssets a = loadAssets(s);
            Image img = gl.render(s, a, makeView(s, a, 0, 0, Aov::Color));
            Errors e = compare(img, t);
            std::printf("| %g | %.4f | %s | %.4f | %.3f | %.3f |\n", m, mean, v.name, e.rmse, e.max,
                        e.energy);
        }
        std::fflush(stdout);
    }
}

// no AA | LEAN through composition | truth, side by side.
void picture(GlRenderer& gl, const SceneSpec& spec, double m, int w, const std::string& path) {
    const size_t n = spec.layers.size();
    Scene sNone = parse(sceneJson(spec, m, w, std::vector<std::string>(n, "none")));
    Scene sLean = parse(sceneJson(spec, m, w, std::vector<std::string>(n, "lean")));
    SceneAssets aNone = loadAssets(sNone), aLean = loadAssets(sLean);
    Image panels[3] = {gl.render(sNone, aNone, makeView(sNone, aNone, 0, 0, Aov::Color)),
                       gl.render(sLean, aLean, makeView(sLean, aLean, 0, 0, Aov::Color)),
                       truth(spec, m, w)};
    const int gap = 4;
    Image out;
    out.width = 3 * w + 2 * gap;
    out.height = w;
    out.pixels.assign(size_t(out.width) * size_t(out.height), glm::vec4(1.0f));
    for (int k = 0; k < 3; ++k)
        for (int y = 0; y < w; ++y)
            for (int x = 0; x < w; ++x) out.at(k * (w + gap) + x, y) = panels[k].at(x, y);
    writeImage(path, out, Aov::Color, 1.0f);
    std::printf("\nwrote %s (m = %g: no AA | LEAN through composition | truth)\n", path.c_str(), m);
}

} // namespace

int main(int argc, char** argv) {
    int w = 64, runs = 7, frames = 5;
    bool quick = false;
    std::string image;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--size" && i + 1 < argc) {
            w = std::clamp(std::atoi(argv[++i]), 16, 512);
        } else if (a == "--runs" && i + 1 < argc) {
            runs = std::clamp(std::atoi(argv[++i]), 1, 100);
        } else if (a == "--frames" && i + 1 < argc) {
            frames = std::clamp(std::atoi(argv[++i]), 1, 100);
        } else if (a == "--image" && i + 1 < argc) {
            image = argv[++i];
        } else if (a == "--quick") {
            quick = true;
        } else {
            std::fprintf(stderr, "usage: antialias_bench [--size W] [--runs N] [--frames N] "
                                 "[--image PNG] [--quick]\n");
            return 2;
        }
    }
    try {
        sg::gl::HeadlessContext ctx;
        GlRenderer gl;
        std::printf("antialias_bench: renderer %s\n",
                    reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
        const std::string dir = std::filesystem::temp_directory_path().string();
        const std::string mapA = writeSineMap(dir + "/antialias_bench_a.exr", 0.012, 0.0);
        const std::string mapB = writeSineMap(dir + "/antialias_bench_b.exr", 0.008, 1.3);
        const SceneSpec tiled{"tiled normal map", {{mapA, 1.0f, 1.0f, 0.0f}}};
        const SceneSpec composed{"two maps composed (second at 1.7x the rate, turned 30 deg)",
                                 {{mapA, 1.0f, 1.0f, 0.0f}, {mapB, 1.0f, 1.7f, 30.0f}}};
        std::vector<double> ms = {1, 2, 4, 8, 16, 32, 64};
        if (quick) ms = {1, 8, 64};
        accuracyTable(gl, tiled, w, ms);
        accuracyTable(gl, composed, w, ms);
        costTable(gl, tiled, quick ? 3 : runs, quick ? 3 : frames);
        costTable(gl, composed, quick ? 3 : runs, quick ? 3 : frames);
        if (!image.empty()) picture(gl, composed, 16.0, 160, image);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "antialias_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}
