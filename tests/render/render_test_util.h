// Helpers shared by the renderer tests: a headless GL context per process,
// scenes from JSON snippets, and GPU/CPU renders of the same view.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "surfgrad/gl/context.h"
#include "surfgrad/render.h"
#include "surfgrad/render/render_shaders.h"

namespace sg::render::test {

// One EGL surfaceless context and renderer for the whole test process.
inline GlRenderer& gpu() {
    static sg::gl::HeadlessContext ctx;
    static GlRenderer renderer;
    return renderer;
}

inline Scene sceneFromJson(const std::string& json, const std::string& name = "test.json") {
    return parseScene(json, name, SURFGRAD_SOURCE_DIR);
}

// A sphere (or any mesh JSON) with one material of the given layers.
// topExtra: more top-level fields, e.g. R"(, "camera": {...})".
inline std::string oneMaterialScene(const std::string& layersJson, const std::string& meshJson,
                                    const std::string& materialExtra = "", int w = 200, int h = 150,
                                    const std::string& topExtra = "") {
    return R"({ "output": {"width": )" + std::to_string(w) + R"(, "height": )" + std::to_string(h) +
           R"(}, "materials": [{"name": "m", )" + materialExtra + R"( "layers": [)" + layersJson +
           R"(]}], "meshes": [)" + meshJson + "]" + topExtra + "}";
}

inline const char* kSphere = R"({"procedural": {"type": "sphere", "size": 1, "segments": 48}})";

// Spot's cage (relative to the source directory, as scenes resolve it).
inline const std::string kSpotCage = "data/meshes/spot/spot_control_mesh.obj";

// Spot's cage as an adaptive mesh (isolation 3, 3 px/edge) under one
// material with `layers`; `meshFields`: further fields of the mesh, each
// with its leading comma, e.g. R"(, "tangents": ["limit"])".
inline std::string adaptiveSpotScene(const std::string& meshFields, const std::string& layers,
                                     int w, int h) {
    return oneMaterialScene(layers,
                            R"({"file": ")" + kSpotCage +
                                R"(", "subdivision": {"mode": "adaptive", "isolation": 3, )"
                                R"("pixels_per_edge": 3})" +
                                meshFields + "}",
                            "", w, h);
}

struct NormalRenders {
    Image gpuNormal, gpuPrim, cpuNormal, cpuPrim;
    VectorImageDiff diff;
};

// The CPU reference set up to reproduce the GPU (the parity comparison):
// derivatives across the pixel's 2x2 quad, as dFdxFine, and llvmpipe's fast
// log2 in the texture LOD.
inline CpuOptions gpuParityOptions() {
    CpuOptions o;
    o.derivatives = CpuDerivatives::Quad;
    o.textureLod = sg::glsl::LodRule::FastLog2;
    return o;
}

inline NormalRenders renderNormalsBoth(const Scene& scene, const SceneAssets& assets,
                                       const CpuOptions& cpu, Aov aov = Aov::Normal) {
    NormalRenders r;
    View v = makeView(scene, assets, 0, 0, aov);
    View p = v;
    p.aov = Aov::PrimId;
    r.gpuNormal = gpu().render(scene, assets, v);
    r.gpuPrim = gpu().render(scene, assets, p);
    r.cpuNormal = renderCpu(scene, assets, v, cpu);
    r.cpuPrim = renderCpu(scene, assets, p, cpu);
    r.diff = compareVectorImages(r.gpuNormal, r.cpuNormal, r.gpuPrim, r.cpuPrim);
    return r;
}

inline size_t countNonFinite(const Image& img) {
    size_t n = 0;
    for (float v : img.samples) n += !std::isfinite(v);
    return n;
}

inline size_t countCovered(const Image& prim) {
    size_t n = 0;
    for (size_t i = 0; i < prim.texelCount(); ++i) n += prim.rgba(i).x > 0.0f;
    return n;
}

} // namespace sg::render::test
