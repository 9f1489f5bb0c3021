// Table 10: antialiased feature curves, the continuous switch from the exact
// evaluator (Parilov, Zorin TOG 2008) to the prefiltered slope chain (LEAN,
// Olano and Baker 2010) of shaders/sg/render/layer_feature_aa.glsl.
//  a. Error vs footprint: the flame outline baked at 256^2 (crease profile,
//     depth 1.5, width 3 texels) on a plane facing the camera, lit by a
//     directional light so the creases' flanks carry highlights (GGX,
//     roughness 0.2). Each "pixel" is a square footprint of rho x rho
//     texels centred on one of 48 x 48 points spread over the map; its
//     truth is the mean radiance of 16 x 16 exact samples in it (the
//     exact evaluator, unwidened lobe: what a 16 x 16 supersampled render
//     at LOD 0 without the chain gives). Methods: "none" (today's layer:
//     the exact sample at the centre) and "lean" (the switch, the lobe
//     widened by the covariance, sgAaRoughness), both through the shared
//     functions' C++ build, the shading of sg/render/shading.glsl.
//  b. No popping: the same points under a slowly receding camera
//     (footprint 0.25 .. 64 texels in steps of 2^(1/16)); the largest
//     per-point radiance change between consecutive footprints, lean and
//     truth.
//  c. Cost: a plane with the layer through the renderer, "lean" vs "none"
//     in the same run (frames interleaved), magnified (exact branch plus
//     the blend's bookkeeping) and minified (the chain alone).
#include <algorithm>
#include <cmath>
#include <string>

#include "layers/feature_assets.h"
#include "render_internal.h"
#include "surfgrad/features/curves.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/render.h"
#include "surfgrad/render/render_shaders.h"
#include "tables.h"

namespace study {

namespace {

namespace G = sg::glsl;
namespace F = sg::features;
using sg::render::TextureImage;

constexpr int kMapSize = 256;
constexpr float kRoughness = 0.2f;

struct Setup {
    sg::render::FeatureMapsAsset maps;
    TextureImage chainA, chainB;
    G::SgFeatProfile profile;
};

Setup makeSetup() {
    Setup s;
    F::CurveNetwork net = F::loadSvg(std::string(SURFGRAD_DATA_DIR) + "/svg/flame.svg");
    F::BakeOptions o;
    o.size = kMapSize;
    const F::FeatureMaps m = F::bake(net, o);
    s.maps.gpu = m.packGpu();
    s.maps.bandTexels = m.bandTexels;
    sg::render::FeatureChainSource c;
    c.profile = "crease";
    c.depth = 1.5f;
    c.w0 = 0.0f;
    c.width = 3.0f;
    c.part = 0;
    sg::render::detail::FeatureChainTextures chain =
        sg::render::detail::featureChainTextures(s.maps, c);
    s.chainA = std::move(chain.part[0]);
    s.chainB = std::move(chain.part[1]);
    s.profile = F::makeProfile("crease", 1.5f, 0.0f, 3.0f);
    return s;
}

// Radiance of a surface gradient on the plane z = 0 facing the camera
// (frame: vT = x, vB = y, normal z), widened by slope covariance cov.
float radiance(glm::vec3 surfGrad, const glm::mat3& cov) {
    const glm::vec3 n = glm::normalize(glm::vec3(0.0f, 0.0f, 1.0f) - surfGrad);
    const glm::vec3 l = glm::normalize(glm::vec3(0.35f, 0.25f, 1.0f));
    const float rough = G::sgAaRoughness(kRoughness, cov);
    const glm::vec3 c = G::sgShadeLight(n, glm::vec3(0.0f, 0.0f, -4.0f), glm::vec4(l, 0.0f),
                                        glm::vec4(3.0f, 3.0f, 3.0f, 0.0f), glm::vec3(0.5f), rough);
    return c.x;
}

// The layer at texel position pos with an isotropic footprint of rho
// texels (lean: the switch; otherwise the exact sample).
float layerRadiance(const Setup& s, glm::vec2 pos, float rho, bool lean) {
    G::SgUvFrame uv;
    uv.st = pos / float(kMapSize);
    uv.dSTdx = glm::vec2(rho / float(kMapSize), 0.0f);
    uv.dSTdy = glm::vec2(0.0f, rho / float(kMapSize));
    uv.vT = glm::vec3(1.0f, 0.0f, 0.0f);
    uv.vB = glm::vec3(0.0f, 1.0f, 0.0f);
    G::SgFeatureLayerParams p{};
    p.strength = 1.0f;
    p.mapSize = float(kMapSize);
    p.tiling = 1.0f;
    G::SgFeatureAaParams aa{lean};
    G::sampler2D a{&s.chainA}, b{&s.chainB};
    glm::mat3 cov(0.0f);
    const glm::vec3 g = G::sgLayerFeatureAa(uv, p, aa, s.profile, s.maps.gpu.cornerSampler(),
                                            s.maps.gpu.edgeSampler(), a, a, b, cov);
    return radiance(g, cov);
}

float truthRadiance(const Setup& s, glm::vec2 pos, float rho, int sub) {
    double sum = 0.0;
    for (int j = 0; j < sub; ++j)
        for (int i = 0; i < sub; ++i) {
            glm::vec2 q = pos + rho * (glm::vec2((i + 0.5f) / sub, (j + 0.5f) / sub) - 0.5f);
            sum += layerRadiance(s, q, 0.0f, false);
        }
    return float(sum / double(sub * sub));
}

std::vector<glm::vec2> points(int k) {
    std::vector<glm::vec2> p;
    for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i)
            p.push_back(
                glm::vec2((i + 0.5f) * kMapSize / k + 0.137f, (j + 0.5f) * kMapSize / k + 0.291f));
    return p;
}

std::vector<double> costs(const Options& o) {
    using namespace sg::render;
    auto scene = [](const std::string& aa) {
        return parseScene(
            R"({"camera": {"position": [0, 2.2, 0.0001], "target": [0, 0, 0], "fov_deg": 50},
                "materials": [{"name": "m", "roughness": 0.2, "layers": [
                  {"type": "feature", "curves": {"svg": "data:svg/flame.svg", "size": 256},
                   "profile": "crease", "depth": 1.5, "width": 3, "antialias": ")" +
                aa +
                R"("}]}],
                "meshes": [{"procedural": {"type": "plane", "size": 2, "segments": 4}}]})",
            "feature-aa-bench.json", ".");
    };
    std::vector<Scene> scenes = {scene("none"), scene("lean")};
    std::vector<SceneAssets> assets;
    for (const auto& s : scenes) assets.push_back(loadAssets(s));
    // Magnified: the plane spans about o.size pixels for 256 texels; minified: 8x fewer.
    const int big = o.size, small = std::max(32, o.size / 8);
    std::vector<View> views;
    for (int size : {big, small})
        for (size_t i = 0; i < 2; ++i)
            views.push_back(makeView(scenes[i], assets[i], size, size, Aov::Color));
    GlRenderer gl;
    return timeVariants(
        4, [&](size_t v) { gl.renderToTexture(scenes[v % 2], assets[v % 2], views[v]); }, o);
}

// The largest per-footprint radiance change of lean between consecutive
// footprints rho / step and rho over the sweep 0.25..64 texels: where, and
// the largest inside the switch (1..2 texels).
struct Sweep {
    double worst = 0.0, worstRho = 0.0, worstSwitch = 0.0;
};

Sweep sweep(const Setup& s, const std::vector<glm::vec2>& pts, float step) {
    Sweep w;
    for (float rho = 0.25f * step; rho <= 64.0f; rho *= step) {
        double m = 0.0;
        for (glm::vec2 p : pts)
            m = std::max(m, double(std::abs(layerRadiance(s, p, rho, true) -
                                            layerRadiance(s, p, rho / step, true))));
        if (m > w.worst) {
            w.worst = m;
            w.worstRho = rho;
        }
        if (rho > 0.99f && rho < 2.1f) w.worstSwitch = std::max(w.worstSwitch, m);
    }
    return w;
}

} // namespace

void tableFeatureAa(const Options& o) {
    const Setup s = makeSetup();
    const int k = o.quick ? 16 : 48, sub = o.quick ? 8 : 16;
    const std::vector<glm::vec2> pts = points(k);
    const float fine = std::exp2(1.0f / 16.0f);

    Table t;
    t.title = "Table 10a: feature curves antialiased, radiance error vs footprint (flame " +
              std::to_string(kMapSize) + "^2, crease 1.5 deep, 3 wide; " + std::to_string(k) +
              "^2 footprints, truth " + std::to_string(sub) + "x" + std::to_string(sub) +
              " exact samples)";
    t.header = {"texels/px", "chain w",     "none RMSE", "none max",  "lean RMSE",
                "lean max",  "lean energy", "jump lean", "jump truth"};
    const float rhos[] = {0.25f, 0.5f, 0.71f, 0.84f, 0.92f, 1.0f,  1.09f, 1.19f, 1.41f,
                          1.68f, 2.0f, 2.83f, 4.0f,  8.0f,  16.0f, 32.0f, 64.0f};
    for (float rho : rhos) {
        double seNone = 0, seLean = 0, maxNone = 0, maxLean = 0, eLean = 0, eTruth = 0;
        double jumpLean = 0, jumpTruth = 0;
        for (glm::vec2 p : pts) {
            const float truth = truthRadiance(s, p, rho, sub);
            const float none = layerRadiance(s, p, rho, false);
            const float lean = layerRadiance(s, p, rho, true);
            seNone += double(none - truth) * double(none - truth);
            seLean += double(lean - truth) * double(lean - truth);
            maxNone = std::max(maxNone, double(std::abs(none - truth)));
            maxLean = std::max(maxLean, double(std::abs(lean - truth)));
            eLean += lean;
            eTruth += truth;
            // One step of the receding camera before this footprint.
            jumpLean =
                std::max(jumpLean, double(std::abs(lean - layerRadiance(s, p, rho / fine, true))));
            jumpTruth =
                std::max(jumpTruth, double(std::abs(truth - truthRadiance(s, p, rho / fine, sub))));
        }
        const double n = double(pts.size());
        t.add({fmt(rho, 2), fmt(G::sgFeatAaChainWeight(rho), 3), fmtErr(std::sqrt(seNone / n)),
               fmtErr(maxNone), fmtErr(std::sqrt(seLean / n)), fmtErr(maxLean),
               fmt(eLean / std::max(eTruth, 1e-30), 3), fmtErr(jumpLean), fmtErr(jumpTruth)});
    }
    const Sweep coarse = sweep(s, pts, fine), dense = sweep(s, pts, std::exp2(1.0f / 64.0f));
    t.plot.id = "feature-aa";
    t.plot.xColumn = 0;
    t.plot.yColumn = 4;
    t.plot.logX = true;
    t.plot.labelColumns = {0};
    t.notes.push_back(
        "Radiance of one directional light (3, 3, 3) and a 0.5 grey base. chain w: "
        "the weight of the chain's mean (0 up to 1 texel, 1 from 2; the chain's covariance enters "
        "from 1/8 texel, scaled by the footprint's area below 1). lean energy: mean lean "
        "radiance / mean truth.");
    t.notes.push_back("jump: largest per-footprint radiance change from the previous step of a "
                      "receding camera (footprint / 2^(1/16)). Whole sweep 0.25..64 texels, "
                      "lean: largest step " +
                      fmtErr(coarse.worst) + " at " + fmt(coarse.worstRho, 2) +
                      " texels; across the switch (1..2 texels): " + fmtErr(coarse.worstSwitch) +
                      ". With steps of 2^(1/64) (4x finer): largest " + fmtErr(dense.worst) +
                      " at " + fmt(dense.worstRho, 2) + " texels, across the switch " +
                      fmtErr(dense.worstSwitch) +
                      " (a discontinuity would keep its size as the step shrinks; a continuous "
                      "change shrinks with it).");
    t.print(o);

    const std::vector<double> ms = costs(o);
    Table c;
    c.title = "Table 10b: feature-curve antialiasing cost (plane, flame 256^2, renderer)";
    c.header = {"view", "texels/px", "none ms", "lean ms", "lean / none"};
    const int small = std::max(32, o.size / 8);
    c.add({std::to_string(o.size) + "^2", fmt(256.0 / (0.83 * o.size), 2), fmt(ms[0], 2),
           fmt(ms[1], 2), fmtRatio(ms[1] / ms[0])});
    c.add({std::to_string(small) + "^2", fmt(256.0 / (0.83 * small), 2), fmt(ms[2], 2),
           fmt(ms[3], 2), fmtRatio(ms[3] / ms[2])});
    c.notes.push_back("texels/px: approximate (the plane spans about 83% of the view). Frames "
                      "interleaved; median over runs of the per-run median; renderer " +
                      o.renderer + ".");
    c.print(o);
}

} // namespace study
