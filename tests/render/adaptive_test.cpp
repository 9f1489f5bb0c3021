// Adaptive subdivision in the renderer ("subdivision": {"mode": "adaptive"}):
// the scene field's validation, effects on demand (only adaptive meshes get
// the tessellation stages; every other program is the triangle program it
// was), and the GPU's tessellated draw of the limit surface against the
// uniform path's limit surface on the same view.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "gpu_stencils.h"
#include "hardcase.h"
#include "render_internal.h"
#include "render_test_util.h"
#include "cli.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/mesh/mesh_io.h"

namespace sg::render::test {
namespace {

std::string cageScene(const std::string& subdivision, const std::string& file,
                      const std::string& layers = "", int w = 240, int h = 180) {
    return oneMaterialScene(
        layers, R"({"file": ")" + file + R"(", "subdivision": )" + subdivision + "}", "", w, h);
}

std::string parseError(const std::string& json) {
    try {
        sceneFromJson(json);
    } catch (const sg::io::InputError& e) {
        return e.what();
    }
    return "";
}

TEST(AdaptiveScene, ParsesModeIsolationAndPixelsPerEdge) {
    Scene s = sceneFromJson(
        cageScene(R"({"mode": "adaptive", "isolation": 4, "pixels_per_edge": 3.5})", kSpotCage));
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_TRUE(s.meshes[0].subdivide);
    EXPECT_TRUE(s.meshes[0].subdivAdaptive);
    EXPECT_EQ(s.meshes[0].subdivIsolation, 4);
    EXPECT_FLOAT_EQ(s.meshes[0].subdivPixelsPerEdge, 3.5f);
    Scene u = sceneFromJson(cageScene(R"({"level": 2})", kSpotCage));
    EXPECT_FALSE(u.meshes[0].subdivAdaptive); // "uniform" is the default
}

TEST(AdaptiveScene, InvalidValuesNameTheField) {
    struct Case {
        const char* subdivision;
        const char* field;
    };
    const Case cases[] = {
        {R"({"mode": "screen"})", "meshes[0].subdivision.mode"},
        {R"({"mode": 1})", "meshes[0].subdivision.mode"},
        {R"({"mode": "adaptive", "isolation": 0})", "meshes[0].subdivision.isolation"},
        {R"({"mode": "adaptive", "isolation": 11})", "meshes[0].subdivision.isolation"},
        {R"({"mode": "adaptive", "isolation": 2.5})", "meshes[0].subdivision.isolation"},
        {R"({"mode": "adaptive", "pixels_per_edge": 0})", "meshes[0].subdivision.pixels_per_edge"},
        {R"({"mode": "adaptive", "pixels_per_edge": -2})", "meshes[0].subdivision.pixels_per_edge"},
        {R"({"mode": "adaptive", "pixels_per_edge": "8"})",
         "meshes[0].subdivision.pixels_per_edge"},
        // Each mode's own fields only.
        {R"({"mode": "adaptive", "level": 2})", "meshes[0].subdivision.level"},
        {R"({"mode": "adaptive", "limit": true})", "meshes[0].subdivision.limit"},
        {R"({"isolation": 2})", "meshes[0].subdivision.isolation"},
        {R"({"mode": "uniform", "pixels_per_edge": 4})", "meshes[0].subdivision.pixels_per_edge"},
        // Patches are Catmull-Clark only.
        {R"({"mode": "adaptive", "scheme": "loop"})", "meshes[0].subdivision.scheme"},
    };
    for (const Case& c : cases) {
        const std::string err = parseError(cageScene(c.subdivision, kSpotCage));
        EXPECT_NE(err.find(c.field), std::string::npos) << c.subdivision << " -> " << err;
    }
}

TEST(AdaptiveScene, UnsupportedRequestsAreClearErrors) {
    // MikkTSpace tangents: the patches have no vertex list ("limit" ones
    // come from the patch derivatives: adaptive_tangents_test.cpp).
    for (const char* tangents : {R"(["mikktspace"])", R"(["pixel", "mikktspace"])"}) {
        std::string err;
        try {
            Scene s = sceneFromJson(
                R"({"materials": [{"name": "m"}], "meshes": [{"file": ")" + kSpotCage +
                R"(", "subdivision": {"mode": "adaptive"}, "uv_sets": [{"from": 0}], "tangents": )" +
                tangents + "}]}");
            loadAssets(s);
        } catch (const sg::io::InputError& e) {
            err = e.what();
        }
        EXPECT_NE(err.find("meshes[0].tangents"), std::string::npos) << tangents << ": " << err;
    }
    // A derived set from a set the mesh does not have names its field.
    Scene d =
        sceneFromJson(R"({"materials": [{"name": "m"}], "meshes": [{"file": ")" + kSpotCage +
                      R"(", "subdivision": {"mode": "adaptive"}, "uv_sets": [{"from": 3}]}]})");
    try {
        loadAssets(d);
        ADD_FAILURE() << "no error";
    } catch (const sg::io::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("meshes[0].uv_sets[0].from"), std::string::npos)
            << e.what();
    }
}

// UV sets on adaptive patches: the cage's set and a derived one (affine
// map of the face-varying values: every basis sums to one), planned and
// assembled like a triangle mesh's (SG_UV_COUNT in the evaluation stage).
TEST(AdaptiveUv, CageAndDerivedSetsReachThePlan) {
    Scene s = sceneFromJson(
        R"({"materials": [{"name": "m", "layers": [{"type": "uv_normal", "uv_set": 1,
              "map": {"procedural": "bricks", "size": 64}}]}],
            "meshes": [{"file": ")" +
        kSpotCage + R"(", "subdivision": {"mode": "adaptive", "isolation": 2},
              "uv_sets": [{"from": 0, "scale": [12, 6], "rotate_deg": 30, "offset": [0.5, 0.25]}]}]})");
    SceneAssets a = loadAssets(s);
    const auto& ap = *a.meshes[0].patches;
    ASSERT_EQ(ap.uvSets.size(), 2u);
    const float r = glm::radians(30.0f);
    const glm::mat2 lin =
        glm::mat2(std::cos(r), std::sin(r), -std::sin(r), std::cos(r)) * glm::mat2(12, 0, 0, 6);
    ASSERT_EQ(ap.uvSets[1].values.size(), ap.uvSets[0].values.size());
    // Read by a repeating map only: stored moved by the whole units of its
    // centre (uv_sets.cpp), the same shift for every value; computed in
    // binary64 and rounded once (values up to ~15: 2e-6).
    const glm::vec2 shift =
        glm::round(lin * ap.uvSets[0].values[0] + glm::vec2(0.5f, 0.25f) - ap.uvSets[1].values[0]);
    for (size_t i = 0; i < ap.uvSets[0].values.size(); ++i) {
        const glm::vec2 want = lin * ap.uvSets[0].values[i] + glm::vec2(0.5f, 0.25f) - shift;
        ASSERT_LT(glm::length(ap.uvSets[1].values[i] - want), 2e-6f) << i;
    }
    EXPECT_EQ(ap.uvSets[1].indices, ap.uvSets[0].indices);
    MaterialPlan p = planMaterial(s, a, 0, 0);
    EXPECT_EQ(p.uvCount, 2);
    ProgramSource src = assembleProgram(p);
    EXPECT_NE(src.tessEval.find("out vec2 vUv1"), std::string::npos);
    EXPECT_NE(src.fragment.find("in vec2 vUv1"), std::string::npos);
    // Without UV sets the evaluation stage is the one it was (its UV code
    // is preprocessed out: SG_UV_COUNT is not defined).
    Scene n = sceneFromJson(
        cageScene(R"({"mode": "adaptive", "isolation": 2})", "data/osd-shapes/catmark_pole8.obj"));
    SceneAssets na = loadAssets(n);
    ASSERT_TRUE(na.meshes[0].patches->uvSets.empty());
    const std::string head = "#version 450 core\n";
    EXPECT_NE(assembleProgram(planMaterial(n, na, 0, 0)).tessEval.rfind(head + "#define", 0), 0u);
    EXPECT_EQ(src.tessEval.rfind(head + "#define SG_UV_COUNT 2\n", 0), 0u);
}

// Non-manifold cages (three quads on one edge; OpenSubdiv's regression
// shape with vertices of two fans) are refused for adaptive patches as for
// the uniform path: an InputError naming the file and the element, no
// patches, no fallback.
TEST(AdaptiveScene, NonManifoldCagesAreClearErrors) {
    const std::filesystem::path dir = std::filesystem::path(SURFGRAD_BINARY_DIR) / "tests/render";
    std::filesystem::create_directories(dir);
    const std::filesystem::path fin = dir / "adaptive_fin.obj";
    std::ofstream(fin) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 -1 0\nv 0 -1 0\n"
                          "v 1 0 1\nv 0 0 1\nf 1 2 3 4\nf 2 1 6 5\nf 1 2 7 8\n";
    for (const std::string& file :
         {fin.string(), std::string("data/osd-shapes/catmark_nonman_verts.obj")}) {
        std::string err;
        try {
            Scene s = sceneFromJson(R"({"materials": [{"name": "m"}], "meshes": [{"file": ")" +
                                    file + R"(", "subdivision": {"mode": "adaptive"}}]})");
            loadAssets(s);
        } catch (const sg::io::InputError& e) {
            err = e.what();
        }
        const std::string name = std::filesystem::path(file).filename().string();
        EXPECT_NE(err.find(name), std::string::npos) << file << ": " << err;
        EXPECT_NE(err.find("non-manifold"), std::string::npos) << file << ": " << err;
    }
}

TEST(AdaptiveScene, OnlyAdaptiveMeshesGetTessellationStages) {
    Scene s = sceneFromJson(
        R"({"materials": [{"name": "m"}], "meshes": [
            {"file": ")" +
        kSpotCage + R"(", "subdivision": {"mode": "adaptive", "isolation": 2}},
            {"file": ")" +
        kSpotCage + R"(", "subdivision": {"level": 1}},
            {"procedural": {"type": "sphere"}}]})");
    SceneAssets a = loadAssets(s);
    ASSERT_TRUE(a.meshes[0].patches);
    EXPECT_FALSE(a.meshes[1].patches);
    EXPECT_FALSE(a.meshes[2].patches);
    EXPECT_GT(a.meshes[0].patches->patchCount(), 0u);
    EXPECT_EQ(a.meshes[0].mesh.triangleCount(), 0u);
    for (int i = 0; i < 3; ++i) {
        MaterialPlan p = planMaterial(s, a, i, 0);
        ProgramSource src = assembleProgram(p);
        const bool adaptive = i == 0;
        EXPECT_EQ(p.adaptive, adaptive);
        EXPECT_EQ(p.signature.find(":patches") != std::string::npos, adaptive) << p.signature;
        EXPECT_EQ(src.tessEval.empty(), !adaptive);
        EXPECT_EQ(src.vertex.find("SgPatchPoints") != std::string::npos, adaptive);
        EXPECT_EQ(src.vertex.find("aPosition") != std::string::npos, !adaptive);
    }
    // The fragment program does not depend on the vertex stages: the
    // adaptive plan's is the one the same plan draws triangles with.
    MaterialPlan pa = planMaterial(s, a, 0, 0);
    MaterialPlan pu = pa;
    pu.adaptive = false;
    // Only the patch AOV's input and output line differ.
    std::string fa = assembleProgram(pa).fragment, fu = assembleProgram(pu).fragment;
    EXPECT_NE(fa.find("vPatchAov"), std::string::npos);
    EXPECT_EQ(fu.find("vPatchAov"), std::string::npos);
    for (const char* line : {"#define SG_AOV_PATCH 8\n",
                             "flat in vec4 vPatchAov; // patch AOV (sg/patch/patch_tes.glsl)\n",
                             "    if (uAov == SG_AOV_PATCH) outValue = vPatchAov;\n"}) {
        const size_t at = fa.find(line);
        ASSERT_NE(at, std::string::npos) << line;
        fa.erase(at, std::string(line).size());
    }
    // #line directives count the removed lines: compare without them.
    auto noLines = [](const std::string& t) {
        std::string r;
        size_t i = 0;
        while (i < t.size()) {
            size_t e = t.find('\n', i);
            if (e == std::string::npos) e = t.size();
            if (t.compare(i, 5, "#line") != 0) r += t.substr(i, e - i + 1);
            i = e + 1;
        }
        return r;
    };
    EXPECT_EQ(noLines(fa), noLines(fu));
}

// Angles (degrees) between two normal AOV images at pixels both cover.
struct NormalAgreement {
    size_t both = 0, onlyOne = 0, nonFinite = 0;
    double p50 = 0, p99 = 0, p999 = 0, max = 0;
};

NormalAgreement compareNormals(const Image& a, const Image& b) {
    NormalAgreement r;
    std::vector<double> deg;
    for (size_t i = 0; i < a.texelCount(); ++i) {
        const glm::vec3 na(a.rgba(i)), nb(b.rgba(i));
        for (int c = 0; c < 3; ++c) r.nonFinite += !std::isfinite(na[c]) || !std::isfinite(nb[c]);
        const bool ca = glm::length(na) > 0.5f, cb = glm::length(nb) > 0.5f;
        if (ca != cb) ++r.onlyOne;
        if (!ca || !cb) continue;
        ++r.both;
        const double c =
            std::clamp(double(glm::dot(glm::normalize(na), glm::normalize(nb))), -1.0, 1.0);
        deg.push_back(std::acos(c) * 180.0 / M_PI);
    }
    std::sort(deg.begin(), deg.end());
    if (!deg.empty()) {
        r.p50 = deg[deg.size() / 2];
        r.p99 = deg[std::min(deg.size() - 1, size_t(0.99 * double(deg.size())))];
        r.p999 = deg[std::min(deg.size() - 1, size_t(0.999 * double(deg.size())))];
        r.max = deg.back();
    }
    return r;
}

// The normal AOV of view `v` of `s` on the GPU and in the CPU reference
// (quad derivatives: llvmpipe's dFdxFine), compared and printed under
// `label`; `gpuImage` receives the GPU's image.
NormalAgreement gpuVsCpuNormals(const Scene& s, const SceneAssets& a, const View& v,
                                const char* label, Image* gpuImage = nullptr) {
    CpuOptions cpu;
    cpu.derivatives = CpuDerivatives::Quad;
    cpu.textureLod = sg::glsl::LodRule::FastLog2;
    const Image g = gpu().render(s, a, v);
    const NormalAgreement r = compareNormals(g, renderCpu(s, a, v, cpu));
    std::printf("%s GPU vs CPU: %zu px both, %zu one only, p50 %.3f p99 %.3f p99.9 %.3f max %.3f "
                "deg\n",
                label, r.both, r.onlyOne, r.p50, r.p99, r.p999, r.max);
    if (gpuImage) *gpuImage = g;
    return r;
}

// What every GPU-vs-CPU parity test of adaptive patches asserts (the
// reasons at GpuMatchesCpuReference): more than `minBoth` pixels covered
// in both images, none non-finite, coverage differing on at most 0.1% of
// them, median and 99th percentile 0.05 degrees (the triangle path's
// parity bound), 99.9th percentile 1 degree (isolated pixels under a
// normal map: GpuMatchesCpuWithAUvNormalLayer), and every pixel `maxDeg`.
void expectParity(const NormalAgreement& r, size_t minBoth, double maxDeg) {
    EXPECT_GT(r.both, minBoth);
    EXPECT_EQ(r.nonFinite, 0u);
    EXPECT_LE(double(r.onlyOne), 0.001 * double(r.both));
    EXPECT_LE(r.p50, 0.05);
    EXPECT_LE(r.p99, 0.05);
    EXPECT_LE(r.p999, 1.0);
    EXPECT_LE(r.max, maxDeg);
}

// expectParity's bound on every pixel of an untextured normal AOV: 0.1
// degrees (GpuMatchesCpuReference).
constexpr double kUntexturedMaxDeg = 0.1;
// ... and of one with a tangent-space normal map: none (isolated pixels,
// the map amplifying the rounding of the UVs' screen derivatives:
// GpuMatchesCpuWithAUvNormalLayer).
constexpr double kMappedMaxDeg = 180.0;

// The tessellated limit surface against the uniform path's limit surface
// (level 4, limit positions and normals) of the spot cage on the same view
// (the camera framed from the uniform mesh's bounds). Both interpolate
// limit normals linearly across their triangles; the adaptive triangles
// are at most 2 pixels per edge here, the uniform level-4 ones about 2-4,
// so the normals differ by the curvature over a few pixels: bounds median
// 1 degree, 99th percentile 6 degrees (measured 0.034 and 1.8). Coverage
// may differ at the silhouette only (a limit surface against two
// piecewise-linear approximations of it): at most 2% of the covered pixels
// (measured 0.12%).
TEST(AdaptiveDraw, MatchesTheUniformLimitSurface) {
    const int w = 320, h = 240;
    Scene su = sceneFromJson(cageScene(R"({"level": 4, "limit": true})", kSpotCage, "", w, h));
    Scene sa = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 2})", kSpotCage, "", w, h));
    SceneAssets au = loadAssets(su), aa = loadAssets(sa);
    View v = makeView(su, au, 0, 0, Aov::Normal);
    Image iu = gpu().render(su, au, v);
    Image ia = gpu().render(sa, aa, v);
    const RenderStats stats = gpu().stats();
    // One draw per patch type, split into draws of patchesPerDraw patches
    // on llvmpipe (the tests' context; render_internal.h).
    const uint32_t perDraw = detail::patchesPerDraw(true);
    int draws = 0;
    for (const auto& arr : aa.meshes[0].patches->arrays)
        draws += int((arr.patchCount + perDraw - 1) / perDraw);
    EXPECT_EQ(stats.drawCalls, draws);
    NormalAgreement r = compareNormals(ia, iu);
    std::printf("adaptive vs uniform level 4: %zu px both, %zu one only, p50 %.3f p99 %.3f deg\n",
                r.both, r.onlyOne, r.p50, r.p99);
    EXPECT_GT(r.both, size_t(w * h / 10)); // the cow fills a good part of the view
    EXPECT_EQ(r.nonFinite, 0u);
    EXPECT_LE(double(r.onlyOne), 0.02 * double(r.both));
    EXPECT_LE(r.p50, 1.0);
    EXPECT_LE(r.p99, 6.0);
    // Colour: finite everywhere.
    Image c = gpu().render(sa, aa, makeView(su, au, 0, 0, Aov::Color));
    EXPECT_EQ(countNonFinite(c), 0u);
}

// GPU vs CPU reference on adaptive patches. The CPU tessellates every patch
// at the levels the GPU's control stage computes (the shared
// sgPatchEdgeTessLevel, same corner vertices) into llvmpipe's own domain
// points and triangles (src/patch_tessellation.cpp; patch_gpu_test.cpp's
// QuadDomainGpu checks both against llvmpipe's) and evaluates the points
// with the shared basis, so both draw the same triangles with vertices
// equal to float rounding (a few ulp, patch_gpu_test.cpp), and the CPU
// reference emulates llvmpipe's derivatives and texture LOD. The bounds
// are then the triangle path's parity bound (image_test.cpp: 0.05
// degrees): median and 99th percentile 0.05 degrees, every pixel 0.1
// (measured 0.000, 0.020 and 0.028; 0.020 is the angle between two float
// unit vectors whose dot product is one ulp below 1); coverage differs only
// where a silhouette pixel's centre lies within rounding of an edge: at
// most 0.1% of the covered pixels (measured 1 of 9621). With a
// triangulation of its own (the ring between the outer edges and the inner
// grid zipped by position, the grid split along one diagonal: same points,
// other diagonals) the CPU measured p99 0.68 and max 9.9 degrees here: two
// piecewise-linear surfaces sharing every vertex differ inside cells of 3
// pixels by the surface's and the interpolated normal's second difference
// across them, largest where the curvature is (ears, horns, hooves). That
// is what a GPU whose tessellator triangulates otherwise shows against
// this reference (docs/platform.md).
TEST(AdaptiveDraw, GpuMatchesCpuReference) {
    const int w = 320, h = 240;
    Scene s = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 3})", kSpotCage, "", w, h));
    SceneAssets a = loadAssets(s);
    const NormalAgreement r = gpuVsCpuNormals(s, a, makeView(s, a, 0, 0, Aov::Normal), "adaptive");
    expectParity(r, size_t(w * h / 10), kUntexturedMaxDeg);
    // The CPU's tessellation is view-dependent like the GPU's: closer, more
    // triangles (the level function of the same edges grows with 1/distance).
    const auto& ap = *a.meshes[0].patches;
    const glm::mat4 farRel = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -20));
    const glm::mat4 nearRel = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -2));
    const size_t nFar = detail::tessellatePatches(ap, farRel, 500.0f, 3.0f).mesh.triangleCount();
    const size_t nNear = detail::tessellatePatches(ap, nearRel, 500.0f, 3.0f).mesh.triangleCount();
    EXPECT_GT(nNear, 4 * nFar);
}

// Dense tessellation (0.5 px/edge, levels up to 49 on this view) on
// llvmpipe, whose draw module emits at most 65535 vertices per chunk of a
// draw (render_internal.h, patchesPerDraw): the renderer splits the patch
// draws so the GPU image stays that of the CPU reference. Bounds as
// GpuMatchesCpuReference's: median and 99th percentile 0.05 degrees, every
// pixel 0.1, coverage 0.1% (measured 0.000, 0.020 and 0.056 degrees, 2 of
// 9638 pixels; with the CPU's earlier triangulation of its own, 0.044 and
// 0.44 degrees on cells of half a pixel; with one draw per patch type:
// 99th percentile 43 degrees and 485 pixels covered by one image only,
// misplaced patches and holes).
TEST(RenderHardCases, AdaptiveDenseTessellationMatchesTheCpuReference) {
    const int w = 320, h = 240;
    Scene s = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 0.5})", kSpotCage, "", w, h));
    SceneAssets a = loadAssets(s);
    const View v = makeView(s, a, 0, 0, Aov::Normal);
    const NormalAgreement r = gpuVsCpuNormals(s, a, v, "adaptive at 0.5 px/edge");
    expectParity(r, size_t(w * h / 10), kUntexturedMaxDeg);
    sg::test::hardCaseAtMost("scales",
                             "adaptive spot at 0.5 px/edge on 320x240 (a draw chunk's patches "
                             "emit more than llvmpipe's 65535 vertices)",
                             "GPU vs CPU normal, 99th percentile (deg)", r.p99, 0.05);
    // The view tessellates densely enough for a draw to pass the limit:
    // some 4096 consecutive control points (a chunk of one patch array)
    // belong to patches whose tessellation has more than 65535 points (the
    // CPU tessellator's points per patch, patch AOV x = 1 + patch index).
    const auto& ap = *a.meshes[0].patches;
    const detail::TessellatedPatches t =
        detail::tessellatePatches(ap, modelToCameraRelative(s.meshes[0].transform, v.cameraPos),
                                  sg::glsl::sgPatchFocalPx(v.proj[1][1], float(v.height)), 0.5f);
    std::vector<size_t> pointsOf(ap.patchCount(), 0);
    for (const glm::vec4& q : t.patchAov) ++pointsOf[size_t(q.x) - 1];
    size_t densestChunk = 0;
    for (const auto& arr : ap.arrays) {
        const size_t window = 4096 / size_t(arr.pointsPerPatch);
        for (size_t p0 = 0; p0 < arr.patchCount; p0 += window) {
            size_t sum = 0;
            for (size_t k = p0; k < std::min<size_t>(p0 + window, arr.patchCount); ++k)
                sum += pointsOf[arr.firstPatch + k];
            densestChunk = std::max(densestChunk, sum);
        }
    }
    std::printf("  densest chunk: %zu tessellated points\n", densestChunk);
    EXPECT_GT(densestChunk, size_t(65535));
}

// The patch AOV: the GPU's control stage and the CPU's tessellator compute
// the same levels (shared sgPatchEdgeTessLevel, same corner vertices, same
// uModelRel), so wherever both show the same patch they show the same
// level, bit for bit. A patch border is an edge of both tessellations, its
// points equal bit for bit (patch_gpu_test.cpp), so pixels show different
// patches only where their centre lies within rounding of a border: at
// most 0.5% of the pixels both cover (measured 4 of 9612, also with the
// CPU's earlier triangulation of its own).
TEST(AdaptiveDraw, PatchAovLevelsMatchTheCpu) {
    const int w = 320, h = 240;
    Scene s = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 2, "pixels_per_edge": 4})", kSpotCage, "", w, h));
    SceneAssets a = loadAssets(s);
    View v = makeView(s, a, 0, 0, Aov::Patch);
    Image g = gpu().render(s, a, v);
    Image c = renderCpu(s, a, v);
    const float patches = float(a.meshes[0].patches->patchCount());
    size_t both = 0, samePatch = 0, sameLevel = 0, bad = 0;
    float maxLevel = 0.0f;
    for (size_t i = 0; i < g.texelCount(); ++i) {
        const glm::vec4 pg = g.rgba(i), pc = c.rgba(i);
        if (pg.x <= 0.0f || pc.x <= 0.0f) continue;
        ++both;
        for (const glm::vec4& p : {pg, pc}) {
            bad += !(p.x >= 1.0f && p.x <= patches && p.y >= 1.0f && p.y <= 64.0f &&
                     p.y == std::floor(p.y) && (p.z == 6.0f || p.z == 9.0f) && p.w >= 0.0f &&
                     p.w <= 2.0f);
        }
        if (pg.x != pc.x) continue;
        ++samePatch;
        sameLevel += pg.y == pc.y && pg.z == pc.z && pg.w == pc.w;
        maxLevel = std::max(maxLevel, pg.y);
    }
    std::printf("patch AOV: %zu px both, %zu same patch, %zu same level, max level %.0f\n", both,
                samePatch, sameLevel, double(maxLevel));
    EXPECT_GT(both, size_t(w * h / 10));
    EXPECT_EQ(bad, 0u);
    EXPECT_GE(double(samePatch), 0.995 * double(both));
    EXPECT_EQ(sameLevel, samePatch);
    EXPECT_GT(maxLevel, 1.0f); // the view does tessellate
}

// Hard cases: the camera inside the cow (patches around and behind the
// eye: levels clamped by sgPatchEdgeTessLevel, primitives clipped) and the
// cow far away (a few pixels: every level 1). Images finite in both
// renderers.
TEST(RenderHardCases, AdaptiveCameraInsideAndFarAwayStayFinite) {
    for (const char* camera :
         {R"("camera": {"distance_scale": 0.02})", R"("camera": {"distance_scale": 60})"}) {
        Scene s = sceneFromJson(
            R"({"output": {"width": 96, "height": 64}, )" + std::string(camera) +
            R"(, "materials": [{"name": "m"}],
            "meshes": [{"file": ")" +
            kSpotCage + R"(", "subdivision": {"mode": "adaptive", "pixels_per_edge": 1}}]})");
        SceneAssets a = loadAssets(s);
        size_t bad = 0;
        for (Aov aov : {Aov::Color, Aov::Normal, Aov::Patch}) {
            View v = makeView(s, a, 0, 0, aov);
            bad += countNonFinite(gpu().render(s, a, v));
            bad += countNonFinite(renderCpu(s, a, v));
        }
        sg::test::hardCaseAtMost(
            "grazing",
            std::string("adaptive spot at 1 px/edge, camera ") +
                (std::strstr(camera, "0.02") ? "inside the mesh" : "60 sizes away") +
                ": patches edge-on, behind and through the camera",
            "non-finite pixels (GPU and CPU, colour, normal and patch AOVs)", double(bad), 0.0);
    }
}

// GPU vs CPU with a tangent-space normal map on UV set 0 of adaptive
// patches: the UVs are evaluated at the same domain points with the same
// face-varying patches on both sides and interpolated over the same
// triangles (see GpuMatchesCpuReference), so the bounds are that test's,
// except on a few isolated pixels: the map's perturbation goes through the
// per-pixel tangent frame, i.e. through screen derivatives of the
// interpolated UVs, which each renderer computes in its own float
// arithmetic, and the untextured normal has no such amplification. So no
// bound on every pixel, 1 degree at the 99.9th percentile (measured p50
// 0.000, p99 0.020, p99.9 0.028, max 2.6 degrees; coverage 1 of 9621
// pixels). With the CPU's earlier triangulation of its own: p99 3.26,
// p99.9 12.2, max 19.3 degrees (the map read through UVs interpolated over
// other triangles).
TEST(AdaptiveUv, GpuMatchesCpuWithAUvNormalLayer) {
    const int w = 320, h = 240;
    Scene s = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 3})", kSpotCage,
        R"({"type": "uv_normal", "uv_set": 0, "map": {"procedural": "bricks", "size": 256}, "strength": 1.0})",
        w, h));
    SceneAssets a = loadAssets(s);
    const View v = makeView(s, a, 0, 0, Aov::Normal);
    Image g;
    const NormalAgreement r = gpuVsCpuNormals(s, a, v, "adaptive uv_normal", &g);
    expectParity(r, size_t(w * h / 10), kMappedMaxDeg);
    // The layer does bend the normals (the map is read through the UVs).
    Scene plain = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 3})", kSpotCage, "", w, h));
    SceneAssets pa = loadAssets(plain);
    NormalAgreement bent = compareNormals(g, gpu().render(plain, pa, v));
    EXPECT_GT(bent.p99, 5.0) << "the normal map changed nothing";
}

// A domed disk around one vertex of valence 64 (a cap of height 0.35 over
// radius 0.75, planar UVs), written as an OBJ cage in the build tree: a fan
// of 64 triangles around the centre (Catmark quads around a vertex of
// valence 64 after the first level) and two rings of 64 quads out to the
// rim.
std::filesystem::path valence64Disk() {
    const std::filesystem::path dir =
        std::filesystem::path(SURFGRAD_BINARY_DIR) / "tests/render/adaptive";
    std::filesystem::create_directories(dir);
    const std::filesystem::path file = dir / "valence64_disk.obj";
    std::ofstream o(file);
    const int k = 64;
    auto point = [&](double r, int i) {
        const double a = 2.0 * M_PI * i / k, z = 0.35 * (1.0 - (r / 0.75) * (r / 0.75));
        o << "v " << r * std::cos(a) << " " << r * std::sin(a) << " " << z << "\n";
        o << "vt " << 0.5 + 0.66 * r * std::cos(a) << " " << 0.5 + 0.66 * r * std::sin(a) << "\n";
    };
    point(0.0, 0); // vertex 1: the centre
    for (const double r : {0.25, 0.5, 0.75})
        for (int i = 0; i < k; ++i) point(r, i); // ring j (0..2): vertices 2 + j k + i
    auto ring = [&](int j, int i) { return 2 + j * k + i % k; };
    auto face = [&](std::initializer_list<int> v) {
        o << "f";
        for (const int x : v) o << " " << x << "/" << x;
        o << "\n";
    };
    for (int i = 0; i < k; ++i) face({1, ring(0, i), ring(0, i + 1)});
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < k; ++i)
            face({ring(j, i), ring(j + 1, i), ring(j + 1, i + 1), ring(j, i + 1)});
    return file;
}

// GPU vs the CPU reference with a tangent-space normal map on coarse
// tessellations, where a cell spans several pixels and a difference of
// triangulation shows most: spot and a disk around a vertex of valence 64
// (thin patches around the centre), both at 8 px/edge. Same triangles, so
// GpuMatchesCpuWithAUvNormalLayer's bounds (measured: spot p50 0.000, p99
// 0.020, p99.9 0.028, max 6.2 degrees; the disk 0.000, 0.020, 0.044, 3.2;
// coverage 0 and 0 pixels). With the CPU's earlier triangulation of its
// own: spot p99 6.9, p99.9 15.9, max 22 degrees; the disk p99 0.68, p99.9
// 1.5 (its largest difference, 3.2 degrees, is not the triangulation's).
TEST(AdaptiveUv, MatchedCpuAgreesOnCoarseTessellations) {
    const int w = 320, h = 240;
    const std::string bricks =
        R"({"type": "uv_normal", "uv_set": 0, "map": {"procedural": "bricks", "size": 256}, "strength": 1.0})";
    const std::string coarse = R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 8})";
    for (const std::string& file : {kSpotCage, valence64Disk().string()}) {
        Scene s = sceneFromJson(cageScene(coarse, file, bricks, w, h));
        SceneAssets a = loadAssets(s);
        const View v = makeView(s, a, 0, 0, Aov::Normal);
        const std::string label =
            std::filesystem::path(file).filename().string() + " at 8 px/edge, uv_normal,";
        const NormalAgreement r = gpuVsCpuNormals(s, a, v, label.c_str());
        expectParity(r, size_t(w * h / 10), kMappedMaxDeg);
    }
}

// The UV AOV of the adaptive draw against the uniform path's limit UVs
// (level 4, limit) on the same view: both are OpenSubdiv's limit UVs,
// interpolated linearly over triangles of 2 (adaptive) and 2-4 (uniform)
// pixels, so they differ by the UVs' curvature over a few pixels: bounds
// median 5e-4, 99th percentile 5e-3 (measured 3.4e-5 and 6.3e-4). Pixels on
// UV seams (a jump of the UVs) and where the two silhouettes differ are
// excluded by a 0.02 cut: at most 3% of the pixels both cover (measured 4
// of 11017).
TEST(AdaptiveUv, UvAovMatchesTheUniformLimitUvs) {
    const int w = 320, h = 240;
    Scene su = sceneFromJson(cageScene(R"({"level": 4, "limit": true})", kSpotCage, "", w, h));
    Scene sa = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 2})", kSpotCage, "", w, h));
    SceneAssets au = loadAssets(su), aa = loadAssets(sa);
    View v = makeView(su, au, 0, 0, Aov::Uv);
    View vp = makeView(su, au, 0, 0, Aov::Normal);
    Image iu = gpu().render(su, au, v), ia = gpu().render(sa, aa, v);
    Image nu = gpu().render(su, au, vp), na = gpu().render(sa, aa, vp);
    std::vector<double> d;
    size_t both = 0, cut = 0, nonFinite = 0;
    for (size_t i = 0; i < iu.texelCount(); ++i) {
        nonFinite += !std::isfinite(ia.rgba(i).x) || !std::isfinite(ia.rgba(i).y);
        if (glm::length(glm::vec3(nu.rgba(i))) < 0.5f || glm::length(glm::vec3(na.rgba(i))) < 0.5f)
            continue;
        ++both;
        const double e = glm::length(glm::vec2(ia.rgba(i)) - glm::vec2(iu.rgba(i)));
        if (e > 0.02) {
            ++cut;
            continue;
        }
        d.push_back(e);
    }
    std::sort(d.begin(), d.end());
    ASSERT_FALSE(d.empty());
    const double p50 = d[d.size() / 2], p99 = d[size_t(0.99 * double(d.size()))];
    std::printf("adaptive vs uniform level 4 UVs: %zu px both, %zu cut, p50 %.2e p99 %.2e\n", both,
                cut, p50, p99);
    EXPECT_EQ(nonFinite, 0u);
    EXPECT_GT(both, size_t(w * h / 10));
    EXPECT_LE(double(cut), 0.03 * double(both));
    EXPECT_LE(p50, 5e-4);
    EXPECT_LE(p99, 5e-3);
}

// Hard case: zero-area UV patches (a cube cage whose every corner has the
// same UV: every face-varying value and every UV patch is one point, the
// UV Jacobian is zero everywhere) with a normal map on that set, at
// isolation 1 and 2: finite images on both renderers, with the frame per
// pixel (its degenerate-UV fallback takes over; nothing in the evaluation
// stage divides by UVs) and with "limit" tangents (sgPatchLimitTangent's
// degenerate-UV fallback).
TEST(RenderHardCases, AdaptiveZeroAreaUvPatchesStayFinite) {
    const std::filesystem::path dir = sg::test::processScratchDir("adaptive_uv");
    const std::filesystem::path obj = dir / "cube_one_uv.obj";
    {
        std::ofstream f(obj);
        f << "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n"
             "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\nvt 0.5 0.5\n"
             "f 1/1 4/1 3/1 2/1\nf 5/1 6/1 7/1 8/1\nf 1/1 2/1 6/1 5/1\n"
             "f 2/1 3/1 7/1 6/1\nf 3/1 4/1 8/1 7/1\nf 4/1 1/1 5/1 8/1\n";
    }
    size_t bad[2] = {0, 0}; // per pixel, limit tangents
    for (int limit : {0, 1}) {
        for (const char* isolation : {"1", "2"}) {
            Scene s = sceneFromJson(
                R"({"output": {"width": 96, "height": 64}, "materials": [{"name": "m", "layers": [
                  {"type": "uv_normal", "uv_set": 0, "map": {"procedural": "bricks", "size": 64}}]}],
                "meshes": [{"file": ")" +
                obj.generic_string() + R"(", "subdivision": {"mode": "adaptive", "isolation": )" +
                isolation + R"(, "pixels_per_edge": 2})" +
                (limit ? R"(, "tangents": "limit")" : "") + "}]}");
            SceneAssets a = loadAssets(s);
            EXPECT_EQ(a.meshes[0].patchTangentSets, limit ? 1u : 0u);
            for (Aov aov : {Aov::Color, Aov::Normal, Aov::Uv, Aov::Tangent}) {
                View v = makeView(s, a, 0, 0, aov);
                bad[limit] += countNonFinite(gpu().render(s, a, v));
                bad[limit] += countNonFinite(renderCpu(s, a, v));
            }
        }
    }
    sg::test::hardCaseAtMost("uv-degenerate",
                             "adaptive patches whose UVs are all one point (cube cage), "
                             "normal map on them, GPU and CPU",
                             "non-finite pixel channels", double(bad[0]), 0.0);
    sg::test::hardCaseAtMost("uv-degenerate",
                             "adaptive patches whose UVs are all one point (cube cage), limit "
                             "tangents and a normal map on them, GPU and CPU",
                             "non-finite pixel channels", double(bad[1]), 0.0);
}

// ---- Displacement ---------------------------------------------------------

const std::string kBumpsHeight = R"({"procedural": "bumps", "output": "height", "size": 128})";

std::string displacedScene(const std::string& displacement, const std::string& layers = "",
                           int w = 240, int h = 180, const std::string& extra = "") {
    return adaptiveSpotScene(R"(, "displacement": )" + displacement + extra, layers, w, h);
}

TEST(AdaptiveDisplacement, InvalidValuesNameTheField) {
    struct Case {
        std::string mesh;
        const char* field;
    };
    const std::string spot = R"({"file": ")" + kSpotCage + R"(", )";
    const Case cases[] = {
        // Adaptive meshes only.
        {spot + R"("subdivision": {"level": 1}, "displacement": {"map": "h.png"}})",
         "meshes[0].displacement"},
        {spot + R"("displacement": {"map": "h.png"}})", "meshes[0].displacement"},
        {spot + R"("subdivision": {"mode": "adaptive"}, "displacement": {"scale": 1}})",
         "meshes[0].displacement"},
        {spot + R"("subdivision": {"mode": "adaptive"}, "displacement": {"map": 3}})",
         "meshes[0].displacement.map"},
        {spot +
             R"("subdivision": {"mode": "adaptive"}, "displacement": {"map": "h.png", "scale": "1"}})",
         "meshes[0].displacement.scale"},
        {spot +
             R"("subdivision": {"mode": "adaptive"}, "displacement": {"map": "h.png", "uv_set": 9}})",
         "meshes[0].displacement.uv_set"},
        {spot +
             R"("subdivision": {"mode": "adaptive"}, "displacement": {"map": "h.png", "strength": 1}})",
         "meshes[0].displacement.strength"},
    };
    for (const Case& c : cases) {
        const std::string err = parseError(oneMaterialScene("", c.mesh));
        EXPECT_NE(err.find(c.field), std::string::npos) << c.mesh << " -> " << err;
    }
    // A UV set the mesh does not have: at load.
    Scene s = sceneFromJson(displacedScene(R"({"map": )" + kBumpsHeight + R"(, "uv_set": 1})"));
    try {
        loadAssets(s);
        ADD_FAILURE() << "no error";
    } catch (const sg::io::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("meshes[0].displacement.uv_set"), std::string::npos)
            << e.what();
    }
}

// Effects on demand: only a displaced mesh's evaluation stage reads a
// height map, and only its fragment program lights at vRelPosLit.
TEST(AdaptiveDisplacement, OnlyDisplacedMeshesCompileIt) {
    Scene d = sceneFromJson(displacedScene(R"({"map": )" + kBumpsHeight + R"(, "scale": 0.05})"));
    Scene n = sceneFromJson(cageScene(R"({"mode": "adaptive", "isolation": 3})", kSpotCage));
    SceneAssets ad = loadAssets(d), an = loadAssets(n);
    MaterialPlan pd = planMaterial(d, ad, 0, 0), pn = planMaterial(n, an, 0, 0);
    EXPECT_EQ(pd.displacementUvSet, 0);
    EXPECT_EQ(pn.displacementUvSet, -1);
    EXPECT_NE(pd.signature.find(":disp0"), std::string::npos);
    EXPECT_EQ(pn.signature.find(":disp"), std::string::npos);
    ProgramSource sd = assembleProgram(pd), sn = assembleProgram(pn);
    // The displacement code is preprocessed in only where SG_DISPLACEMENT is 1.
    EXPECT_EQ(sd.tessEval.rfind("#version 450 core\n#define SG_UV_COUNT 1\n#define SG_DISPLACEMENT "
                                "1\n#define SG_DISP_UV_SET 0\n",
                                0),
              0u);
    EXPECT_EQ(sn.tessEval.find("#define SG_DISPLACEMENT 1"), std::string::npos);
    EXPECT_NE(sd.fragment.find("vRelPosLit"), std::string::npos);
    EXPECT_EQ(sn.fragment.find("vRelPosLit"), std::string::npos);
    EXPECT_EQ(ad.textures.size(), 1u); // the height map, loaded for the mesh
    EXPECT_TRUE(an.textures.empty());
}

// GPU vs CPU with displacement: both displace the same points by the same
// height (the shared sgDisplaceLod and sgDisplacePoint, textureLod at the
// same level: filtering differs by llvmpipe's fixed-point weights, a few
// 1e-3 of a texel step) and draw the same triangles, so the bounds of
// GpuMatchesCpuReference hold, coverage of the displaced silhouette
// included. Measured: p50 0.000, p99 0.020, max 0.040 degrees, 0 of 10532
// pixels differ in coverage (with the CPU's earlier triangulation of its
// own: p99 0.70, max 11.3 degrees, 2 pixels).
TEST(AdaptiveDisplacement, GpuMatchesCpuReference) {
    const int w = 320, h = 240;
    Scene s = sceneFromJson(
        displacedScene(R"({"map": )" + kBumpsHeight + R"(, "scale": 0.03})", "", w, h));
    SceneAssets a = loadAssets(s);
    const View v = makeView(s, a, 0, 0, Aov::Normal);
    Image g;
    const NormalAgreement r = gpuVsCpuNormals(s, a, v, "displaced", &g);
    expectParity(r, size_t(w * h / 10), kUntexturedMaxDeg);
    // The displacement moves the silhouette: coverage differs from the
    // undisplaced surface's.
    Scene u = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 3})", kSpotCage, "", w, h));
    SceneAssets au = loadAssets(u);
    NormalAgreement moved = compareNormals(g, gpu().render(u, au, v));
    std::printf("displaced vs undisplaced: %zu px differ in coverage\n", moved.onlyOne);
    EXPECT_GT(moved.onlyOne, size_t(50));
}

// The displacement's "offset" (object units added to scale * height, for
// unsigned maps such as the bake's 16-bit PNG): the GPU and the CPU move
// the same points by the same distance (the parity bounds above hold), and
// the offset moves the silhouette (coverage differs from the same scene
// without it).
TEST(AdaptiveDisplacement, OffsetMovesBothRenderersAlike) {
    const int w = 320, h = 240;
    Scene s = sceneFromJson(displacedScene(
        R"({"map": )" + kBumpsHeight + R"(, "scale": 0.03, "offset": -0.02})", "", w, h));
    SceneAssets a = loadAssets(s);
    const View v = makeView(s, a, 0, 0, Aov::Normal);
    Image g;
    const NormalAgreement r = gpuVsCpuNormals(s, a, v, "displaced with an offset", &g);
    // The single worst pixel follows where the displaced silhouette and the
    // map's steepest texels fall (llvmpipe's fixed-point filter weights
    // against the CPU's): 0.04 degrees on GpuMatchesCpuReference's surface,
    // 0.115 on this one (its p50 and p99 are the same, 0.000 and 0.020);
    // bound 0.25.
    expectParity(r, size_t(w * h / 10), 0.25);
    Scene z = sceneFromJson(
        displacedScene(R"({"map": )" + kBumpsHeight + R"(, "scale": 0.03})", "", w, h));
    SceneAssets az = loadAssets(z);
    NormalAgreement moved = compareNormals(g, gpu().render(z, az, v));
    std::printf("offset -0.02 vs none: %zu px differ in coverage\n", moved.onlyOne);
    EXPECT_GT(moved.onlyOne, size_t(50));
}

// Pinholes: an uncovered pixel whose four neighbours are covered, inside
// the cow at 2 pixels per tessellated edge, counted on the displaced
// surface and on the same draw with scale 0 (same programs, zero offset).
// Displaced shared edges are evaluated from one site on both sides (UV,
// normal, map level): the owner's on edges between patches of the same
// depth, the fine half's owner on transition edges between depths (no
// T-junctions: both sides put the same points on the edge). So the
// displacement opens no pinhole: measured 0 with and without it, on the
// GPU and the CPU (4 with it before transition edges were matched); bound
// 0.
TEST(AdaptiveDisplacement, DisplacedSurfacePinholes) {
    const int w = 480, h = 360;
    size_t counts[2][2] = {};
    for (int d = 0; d < 2; ++d) {
        Scene s = sceneFromJson(oneMaterialScene(
            "",
            R"({"file": ")" + kSpotCage +
                R"(", "subdivision": {"mode": "adaptive", "isolation": 2, "pixels_per_edge": 2},
                "displacement": {"map": )" +
                kBumpsHeight + R"(, "scale": )" + (d ? "0.06" : "0") + "}}",
            "", w, h));
        SceneAssets a = loadAssets(s);
        View v = makeView(s, a, 0, 0, Aov::Normal);
        for (int pass = 0; pass < 2; ++pass) {
            Image img = pass == 0 ? gpu().render(s, a, v) : renderCpu(s, a, v);
            auto covered = [&](int x, int y) {
                return glm::length(glm::vec3(img.rgba(size_t(y) * size_t(w) + size_t(x)))) > 0.5f;
            };
            size_t holes = 0, inside = 0;
            for (int y = 1; y + 1 < h; ++y)
                for (int x = 1; x + 1 < w; ++x) {
                    if (covered(x, y)) {
                        ++inside;
                        continue;
                    }
                    holes += (covered(x - 1, y) && covered(x + 1, y) && covered(x, y - 1) &&
                              covered(x, y + 1));
                }
            std::printf("scale %s, %s: %zu covered px, %zu pinholes\n", d ? "0.06" : "0",
                        pass == 0 ? "GPU" : "CPU", inside, holes);
            EXPECT_GT(inside, size_t(w * h / 10));
            counts[d][pass] = holes;
        }
    }
    EXPECT_EQ(counts[0][0], 0u);
    EXPECT_EQ(counts[0][1], 0u);
    EXPECT_EQ(counts[1][0], 0u);
    EXPECT_EQ(counts[1][1], 0u);
}

// Hard case: displacement with the eye inside the cow (patches around and
// behind the eye) and far away: finite images, and every displaced point
// within |scale| * max height (1 for an 8-bit map) of its limit point.
// Bounded is not the same as working: the displacement must also move the
// points (the largest offset close to the map's top, 1) and change what the
// renderers show against the same draw with scale 0 (the eye inside: the
// surface around it moves by up to 0.1 of a cow about 1.5 long).
TEST(RenderHardCases, AdaptiveDisplacementBehindTheEyeIsBounded) {
    double worst = 0.0;
    size_t bad = 0;
    size_t changed[2] = {0, 0}; // GPU, CPU: inside camera, normal AOV vs scale 0
    auto sceneOf = [](const char* camera, const char* scale) {
        return sceneFromJson(R"({"output": {"width": 96, "height": 64}, )" + std::string(camera) +
                             R"(, "materials": [{"name": "m"}],
            "meshes": [{"file": ")" +
                             kSpotCage +
                             R"(", "subdivision": {"mode": "adaptive", "pixels_per_edge": 1},
            "displacement": {"map": )" +
                             kBumpsHeight + R"(, "scale": )" + scale + "}}]}");
    };
    bool inside = true;
    for (const char* camera :
         {R"("camera": {"distance_scale": 0.02})", R"("camera": {"distance_scale": 60})"}) {
        Scene s = sceneOf(camera, "0.1");
        SceneAssets a = loadAssets(s);
        for (Aov aov : {Aov::Color, Aov::Normal}) {
            View v = makeView(s, a, 0, 0, aov);
            const Image g = gpu().render(s, a, v), c = renderCpu(s, a, v);
            bad += countNonFinite(g);
            bad += countNonFinite(c);
            if (inside && aov == Aov::Normal) {
                Scene s0 = sceneOf(camera, "0");
                SceneAssets a0 = loadAssets(s0);
                const View v0 = makeView(s0, a0, 0, 0, aov);
                const Image g0 = gpu().render(s0, a0, v0), c0 = renderCpu(s0, a0, v0);
                for (size_t i = 0; i < g.texelCount(); ++i) {
                    // A pixel changes when its normal turns by more than 1
                    // degree or its coverage changes.
                    auto differs = [](glm::vec4 p, glm::vec4 q) {
                        const glm::vec3 np(p), nq(q);
                        const float la = glm::length(np), lb = glm::length(nq);
                        if ((la > 0.5f) != (lb > 0.5f)) return true;
                        return la > 0.5f &&
                               glm::dot(np, nq) < std::cos(glm::radians(1.0f)) * la * lb;
                    };
                    changed[0] += differs(g.rgba(i), g0.rgba(i));
                    changed[1] += differs(c.rgba(i), c0.rgba(i));
                }
            }
            detail::PatchDisplacement d;
            d.map.image = a.textures.begin()->second.get();
            d.scale = 0.1f;
            const float focalPx = sg::glsl::sgPatchFocalPx(v.proj[1][1], float(v.height));
            const detail::TessellatedPatches t = detail::tessellatePatches(
                *a.meshes[0].patches, modelToCameraRelative(glm::dmat4(1.0), v.cameraPos), focalPx,
                1.0f, &d);
            for (size_t i = 0; i < t.framePositions.size(); ++i) {
                const double moved = glm::length(t.mesh.positions[i] - t.framePositions[i]) / 0.1;
                worst = std::isfinite(moved) ? std::max(worst, moved) : INFINITY;
            }
        }
        inside = false;
    }
    std::printf("largest offset %.4f of the scale; eye inside, pixels changed by the "
                "displacement: GPU %zu, CPU %zu of %d\n",
                worst, changed[0], changed[1], 96 * 64);
    EXPECT_EQ(bad, 0u);
    // The map's top is 1 (bumps: 255 at the bump centres): the tessellated
    // points that reach it move by the whole scale (measured 0.994).
    EXPECT_GT(worst, 0.9);
    // With the eye inside, the displaced surface around it turns the
    // normal by more than a degree, or moves an edge, at 230 (GPU) and 231
    // (CPU) of the 6144 pixels (measured; 0 when the displacement does
    // nothing).
    EXPECT_GT(changed[0], size_t(100));
    EXPECT_GT(changed[1], size_t(100));
    sg::test::hardCaseAtMost("grazing",
                             "adaptive displacement (scale 0.1), eye inside the mesh and 60 "
                             "sizes away: |displaced - limit point| / scale, CPU tessellator",
                             "offset in units of the scale", worst, 1.0 + 1e-5);
}

// ---- Animated cages ----------------------------------------------------

std::filesystem::path sourcePath(const std::string& rel) {
    return std::filesystem::path(SURFGRAD_SOURCE_DIR) / rel;
}

// A deterministic motion of every cage vertex: a few percent of the cage's
// size, different per vertex and per axis.
std::vector<glm::vec3> movedCage(const std::vector<glm::vec3>& cage, float t) {
    float extent = 0.0f;
    for (const glm::vec3& p : cage)
        extent = std::max({extent, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    std::vector<glm::vec3> out = cage;
    for (size_t v = 0; v < out.size(); ++v) {
        const float k = float(v);
        out[v] += 0.05f * extent *
                  glm::vec3(std::sin(1.3f * k + t), std::cos(0.7f * k + 2.0f * t),
                            std::sin(0.31f * k - t));
    }
    return out;
}

// Bits in which two floats differ, counted over points (0: bitwise equal).
size_t differingPoints(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i) n += std::memcmp(&a[i], &b[i], sizeof(glm::vec3)) != 0;
    return n;
}

// The compute stage (sg/patch/stencils.comp.glsl: one dispatch per stencil
// pass, in place in the points buffer) against
// sg::mesh::updateAdaptivePoints for a moved cage, three poses: the same
// rows summed in the same order with every product rounded (`precise` on
// the GPU; the CPU build has no FMA contraction), so every point is equal
// bit for bit. Spot (valence 3..6 vertices: Gregory end caps), bob (a
// triangle cage: Gregory patches at every face centre, isolation 2) and
// two osd-shapes with creases and corners next to extraordinary vertices
// and a boundary; the upload holds the rows, the frame the cage only.
TEST(AdaptiveAnim, GpuStencilsEqualTheCpuBitwise) {
    gpu(); // the context
    const sg::gl::Program program = detail::makeStencilProgram();
    for (const std::string& file : {kSpotCage, std::string("data/meshes/bob/bob_tri.obj"),
                                    std::string("data/osd-shapes/catmark_cube_creases2.obj"),
                                    std::string("data/osd-shapes/catmark_pyramid_creases1.obj"),
                                    std::string("data/osd-shapes/catmark_xord_boundary.obj")}) {
        SCOPED_TRACE(file);
        const sg::mesh::PolygonMesh cage = sg::mesh::loadPolygonMesh(sourcePath(file));
        const int isolation = file.find("bob") != std::string::npos ? 2 : 3;
        sg::mesh::AdaptivePatches ap =
            sg::mesh::buildAdaptivePatches(cage, cage.options, isolation, file);
        bool gregory = false;
        for (const auto& arr : ap.arrays) gregory |= arr.type == 9 && arr.patchCount > 0;
        EXPECT_TRUE(gregory); // end caps around extraordinary vertices
        if (file.find("creases") != std::string::npos) {
            EXPECT_FALSE(cage.creases.empty());
        }
        EXPECT_GE(ap.stencilPasses.size(), size_t(isolation) + 1); // levels (+ end caps)
        GLuint points = 0;
        glCreateBuffers(1, &points);
        detail::GpuStencils st;
        EXPECT_EQ(st.upload(ap, points),
                  (ap.stencilOffsets.size() + ap.stencilIndices.size() + ap.stencilWeights.size()) *
                      4);
        const std::vector<glm::vec3> rest = ap.points;
        for (float t : {0.0f, 0.4f, 1.7f}) {
            const std::vector<glm::vec3> moved = movedCage(cage.positions, t);
            EXPECT_EQ(st.apply(moved, program), moved.size() * 12); // the cage only
            const std::vector<glm::vec3> g = detail::readPoints(points, ap.points.size());
            sg::mesh::updateAdaptivePoints(ap, moved);
            EXPECT_EQ(differingPoints(g, ap.points), 0u) << " t " << t;
            EXPECT_GT(differingPoints(g, rest), ap.points.size() / 2); // they moved
        }
        glDeleteBuffers(1, &points);
    }
}

std::string blobScene(const std::string& morph, int w = 240, int h = 180) {
    return R"({"output": {"width": )" + std::to_string(w) + R"(, "height": )" + std::to_string(h) +
           R"(}, "materials": [{"name": "m"}], "meshes": [{"file": "examples/data/morph_blob.gltf",
           "subdivision": {"mode": "adaptive", "isolation": 3, "pixels_per_edge": 3}, "morph": )" +
           morph + "}]}";
}

// Blendshapes on the cage of an adaptive mesh: applyFrame moves the cage,
// the GPU renderer uploads the cage only (cagePointCount x 12 bytes per
// frame) and its compute stage recomputes the points; the CPU reference
// follows the same points (updateAdaptivePoints) and agrees with the GPU
// within GpuMatchesCpuReference's bounds (the same triangles; measured p99
// 0.020, max 0.028 degrees, with the CPU's earlier triangulation of its
// own p99 0.14, max 0.29); the moved frame differs from the rest pose.
TEST(AdaptiveAnim, BlendshapesMoveTheCageOnTheGpu) {
    Scene s = sceneFromJson(blobScene(R"({"animation": {"loop": true, "keys": [
        {"time": 0.0, "weights": [0.0, 0.0]}, {"time": 1.0, "weights": [1.0, 0.6]}]}})"));
    SceneAssets a = loadAssets(s);
    const MeshAsset& m = a.meshes[0];
    ASSERT_TRUE(m.patches);
    ASSERT_TRUE(m.morphCage);
    ASSERT_EQ(m.morphCage->morphTargets.size(), 2u);
    const size_t cageBytes = size_t(m.patches->cagePointCount) * 12;
    View v = makeView(s, a, 0, 0, Aov::Normal);
    const Image rest = gpu().render(s, a, v);
    applyFrame(s, a, 0.9f);
    const Image g = gpu().render(s, a, v);
    EXPECT_EQ(gpu().stats().meshUploadBytes, cageBytes);
    gpu().render(s, a, v); // nothing moved: nothing uploaded
    EXPECT_EQ(gpu().stats().meshUploadBytes, 0u);
    const NormalAgreement r = gpuVsCpuNormals(s, a, v, "animated cage");
    expectParity(r, size_t(240 * 180 / 20), kUntexturedMaxDeg);
    NormalAgreement moved = compareNormals(g, rest);
    EXPECT_GT(moved.p99 + double(moved.onlyOne), 5.0); // the blob did move
}

// Hard cases of an animated cage: a cage that is not finite after
// animation (a NaN or infinite vertex) or beyond kMaxCagePosition refuses
// the frame with an InputError naming the mesh's field, the assets left as
// they were (no NaN image follows); a cage at the largest accepted size
// keeps every control point finite on the GPU and in the CPU reference.
TEST(AdaptiveAnimHardCases, NonFiniteOrHugeCageRefusesTheFrame) {
    Scene s = sceneFromJson(cageScene(R"({"mode": "adaptive", "isolation": 2})", kSpotCage));
    SceneAssets a = loadAssets(s);
    const sg::mesh::AdaptivePatches& ap = *a.meshes[0].patches;
    const std::vector<glm::vec3> cage(ap.points.begin(), ap.points.begin() + ap.cagePointCount);
    setCagePositions(s, a, 0, movedCage(cage, 0.5f));
    const uint64_t version = a.meshVersion;
    const std::vector<glm::vec3> before = a.meshes[0].cagePositions;
    int refused = 0;
    for (float bad : {std::nanf(""), INFINITY, -1e38f, 0x1p101f}) {
        std::vector<glm::vec3> c = cage;
        c[cage.size() / 2].y = bad;
        try {
            setCagePositions(s, a, 0, c);
            ADD_FAILURE() << "accepted " << bad;
        } catch (const sg::io::InputError& e) {
            ++refused;
            EXPECT_NE(std::string(e.what()).find("meshes[0]"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("cage vertex"), std::string::npos) << e.what();
        }
        EXPECT_EQ(a.meshVersion, version);
        EXPECT_EQ(differingPoints(a.meshes[0].cagePositions, before), 0u);
    }
    View v = makeView(s, a, 0, 0, Aov::Normal);
    EXPECT_EQ(countNonFinite(gpu().render(s, a, v)), 0u);
    sg::test::reportHardCaseHolds(
        "scales", "animated adaptive cage with a NaN, inf, -1e38 or 2^101 vertex", "frame",
        "refused (InputError), assets unchanged", refused == 4 ? "refused" : "accepted");

    // The largest accepted cage: every point finite on both sides.
    std::vector<glm::vec3> huge = cage;
    for (glm::vec3& p : huge) p *= 0x1p100f / 2.0f;
    setCagePositions(s, a, 0, huge); // accepted
    const sg::gl::Program program = detail::makeStencilProgram();
    GLuint points = 0;
    glCreateBuffers(1, &points);
    detail::GpuStencils st;
    st.upload(ap, points);
    st.apply(huge, program);
    const std::vector<glm::vec3> g = detail::readPoints(points, ap.points.size());
    glDeleteBuffers(1, &points);
    sg::mesh::AdaptivePatches cpu = ap;
    sg::mesh::updateAdaptivePoints(cpu, huge);
    size_t nonFinite = 0;
    for (size_t i = 0; i < g.size(); ++i)
        nonFinite += !std::isfinite(g[i].x + g[i].y + g[i].z) ||
                     !std::isfinite(cpu.points[i].x + cpu.points[i].y + cpu.points[i].z);
    sg::test::hardCaseAtMost("scales", "animated adaptive cage scaled to 2^100 (largest accepted)",
                             "control points not finite (GPU or CPU)", double(nonFinite), 0.0);
    EXPECT_EQ(differingPoints(g, cpu.points), 0u);
}

} // namespace
} // namespace sg::render::test
