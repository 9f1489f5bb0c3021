// Adaptive subdivision in the renderer ("subdivision": {"mode": "adaptive"}):
// the scene field's validation, effects on demand (only adaptive meshes get
// the tessellation stages; every other program is the triangle program it
// was), and the GPU's tessellated draw of the limit surface against the
// uniform path's limit surface on the same view.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "render_internal.h"
#include "render_test_util.h"
#include "surfgrad/adaptive_patches.h"

namespace sg::render::test {
namespace {

std::string cageScene(const std::string& subdivision, const std::string& file,
                      const std::string& layers = "", int w = 240, int h = 180) {
    return oneMaterialScene(
        layers, R"({"file": ")" + file + R"(", "subdivision": )" + subdivision + "}", "", w, h);
}

const std::string kSpot = "data/meshes/spot/spot_control_mesh.obj";

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
        cageScene(R"({"mode": "adaptive", "isolation": 4, "pixels_per_edge": 3.5})", kSpot));
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_TRUE(s.meshes[0].subdivide);
    EXPECT_TRUE(s.meshes[0].subdivAdaptive);
    EXPECT_EQ(s.meshes[0].subdivIsolation, 4);
    EXPECT_FLOAT_EQ(s.meshes[0].subdivPixelsPerEdge, 3.5f);
    Scene u = sceneFromJson(cageScene(R"({"level": 2})", kSpot));
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
        const std::string err = parseError(cageScene(c.subdivision, kSpot));
        EXPECT_NE(err.find(c.field), std::string::npos) << c.subdivision << " -> " << err;
    }
}

TEST(AdaptiveScene, UnsupportedRequestsAreClearErrors) {
    // A layer reading a UV set: the patches carry none yet.
    Scene s = sceneFromJson(
        cageScene(R"({"mode": "adaptive"})", kSpot,
                  R"({"type": "uv_normal", "map": {"procedural": "bricks", "size": 64}})"));
    SceneAssets a = loadAssets(s);
    try {
        planMaterial(s, a, 0, 0);
        ADD_FAILURE() << "no error";
    } catch (const sg::io::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("UV set"), std::string::npos) << e.what();
    }
    // Derived UV sets: refused, naming the field.
    Scene d =
        sceneFromJson(R"({"materials": [{"name": "m"}], "meshes": [{"file": ")" + kSpot +
                      R"(", "subdivision": {"mode": "adaptive"}, "uv_sets": [{"from": 0}]}]})");
    try {
        loadAssets(d);
        ADD_FAILURE() << "no error";
    } catch (const sg::io::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("meshes[0].uv_sets"), std::string::npos) << e.what();
    }
}

TEST(AdaptiveScene, OnlyAdaptiveMeshesGetTessellationStages) {
    Scene s = sceneFromJson(
        R"({"materials": [{"name": "m"}], "meshes": [
            {"file": ")" +
        kSpot + R"(", "subdivision": {"mode": "adaptive", "isolation": 2}},
            {"file": ")" +
        kSpot + R"(", "subdivision": {"level": 1}},
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
    double p50 = 0, p99 = 0;
};

NormalAgreement compareNormals(const Image& a, const Image& b) {
    NormalAgreement r;
    std::vector<double> deg;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        const glm::vec3 na(a.pixels[i]), nb(b.pixels[i]);
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
    }
    return r;
}

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
    Scene su = sceneFromJson(cageScene(R"({"level": 4, "limit": true})", kSpot, "", w, h));
    Scene sa = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 2})", kSpot, "", w, h));
    SceneAssets au = loadAssets(su), aa = loadAssets(sa);
    View v = makeView(su, au, 0, 0, Aov::Normal);
    Image iu = gpu().render(su, au, v);
    Image ia = gpu().render(sa, aa, v);
    const RenderStats stats = gpu().stats();
    EXPECT_EQ(stats.drawCalls, int(aa.meshes[0].patches->arrays.size()));
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
// sgPatchEdgeTessLevel, same corner vertices) and evaluates the same domain
// points with the shared basis, so the points agree to float rounding; what
// differs is the triangulation GL leaves to the implementation (the ring
// between the outer edges and the inner grid, the grid's diagonals:
// src/patch_tessellation.cpp): the two piecewise-linear surfaces share
// every vertex and differ inside a cell of about pixels_per_edge pixels by
// at most the surface's (and the interpolated normal's) second difference
// across it. At 3 pixels per edge on this view that is a fraction of a
// degree of normal on most pixels and a few degrees where the curvature is
// high (ears, horns, hooves): bounds median 0.5, 99th percentile 5
// degrees (measured 0.000 and 0.86: most pixels lie in cells both
// triangulate alike); coverage differs at silhouette pixels whose centre
// lies between the two triangulations: at most 1.5% of the covered pixels
// (measured 1 of 9612). With the
// triangles identical (parity of the triangle path, image_test.cpp) the
// bound is 0.05 degrees; the larger bounds here are the triangulation.
TEST(AdaptiveDraw, GpuMatchesCpuReference) {
    const int w = 320, h = 240;
    Scene s = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 3, "pixels_per_edge": 3})", kSpot, "", w, h));
    SceneAssets a = loadAssets(s);
    View v = makeView(s, a, 0, 0, Aov::Normal);
    CpuOptions cpu;
    cpu.derivatives = CpuDerivatives::Quad;
    Image g = gpu().render(s, a, v);
    Image c = renderCpu(s, a, v, cpu);
    NormalAgreement r = compareNormals(g, c);
    std::printf("adaptive GPU vs CPU: %zu px both, %zu one only, p50 %.3f p99 %.3f deg\n", r.both,
                r.onlyOne, r.p50, r.p99);
    EXPECT_GT(r.both, size_t(w * h / 10));
    EXPECT_EQ(r.nonFinite, 0u);
    EXPECT_LE(double(r.onlyOne), 0.015 * double(r.both));
    EXPECT_LE(r.p50, 0.5);
    EXPECT_LE(r.p99, 5.0);
    // The CPU's tessellation is view-dependent like the GPU's: closer, more
    // triangles (the level function of the same edges grows with 1/distance).
    const auto& ap = *a.meshes[0].patches;
    const glm::mat4 farRel = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -20));
    const glm::mat4 nearRel = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -2));
    const size_t nFar = detail::tessellatePatches(ap, farRel, 500.0f, 3.0f).mesh.triangleCount();
    const size_t nNear = detail::tessellatePatches(ap, nearRel, 500.0f, 3.0f).mesh.triangleCount();
    EXPECT_GT(nNear, 4 * nFar);
}

// The patch AOV: the GPU's control stage and the CPU's tessellator compute
// the same levels (shared sgPatchEdgeTessLevel, same corner vertices, same
// uModelRel), so wherever both show the same patch they show the same
// level, bit for bit. Pixels may show different patches along patch
// borders (the two triangulations differ by a fraction of a pixel there):
// at most 3% of the pixels both cover.
TEST(AdaptiveDraw, PatchAovLevelsMatchTheCpu) {
    const int w = 320, h = 240;
    Scene s = sceneFromJson(cageScene(
        R"({"mode": "adaptive", "isolation": 2, "pixels_per_edge": 4})", kSpot, "", w, h));
    SceneAssets a = loadAssets(s);
    View v = makeView(s, a, 0, 0, Aov::Patch);
    Image g = gpu().render(s, a, v);
    Image c = renderCpu(s, a, v);
    const float patches = float(a.meshes[0].patches->patchCount());
    size_t both = 0, samePatch = 0, sameLevel = 0, bad = 0;
    float maxLevel = 0.0f;
    for (size_t i = 0; i < g.pixels.size(); ++i) {
        const glm::vec4 pg = g.pixels[i], pc = c.pixels[i];
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
    EXPECT_GE(double(samePatch), 0.97 * double(both));
    EXPECT_EQ(sameLevel, samePatch);
    EXPECT_GT(maxLevel, 1.0f); // the view does tessellate
}

// Hard cases: the camera inside the cow (patches around and behind the
// eye: levels clamped by sgPatchEdgeTessLevel, primitives clipped) and the
// cow far away (a few pixels: every level 1). Images finite in both
// renderers.
TEST(AdaptiveDraw, CameraInsideAndFarAwayStayFinite) {
    for (const char* camera :
         {R"("camera": {"distance_scale": 0.02})", R"("camera": {"distance_scale": 60})"}) {
        Scene s = sceneFromJson(
            R"({"output": {"width": 96, "height": 64}, )" + std::string(camera) +
            R"(, "materials": [{"name": "m"}],
            "meshes": [{"file": ")" +
            kSpot + R"(", "subdivision": {"mode": "adaptive", "pixels_per_edge": 1}}]})");
        SceneAssets a = loadAssets(s);
        for (Aov aov : {Aov::Color, Aov::Normal, Aov::Patch}) {
            View v = makeView(s, a, 0, 0, aov);
            EXPECT_EQ(countNonFinite(gpu().render(s, a, v)), 0u) << camera;
            EXPECT_EQ(countNonFinite(renderCpu(s, a, v)), 0u) << camera;
        }
    }
}

} // namespace
} // namespace sg::render::test
