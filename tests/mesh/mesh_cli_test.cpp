// `surfgrad mesh ...` from outside, where users meet the mesh pipeline:
// runs the built binary (tests/common/cli.h) on small files and checks the
// message, the exit status and what was (or was not) written.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "mesh_test_util.h"
#include "surfgrad/mesh/mesh_io.h"

namespace {

namespace fs = std::filesystem;
using sg::test::runSurfgrad;
using sg::test::shellQuote;
using sg::test::TempDir;
using sg::test::writeText;

std::string binaryStlWithNan() {
    std::string b(80, '\0');
    const uint32_t n = 1;
    b.append(reinterpret_cast<const char*>(&n), 4);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float record[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, nan, 1, 0};
    b.append(reinterpret_cast<const char*>(record), sizeof record);
    b.append(2, '\0');
    return b;
}

// A NaN coordinate in any format: "FILE: vertex N: non-finite coordinate",
// exit status 1, nothing written (it used to be a dropped face or a wrong
// reason for OFF, PLY and STL).
TEST(MeshCli, NonFiniteCoordinatesInEveryFormat) {
    TempDir dir;
    writeText(dir / "a.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    writeText(dir / "a.off", "OFF\n3 1 0\n0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n");
    writeText(dir / "a.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                             "property float y\nproperty float z\nelement face 1\n"
                             "property list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\nnan 1 0\n3 0 1 2\n");
    writeText(dir / "a.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                             "vertex 1 0 0\nvertex nan 1 0\nendloop\nendfacet\nendsolid t\n");
    writeText(dir / "b.stl", binaryStlWithNan());
    // The vertex as each format numbers it: OBJ's v statements from 1,
    // OFF/PLY indices and STL corners in file order from 0.
    for (const auto& [name, vertex] : std::vector<std::pair<std::string, int>>{
             {"a.obj", 3}, {"a.off", 2}, {"a.ply", 2}, {"a.stl", 2}, {"b.stl", 2}}) {
        SCOPED_TRACE(name);
        const fs::path in = dir / name;
        std::vector<std::string> commands = {"mesh info " + shellQuote(in)};
        if (name == "a.stl")
            commands.push_back("mesh subdivide " + shellQuote(in) + " --level 1 -o " +
                               shellQuote(dir / "o.obj"));
        for (const std::string& cmd : commands) {
            const sg::test::CommandResult r = runSurfgrad(cmd);
            EXPECT_EQ(r.exitCode, 1) << r.err;
            EXPECT_NE(r.err.find("surfgrad: error: " + in.string() + ": vertex " +
                                 std::to_string(vertex) + ": non-finite coordinate"),
                      std::string::npos)
                << r.err;
            EXPECT_FALSE(fs::exists(dir / "o.obj"));
        }
    }
}

// OBJ errors name faces and vertices with the file's own numbers (from 1):
// catmark_nonman_edges' line 161 is "f 41/48 42/49 52/60 52/59".
TEST(MeshCli, ObjErrorsUseTheFilesNumbers) {
    const fs::path in = sg::test::dataPath("osd-shapes/catmark_nonman_edges.obj");
    TempDir dir;
    const sg::test::CommandResult r = runSurfgrad("mesh subdivide " + shellQuote(in) +
                                                  " --level 1 -o " + shellQuote(dir / "o.obj"));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find(in.string() + ": face 25 (line 161): uses vertex 52 twice"),
              std::string::npos)
        << r.err;
}

// A glTF whose primitives have different UV sets: the note says which
// sets were dropped (set 0 too when a primitive has none) and why, not
// "UV sets beyond 0 dropped".
TEST(MeshCli, DroppedUvSetsAreNamedWithTheReason) {
    const fs::path in =
        sg::test::dataPath("gltf/TextureCoordinateTest/glTF/TextureCoordinateTest.gltf");
    const sg::test::CommandResult r = runSurfgrad("mesh info " + shellQuote(in));
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("surfgrad: note: UV sets TEXCOORD_0 dropped from every primitive: "
                         "primitive 0 of mesh 3 'BackPlaneMesh' (node 0) has no texture "
                         "coordinates, and a merged mesh keeps only the sets every primitive has"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("beyond"), std::string::npos) << r.err;
}

// `mesh morph ... -o out.obj|.ply` keeps the topology: the morphed cube
// reads back as one closed surface of 8 vertices (it used to come back as
// six separate squares: the render mesh's vertices, split at UV seams,
// were written as they were).
TEST(MeshCli, MorphToObjAndPlyKeepsTheTopology) {
    TempDir dir;
    writeText(dir / "cube.obj", sg::test::kCubeObj);
    sg::mesh::RenderMesh cube = sg::mesh::loadRenderMesh(dir / "cube.obj");
    ASSERT_GT(cube.vertexCount(), 8u); // split at the UV seams
    sg::mesh::MorphTarget grow;
    grow.name = "grow";
    for (const glm::vec3& p : cube.positions) grow.positionDeltas.push_back(0.5f * p);
    cube.morphTargets = {grow};
    cube.morphWeights = {0.0f};
    sg::mesh::writeRenderMesh(dir / "cube.glb", cube);
    for (const char* out : {"out.obj", "out.ply"}) {
        SCOPED_TRACE(out);
        const sg::test::CommandResult r = runSurfgrad("mesh morph " + shellQuote(dir / "cube.glb") +
                                                      " --weights 1 -o " + shellQuote(dir / out));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const sg::mesh::PolygonMesh back = sg::mesh::loadPolygonMesh(dir / out);
        EXPECT_EQ(back.vertexCount(), 8u);
        EXPECT_EQ(back.faceCount(), 12u);
        const sg::mesh::MeshInfo info = sg::mesh::describe(back);
        EXPECT_EQ(info.boundaryEdges, 0u);
        EXPECT_EQ(info.eulerCharacteristic, 2);
        for (const glm::vec3& p : back.positions) EXPECT_EQ(glm::abs(p), glm::vec3(1.5f));
    }
}

} // namespace

// A subdivision too large for the memory: refused before anything is
// allocated, naming the level, the face count, the bytes needed and the
// option that raises the limit; exit 1, nothing written (it used to die
// after seconds with "std::bad_alloc"). Under `ulimit -v` the default
// budget (3/4 of the limit) refuses spot at level 7 with limit evaluation
// (3 M faces, about 4 GiB).
TEST(MeshCli, SubdivisionAboveTheMemoryBudgetIsRefused) {
    TempDir dir;
    const std::string spot =
        shellQuote(sg::test::dataPath("meshes/spot/spot_control_mesh.obj").string());
    const fs::path out = dir / "out.glb";
    {
        const sg::test::CommandResult r = runSurfgrad(
            "mesh subdivide " + spot + " --level 4 --limit --max-memory 64M -o " + shellQuote(out));
        EXPECT_EQ(r.exitCode, 1) << r.output();
        EXPECT_NE(r.err.find("surfgrad: error: "), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("level 4: would make 46848 faces with limit evaluation and need "
                             "about "),
                  std::string::npos)
            << r.err;
        EXPECT_NE(r.err.find("the limit is 64.0 MiB (raise it with --max-memory SIZE)"),
                  std::string::npos)
            << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
    // The same build within a raised limit.
    {
        const sg::test::CommandResult r = runSurfgrad(
            "mesh subdivide " + spot + " --level 2 --limit --max-memory 1G -o " + shellQuote(out));
        EXPECT_EQ(r.exitCode, 0) << r.output();
        EXPECT_TRUE(fs::exists(out));
    }
    // The default budget follows the address-space limit. Not under
    // AddressSanitizer: its shadow memory reserves terabytes of address
    // space, so no process starts under `ulimit -v` (the budget's rule is
    // the same code in every build).
#ifndef SG_TEST_ASAN
    {
        const sg::test::CommandResult r = sg::test::runCommand(
            "ulimit -v 3000000 && " + shellQuote(sg::test::surfgradBinary()) + " mesh subdivide " +
            spot + " --level 7 --limit -o " + shellQuote(dir / "big.glb"));
        EXPECT_EQ(r.exitCode, 1) << r.output();
        EXPECT_NE(r.err.find("level 7: would make 2998272 faces with limit evaluation"),
                  std::string::npos)
            << r.err;
        EXPECT_NE(r.err.find("the limit is 2.1 GiB"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
    }
#endif
    // Every subdividing command takes the option (a cube with one morph
    // target for `mesh morph`).
    fs::remove(out);
    writeText(dir / "cube.obj", sg::test::kCubeObj);
    sg::mesh::RenderMesh cube = sg::mesh::loadRenderMesh(dir / "cube.obj");
    sg::mesh::MorphTarget grow;
    grow.name = "grow";
    grow.positionDeltas = cube.positions;
    cube.morphTargets = {grow};
    cube.morphWeights = {0.0f};
    sg::mesh::writeRenderMesh(dir / "cube.glb", cube);
    for (const std::string& cmd :
         {"mesh tangents " + spot + " --method limit --level 4 -o " + shellQuote(out),
          "mesh morph " + shellQuote(dir / "cube.glb") + " --weights 1 --level 6 -o " +
              shellQuote(out)}) {
        const sg::test::CommandResult r = runSurfgrad(cmd + " --max-memory 1M");
        EXPECT_EQ(r.exitCode, 1) << cmd << "\n" << r.output();
        EXPECT_NE(r.err.find("the limit is 1.0 MiB (raise it with --max-memory SIZE)"),
                  std::string::npos)
            << cmd << "\n"
            << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
}

// `mesh subdivide|tangents|morph` with glTF in and out keep the material
// and its textures (they used to be dropped); OBJ output says it keeps no
// material; several materials on the merged mesh: the first, with a note.
TEST(MeshCli, GltfMaterialsAndTexturesAreKept) {
    TempDir dir;
    const std::string box =
        shellQuote(sg::test::dataPath("gltf/BoxTextured/glTF/BoxTextured.gltf").string());
    const std::string morph = shellQuote(
        sg::test::dataPath("gltf/MorphPrimitivesTest/glTF/MorphPrimitivesTest.gltf").string());
    const fs::path out = dir / "out.gltf";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"mesh subdivide " + box + " --level 1 -o " + shellQuote(out), "CesiumLogoFlat.png"},
        {"mesh tangents " + box + " -o " + shellQuote(out), "CesiumLogoFlat.png"},
        {"mesh morph " + morph + " --weights 0.5 -o " + shellQuote(out), "uv_texture.jpg"},
    };
    for (const auto& [cmd, image] : cases) {
        SCOPED_TRACE(cmd);
        fs::remove(out);
        const sg::test::CommandResult r = runSurfgrad(cmd);
        ASSERT_EQ(r.exitCode, 0) << r.output();
        const nlohmann::json doc = nlohmann::json::parse(sg::io::readFile(out));
        ASSERT_TRUE(doc.contains("materials")) << doc.dump();
        ASSERT_EQ(doc["materials"].size(), 1u);
        EXPECT_EQ(doc["meshes"][0]["primitives"][0]["material"], 0);
        const nlohmann::json& tex = doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"];
        ASSERT_TRUE(tex.is_object()) << doc["materials"].dump();
        const std::string uri =
            doc["images"][size_t(doc["textures"][size_t(tex["index"])]["source"])]["uri"];
        EXPECT_EQ(fs::path(uri).filename(), image);
        EXPECT_TRUE(fs::exists(dir.path() / uri)) << uri;
        if (image == "uv_texture.jpg") {
            EXPECT_EQ(doc["materials"][0]["name"], "red");
            EXPECT_NE(r.err.find("has 2 materials on the merged mesh; the output keeps the first, "
                                 "'red'"),
                      std::string::npos)
                << r.err;
        }
    }
    const sg::test::CommandResult obj =
        runSurfgrad("mesh subdivide " + box + " --level 1 -o " + shellQuote(dir / "out.obj"));
    ASSERT_EQ(obj.exitCode, 0) << obj.output();
    EXPECT_NE(obj.err.find("the material 'Texture' of "), std::string::npos) << obj.err;
    EXPECT_NE(obj.err.find("OBJ and PLY outputs keep no material"), std::string::npos) << obj.err;
}

// `mesh info` gives the bounding box (placing a decal needs it): min, max
// and size of the positions in object units, in text and JSON. Expected
// values: the file's coordinates, by hand.
TEST(MeshCli, InfoGivesTheBoundingBox) {
    sg::test::TempDir dir;
    sg::test::writeText(dir / "box.obj", "v -1 2 3\nv 4 -5 6\nv 0 0.5 -7\nf 1 2 3\n");
    const sg::test::CommandResult r =
        sg::test::runSurfgrad("mesh info " + sg::test::shellQuote(dir / "box.obj"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("  bounding box min (-1, -5, -7), max (4, 2, 6), size 5 x 7 x 13\n"),
              std::string::npos)
        << r.out;
    const sg::test::CommandResult j =
        sg::test::runSurfgrad("mesh info --json " + sg::test::shellQuote(dir / "box.obj"));
    ASSERT_EQ(j.exitCode, 0) << j.err;
    const nlohmann::json box = nlohmann::json::parse(j.out).at("bounding_box");
    // Exact: the coordinates are small integers, exact in binary32.
    EXPECT_EQ(box.at("min"), nlohmann::json({-1.0, -5.0, -7.0}));
    EXPECT_EQ(box.at("max"), nlohmann::json({4.0, 2.0, 6.0}));
    EXPECT_EQ(box.at("size"), nlohmann::json({5.0, 7.0, 13.0}));
    EXPECT_EQ(box.at("space"), "object");
}

// glTF: the box of the scene as info loads it, in world space (the node's
// translation and scale applied). The triangle (0,0,0), (1,0,0), (0,1,0)
// under scale (2, 3, 4) then translation (10, 20, 30): by hand, min
// (10, 20, 30), max (12, 23, 30).
TEST(MeshCli, InfoGivesTheGltfBoundingBoxInWorldSpace) {
    sg::test::TempDir dir;
    sg::test::writeText(dir / "tri.gltf",
                        R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"mesh": 0, "translation": [10, 20, 30], "scale": [2, 3, 4]}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [0, 0, 0], "max": [1, 1, 0]}],
 "bufferViews": [{"buffer": 0, "byteLength": 36}],
 "buffers": [{"byteLength": 36, "uri":
   "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})");
    const sg::test::CommandResult r =
        sg::test::runSurfgrad("mesh info " + sg::test::shellQuote(dir / "tri.gltf"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("  bounding box min (10, 20, 30), max (12, 23, 30), size 2 x 3 x 0 "
                         "(world space: node transforms applied)\n"),
              std::string::npos)
        << r.out;
    const sg::test::CommandResult j =
        sg::test::runSurfgrad("mesh info --json " + sg::test::shellQuote(dir / "tri.gltf"));
    ASSERT_EQ(j.exitCode, 0) << j.err;
    const nlohmann::json box = nlohmann::json::parse(j.out).at("bounding_box");
    // Exact: products and sums of small integers, exact in binary32.
    EXPECT_EQ(box.at("min"), nlohmann::json({10.0, 20.0, 30.0}));
    EXPECT_EQ(box.at("max"), nlohmann::json({12.0, 23.0, 30.0}));
    EXPECT_EQ(box.at("space"), "world");
}

// A grid of nx x ny unit quads in the plane z = 0, as OBJ.
std::string quadGridObj(int nx, int ny) {
    std::string obj;
    for (int y = 0; y <= ny; ++y)
        for (int x = 0; x <= nx; ++x)
            obj += "v " + std::to_string(x) + " " + std::to_string(y) + " 0\n";
    auto v = [&](int x, int y) { return std::to_string(y * (nx + 1) + x + 1); };
    for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x)
            obj += "f " + v(x, y) + " " + v(x + 1, y) + " " + v(x + 1, y + 1) + " " + v(x, y + 1) +
                   "\n";
    return obj;
}

// A long subdivision says so on stderr before it starts and before the
// output is written; a short one says nothing. 8 quads at level 8 are
// 8 x 4^8 = 524288 faces, below the threshold (2^20); 16 quads at level 8
// are 16 x 4^8 = 2^20, at it.
TEST(MeshCli, LongSubdivisionsReportProgress) {
    sg::test::TempDir dir;
    sg::test::writeText(dir / "eight.obj", quadGridObj(4, 2));
    sg::test::writeText(dir / "sixteen.obj", quadGridObj(4, 4));
    const sg::test::CommandResult quiet =
        sg::test::runSurfgrad("mesh subdivide " + sg::test::shellQuote(dir / "eight.obj") +
                              " --level 8 -o " + sg::test::shellQuote(dir / "t.ply"));
    ASSERT_EQ(quiet.exitCode, 0) << quiet.err;
    EXPECT_EQ(quiet.err.find("subdividing"), std::string::npos) << quiet.err;
    const std::filesystem::path in = dir / "sixteen.obj";
    const sg::test::CommandResult r =
        sg::test::runSurfgrad("mesh subdivide " + sg::test::shellQuote(in) + " --level 8 -o " +
                              sg::test::shellQuote(dir / "f.ply"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("surfgrad: " + in.string() + ": subdividing to level 8: 1048576 faces, "),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("surfgrad: " + in.string() + ": refined in "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(" s; writing " + (dir / "f.ply").string() + "\n"), std::string::npos)
        << r.err;
    // The lines come before the result line on stdout, which is unchanged.
    EXPECT_NE(r.out.find(": level 8 catmark: 1048576 faces"), std::string::npos) << r.out;
}
