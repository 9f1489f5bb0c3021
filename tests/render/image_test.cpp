// GPU (OpenGL on llvmpipe) against the CPU reference renderer, per layer
// kind, on the normal AOV. Metric: the angle between the two renderers'
// perturbed normals at every pixel covered by the same primitive in both
// (primid AOVs; silhouette pixels whose coverage differs are counted, not
// compared: a pixel centre exactly on an edge may go either way).
//
// Two comparisons per case, with different bounds and different purposes:
//  1. Parity: the CPU emulates the GPU's derivative (2x2-quad differences,
//     dFdxFine) and llvmpipe's texture LOD (fast log2). What is left is
//     float rounding in a different evaluation order, so the bound is
//     tight: max 0.05 degrees (measured max 0.005). This proves both
//     renderers run the same layer code in the same order.
//  2. Reference: the CPU uses exact analytic derivatives and the GL
//     specification's LOD. The GPU's quad differences are off by half a
//     pixel's second derivative and llvmpipe's LOD by up to 0.086 mip
//     levels, which changes the filtered normal where the map has contrast
//     at the pixel scale. Bounds: median <= 0.3 degrees, 99th percentile <=
//     4 degrees (measured at most 0.16 and 1.6 on these scenes; POM's
//     occlusion edges: 10, measured 4.0, see KindImageCase::referenceP99Deg).
// No compared pixel may be NaN/Inf in either image, and coverage may differ
// on at most 1% of the covered pixels.
#include <gtest/gtest.h>

#include <set>

#include "hardcase.h"
#include "render_test_util.h"
#include "layer_kind.h"
#include "surfgrad/mesh/mesh_io.h"

namespace sg::render::test {
namespace {

struct LayerCase {
    std::string name;
    std::string json; // the whole scene
    // Reference comparison's 99th percentile bound (degrees): 4 unless the
    // kind's case says otherwise (KindImageCase::referenceP99Deg, e.g.
    // POM's occlusion edges).
    double refP99Deg = 4.0;
};

std::ostream& operator<<(std::ostream& o, const LayerCase& c) {
    return o << c.name;
}

// Every registered kind's own scenes (LayerKind::imageCases), in registry
// order, then scenes of meshes and tangent sources rather than of a kind.
std::vector<LayerCase> layerCases() {
    std::vector<LayerCase> cases;
    for (const LayerKind* k : layerKinds()) {
        for (const KindImageCase& c : k->imageCases) {
            cases.push_back({c.name,
                             oneMaterialScene(c.layers, c.mesh.empty() ? kSphere : c.mesh, "", 200,
                                              150, c.sceneExtra),
                             c.referenceP99Deg});
        }
    }
    const std::string bricks = R"({"procedural": "bricks", "size": 256})";
    const std::string tiles = R"({"procedural": "tiles", "size": 128})";
    std::vector<LayerCase> scenes = {
        {"spot_subdivided_mikktspace_tangents",
         oneMaterialScene(
             R"({"type": "uv_normal", "map": )" + bricks + "}",
             R"({"file": ")" + std::string(SURFGRAD_DATA_DIR) +
                 R"(/meshes/spot/spot_control_mesh.obj", "subdivision": {"level": 2}, "tangents": ["mikktspace"]})")},
        {"spot_limit_surface_tangents",
         oneMaterialScene(
             R"({"type": "uv_normal", "map": )" + bricks + "}",
             R"({"file": ")" + std::string(SURFGRAD_DATA_DIR) +
                 R"(/meshes/spot/spot_control_mesh.obj", "subdivision": {"level": 2, "limit": true}, "tangents": ["limit"]})")},
        // Two UV sets, two vertex-tangent sources: limit tangents on the
        // unwrap, MikkTSpace on a derived tiling set (tangent_sets_test.cpp
        // checks the tangents themselves).
        {"spot_two_uv_sets_limit_and_mikktspace_tangents",
         oneMaterialScene(
             R"({"type": "uv_normal", "map": )" + bricks +
                 R"(}, {"type": "uv_normal", "uv_set": 1, "strength": 0.6, "map": )" + tiles + "}",
             R"({"file": ")" + std::string(SURFGRAD_DATA_DIR) +
                 R"(/meshes/spot/spot_control_mesh.obj", "subdivision": {"level": 2, "limit": true},
                              "uv_sets": [{"from": 0, "scale": [3, 3], "rotate_deg": 30}], "tangents": ["limit", "mikktspace"]})")},
        {"everything_double_sided_flip",
         oneMaterialScene(
             R"({"type": "uv_normal", "map": )" + bricks + R"(}, {"type": "noise", "noise": "fbm"},
                    {"type": "decal", "position": [0, 0.5, 0], "direction": [0, -1, 0], "up": [0, 0, -1], "size": [1, 1, 1], "map": )" +
                 tiles + "}",
             R"({"procedural": {"type": "plane", "segments": 4}})", R"("double_sided": "flip",)",
             200, 150, R"(, "camera": {"position": [0.3, -1.2, 0.8], "target": [0, 0, 0]})")},
    };
    cases.insert(cases.end(), scenes.begin(), scenes.end());
    return cases;
}

// Adding a kind brings its scenes: a kind without one would be unchecked.
TEST(LayerImageCases, EveryKindHasAScene) {
    std::set<std::string> names;
    for (const LayerKind* k : layerKinds()) {
        EXPECT_FALSE(k->imageCases.empty()) << k->name << " has no image case";
        for (const KindImageCase& c : k->imageCases) {
            EXPECT_TRUE(names.insert(c.name).second) << "two cases named " << c.name;
            EXPECT_NE(c.layers.find(std::string("\"type\": \"") + k->name + "\""),
                      std::string::npos)
                << c.name << " does not use its kind " << k->name;
        }
    }
}

class LayerImage : public ::testing::TestWithParam<LayerCase> {};

TEST_P(LayerImage, GpuMatchesCpuReference) {
    Scene s = sceneFromJson(GetParam().json);
    SceneAssets a = loadAssets(s);

    const CpuOptions parity = gpuParityOptions();
    NormalRenders p = renderNormalsBoth(s, a, parity);
    size_t covered = countCovered(p.gpuPrim);
    ASSERT_GT(covered, 1000u) << "the view must show the surface";
    EXPECT_EQ(countNonFinite(p.gpuNormal), 0u);
    EXPECT_EQ(countNonFinite(p.cpuNormal), 0u);
    EXPECT_EQ(p.diff.nonFinite, 0u);
    EXPECT_LE(double(p.diff.coverageMismatch), 0.01 * double(covered));
    EXPECT_LE(p.diff.maxDeg, 0.05)
        << "parity max at (" << p.diff.maxX << ", " << p.diff.maxY << ")";

    NormalRenders r = renderNormalsBoth(s, a, CpuOptions{});
    EXPECT_EQ(r.diff.nonFinite, 0u);
    EXPECT_LE(r.diff.p50Deg, 0.3);
    EXPECT_LE(r.diff.p99Deg, GetParam().refP99Deg);
    std::printf(
        "[%s] parity: max %.5f deg | reference: p50 %.4f p90 %.4f p99 %.4f max %.3f deg, %zu px, "
        "%zu coverage mismatches\n",
        GetParam().name.c_str(), p.diff.maxDeg, r.diff.p50Deg, r.diff.p90Deg, r.diff.p99Deg,
        r.diff.maxDeg, r.diff.compared, r.diff.coverageMismatch);

    // The bumps are really there: the perturbed normal differs from the
    // base normal somewhere (a test of a no-op layer would pass the above).
    View v = makeView(s, a, 0, 0, Aov::BaseNormal);
    Image base = gpu().render(s, a, v);
    double maxTilt = 0.0;
    for (size_t i = 0; i < base.texelCount(); ++i) {
        if (p.gpuPrim.rgba(i).x <= 0.0f) continue;
        glm::vec3 n(p.gpuNormal.rgba(i)), b(base.rgba(i));
        maxTilt = std::max(
            maxTilt, double(glm::degrees(std::acos(std::clamp(glm::dot(n, b), -1.0f, 1.0f)))));
    }
    EXPECT_GT(maxTilt, 2.0) << "the layer did not perturb the normal";
}

// The same cases drawn by the programs carried to GLSL 3.30 and ES 3.00
// (GlRenderer::setDialect, sg::shaders::inDialect: what `surfgrad shader
// --target glsl330|es300` writes), against the CPU reference under the
// parity options above, with the same bound: the legacy paths of the
// shared source (frexp/ldexp and imulExtended from bit patterns, the
// feature layers unrolled, dFdx for dFdxFine, no `precise`) are exact or
// reorder binary32 operations only, and llvmpipe's dFdx is its dFdxFine
// (docs/engines.md). ES 3.00 has no gl_PrimitiveID, so the coverage mask is
// the GLSL 4.50 program's primitive ids.
TEST_P(LayerImage, LegacyDialectsMatchCpuReference) {
    Scene s = sceneFromJson(GetParam().json);
    SceneAssets a = loadAssets(s);
    const CpuOptions parity = gpuParityOptions();
    const View v = makeView(s, a, 0, 0, Aov::Normal);
    View p = v;
    p.aov = Aov::PrimId;
    const Image cpuNormal = renderCpu(s, a, v, parity), cpuPrim = renderCpu(s, a, p, parity);
    const Image gpuPrim = gpu().render(s, a, p);
    for (const sg::shaders::Target dialect :
         {sg::shaders::Target::Glsl330, sg::shaders::Target::Es300}) {
        gpu().setDialect(dialect);
        const Image gpuNormal = gpu().render(s, a, v);
        gpu().setDialect(sg::shaders::Target::Glsl450);
        const VectorImageDiff d = compareVectorImages(gpuNormal, cpuNormal, gpuPrim, cpuPrim);
        const char* name = sg::shaders::targetName(dialect);
        EXPECT_EQ(countNonFinite(gpuNormal), 0u) << name;
        EXPECT_GT(d.compared, 1000u) << name;
        EXPECT_LE(double(d.coverageMismatch), 0.01 * double(d.compared)) << name;
        EXPECT_LE(d.maxDeg, 0.05) << name << ": max at (" << d.maxX << ", " << d.maxY << ")";
        std::printf("[%s] %s: max %.5f deg over %zu px\n", GetParam().name.c_str(), name, d.maxDeg,
                    d.compared);
    }
}

INSTANTIATE_TEST_SUITE_P(Kinds, LayerImage, ::testing::ValuesIn(layerCases()),
                         [](const auto& tpi) { return std::string(tpi.param.name); });

// Blendshapes: a glTF weight animation sampled mid-way; the morphed mesh is
// re-uploaded (SceneAssets::meshVersion) and both renderers see the same
// shape. Same bounds as the layer cases.
TEST(Morph, AnimatedMorphSphereMidAnimation) {
    Scene s = sceneForModel(std::string(SURFGRAD_DATA_DIR) +
                            "/gltf/AnimatedMorphSphere/glTF/AnimatedMorphSphere.gltf");
    s.output.width = 200;
    s.output.height = 150;
    ASSERT_FALSE(s.meshes[0].morphKeys.empty()) << "the glTF weight animation becomes morph keys";
    SceneAssets a = loadAssets(s);
    View v0 = makeView(s, a, 0, 0, Aov::Normal);
    Image at0 = gpu().render(s, a, v0);
    uint64_t version = a.meshVersion;
    applyFrame(s, a, 0.5f * s.meshes[0].morphKeys.back().time);
    EXPECT_NE(a.meshVersion, version);
    const CpuOptions parity = gpuParityOptions();
    NormalRenders p = renderNormalsBoth(s, a, parity);
    EXPECT_GT(p.diff.compared, 2000u);
    EXPECT_EQ(p.diff.nonFinite, 0u);
    EXPECT_LE(p.diff.maxDeg, 0.05);
    // The shape moved: normals differ from frame 0 somewhere.
    double maxChange = 0.0;
    for (size_t i = 0; i < at0.texelCount(); ++i) {
        if (p.gpuPrim.rgba(i).x <= 0.0f || glm::length(glm::vec3(at0.rgba(i))) < 0.5f) continue;
        float c = glm::dot(glm::vec3(at0.rgba(i)), glm::vec3(p.gpuNormal.rgba(i)));
        maxChange =
            std::max(maxChange, double(glm::degrees(std::acos(std::clamp(c, -1.0f, 1.0f)))));
    }
    EXPECT_GT(maxChange, 5.0);
}

// Section 2.10 on a plane seen from BELOW (every fragment back-facing):
//   none   - n' = normalize(n - g): the front side's normal;
//   mirror - n' = normalize(-n - g): the normal component flips, the
//            tangential part (the bump) is the same;
//   flip   - n' = normalize(-n + g) = -(none).
// With n = +y, that is: mirror = none with y negated, flip = -none.
TEST(DoubleSided, BackFaceModesFollowSection210) {
    auto render = [](const char* mode) {
        Scene s = sceneFromJson(oneMaterialScene(
            R"({"type": "uv_normal", "map": {"procedural": "bricks", "size": 128}}, {"type": "noise", "amplitude": 0.01})",
            R"({"procedural": {"type": "plane", "segments": 2}})",
            std::string(R"("double_sided": ")") + mode + "\",", 120, 90,
            R"(, "camera": {"position": [0.2, -1.5, 0.6], "target": [0, 0, 0]})"));
        SceneAssets a = loadAssets(s);
        View v = makeView(s, a, 0, 0, Aov::Normal);
        return std::make_pair(gpu().render(s, a, v), renderCpu(s, a, v));
    };
    auto none = render("none"), mirror = render("mirror"), flip = render("flip");
    size_t n = 0;
    sg::test::Worst mirrorErr, flipErr, cpuAngle;
    for (size_t i = 0; i < none.first.texelCount(); ++i) {
        glm::vec3 a(none.first.rgba(i));
        if (glm::length(a) < 0.5f) continue; // background
        ++n;
        glm::vec3 m(mirror.first.rgba(i)), f(flip.first.rgba(i));
        // Same rasterisation and the same arithmetic up to sign flips:
        // float-rounding-level agreement (1e-5 on unit vectors).
        EXPECT_NEAR(m.x, a.x, 1e-5f);
        EXPECT_NEAR(m.y, -a.y, 1e-5f);
        EXPECT_NEAR(m.z, a.z, 1e-5f);
        EXPECT_NEAR(glm::length(f + a), 0.0f, 1e-5f);
        mirrorErr.add(glm::length(m - glm::vec3(a.x, -a.y, a.z)));
        flipErr.add(glm::length(f + a));
        // The front-side normal points up; seen from below in NONE mode it
        // still does (the paper's "perturbed normal remains the same").
        EXPECT_GT(a.y, 0.0f);
        // CPU reference agrees on the mode logic (its own bound: see above).
        glm::vec3 c(flip.second.rgba(i));
        if (glm::length(c) > 0.5f) {
            EXPECT_GT(glm::dot(c, f), std::cos(glm::radians(10.0f)));
            cpuAngle.add(glm::degrees(std::acos(std::clamp(double(glm::dot(c, f)), -1.0, 1.0))));
        }
    }
    EXPECT_GT(n, 1000u);
    // GPU values: llvmpipe's arithmetic (machine-dependent, see hardcase.h).
    sg::test::reportHardCase({"back-faces",
                              "a bumped plane seen from below, mirror mode, GPU (llvmpipe)",
                              "|n'(mirror) - n'(none) with y negated|", "<= 1e-05",
                              sg::test::hardCaseNumber(mirrorErr.value), false});
    sg::test::reportHardCase({"back-faces", "the same, flip mode, GPU", "|n'(flip) + n'(none)|",
                              "<= 1e-05", sg::test::hardCaseNumber(flipErr.value), false});
    sg::test::reportHardCase({"back-faces", "the same, flip mode, CPU reference vs GPU",
                              "angle between the two (deg)", "< 10",
                              sg::test::hardCaseNumber(cpuAngle.value), false});
}

TEST(DoubleSided, OffCullsBackFaces) {
    Scene s = sceneFromJson(
        oneMaterialScene("", R"({"procedural": {"type": "plane"}})", "", 64, 48,
                         R"(, "camera": {"position": [0, -2, 0.5], "target": [0, 0, 0]})"));
    SceneAssets a = loadAssets(s);
    View v = makeView(s, a, 0, 0, Aov::PrimId);
    EXPECT_EQ(countCovered(gpu().render(s, a, v)), 0u);
    EXPECT_EQ(countCovered(renderCpu(s, a, v)), 0u);
    sg::test::reportHardCaseHolds("back-faces", "a plane seen from below, double_sided off",
                                  "covered pixels, GPU and CPU", "0", "0");
}

// glTF's material.doubleSided (sec. 3.9.5) when a model is framed with
// sceneForModel: false (written, or absent as in BoxTextured) culls back
// faces, true renders them in mirror mode. Seen from the opposite side of
// the default camera, the single-sided plane of MorphPrimitivesTest
// vanishes in both renderers (all but the few pixels of its morphed bump's
// side faces that really face that camera: under 5% of what the same model
// shows in mirror mode); the double-sided NormalTangentTest does not.
TEST(DoubleSided, GltfModelsFollowTheirMaterialsDoubleSidedFlag) {
    auto model = [](const char* name) {
        return std::string(SURFGRAD_DATA_DIR) + "/gltf/" + name + "/glTF/" + name + ".gltf";
    };
    struct Case {
        const char* name;
        bool doubleSided;
    };
    for (const Case& c : {Case{"MorphPrimitivesTest", false}, Case{"BoxTextured", false},
                          Case{"NormalTangentTest", true}}) {
        SCOPED_TRACE(c.name);
        sg::mesh::Scene file = sg::mesh::loadScene(model(c.name));
        ASSERT_FALSE(file.materials.empty());
        for (const auto& m : file.materials) EXPECT_EQ(m.doubleSided, c.doubleSided);
        Scene s = sceneForModel(model(c.name));
        for (const auto& m : s.materials)
            EXPECT_EQ(m.doubleSided, c.doubleSided ? DoubleSided::Mirror : DoubleSided::Off);
    }
    auto coverage = [](Scene s, bool fromBehind) {
        s.output.width = 96;
        s.output.height = 72;
        if (fromBehind) { // the automatic camera's direction reversed
            s.camera.azimuthDeg += 180.0f;
            s.camera.elevationDeg = -s.camera.elevationDeg;
        }
        SceneAssets a = loadAssets(s);
        View v = makeView(s, a, 0, 0, Aov::PrimId);
        return std::make_pair(countCovered(gpu().render(s, a, v)),
                              countCovered(renderCpu(s, a, v)));
    };
    Scene single = sceneForModel(model("MorphPrimitivesTest"));
    auto front = coverage(single, false), back = coverage(single, true);
    EXPECT_GT(front.first, 500u);
    EXPECT_GT(front.second, 500u);
    Scene forced = single;
    for (auto& m : forced.materials) m.doubleSided = DoubleSided::Mirror;
    auto backMirror = coverage(forced, true);
    EXPECT_GT(backMirror.first, 500u);
    EXPECT_LT(double(back.first), 0.05 * double(backMirror.first))
        << "single-sided: back faces culled (GPU)";
    EXPECT_LT(double(back.second), 0.05 * double(backMirror.second))
        << "single-sided: back faces culled (CPU)";
    Scene twoSided = sceneForModel(model("NormalTangentTest"));
    auto twoBack = coverage(twoSided, true);
    EXPECT_GT(twoBack.first, 500u);
    EXPECT_GT(twoBack.second, 500u);
}

// glTF sample models through the whole pipeline (mesh module loader, base
// colour and normal maps, MikkTSpace tangents): the per-pixel frame
// (listing 6) against MikkTSpace vertex tangents (section 2.2) on the same
// views. In general they differ where the UV mapping is not a similarity of
// the surface (the per-pixel frame is orthonormal, MikkTSpace's need not
// be) and where MikkTSpace averages tangents across triangles. These two
// models put their normal maps on planar cells with affine, conformal UVs
// (mirrored in the mirror test), where both frames are the same up to
// interpolation and rounding: p99 <= 0.5 degrees, max <= 2 (measured 0.06
// and 0.11). A larger difference means a wrong frame or green convention.
void compareTangentFrames(const char* model) {
    std::string path =
        std::string(SURFGRAD_DATA_DIR) + "/gltf/" + model + "/glTF/" + model + ".gltf";
    Scene s = sceneForModel(path);
    s.output.width = 256;
    s.output.height = 256;
    SceneAssets pixelAssets = loadAssets(s);
    Scene mk = s;
    for (auto& m : mk.meshes) m.tangents = {TangentSource::MikkTSpace};
    SceneAssets mikkAssets = loadAssets(mk);
    ASSERT_FALSE(mikkAssets.meshes[0].vertexTangents[0].empty());
    View v = makeView(s, pixelAssets, 0, 0, Aov::Normal);
    View pv = v;
    pv.aov = Aov::PrimId;
    Image np = gpu().render(s, pixelAssets, v), pp = gpu().render(s, pixelAssets, pv);
    // MikkTSpace may split vertices but keeps triangle order: primids match.
    Image nm = gpu().render(mk, mikkAssets, v), pm = gpu().render(mk, mikkAssets, pv);
    VectorImageDiff d = compareVectorImages(np, nm, pp, pm);
    EXPECT_EQ(countNonFinite(np), 0u);
    EXPECT_EQ(countNonFinite(nm), 0u);
    EXPECT_GT(d.compared, 5000u);
    EXPECT_LE(d.p99Deg, 0.5);
    EXPECT_LE(d.maxDeg, 2.0);
    // Where: the share of pixels by angle band, and the worst pixel.
    size_t over1 = 0, over5 = 0;
    for (size_t i = 0; i < np.texelCount(); ++i) {
        if (pp.rgba(i).x <= 0 || pp.rgba(i).x != pm.rgba(i).x) continue;
        float ang = glm::degrees(std::acos(
            std::clamp(glm::dot(glm::vec3(np.rgba(i)), glm::vec3(nm.rgba(i))), -1.0f, 1.0f)));
        over1 += ang > 1.0f;
        over5 += ang > 5.0f;
    }
    std::printf("[%s] pixel vs mikktspace frames (normal AOV, %zu px): mean %.3f p50 %.3f p90 %.3f "
                "p99 %.3f max %.2f deg "
                "at (%d, %d); %.2f%% of pixels > 1 deg, %.2f%% > 5 deg\n",
                model, d.compared, d.meanDeg, d.p50Deg, d.p90Deg, d.p99Deg, d.maxDeg, d.maxX,
                d.maxY, 100.0 * double(over1) / double(d.compared),
                100.0 * double(over5) / double(d.compared));
}

TEST(TangentFrames, NormalTangentTestPixelVsMikkTSpace) {
    compareTangentFrames("NormalTangentTest");
}
TEST(TangentFrames, NormalTangentMirrorTestPixelVsMikkTSpace) {
    compareTangentFrames("NormalTangentMirrorTest");
}

// The three tangent sources on a curved, subdivided mesh (spot's cage at
// level 2, its own UVs, a bricks normal map): per-pixel frame (listing 6),
// MikkTSpace vertex tangents and exact limit-surface tangents (both with
// the section 2.2 basis). Here the frames really differ: MikkTSpace and
// limit tangents follow dP/ds of the (non-conformal) UV map, the per-pixel
// frame is orthonormal. The bounds only catch a broken frame (a flipped
// axis moves the median by tens of degrees): median <= 3, p99 <= 25.
TEST(TangentFrames, SpotPixelVsMikkTSpaceVsLimit) {
    std::string spot = std::string(SURFGRAD_DATA_DIR) + "/meshes/spot/spot_control_mesh.obj";
    auto scene = [&](const char* tangents, bool limit) {
        return sceneFromJson(oneMaterialScene(
            R"({"type": "uv_normal", "map": {"procedural": "bricks", "size": 512}})",
            R"({"file": ")" + spot + R"(", "subdivision": {"level": 2, "limit": )" +
                (limit ? "true" : "false") + R"(}, "tangents": [")" + tangents + "\"]}",
            "", 320, 240));
    };
    Scene sp = scene("pixel", true), sm = scene("mikktspace", true), sl = scene("limit", true);
    SceneAssets ap = loadAssets(sp), am = loadAssets(sm), al = loadAssets(sl);
    View v = makeView(sp, ap, 0, 0, Aov::Normal), pv = v;
    pv.aov = Aov::PrimId;
    Image np = gpu().render(sp, ap, v), pp = gpu().render(sp, ap, pv);
    Image nm = gpu().render(sm, am, v), pm = gpu().render(sm, am, pv);
    Image nl = gpu().render(sl, al, v), pl = gpu().render(sl, al, pv);
    auto report = [](const char* what, const VectorImageDiff& d) {
        std::printf("[spot L2] %s: %zu px, mean %.3f p50 %.3f p90 %.3f p99 %.3f max %.2f deg\n",
                    what, d.compared, d.meanDeg, d.p50Deg, d.p90Deg, d.p99Deg, d.maxDeg);
        EXPECT_GT(d.compared, 5000u);
        EXPECT_LE(d.p50Deg, 3.0);
        EXPECT_LE(d.p99Deg, 25.0);
    };
    report("pixel vs mikktspace", compareVectorImages(np, nm, pp, pm));
    report("pixel vs limit", compareVectorImages(np, nl, pp, pl));
    report("mikktspace vs limit", compareVectorImages(nm, nl, pm, pl));
}

TEST(DefaultScene, RendersWithoutNaNAndMatchesTheCpuReference) {
    Scene s = defaultScene();
    s.output.width = 240;
    s.output.height = 135;
    SceneAssets a = loadAssets(s);
    View v = makeView(s, a, 0, 0, Aov::Color);
    Image g = gpu().render(s, a, v), c = renderCpu(s, a, v);
    EXPECT_EQ(countNonFinite(g), 0u);
    EXPECT_EQ(countNonFinite(c), 0u);
    // Colour after tone mapping: mean absolute difference per channel.
    // The normals differ as bounded above; the display values by less than
    // 1% on average (measured 0.2%).
    double sum = 0;
    for (size_t i = 0; i < g.texelCount(); ++i) {
        glm::vec3 dg = sg::glsl::sgToneMap(glm::vec3(g.rgba(i)), 1.0f),
                  dc = sg::glsl::sgToneMap(glm::vec3(c.rgba(i)), 1.0f);
        sum += double(std::abs(dg.x - dc.x) + std::abs(dg.y - dc.y) + std::abs(dg.z - dc.z)) / 3.0;
    }
    EXPECT_LT(sum / double(g.texelCount()), 0.01);
}

} // namespace
} // namespace sg::render::test
