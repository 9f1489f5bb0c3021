// glTF input (tinygltf + our checks): UV sets, tangents, morph targets,
// animations, node transforms, materials; hostile files give InputError
// naming the accessor/node/chunk.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include <glm/geometric.hpp>

#include "mesh_test_util.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

using namespace sg::mesh;
using nlohmann::json;
using sg::test::dataPath;
using sg::test::expectInputError;

std::string readBytes(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Raw float accessor through tinygltf only (the oracle for our reader).
std::vector<float> rawFloats(const tinygltf::Model& m, int acc) {
    const auto& a = m.accessors[size_t(acc)];
    const auto& v = m.bufferViews[size_t(a.bufferView)];
    const auto& b = m.buffers[size_t(v.buffer)];
    int comps = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    size_t stride = v.byteStride ? v.byteStride : size_t(comps) * 4;
    std::vector<float> out(a.count * size_t(comps));
    for (size_t i = 0; i < a.count; ++i)
        std::memcpy(&out[i * size_t(comps)], &b.data[v.byteOffset + a.byteOffset + i * stride],
                    size_t(comps) * 4);
    return out;
}

tinygltf::Model rawModel(const std::filesystem::path& p) {
    tinygltf::TinyGLTF loader;
    tinygltf::Model m;
    std::string err, warn;
    loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int,
                             const unsigned char*, int, void*) { return true; },
                          nullptr);
    EXPECT_TRUE(p.extension() == ".glb" ? loader.LoadBinaryFromFile(&m, &err, &warn, p.string())
                                        : loader.LoadASCIIFromFile(&m, &err, &warn, p.string()))
        << err;
    return m;
}

TEST(Gltf, MultiUvTestHasTwoFlippedUvSets) {
    for (const char* file : {"gltf/MultiUVTest/glTF/MultiUVTest.gltf",
                             "gltf/MultiUVTest/glTF-Binary/MultiUVTest.glb"}) {
        Scene scene = loadScene(dataPath(file));
        ASSERT_EQ(scene.instances.size(), 1u) << file;
        const RenderMesh& m = scene.instances[0].mesh;
        ASSERT_EQ(m.uvSets.size(), 2u);
        tinygltf::Model raw = rawModel(dataPath(file));
        const auto& attrs = raw.meshes[0].primitives[0].attributes;
        for (int set = 0; set < 2; ++set) {
            std::vector<float> uv = rawFloats(raw, attrs.at("TEXCOORD_" + std::to_string(set)));
            ASSERT_EQ(uv.size(), 2 * m.vertexCount());
            for (size_t i = 0; i < m.vertexCount(); ++i) {
                EXPECT_EQ(m.uvSets[size_t(set)][i].x, uv[2 * i]);
                EXPECT_EQ(m.uvSets[size_t(set)][i].y, 1.0f - uv[2 * i + 1]); // t up
            }
        }
        ASSERT_EQ(m.tangents.size(), m.vertexCount());
        for (const auto& t : m.tangents) EXPECT_TRUE(t.w == 1.0f || t.w == -1.0f);
        ASSERT_EQ(scene.materials.size(), 1u);
        // .gltf names the image file; .glb embeds it (no path).
        if (std::string(file).ends_with(".gltf"))
            EXPECT_TRUE(scene.materials[0].baseColorTexture.ends_with("uv0.png"));
        else
            EXPECT_TRUE(scene.materials[0].baseColorTexture.empty());
        EXPECT_EQ(scene.instances[0].objectToWorld,
                  glm::mat4(1.0f)); // the mesh node is a root without transform
    }
}

TEST(Gltf, MirroredTangentsKeepTheirSign) {
    RenderMesh m =
        loadRenderMesh(dataPath("gltf/NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf"));
    size_t neg = 0, pos = 0;
    for (const auto& t : m.tangents) (t.w < 0 ? neg : pos)++;
    EXPECT_GT(neg, 0u);
    EXPECT_GT(pos, 0u);
    for (const auto& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
    Scene scene =
        loadScene(dataPath("gltf/NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf"));
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_NE(scene.materials[0].normalTexture.find("NormalTangentTest_Normal.png"),
              std::string::npos);
    EXPECT_EQ(scene.materials[0].normalTexCoord, 0);
    EXPECT_EQ(scene.materials[0].normalScale, 1.0f);
}

TEST(Gltf, MorphPrimitivesTest) {
    for (const char* file : {"gltf/MorphPrimitivesTest/glTF/MorphPrimitivesTest.gltf",
                             "gltf/MorphPrimitivesTest/glTF-Binary/MorphPrimitivesTest.glb"}) {
        Scene scene = loadScene(dataPath(file));
        ASSERT_EQ(scene.instances.size(), 2u) << file;
        ASSERT_EQ(scene.materials.size(), 2u);
        EXPECT_EQ(scene.materials[0].baseColorFactor, glm::vec4(1, 0, 0, 1));
        for (const SceneInstance& inst : scene.instances) {
            ASSERT_EQ(inst.mesh.morphTargets.size(), 1u);
            EXPECT_EQ(inst.mesh.morphWeights, std::vector<float>{0.5f});
            EXPECT_EQ(inst.mesh.morphTargets[0].positionDeltas.size(), inst.mesh.vertexCount());
            EXPECT_EQ(inst.mesh.uvSets.size(), 1u);
        }
        EXPECT_NE(scene.instances[0].material, scene.instances[1].material);
        // As one cage: both primitives, welded, with the target carried.
        PolygonMesh cage = loadPolygonMesh(dataPath(file));
        ASSERT_EQ(cage.morphTargets.size(), 1u);
        EXPECT_LT(cage.vertexCount(),
                  scene.instances[0].mesh.vertexCount() + scene.instances[1].mesh.vertexCount());
    }
}

TEST(Gltf, AnimatedMorphSphere) {
    std::filesystem::path p = dataPath("gltf/AnimatedMorphSphere/glTF/AnimatedMorphSphere.gltf");
    Scene scene = loadScene(p);
    ASSERT_EQ(scene.instances.size(), 1u);
    const RenderMesh& m = scene.instances[0].mesh;
    EXPECT_EQ(m.vertexCount(), 1876u);
    ASSERT_EQ(m.morphTargets.size(), 2u);
    for (const MorphTarget& t : m.morphTargets) {
        EXPECT_EQ(t.positionDeltas.size(), m.vertexCount());
        EXPECT_EQ(t.normalDeltas.size(), m.vertexCount());
        EXPECT_EQ(t.tangentDeltas.size(), m.vertexCount());
    }
    // Node: rotation + uniform scale 100.
    glm::vec3 col0(scene.instances[0].objectToWorld[0]);
    EXPECT_NEAR(glm::length(col0), 100.0f, 1e-3f);
    ASSERT_EQ(scene.animations.size(), 1u);
    const MorphWeightAnimation& a = scene.animations[0];
    EXPECT_EQ(a.targetCount, 2u);
    EXPECT_EQ(a.interpolation, AnimInterpolation::Linear);
    ASSERT_EQ(a.times.size(), 217u);
    // Sampling at a key returns the key; between keys a linear blend;
    // outside the range the end keys.
    for (size_t k : {size_t(0), size_t(50), size_t(216)}) {
        std::vector<float> w = sampleWeights(a, a.times[k]);
        EXPECT_EQ(w[0], a.weights[2 * k]);
        EXPECT_EQ(w[1], a.weights[2 * k + 1]);
    }
    float tm = 0.5f * (a.times[10] + a.times[11]);
    std::vector<float> w = sampleWeights(a, tm);
    EXPECT_NEAR(w[0], 0.5f * (a.weights[20] + a.weights[22]), 1e-6f);
    EXPECT_EQ(sampleWeights(a, -5.0f)[0], a.weights[0]);
    EXPECT_EQ(sampleWeights(a, 1e6f)[1], a.weights[2 * 216 + 1]);
    // Subdivided to >= 100k vertices for the blendshape benchmark, targets refined too.
    PolygonMesh cage = loadPolygonMesh(p);
    EXPECT_LT(cage.vertexCount(), m.vertexCount()); // seams welded
    SubdivisionSettings s;
    s.level = 3;
    Subdivider sub(cage, s);
    EXPECT_EQ(sub.renderMesh().morphTargets.size(), 2u);
    EXPECT_GT(sub.refined().vertexCount(), 40000u);
}

TEST(Gltf, TextureCoordinateTestMergesInWorldSpace) {
    std::filesystem::path p =
        dataPath("gltf/TextureCoordinateTest/glTF/TextureCoordinateTest.gltf");
    Scene scene = loadScene(p);
    EXPECT_EQ(scene.instances.size(), 5u);
    LoadReport report;
    RenderMesh merged = loadRenderMesh(p, {}, &report);
    size_t total = 0;
    for (const auto& inst : scene.instances) total += inst.mesh.vertexCount();
    EXPECT_EQ(merged.vertexCount(), total);
    EXPECT_TRUE(merged.uvSets.empty()); // the back plane has no TEXCOORD_0
    // The note says which sets went and why: set 0 too, because one
    // primitive has none.
    std::string note;
    for (const auto& n : report.notes) {
        if (n.find("UV sets") != std::string::npos) note = n;
    }
    EXPECT_EQ(note.substr(0, note.find(", and")),
              "UV sets TEXCOORD_0 dropped from every primitive: primitive 0 of mesh 3 "
              "'BackPlaneMesh' (node 0) has no texture coordinates")
        << note;
}

// A one-triangle glTF written by our writer, as JSON, for corruption.
json triangleGltf() {
    RenderMesh t;
    t.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    t.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    t.uvSets = {{{0, 0}, {1, 0}, {0, 1}}};
    t.indices = {0, 1, 2};
    sg::test::TempDir dir;
    writeRenderMesh(dir / "t.gltf", t);
    return json::parse(readBytes(dir / "t.gltf"));
}

Scene parse(const json& j, const InputLimits& limits = {}) {
    return parseGltf(j.dump(), "t.gltf", {}, limits);
}

TEST(Gltf, HostileFilesAreNamed) {
    json ok = triangleGltf();
    EXPECT_EQ(parse(ok).instances[0].mesh.triangleCount(), 1u);

    json count = ok;
    count["accessors"][0]["count"] = 1000000;
    expectInputError([&] { parse(count); }, "accessor 0", "need more than");
    json huge = ok;
    huge["accessors"][0]["count"] = 1u << 30;
    expectInputError([&] { parse(huge); }, "accessor 0", "exceeds the limit");
    json index = ok;
    // Point the index accessor at the POSITION bytes reinterpreted: indices out of range.
    int ia = index["meshes"][0]["primitives"][0]["indices"].get<int>();
    index["accessors"][ia]["bufferView"] = 0;
    index["accessors"][ia]["byteOffset"] = 12; // x of vertex 1 = 1.0f = 0x3f800000 as an index
    index["accessors"][ia]["componentType"] = 5125;
    expectInputError([&] { parse(index); }, "indices", "out of range");
    json type = ok;
    type["accessors"][0]["type"] = "VEC2";
    expectInputError([&] { parse(type); }, "POSITION", "expected 3");
    json view = ok;
    view["accessors"][0]["bufferView"] = 42;
    expectInputError([&] { parse(view); }, "accessor 0", "bufferView 42 does not exist");
    json cycle = ok;
    cycle["nodes"][0]["children"] = {0};
    expectInputError([&] { parse(cycle); }, "node 0", "cycle");
    json nodeRef = ok;
    nodeRef["scenes"][0]["nodes"] = {7};
    expectInputError([&] { parse(nodeRef); }, "node 7", "does not exist");
    json matrix = ok;
    matrix["nodes"][0]["matrix"] = {1, 0, 0};
    expectInputError([&] { parse(matrix); }, "node 0", "16 finite numbers");
    json external = ok;
    external["buffers"][0]["uri"] = "t.bin";
    expectInputError([&] { parse(external); }, "", "refused");
    // A data URI cut short: the buffer, its decoded size and byteLength
    // (tinygltf says only "Failed to decode 'uri'" and quotes the URI).
    json shortUri = ok;
    std::string uri = shortUri["buffers"][0]["uri"].get<std::string>();
    const size_t payload = uri.find(";base64,") + 8;
    const size_t keep = (uri.size() - payload) / 2 / 4 * 4; // whole base64 quads
    shortUri["buffers"][0]["uri"] = uri.substr(0, payload + keep);
    expectInputError([&] { parse(shortUri); }, "buffer 0",
                     "its data URI decodes to " + std::to_string(keep / 4 * 3) +
                         " bytes, but byteLength is " +
                         std::to_string(ok["buffers"][0]["byteLength"].get<size_t>()));
    json badChar = ok;
    badChar["buffers"][0]["uri"] = uri.substr(0, payload) + "AA!A" + uri.substr(payload + 4);
    expectInputError([&] { parse(badChar); }, "buffer 0", "not base64");
    json noPos = ok;
    noPos["meshes"][0]["primitives"][0]["attributes"].erase("POSITION");
    expectInputError([&] { parse(noPos); }, "mesh 0 primitive 0", "no POSITION");
    json weights = ok;
    weights["meshes"][0]["weights"] = {0.5, 0.5};
    weights["meshes"][0]["primitives"][0]["targets"] = json::array({{{"POSITION", 0}}});
    expectInputError([&] { parse(weights); }, "mesh 0 primitive 0",
                     "2 default weights for 1 morph targets");
    expectInputError([&] { parseGltf("{not json", "t.gltf", {}); }, "", "glTF parse error");
    expectInputError([&] { parseGltf("", "t.gltf", {}); }, "", "");
}

// Buffer and image URIs stay inside the model's folder: "..", absolute
// paths and symbolic links that lead out are refused before anything is
// read (so nothing of the file, not even its size, is disclosed), unless
// InputLimits::allowOutsideFolder says otherwise.
TEST(Gltf, UrisThatLeaveTheModelsFolderAreRefused) {
    sg::test::TempDir dir;
    json ok = triangleGltf();
    // The buffer as a file inside the model's folder, and one outside it.
    std::filesystem::create_directories(dir / "model/bin");
    std::filesystem::create_directories(dir / "elsewhere");
    {
        // Decode the embedded buffer through the reader's own oracle: tinygltf.
        tinygltf::TinyGLTF loader;
        tinygltf::Model m;
        std::string err, warn, text = ok.dump();
        ASSERT_TRUE(
            loader.LoadASCIIFromString(&m, &err, &warn, text.data(), unsigned(text.size()), ""))
            << err;
        const auto& bytes = m.buffers[0].data;
        for (const char* p : {"model/bin/t.bin", "elsewhere/t.bin"})
            std::ofstream(dir / p, std::ios::binary)
                .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    }
    std::filesystem::create_directory_symlink(dir / "elsewhere", dir / "model/link");
    auto load = [&](const std::string& uri, bool allow) {
        json j = ok;
        j["buffers"][0]["uri"] = uri;
        std::ofstream(dir / "model/m.gltf") << j.dump();
        LoadOptions lo;
        lo.limits.allowOutsideFolder = allow;
        return loadScene(dir / "model/m.gltf", lo);
    };
    EXPECT_EQ(load("bin/t.bin", false).instances[0].mesh.triangleCount(), 1u);
    EXPECT_EQ(load("bin/../bin/t.bin", false).instances[0].mesh.triangleCount(), 1u);
    for (const std::string& uri :
         {std::string("../elsewhere/t.bin"), std::string("link/t.bin"),
          (dir / "elsewhere/t.bin").string(), std::string("../../../../../../../../etc/passwd")}) {
        SCOPED_TRACE(uri);
        expectInputError([&] { load(uri, false); }, "", "outside the model's folder (refused");
        try {
            load(uri, false);
        } catch (const sg::io::InputError& e) {
            EXPECT_EQ(e.reason().find("bytes"), std::string::npos) << e.what(); // no size
        }
    }
    // Allowed explicitly: read as before.
    EXPECT_EQ(load("../elsewhere/t.bin", true).instances[0].mesh.triangleCount(), 1u);
    EXPECT_EQ(load("link/t.bin", true).instances[0].mesh.triangleCount(), 1u);

    // A material's image: the same rule (its path is handed to the renderer).
    json img = ok;
    img["images"] = json::array({{{"uri", "../secret.png"}}});
    img["textures"] = json::array({{{"source", 0}}});
    img["materials"] = json::array({{{"normalTexture", {{"index", 0}}}}});
    img["meshes"][0]["primitives"][0]["material"] = 0;
    std::ofstream(dir / "secret.png") << "x";
    std::ofstream(dir / "model/img.gltf") << img.dump();
    expectInputError([&] { loadScene(dir / "model/img.gltf"); }, "",
                     "outside the model's folder (refused");
}

TEST(Gltf, NanPositionsAreRefused) {
    RenderMesh t;
    t.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    t.indices = {0, 1, 2};
    sg::test::TempDir dir;
    writeRenderMesh(dir / "t.glb", t);
    std::string glb = readBytes(dir / "t.glb");
    // BIN chunk data starts after the 12-byte header, the JSON chunk and
    // the BIN chunk header; POSITION is the first bufferView (offset 0).
    uint32_t jsonLen;
    std::memcpy(&jsonLen, glb.data() + 12, 4);
    size_t bin = 20 + jsonLen + 8;
    float nan = std::nanf("");
    std::memcpy(glb.data() + bin + (2 * 3 + 1) * 4, &nan, 4); // vertex 2, y
    expectInputError([&] { parseGltf(glb, "nan.glb", {}); }, "POSITION (accessor 0)",
                     "element 2 is not finite");
}

TEST(Gltf, TruncatedGlb) {
    std::string glb = readBytes(dataPath("gltf/MultiUVTest/glTF-Binary/MultiUVTest.glb"));
    ASSERT_GT(glb.size(), 100u);
    expectInputError(
        [&] { parseGltf(std::string_view(glb).substr(0, glb.size() - 10), "m.glb", {}); },
        "GLB header", "truncated");
    expectInputError([&] { parseGltf(std::string_view(glb).substr(0, 12), "m.glb", {}); },
                     "GLB header", "truncated");
    std::string badChunk = glb;
    uint32_t huge = 0x7fffffff;
    std::memcpy(badChunk.data() + 12, &huge, 4);
    expectInputError([&] { parseGltf(badChunk, "m.glb", {}); }, "GLB chunk 0", "past the end");
}

} // namespace
