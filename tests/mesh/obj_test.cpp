// OBJ tokenizer (parseObj / loadPolygonMesh): statements, negative
// indices, OpenSubdiv tag lines, and errors that name the line.
#include <gtest/gtest.h>

#include "mesh_test_util.h"
#include "surfgrad/mesh/mesh_io.h"

namespace {

using namespace sg::mesh;
using sg::test::expectInputError;

TEST(Obj, ParsesPositionsUvsNormalsAndFaces) {
    LoadReport report;
    PolygonMesh m = parseObj("# comment\n"
                             "o thing\n"
                             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 1.0\n"
                             "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                             "vn 0 0 1\n"
                             "s 1\nusemtl red\n"
                             "f 1/1/1 2/2/1 3/3/1 4/4/1\r\n"
                             "f -4/1/-1 -2/3/1 -1/4/1\n",
                             "q.obj", {}, &report);
    ASSERT_EQ(m.vertexCount(), 4u);
    ASSERT_EQ(m.faceCount(), 2u);
    EXPECT_EQ(m.faceSizes[0], 4u);
    EXPECT_EQ(m.faceSizes[1], 3u);
    EXPECT_EQ(m.faceVertices, (std::vector<uint32_t>{0, 1, 2, 3, 0, 2, 3}));
    ASSERT_EQ(m.uvSets.size(), 1u);
    EXPECT_EQ(m.uvSets[0].indices, (std::vector<uint32_t>{0, 1, 2, 3, 0, 2, 3}));
    EXPECT_EQ(m.uvSets[0].values[2], glm::vec2(1, 1));
    ASSERT_EQ(m.normalIndices.size(), 7u);
    EXPECT_EQ(m.normals[0], glm::vec3(0, 0, 1));
    // o, s, usemtl are ignored and counted.
    ASSERT_FALSE(report.notes.empty());
    EXPECT_NE(report.notes.back().find("ignored 3 statements"), std::string::npos);
}

TEST(Obj, ReadsOpenSubdivTags) {
    PolygonMesh m =
        parseObj(std::string(sg::test::kCubeObj) + "t crease 2/1/0 0 1 2.5\n"
                                                   "t crease 3/2/0 4 5 6 1.0 10\n"
                                                   "t corner 2/1/0 2 3 4.0\n"
                                                   "t hole 1/0/0 5\n"
                                                   "t interpolateboundary 1/0/0 1\n"
                                                   "t facevaryinginterpolateboundary 1/0/0 5\n"
                                                   "t creasemethod 0/0/1 chaikin\n"
                                                   "t smoothtriangles 0/0/1 catmark\n"
                                                   "t scheme 0/0/1 bilinear\n"
                                                   "#t crease 2/1/0 0 1 99\n",
                 "tags.obj");
    ASSERT_EQ(m.creases.size(), 3u);
    EXPECT_EQ(m.creases[0].v0, 0u);
    EXPECT_EQ(m.creases[0].v1, 1u);
    EXPECT_EQ(m.creases[0].sharpness, 2.5f);
    // A chain of 3 vertices with one sharpness per edge.
    EXPECT_EQ(m.creases[1].v0, 4u);
    EXPECT_EQ(m.creases[1].v1, 5u);
    EXPECT_EQ(m.creases[1].sharpness, 1.0f);
    EXPECT_EQ(m.creases[2].v0, 5u);
    EXPECT_EQ(m.creases[2].v1, 6u);
    EXPECT_EQ(m.creases[2].sharpness, 10.0f);
    ASSERT_EQ(m.corners.size(), 2u);
    EXPECT_EQ(m.corners[1].vertex, 3u);
    EXPECT_EQ(m.corners[1].sharpness, 4.0f);
    EXPECT_EQ(m.holes, std::vector<uint32_t>{5});
    EXPECT_EQ(m.options.boundary, BoundaryInterpolation::EdgeAndCorner);
    EXPECT_EQ(m.options.fvar, FVarInterpolation::All);
    EXPECT_EQ(m.options.creaseMethod, CreaseMethod::Chaikin);
    EXPECT_EQ(m.options.triangles, TriangleRule::Smooth);
    EXPECT_EQ(m.options.scheme, Scheme::Bilinear);
    EXPECT_EQ(m.explicitTags,
              kTagScheme | kTagBoundary | kTagFVar | kTagCreaseMethod | kTagTriangles);
    // Creases on existing edges: validation passes.
    validate(m, "tags.obj");
}

TEST(Obj, ErrorsNameTheLine) {
    expectInputError([] { parseObj("v 0 0 0\nv 1 0\n", "a.obj"); }, "line 2",
                     "fewer than 3 coordinates");
    expectInputError([] { parseObj("v 0 0 0\nv 0 0 nan\n", "a.obj"); }, "vertex 2",
                     "non-finite coordinate (0, 0, nan) (line 2)");
    expectInputError([] { parseObj("v 0 0 1e39\n", "a.obj"); }, "line 1", "bad number");
    expectInputError([] { parseObj("v 0 0 0\nf 1 2 0\n", "a.obj"); }, "line 2", "index 0");
    expectInputError([] { parseObj("v 0 0 0\nf 1 2 -5\n", "a.obj"); }, "line 2",
                     "before the first");
    expectInputError([] { parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", "a.obj"); }, "line 5",
                     "vertex index 4 is out of range (3 vertices)");
    expectInputError(
        [] { parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", "a.obj"); }, "line 5",
        "texture coordinate index 2 is out of range");
    expectInputError([] { parseObj("f 1/2/3/4\n", "a.obj"); }, "line 1", "more than 3 parts");
    expectInputError([] { parseObj("t crease 2/1/0 0\n", "a.obj"); }, "line 1",
                     "missing or bad integer");
    expectInputError([] { parseObj("t crease 2/2/0 0 1 1 2\n", "a.obj"); }, "line 1",
                     "1 or 1 sharpness");
    expectInputError([] { parseObj("t crease 99999999/0/0\n", "a.obj"); }, "line 1",
                     "line is shorter");
    expectInputError([] { parseObj("t crease x/1/0 0 1 1\n", "a.obj"); }, "line 1",
                     "nInts/nFloats/nStrings");
    expectInputError([] { parseObj("t corner 1/1/0 -3 1\n", "a.obj"); }, "line 1", "out of range");
    expectInputError([] { parseObj("t interpolateboundary 1/0/0 7\n", "a.obj"); }, "line 1",
                     "expected 0, 1 or 2");
    expectInputError([] { parseObj("t creasemethod 0/0/1 wobbly\n", "a.obj"); }, "line 1",
                     "expected normal or chaikin");
}

TEST(Obj, LimitsAreCheckedWhileReading) {
    InputLimits limits;
    limits.maxVertices = 2;
    expectInputError([&] { parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "a.obj", limits); }, "line 3",
                     "more than 2 vertices");
    limits = InputLimits();
    limits.maxFaceDegree = 4;
    expectInputError([&] { parseObj("f 1 2 3 4 5\n", "a.obj", limits); }, "line 1",
                     "more than 4 corners");
}

TEST(Obj, MixedUvCornersGetAFallbackValue) {
    LoadReport report;
    PolygonMesh m =
        parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0.5 0.5\nf 1/1 2/1 3/1\nf 2 4 3\n",
                 "mixed.obj", {}, &report);
    ASSERT_EQ(m.uvSets.size(), 1u);
    EXPECT_EQ(m.uvSets[0].values.size(), 2u);
    EXPECT_EQ(m.uvSets[0].values[1], glm::vec2(0.0f));
    EXPECT_EQ(m.uvSets[0].indices[3], 1u);
    bool noted = false;
    for (const auto& n : report.notes) noted |= n.find("without vt") != std::string::npos;
    EXPECT_TRUE(noted);
}

// Non-manifold edges and vertices of an OBJ file are named with the
// file's own vertex and face numbers (from 1), not the 0-based indices of
// the loaded mesh.
TEST(Obj, TopologyErrorsUseTheFilesNumbers) {
    sg::test::TempDir dir;
    // Three triangles on the edge between v 1 and v 2.
    sg::test::writeText(dir / "fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                                         "f 1 2 3\nf 2 1 4\nf 1 2 5\n");
    expectInputError([&] { loadPolygonMesh(dir / "fin.obj"); }, "edge (1, 2)",
                     "shared by 3 faces (1, 2, 3)");
    // Two triangles touching at v 1 only.
    sg::test::writeText(dir / "bowtie.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\n"
                                            "f 1 2 3\nf 1 4 5\n");
    expectInputError([&] { loadPolygonMesh(dir / "bowtie.obj"); }, "vertex 1", "2 separate fans");
    // Two faces traversing v 2 -> v 3 the same way.
    sg::test::writeText(dir / "flip.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 3 4\n");
    expectInputError([&] { loadPolygonMesh(dir / "flip.obj"); }, "edge (2, 3)",
                     "faces 1 and 2 traverse it in the same direction");
}

TEST(Obj, LoadNamesTheFileAndTheFaceLine) {
    sg::test::TempDir dir;
    sg::test::writeText(dir / "bad.obj",
                        "v 0 0 0\nv 1 0 0\nv 0 1 0\n# a comment\nf 1 2 3\nf 1 1 2\n");
    std::string file = (dir / "bad.obj").string();
    try {
        loadPolygonMesh(dir / "bad.obj");
        FAIL() << "expected InputError";
    } catch (const sg::io::InputError& e) {
        EXPECT_EQ(e.file(), file);
        // Named as the file numbers them: the second face, and the vertex
        // its line names ("f 1 1 2"), both counted from 1.
        EXPECT_EQ(e.element(), "face 2 (line 6)");
        EXPECT_NE(e.reason().find("uses vertex 1 twice"), std::string::npos) << e.what();
    }
    // --repair drops it and says so.
    LoadOptions o;
    o.repair = true;
    LoadReport report;
    PolygonMesh m = loadPolygonMesh(dir / "bad.obj", o, &report);
    EXPECT_EQ(m.faceCount(), 1u);
    EXPECT_EQ(report.degenerateFacesDropped, 1u);
    expectInputError([&] { loadPolygonMesh(dir / "missing.obj"); }, "", "no such file");
    expectInputError([&] { loadPolygonMesh(dir / "x.fbx"); }, "", "unknown mesh format '.fbx'");
}

} // namespace
