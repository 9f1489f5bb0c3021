// Effects on demand: the assembled program of a scene contains the code of
// the layer kinds it uses and none of the others (checked on the same text
// `surfgrad shader` prints); every variant passes glslangValidator (and a
// broken one fails it); programs are cached by effect signature; textures
// of disabled layers are not loaded; meshes are refined exactly as asked.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>

#include "cli.h"
#include "render_test_util.h"

namespace sg::render::test {
namespace {

// What each layer kind brings into a program: its include guard and entry
// function (a program without the kind must contain neither), plus helper
// functions only that kind calls.
struct KindMarker {
    const char* name;
    std::string layerJson;
    std::vector<std::string> markers;
};

std::vector<KindMarker> kinds() {
    const std::string map = R"("map": {"procedural": "bumps", "size": 16})";
    return {
        {"uv_normal",
         R"({"type": "uv_normal", )" + map + "}",
         {"SG_RENDER_LAYER_UV_NORMAL_GLSL", "sgLayerUvNormal("}},
        {"object_normal",
         R"({"type": "object_normal", )" + map + "}",
         {"SG_RENDER_LAYER_OBJECT_NORMAL_GLSL", "sgLayerObjectNormal",
          "sgSurfgradFromPerturbedNormal"}},
        {"height",
         R"({"type": "height", )" + map + "}",
         {"SG_RENDER_LAYER_HEIGHT_GLSL", "sgLayerHeight", "sgHeightDeriv3Tap"}},
        {"deriv_map",
         R"({"type": "deriv_map", )" + map + "}",
         {"SG_RENDER_LAYER_DERIV_MAP_GLSL", "sgLayerDerivMap"}},
        {"triplanar",
         R"({"type": "triplanar", )" + map + "}",
         {"SG_RENDER_LAYER_TRIPLANAR_GLSL", "sgLayerTriplanar", "sgTriplanarWeights",
          "sgTriplanarVolumeGradient"}},
        {"decal",
         R"({"type": "decal", )" + map + "}",
         {"SG_RENDER_LAYER_DECAL_GLSL", "sgLayerDecal", "sgDecalVolumeGradient",
          "sgSurfgradFromDecal"}},
        {"noise",
         R"({"type": "noise"})",
         {"SG_RENDER_LAYER_NOISE_GLSL", "sgLayerNoise", "sgPerlinNoise", "sgNoiseHash"}},
        {"modifiers",
         R"({"type": "uv_normal", )" + map + R"(, "modifiers": [{"type": "scale", "alpha": 2}]})",
         {"SG_RENDER_DERIV_MODS_GLSL", "sgModScale", "sgSampleUvNormalHD"}},
        {"feature",
         R"({"type": "feature", "curves": {"svg": ")" + std::string(SURFGRAD_DATA_DIR) +
             R"(/svg/flame.svg", "size": 32}})",
         {"SG_RENDER_LAYER_FEATURE_GLSL", "sgLayerFeature", "sgFeatSample", "sgFeatDeriv",
          "usampler2D"}},
        {"post_resolve",
         R"({"type": "post_resolve", "layers": [{"type": "noise"}]})",
         {"sgReprologue"}},
    };
}

// The program's code without its comments (documentation may name other
// functions; the claim is about code).
std::string codeOnly(const std::string& text) {
    std::string out;
    size_t i = 0;
    while (i < text.size()) {
        size_t c = text.find("//", i);
        if (c == std::string::npos) {
            out.append(text, i, std::string::npos);
            break;
        }
        out.append(text, i, c - i);
        size_t e = text.find('\n', c);
        if (e == std::string::npos) break;
        i = e;
    }
    return out;
}

std::string programFor(const std::string& layers) {
    Scene s = sceneFromJson(oneMaterialScene(layers, kSphere));
    SceneAssets a = loadAssets(s);
    return codeOnly(assembleProgram(planMaterial(s, a, 0, 0)).fragment);
}

TEST(EffectsOnDemand, AProgramHoldsOnlyTheLayerKindsItUses) {
    auto all = kinds();
    for (size_t k = 0; k < all.size(); ++k) {
        SCOPED_TRACE(all[k].name);
        // Every other kind, and this one alone.
        std::string others, mods;
        for (size_t j = 0; j < all.size(); ++j) {
            if (j == k) continue;
            // post_resolve must come last; uv_normal without modifiers must
            // not be dropped when "modifiers" is the kind under test.
            if (std::string(all[j].name) == "post_resolve") continue;
            others += (others.empty() ? "" : ", ") + all[j].layerJson;
        }
        if (std::string(all[k].name) != "post_resolve") {
            // A post-resolve group whose layer is of another kind.
            std::string child =
                std::string(all[k].name) == "noise" ? all[2].layerJson : all[6].layerJson;
            others += R"(, {"type": "post_resolve", "layers": [)" + child + "]}";
        }
        std::string without = programFor(others);
        std::string with = programFor(all[k].layerJson);
        for (const auto& m : all[k].markers) {
            bool sharedWithOthers = false;
            // uv_normal's file is part of the modifiers variant too.
            if (std::string(all[k].name) == "uv_normal" && m == "SG_RENDER_LAYER_UV_NORMAL_GLSL")
                sharedWithOthers = true;
            if (!sharedWithOthers) {
                EXPECT_EQ(without.find(m), std::string::npos)
                    << m << " found in a program without " << all[k].name;
            }
            EXPECT_NE(with.find(m), std::string::npos)
                << m << " missing from a program with " << all[k].name;
        }
    }
}

int glslang(const ProgramSource& src, const std::string& tag);

// The exact near field (sg/features/near.glsl) is compiled only when a
// feature layer asks for it ("near": "exact"): not for a feature layer on the
// same curves without it.
TEST(EffectsOnDemand, NearFieldOnlyWhenALayerUsesIt) {
    const std::string curves = R"("curves": {"svg": ")" + std::string(SURFGRAD_DATA_DIR) +
                               R"(/svg/flame.svg", "size": 32, "mode": "quadratic"})";
    std::string paper = programFor(R"({"type": "feature", )" + curves + "}");
    std::string exact = programFor(R"({"type": "feature", "near": "exact", )" + curves + "}");
    for (const char* m : {"sgFeatSampleNear", "sgFeatNearEval", "sgFeatClosestOnPiece",
                          "sgFeatCurveProfile", "uFeatNear", "uFeatPieces"}) {
        EXPECT_EQ(paper.find(m), std::string::npos) << m;
        EXPECT_NE(exact.find(m), std::string::npos) << m;
    }
    Scene s = sceneFromJson(
        oneMaterialScene(R"({"type": "feature", "near": "exact", )" + curves + "}", kSphere));
    SceneAssets a = loadAssets(s);
    EXPECT_EQ(glslang(assembleProgram(planMaterial(s, a, 0, 0)), "near"), 0);
}

TEST(EffectsOnDemand, NoLayersMeansNoBumpCode) {
    std::string p = programFor("");
    for (const char* m : {"sgLayer", "sgTspaceNormalToDeriv", "sgPerlinNoise", "sgTriplanar",
                          "sgReprologue", "textureGrad", "sampler2D"}) {
        EXPECT_EQ(p.find(m), std::string::npos) << m;
    }
    // The prologue and the resolve are always there (listing 16, listing 1).
    EXPECT_NE(p.find("sgPrologue"), std::string::npos);
    EXPECT_NE(p.find("sgResolve"), std::string::npos);
}

// glslangValidator on a complete program (both stages linked).
int glslang(const ProgramSource& src, const std::string& tag) {
    std::string dir = std::string(SURFGRAD_BINARY_DIR) + "/tests/render";
    std::string vs = dir + "/glslang_" + tag + ".vert", fs = dir + "/glslang_" + tag + ".frag";
    std::ofstream(vs) << src.vertex;
    std::ofstream(fs) << src.fragment;
    const sg::test::CommandResult r =
        sg::test::runCommand(std::string(SURFGRAD_GLSLANG) + " -l " + vs + " " + fs);
    std::ofstream(dir + "/glslang_" + tag + ".log") << r.output();
    return r.exitCode;
}

TEST(EffectsOnDemand, EveryVariantPassesGlslangValidator) {
    auto all = kinds();
    int i = 0;
    for (const auto& k : all) {
        Scene s = sceneFromJson(oneMaterialScene(k.layerJson, kSphere));
        SceneAssets a = loadAssets(s);
        EXPECT_EQ(glslang(assembleProgram(planMaterial(s, a, 0, 0)), "kind" + std::to_string(i++)),
                  0)
            << k.name;
    }
    // The default scene and an uber-shader (every kind compiled in).
    Scene d = defaultScene();
    SceneAssets da = loadAssets(d);
    for (size_t m = 0; m < d.meshes.size(); ++m) {
        EXPECT_EQ(glslang(assembleProgram(planMaterial(d, da, int(m), d.meshes[m].material)),
                          "default" + std::to_string(m)),
                  0);
    }
    EXPECT_EQ(glslang(assembleProgram(planUberMaterial(d, da, 0, d.meshes[0].material)), "uber"),
              0);
    // The check can fail: a program with an undefined function.
    ProgramSource bad = assembleProgram(planMaterial(d, da, 0, d.meshes[0].material));
    bad.fragment.replace(bad.fragment.find("sgResolve(frame, surfGrad)"), 9, "sgNoSuchFn");
    EXPECT_NE(glslang(bad, "mustfail"), 0);
}

TEST(EffectsOnDemand, ProgramsAreCachedByEffectSignature) {
    // Two meshes, same material: one program. Different strengths: same
    // signature. Another layer kind: another signature.
    Scene s = sceneFromJson(R"({"materials": [{"name": "a", "layers": [{"type": "noise"}]}],
        "meshes": [{"procedural": {"type": "sphere", "segments": 16}}, {"procedural": {"type": "sphere", "segments": 16},
                   "transform": {"translate": [3, 0, 0]}}], "output": {"width": 64, "height": 48}})");
    SceneAssets a = loadAssets(s);
    GlRenderer& gl = gpu();
    size_t before = gl.cachedPrograms();
    View v = makeView(s, a);
    gl.render(s, a, v);
    EXPECT_EQ(gl.stats().drawCalls, 2);
    EXPECT_EQ(gl.cachedPrograms(), before + 1);
    EXPECT_EQ(gl.stats().programsCompiled, 1);
    gl.render(s, a, v);
    EXPECT_EQ(gl.stats().programsCompiled, 0);
    MaterialPlan p0 = planMaterial(s, a, 0, 0);
    s.materials[0].layers[0].params<NoiseParams>().amplitude = 0.5f;
    EXPECT_EQ(planMaterial(s, a, 0, 0).signature, p0.signature);
    s.materials[0].layers[0].enabled = false; // a disabled layer is not compiled in
    EXPECT_NE(planMaterial(s, a, 0, 0).signature, p0.signature);
    EXPECT_EQ(assembleProgram(planMaterial(s, a, 0, 0)).fragment.find("sgLayerNoise"),
              std::string::npos);
}

TEST(EffectsOnDemand, TexturesOfUnusedLayersAreNotLoaded) {
    // The disabled layer names a file that does not exist: loading it would throw.
    Scene s = sceneFromJson(R"({"materials": [{"name": "a", "layers": [
        {"type": "uv_normal", "enabled": false, "map": "does/not/exist.png"},
        {"type": "uv_normal", "map": {"procedural": "tiles", "size": 32}}]},
        {"name": "unused", "layers": [{"type": "uv_normal", "map": "also/missing.png"}]}],
        "meshes": [{"procedural": {"type": "plane"}, "material": "a"}]})");
    SceneAssets a;
    ASSERT_NO_THROW(a = loadAssets(s));
    ASSERT_EQ(a.textures.size(), 1u);
    EXPECT_EQ(a.textures.begin()->first.rfind("proc:tiles", 0), 0u);
}

TEST(EffectsOnDemand, MeshesAreRefinedExactlyAsAsked) {
    // catmark_cube: 6 quads. Level L has 6 * 4^L quads = 12 * 4^L triangles.
    std::string cube = std::string(SURFGRAD_DATA_DIR) + "/osd-shapes/catmark_cube.obj";
    for (int level : {0, 1, 2}) {
        std::string sub =
            level == 0 ? "" : R"(, "subdivision": {"level": )" + std::to_string(level) + "}";
        Scene s = sceneFromJson(R"({"meshes": [{"file": ")" + cube + "\"" + sub + "}]}");
        SceneAssets a = loadAssets(s);
        EXPECT_EQ(a.meshes[0].mesh.triangleCount(), size_t(12) << (2 * level)) << "level " << level;
    }
}

TEST(EffectsOnDemand, ShaderOutputNamesEveryIncludedFile) {
    // `surfgrad shader` prints the assembled text; #line directives map
    // every line back to a library file (the assembler's source list).
    Scene s = sceneFromJson(oneMaterialScene(kinds()[4].layerJson, kSphere));
    SceneAssets a = loadAssets(s);
    ProgramSource src = assembleProgram(planMaterial(s, a, 0, 0));
    std::set<std::string> files(src.fragmentFiles.begin(), src.fragmentFiles.end());
    EXPECT_TRUE(files.count("sg/render/layer_triplanar.glsl"));
    EXPECT_TRUE(files.count("sg/surfgrad.glsl"));
    EXPECT_FALSE(files.count("sg/render/layer_decal.glsl"));
}

} // namespace
} // namespace sg::render::test
