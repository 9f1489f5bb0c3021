// Tangent sources per UV set ("tangent source pixel|mikktspace|limit per UV
// set") and derived UV sets of mesh files (the mesh-level "uv_sets"
// field, docs/scene.md):
//  - every UV set that asks for vertex tangents gets exactly what the mesh
//    module computes for that set alone (sg::mesh::generateLimitTangents,
//    generateMikkTSpaceTangents), compared corner by corner and bit for bit,
//    also when MikkTSpace splits vertices for one set after another;
//  - effects on demand: only sets whose enabled layers read the tangent
//    basis get tangents, and only those reach the programs; a scene with
//    per-pixel frames only has no tangent attribute in either stage (after
//    the GLSL preprocessor); enabling a layer later (the viewer) rebuilds
//    the mesh with the new set and both renderers still agree;
//  - derived sets are the affine map of their source, on the limit
//    surface too (UV derivatives mapped by the linear part).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "cli.h"
#include "render_test_util.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"

namespace sg::render::test {
namespace {

namespace fs = std::filesystem;
namespace sm = sg::mesh;

const std::string kSpot = std::string(SURFGRAD_DATA_DIR) + "/meshes/spot/spot_control_mesh.obj";

fs::path scratch(const std::string& name) {
    fs::path p = fs::path(SURFGRAD_BINARY_DIR) / "tests/render/tangent_sets" / name;
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

// A uv_normal layer on UV set k (small procedural maps: the frames are the
// subject, not the maps).
std::string uvLayer(int set, bool enabled = true) {
    static const char* maps[] = {"bricks", "tiles", "weave", "bumps"};
    return std::string(R"({"type": "uv_normal", "uv_set": )") + std::to_string(set) +
           R"(, "enabled": )" + (enabled ? "true" : "false") +
           R"(, "strength": 0.8, "map": {"procedural": ")" + maps[set] + R"(", "size": 64}})";
}

// Expected derived set: R(deg) (scale * st) + offset, in double.
glm::vec2 affine(glm::vec2 st, glm::vec2 scale, double deg, glm::vec2 offset) {
    double a = deg * 3.14159265358979323846 / 180.0, c = std::cos(a), s = std::sin(a);
    double x = double(scale.x) * st.x, y = double(scale.y) * st.y;
    return glm::vec2(float(c * x - s * y + offset.x), float(s * x + c * y + offset.y));
}

// Spot's cage at level 2 on the limit surface with a derived second set:
// set 0 limit tangents, set 1 (8x, rotated 30 degrees, offset) MikkTSpace.
TEST(TangentSets, LimitAndMikkTSpaceOnTwoSetsMatchTheMeshModule) {
    const glm::vec2 scale(8.0f, 6.0f), offset(0.25f, -0.5f);
    const double deg = 30.0;
    Scene s = sceneFromJson(
        oneMaterialScene(uvLayer(0) + ", " + uvLayer(1),
                         R"({"file": ")" + kSpot + R"(", "subdivision": {"level": 2, "limit": true},
                                                 "uv_sets": [{"from": 0, "scale": [8, 6], "rotate_deg": 30, "offset": [0.25, -0.5]}],
                                                 "tangents": ["limit", "mikktspace"]})"));
    SceneAssets a = loadAssets(s);
    const MeshAsset& got = a.meshes[0];
    ASSERT_EQ(got.mesh.uvSets.size(), 2u);
    ASSERT_EQ(got.vertexTangents.size(), 2u);
    ASSERT_EQ(got.vertexTangents[0].size(), got.mesh.vertexCount());
    ASSERT_EQ(got.vertexTangents[1].size(), got.mesh.vertexCount());

    // The same refinement through the mesh module directly.
    sm::PolygonMesh cage = sm::loadPolygonMesh(kSpot);
    sm::SubdivisionSettings st;
    st.level = 2;
    st.options = cage.options;
    st.limit = true;
    sm::Subdivider sub(cage, st, kSpot);
    sm::RenderMesh ref = sub.renderMesh();
    ASSERT_EQ(ref.indices.size(), got.mesh.indices.size()) << "tangents never change the triangles";

    // Set 0: generateLimitTangents (neighbour fallback, orthogonal to the
    // stored normal), no vertex split.
    sm::RenderMesh lim = ref;
    sm::generateLimitTangents(lim, sub.limitFrame(), 0);
    // Set 1: the derived set as the renderer stored it, then MikkTSpace
    // on that set alone.
    sm::RenderMesh mk = ref;
    mk.uvSets.resize(2, std::vector<glm::vec2>(ref.vertexCount()));
    for (size_t c = 0; c < ref.indices.size(); ++c)
        mk.uvSets[1][ref.indices[c]] = got.mesh.uvSets[1][got.mesh.indices[c]];
    sm::generateMikkTSpaceTangents(mk, 1);

    size_t badUv = 0, badLimit = 0, badMikk = 0, badPos = 0;
    // The derived set is read by a repeating map only: stored moved by the
    // whole units of its centre (uv_sets.cpp), the same for every value.
    glm::vec2 lo(1e30f), hi(-1e30f);
    for (const glm::vec2& v : got.mesh.uvSets[1]) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
    }
    EXPECT_LT(std::max(std::fabs(0.5f * (lo.x + hi.x)), std::fabs(0.5f * (lo.y + hi.y))), 1.0f);
    const glm::vec2 shift = glm::round(affine(ref.uvSets[0][ref.indices[0]], scale, deg, offset) -
                                       got.mesh.uvSets[1][got.mesh.indices[0]]);
    for (size_t c = 0; c < ref.indices.size(); ++c) {
        const uint32_t g = got.mesh.indices[c], r = ref.indices[c];
        badPos += got.mesh.positions[g] != ref.positions[r];
        // Derived set: the affine map of set 0 minus the whole-unit shift
        // (float rounding of values up to ~10: 1e-5).
        glm::vec2 want = affine(ref.uvSets[0][r], scale, deg, offset) - shift;
        badUv += glm::length(got.mesh.uvSets[1][g] - want) > 1e-5f;
        badLimit += got.vertexTangents[0][g] != lim.tangents[r];
        badMikk += got.vertexTangents[1][g] != mk.tangents[mk.indices[c]];
    }
    EXPECT_EQ(badPos, 0u);
    EXPECT_EQ(badUv, 0u);
    EXPECT_EQ(badLimit, 0u) << "set 0 must be generateLimitTangents' output, bit for bit";
    EXPECT_EQ(badMikk, 0u) << "set 1 must be MikkTSpace of the derived set, bit for bit";

    // Both sets reach the program as vertex attributes, set 2/3 do not exist.
    MaterialPlan plan = planMaterial(s, a, 0, 0);
    EXPECT_EQ(plan.vertexTangentMask, 3u);
    EXPECT_NE(plan.signature.find("uvn@uv0v"), std::string::npos) << plan.signature;
    EXPECT_NE(plan.signature.find("uvn@uv1v"), std::string::npos) << plan.signature;
}

// Limit tangents on a derived set: its limit UV derivatives are those of
// its source through the map's linear part (chain rule), so
// generateLimitTangents on a mesh-module copy with those derivatives
// (mapped here in double) must give the renderer's set 1; and they are not
// set 0's (the derived chart is rotated and mirrored).
TEST(TangentSets, LimitTangentsOnADerivedSetUseTheMappedUvDerivatives) {
    Scene s = sceneFromJson(oneMaterialScene(
        uvLayer(1), R"({"file": ")" + kSpot + R"(", "subdivision": {"level": 1, "limit": true},
                                                 "uv_sets": [{"scale": [4, -2], "rotate_deg": 75}],
                                                 "tangents": ["pixel", "limit"]})"));
    SceneAssets a = loadAssets(s);
    const MeshAsset& got = a.meshes[0];
    EXPECT_TRUE(got.vertexTangents[0].empty()) << "set 0 asked for pixel frames";
    ASSERT_EQ(got.vertexTangents[1].size(), got.mesh.vertexCount());

    sm::PolygonMesh cage = sm::loadPolygonMesh(kSpot);
    sm::SubdivisionSettings st;
    st.level = 1;
    st.options = cage.options;
    st.limit = true;
    sm::Subdivider sub(cage, st, kSpot);
    sm::RenderMesh ref = sub.renderMesh();
    sm::LimitFrame frame = sub.limitFrame();
    // The map's linear part, independently: rotation by 75 degrees after a
    // (4, -2) scale.
    double ang = 75.0 * 3.14159265358979323846 / 180.0;
    glm::dmat2 lin = glm::dmat2(std::cos(ang), std::sin(ang), -std::sin(ang), std::cos(ang)) *
                     glm::dmat2(4.0, 0.0, 0.0, -2.0);
    auto map = [&](const std::vector<glm::vec2>& v) {
        std::vector<glm::vec2> out(v.size());
        for (size_t i = 0; i < v.size(); ++i) out[i] = glm::vec2(lin * glm::dvec2(v[i]));
        return out;
    };
    ref.uvSets.push_back(map(ref.uvSets[0]));
    frame.dUVdu.push_back(map(frame.dUVdu[0]));
    frame.dUVdv.push_back(map(frame.dUVdv[0]));
    sm::generateLimitTangents(ref, frame, 1);
    ASSERT_EQ(ref.vertexCount(), got.mesh.vertexCount()) << "limit tangents split no vertex";
    // The renderer maps in float, this test in double: tangents agree to
    // float rounding of a well-conditioned chain rule (1e-4 rad at the
    // worst conditioning generateLimitTangents accepts as regular), and the
    // handedness exactly (the map mirrors: det < 0 flips w everywhere).
    size_t far = 0, signs = 0;
    for (size_t v = 0; v < ref.vertexCount(); ++v) {
        far +=
            glm::length(glm::vec3(got.vertexTangents[1][v]) - glm::vec3(ref.tangents[v])) > 1e-3f;
        signs += got.vertexTangents[1][v].w != ref.tangents[v].w;
    }
    EXPECT_LE(far, ref.vertexCount() / 1000) << "of " << ref.vertexCount();
    EXPECT_EQ(signs, 0u);
    // And set 1's tangents are not set 0's: the derived chart is rotated.
    sm::RenderMesh base = sub.renderMesh();
    sm::generateLimitTangents(base, sub.limitFrame(), 0);
    size_t rotated = 0;
    for (size_t v = 0; v < base.vertexCount(); ++v) {
        rotated +=
            glm::dot(glm::vec3(base.tangents[v]), glm::vec3(got.vertexTangents[1][v])) < 0.9f;
    }
    EXPECT_GT(rotated, base.vertexCount() / 2);
}

// A grid whose three UV sets fold at different lines: set 0 is regular,
// set 1 is mirrored about s = 0.5 and set 2 about t = 0.5, so MikkTSpace
// must split the vertices on the fold of set 1, and then those on the fold
// of set 2 (which already carry set 0's and set 1's tangents).
fs::path writeFoldedGrid(const fs::path& dir) {
    sm::RenderMesh m;
    m.name = "folded";
    const int n = 8;
    m.uvSets.resize(3);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            float u = float(i) / float(n), v = float(j) / float(n);
            // A gentle bump so normals vary.
            m.positions.emplace_back(u - 0.5f, 0.1f * std::sin(3.0f * u) * std::cos(2.0f * v),
                                     0.5f - v);
            m.uvSets[0].emplace_back(u, v);
            m.uvSets[1].emplace_back(0.5f - std::abs(u - 0.5f), v);
            m.uvSets[2].emplace_back(u, 0.5f - std::abs(v - 0.5f));
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
            for (uint32_t x : {a, b, d, a, d, c}) m.indices.push_back(x);
        }
    sm::computeVertexNormals(m);
    fs::path file = dir / "folded.gltf";
    sm::writeRenderMesh(file, m);
    return file;
}

TEST(TangentSets, MikkTSpaceOnThreeSetsSplitsVerticesForEachAndKeepsTheOthers) {
    fs::path file = writeFoldedGrid(scratch("folded"));
    Scene s = sceneFromJson(
        oneMaterialScene(uvLayer(0) + ", " + uvLayer(1) + ", " + uvLayer(2),
                         R"({"file": ")" + file.string() +
                             R"(", "tangents": ["mikktspace", "mikktspace", "mikktspace"]})",
                         R"("double_sided": "mirror",)", 160, 120,
                         R"(, "camera": {"position": [0.3, 1.2, 0.9], "target": [0, 0, 0]})"));
    SceneAssets a = loadAssets(s);
    const MeshAsset& got = a.meshes[0];
    sm::RenderMesh ref = sm::loadRenderMesh(file);
    EXPECT_GT(got.mesh.vertexCount(), ref.vertexCount() + 8)
        << "the folds of sets 1 and 2 split vertices";
    for (int k = 0; k < 3; ++k) {
        SCOPED_TRACE("UV set " + std::to_string(k));
        sm::RenderMesh one = ref;
        sm::generateMikkTSpaceTangents(one, k);
        ASSERT_EQ(got.vertexTangents[size_t(k)].size(), got.mesh.vertexCount());
        size_t bad = 0;
        for (size_t c = 0; c < ref.indices.size(); ++c) {
            const uint32_t g = got.mesh.indices[c];
            bad += got.vertexTangents[size_t(k)][g] != one.tangents[one.indices[c]];
            bad += got.mesh.positions[g] != ref.positions[ref.indices[c]];
            for (size_t u = 0; u < 3; ++u)
                bad += got.mesh.uvSets[u][g] != ref.uvSets[u][ref.indices[c]];
        }
        EXPECT_EQ(bad, 0u)
            << "every corner keeps its attributes and gets this set's own MikkTSpace tangent";
    }
    // Both renderers read the three tangent attributes alike.
    CpuOptions parity;
    parity.derivatives = CpuDerivatives::Quad;
    parity.textureLod = sg::glsl::LodRule::FastLog2;
    NormalRenders p = renderNormalsBoth(s, a, parity);
    EXPECT_GT(p.diff.compared, 3000u);
    EXPECT_EQ(p.diff.nonFinite, 0u);
    EXPECT_LE(p.diff.maxDeg, 0.05) << "the parity bound of image_test.cpp";
}

// glslangValidator -E: the program text after the GLSL preprocessor (the
// vertex and fragment stages keep their tangent inputs behind
// #if SG_VTX_TANGENT_k, so a text search before preprocessing would see them).
std::string preprocessed(const std::string& text, const std::string& tag, const char* stage) {
    fs::path dir = scratch("pre_" + tag);
    fs::path in = dir / (std::string("p.") + stage);
    std::ofstream(in) << text;
    const std::string cmd = std::string(SURFGRAD_GLSLANG) + " -E " + in.string();
    const sg::test::CommandResult r = sg::test::runCommand(cmd);
    EXPECT_EQ(r.exitCode, 0) << cmd;
    return r.output();
}

struct Stages {
    std::string vertex, fragment;
};

Stages programStages(const Scene& s, const SceneAssets& a, const std::string& tag) {
    ProgramSource src = assembleProgram(planMaterial(s, a, 0, 0));
    return {preprocessed(src.vertex, tag, "vert"), preprocessed(src.fragment, tag, "frag")};
}

TEST(TangentSets, OnlyTheSetsThatNeedVertexTangentsGetThem) {
    const std::string sphere2 =
        R"({"procedural": {"type": "sphere", "segments": 24, "uv_sets": 3}})";
    auto meshWith = [&](const std::string& tangents) {
        return sphere2.substr(0, sphere2.size() - 1) + R"(, "tangents": )" + tangents + "}";
    };
    const char* tangentCode[] = {"aTangent", "vTangent", "sgUvFrameVertex", "sgMikktsBasis"};

    // Per-pixel frames only (the default): no tangent attribute or code in
    // either stage, and no tangents generated.
    {
        Scene s = sceneFromJson(oneMaterialScene(uvLayer(0) + ", " + uvLayer(1), sphere2));
        SceneAssets a = loadAssets(s);
        for (const auto& t : a.meshes[0].vertexTangents) EXPECT_TRUE(t.empty());
        Stages st = programStages(s, a, "pixel");
        ASSERT_NE(st.fragment.find("sgUvFramePixel"), std::string::npos)
            << "preprocessed text expected";
        for (const char* m : tangentCode) {
            EXPECT_EQ(st.vertex.find(m), std::string::npos) << m << " in the vertex stage";
            EXPECT_EQ(st.fragment.find(m), std::string::npos) << m << " in the fragment stage";
        }
    }
    // Sets 0 and 2 ask for MikkTSpace; set 2's only layer is disabled and
    // set 1 (pixel) has a layer: only set 0 gets tangents and an attribute.
    {
        Scene s = sceneFromJson(
            oneMaterialScene(uvLayer(0) + ", " + uvLayer(1) + ", " + uvLayer(2, false),
                             meshWith(R"(["mikktspace", "pixel", "mikktspace"])")));
        SceneAssets a = loadAssets(s);
        EXPECT_FALSE(a.meshes[0].vertexTangents[0].empty());
        EXPECT_TRUE(a.meshes[0].vertexTangents[1].empty());
        EXPECT_TRUE(a.meshes[0].vertexTangents[2].empty()) << "no enabled layer reads set 2";
        Stages st = programStages(s, a, "set0");
        for (std::string stage : {st.vertex, st.fragment}) {
            EXPECT_NE(stage.find("vTangent0"), std::string::npos);
            EXPECT_EQ(stage.find("vTangent1"), std::string::npos);
            EXPECT_EQ(stage.find("vTangent2"), std::string::npos);
        }
        EXPECT_NE(st.vertex.find("aTangent0"), std::string::npos);
        EXPECT_EQ(st.vertex.find("aTangent2"), std::string::npos);

        // The viewer enables set 2's layer: the mesh is rebuilt with set 2's
        // tangents (MikkTSpace may re-split), the GPU re-uploads the new
        // layout and both renderers agree.
        uint64_t version = a.meshVersion, layout = a.meshes[0].layoutId;
        gpu().render(s, a, makeView(s, a, 120, 90, Aov::Normal)); // uploads the old layout
        s.materials[0].layers[2].enabled = true;
        loadMissingAssets(s, a);
        EXPECT_NE(a.meshVersion, version);
        EXPECT_NE(a.meshes[0].layoutId, layout);
        EXPECT_FALSE(a.meshes[0].vertexTangents[2].empty());
        EXPECT_EQ(planMaterial(s, a, 0, 0).vertexTangentMask, 5u);
        s.output.width = 120;
        s.output.height = 90;
        CpuOptions parity;
        parity.derivatives = CpuDerivatives::Quad;
        parity.textureLod = sg::glsl::LodRule::FastLog2;
        NormalRenders p = renderNormalsBoth(s, a, parity);
        EXPECT_GT(p.diff.compared, 1500u); // the sphere covers about 2000 pixels at 120x90
        EXPECT_EQ(p.diff.nonFinite, 0u);
        EXPECT_LE(double(p.diff.coverageMismatch), 0.01 * double(p.diff.compared));
        EXPECT_LE(p.diff.maxDeg, 0.05) << "the parity bound of image_test.cpp";
        // Nothing more to do on a second call.
        version = a.meshVersion;
        loadMissingAssets(s, a);
        EXPECT_EQ(a.meshVersion, version);
    }
    // Layers that never read a vertex basis: texel-space derivative maps,
    // height maps and layers inside post_resolve groups (per-pixel frames
    // of the resolved normal, section 2.11).
    {
        std::string layers =
            R"({"type": "deriv_map", "uv_set": 0, "space": "texel", "map": {"procedural": "weave", "output": "derivative", "size": 32}},
               {"type": "height", "uv_set": 1, "map": {"procedural": "bumps", "output": "height", "size": 32}},
               {"type": "post_resolve", "layers": [)" +
            uvLayer(2) + "]}";
        Scene s = sceneFromJson(
            oneMaterialScene(layers, meshWith(R"(["mikktspace", "mikktspace", "mikktspace"])")));
        EXPECT_EQ(tangentBasisUvSets(s.materials[0]), 0u);
        SceneAssets a = loadAssets(s);
        for (const auto& t : a.meshes[0].vertexTangents) EXPECT_TRUE(t.empty());
        Stages st = programStages(s, a, "nobasis");
        for (const char* m : tangentCode) {
            EXPECT_EQ(st.vertex.find(m), std::string::npos) << m;
            EXPECT_EQ(st.fragment.find(m), std::string::npos) << m;
        }
    }
}

// Whole-unit re-centring of UV sets (uv_sets.cpp): a derived set offset by
// (1e4, -2e4), computed in binary64, is stored moved by the whole units of
// its centre when only repeating maps read it: every value is then the
// binary64 value minus that shift, rounded once (bit for bit), the centre
// within a unit of 0. Read by a clamped map (or a feature layer, whose maps
// are clamped at their border) it keeps its coordinates: the map would not
// sample the same texels after a shift.
TEST(UvSets, RepeatOnlySetsAreRecentredExactly) {
    auto scene = [](const std::string& layer) {
        return sceneFromJson(oneMaterialScene(
            layer,
            R"({"procedural": {"type": "sphere", "size": 1, "segments": 16, "uv_sets": 1},
                "uv_sets": [{"from": 0, "scale": 8, "offset": [10000, -20000]}]})"));
    };
    const std::string repeat =
        R"({"type": "uv_normal", "uv_set": 1, "map": {"procedural": "weave", "size": 16}})";
    const std::string clamp =
        R"({"type": "uv_normal", "uv_set": 1, "map": {"procedural": "weave", )"
        R"("size": 16, "wrap": "clamp"}})";
    const std::string feature =
        R"({"type": "feature", "uv_set": 1, "curves": {"svg": "data:svg/flame.svg", "size": 32}})";
    for (const std::string* layer : {&repeat, &clamp, &feature}) {
        const Scene s = scene(*layer);
        const SceneAssets a = loadAssets(s);
        const auto& set0 = a.meshes[0].mesh.uvSets[0];
        const auto& set1 = a.meshes[0].mesh.uvSets[1];
        ASSERT_EQ(set0.size(), set1.size());
        // The exact values and their centre's whole units (set 0 spans
        // [0, 1]^2, so set 1 spans [1e4, 1e4 + 8] x [-2e4, -2e4 + 8]).
        const glm::dvec2 shift = layer == &repeat ? glm::dvec2(10004.0, -19996.0) : glm::dvec2(0.0);
        size_t bad = 0;
        glm::vec2 lo(1e30f), hi(-1e30f);
        for (size_t i = 0; i < set0.size(); ++i) {
            const glm::dvec2 exact = 8.0 * glm::dvec2(set0[i]) + glm::dvec2(1e4, -2e4);
            bad += set1[i] != glm::vec2(exact - shift);
            lo = glm::min(lo, set1[i]);
            hi = glm::max(hi, set1[i]);
        }
        EXPECT_EQ(bad, 0u) << *layer;
        const glm::vec2 centre = 0.5f * (lo + hi);
        if (layer == &repeat) {
            EXPECT_LT(std::max(std::fabs(centre.x), std::fabs(centre.y)), 1.0f);
        } else {
            EXPECT_GT(std::fabs(centre.x), 9000.0f) << *layer;
        }
    }
}

} // namespace
} // namespace sg::render::test
