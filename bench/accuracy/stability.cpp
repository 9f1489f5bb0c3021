// Stability measurement (stability.h): the renders of a case and their
// comparison. The cases are in stability_cases.cpp, their inputs in
// stability_inputs.cpp.
#include "stability.h"

#include <algorithm>
#include <cmath>

namespace study::stability {

namespace fs = std::filesystem;
using sg::render::Aov;
using sg::render::Image;
using sg::render::Scene;

// ---------------------------------------------------------------------------
// Measurement

sg::render::CpuOptions matchedCpu() {
    sg::render::CpuOptions o;
    o.derivatives = sg::render::CpuDerivatives::Quad;
    o.textureLod = sg::glsl::LodRule::FastLog2;
    return o;
}

AngleStats compare(const Image& a, const Image& b, const Image& primA, const Image& primB,
                   float signB) {
    AngleStats s;
    if (a.width != b.width || a.height != b.height) {
        s.coverageMismatch = size_t(-1);
        return s;
    }
    std::vector<double> angles;
    for (size_t i = 0; i < a.texelCount(); ++i) {
        const float pa = primA.rgba(i).x, pb = primB.rgba(i).x;
        if (pa != pb) {
            ++s.coverageMismatch;
            continue;
        }
        if (pa <= 0.0f) continue;
        const glm::dvec3 va(a.rgba(i)), vb = double(signB) * glm::dvec3(b.rgba(i));
        ++s.compared;
        if (!std::isfinite(va.x + va.y + va.z + vb.x + vb.y + vb.z)) {
            ++s.nonFinite;
            angles.push_back(180.0);
            continue;
        }
        const double la = glm::length(va), lb = glm::length(vb);
        double deg = 180.0;
        if (la > 0.0 && lb > 0.0) {
            deg = std::atan2(glm::length(glm::cross(va, vb)), glm::dot(va, vb)) * 180.0 /
                  3.14159265358979323846;
        } else if (la == lb) {
            deg = 0.0;
        }
        angles.push_back(deg);
    }
    if (angles.empty()) return s;
    std::sort(angles.begin(), angles.end());
    auto pct = [&](double p) {
        return angles[std::min(angles.size() - 1, size_t(p * double(angles.size())))];
    };
    s.p50 = pct(0.5);
    s.p99 = pct(0.99);
    s.max = angles.back();
    return s;
}

namespace {

struct Renders {
    Image normal, prim;
};

// The AOV whose x channel says which primitive covers a pixel the same way
// in both renderers: the primitive ID, or for adaptive meshes the patch
// (the GPU's gl_PrimitiveID is the patch's; the CPU numbers its own
// tessellated triangles).
Aov maskAov(const Scene& scene) {
    for (const auto& m : scene.meshes)
        if (m.drawsPatches()) return Aov::Patch;
    return Aov::PrimId;
}

Renders renderGpu(sg::render::GlRenderer& gpu, const Scene& scene,
                  const sg::render::SceneAssets& assets, int w, int h) {
    sg::render::View v = sg::render::makeView(scene, assets, w, h, Aov::Normal);
    Renders r;
    r.normal = gpu.render(scene, assets, v);
    v.aov = maskAov(scene);
    r.prim = gpu.render(scene, assets, v);
    return r;
}

Renders renderCpu(const Scene& scene, const sg::render::SceneAssets& assets, int w, int h,
                  const sg::render::CpuOptions& options = matchedCpu()) {
    sg::render::View v = sg::render::makeView(scene, assets, w, h, Aov::Normal);
    Renders r;
    r.normal = sg::render::renderCpu(scene, assets, v, options);
    v.aov = maskAov(scene);
    r.prim = sg::render::renderCpu(scene, assets, v, options);
    return r;
}

fs::path freshDir(const fs::path& scratch, const std::string& name) {
    const fs::path d = scratch / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

} // namespace

Result run(const Case& c, sg::render::GlRenderer& gpu, const fs::path& scratch) {
    Result r;
    const fs::path d0 = freshDir(scratch, "base"), d1 = freshDir(scratch, "perturbed");
    const Scene s0 = c.build(false, d0), s1 = c.build(true, d1);
    const sg::render::SceneAssets a0 = sg::render::loadAssets(s0), a1 = sg::render::loadAssets(s1);
    const Renders g0 = renderGpu(gpu, s0, a0, c.width, c.height);
    const Renders g1 = renderGpu(gpu, s1, a1, c.width, c.height);
    const Renders c0 = renderCpu(s0, a0, c.width, c.height);
    const Renders c1 = renderCpu(s1, a1, c.width, c.height);
    r.perturbedGpu = compare(g0.normal, g1.normal, g0.prim, g1.prim);
    r.perturbedCpu = compare(c0.normal, c1.normal, c0.prim, c1.prim);
    r.gpuVsCpu = compare(g0.normal, c0.normal, g0.prim, c0.prim);
    if (c.withDefaultCpu) {
        const Renders ref = renderCpu(s0, a0, c.width, c.height, sg::render::CpuOptions{});
        r.gpuVsDefaultCpu = compare(g0.normal, ref.normal, g0.prim, ref.prim);
    }
    if (c.expected) {
        const fs::path de = freshDir(scratch, "expected");
        const Scene se = c.expected(de);
        const sg::render::SceneAssets ae = sg::render::loadAssets(se);
        const Renders ge = renderGpu(gpu, se, ae, c.width, c.height);
        r.expected = compare(g0.normal, ge.normal, g0.prim, ge.prim, c.expectSign);
    }
    return r;
}

void dumpImages(const Case& c, sg::render::GlRenderer& gpu, const fs::path& scratch,
                const fs::path& dir) {
    fs::create_directories(dir);
    std::string stem = c.id;
    std::replace(stem.begin(), stem.end(), '/', '_');
    for (bool p : {false, true}) {
        const fs::path d = freshDir(scratch, p ? "perturbed" : "base");
        const Scene s = c.build(p, d);
        const sg::render::SceneAssets a = sg::render::loadAssets(s);
        const std::string suffix = p ? "_perturbed.exr" : ".exr";
        sg::render::writeImage(dir / (stem + "_gpu" + suffix),
                               renderGpu(gpu, s, a, c.width, c.height).normal, Aov::Normal, 1.0f);
        sg::render::writeImage(dir / (stem + "_cpu" + suffix),
                               renderCpu(s, a, c.width, c.height).normal, Aov::Normal, 1.0f);
    }
}

} // namespace study::stability
