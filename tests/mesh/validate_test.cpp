// validate() and describe(): every rejection names the element and the
// reason; repair fixes only what has one honest fix.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hardcase.h"
#include "mesh_test_util.h"
#include "surfgrad/mesh/mesh_io.h"

namespace {

using namespace sg::mesh;
using sg::test::expectInputError;

PolygonMesh fromObj(const std::string& text) {
    return parseObj(text, "t.obj");
}

TEST(Validate, AcceptsAClosedCube) {
    PolygonMesh m = fromObj(sg::test::kCubeObj);
    LoadReport report;
    validate(m, "cube.obj", false, &report);
    EXPECT_FALSE(report.changed());
    MeshInfo info = describe(m);
    EXPECT_TRUE(info.manifold);
    EXPECT_EQ(info.edges, 12u);
    EXPECT_EQ(info.boundaryLoops, 0u);
    EXPECT_EQ(info.eulerCharacteristic, 2);
    EXPECT_EQ(info.faceDegreeHistogram[4], 6u);
}

TEST(Validate, NonManifoldEdge) {
    // Three triangles on the edge (0,1).
    PolygonMesh m =
        fromObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
    MeshInfo info = describe(m);
    EXPECT_FALSE(info.manifold);
    EXPECT_EQ(info.nonManifoldEdges, 1u);
    expectInputError([&] { validate(m, "t.obj"); }, "edge (0, 1)", "shared by 3 faces");
    LoadReport r;
    expectInputError([&] { validate(m, "t.obj", true, &r); }, "edge (0, 1)",
                     "non-manifold edge"); // no repair for it
    sg::test::reportHardCaseHolds("non-manifold", "three triangles on one edge (OBJ)",
                                  "validation, with and without repair",
                                  "InputError naming the edge", "InputError naming the edge");
}

TEST(Validate, InconsistentOrientation) {
    // Two triangles traverse (1,2) the same way.
    PolygonMesh m = fromObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 3 4\n");
    expectInputError([&] { validate(m, "t.obj"); }, "edge (1, 2)", "same direction");
}

TEST(Validate, NonManifoldVertex) {
    // Two triangles touching at vertex 0 only (a bowtie).
    PolygonMesh m = fromObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n");
    MeshInfo info = describe(m);
    EXPECT_EQ(info.nonManifoldVertices, 1u);
    EXPECT_EQ(info.nonManifoldEdges, 0u);
    expectInputError([&] { validate(m, "t.obj"); }, "vertex 0", "2 separate fans");
    // mesh info describes such files instead of refusing them.
    validate(m, "t.obj", false, nullptr, {}, /*allowNonManifold=*/true);
    sg::test::reportHardCaseHolds("non-manifold", "two fans sharing one vertex (a bowtie)",
                                  "validation", "InputError naming the vertex",
                                  "InputError naming the vertex");
}

TEST(Validate, DegenerateFaces) {
    PolygonMesh collinear = fromObj("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 3 2\n");
    expectInputError([&] { validate(collinear, "t.obj"); }, "face 1", "zero area");
    PolygonMesh twoCorners = fromObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n");
    expectInputError([&] { validate(twoCorners, "t.obj"); }, "face 1", "has 2 corners");
    LoadReport r;
    validate(twoCorners, "t.obj", true, &r);
    EXPECT_EQ(r.degenerateFacesDropped, 1u);
    EXPECT_EQ(twoCorners.faceCount(), 1u);
    sg::test::reportHardCaseHolds("zero-area", "a collinear triangle, a face with 2 corners",
                                  "validation; with repair", "InputError naming the face; dropped",
                                  "InputError naming the face; dropped");
}

TEST(Validate, BadValuesAndIndices) {
    PolygonMesh m = fromObj(sg::test::kCubeObj);
    PolygonMesh nan = m;
    nan.positions[3].y = std::numeric_limits<float>::quiet_NaN();
    expectInputError([&] { validate(nan, "t.obj"); }, "vertex 3", "non-finite");
    PolygonMesh inf = m;
    inf.uvSets[0].values[1].x = std::numeric_limits<float>::infinity();
    expectInputError([&] { validate(inf, "t.obj"); }, "uv set 0 value 1", "non-finite UV");
    PolygonMesh range = m;
    range.faceVertices[5] = 99;
    expectInputError([&] { validate(range, "t.obj"); }, "face 1",
                     "vertex index 99 is out of range (8 vertices)");
    PolygonMesh uvRange = m;
    uvRange.uvSets[0].indices[2] = 40;
    expectInputError([&] { validate(uvRange, "t.obj"); }, "uv set 0 corner 2",
                     "out of range (4 UVs)");
    PolygonMesh sizes = m;
    sizes.faceSizes[0] = 5;
    expectInputError([&] { validate(sizes, "t.obj"); }, "faces", "add up to 25");
    PolygonMesh crease = m;
    crease.creases.push_back({0, 6, 1.0f}); // a diagonal, not an edge
    expectInputError([&] { validate(crease, "t.obj"); }, "crease 0 (0, 6)", "no face has an edge");
    PolygonMesh sharp = m;
    sharp.creases.push_back({0, 1, -1.0f});
    expectInputError([&] { validate(sharp, "t.obj"); }, "crease 0", "not a finite value >= 0");
    PolygonMesh hole = m;
    hole.holes.push_back(6);
    expectInputError([&] { validate(hole, "t.obj"); }, "hole tag (face 6)", "out of range");
    PolygonMesh morph = m;
    morph.morphTargets.push_back({"t", std::vector<glm::vec3>(3)});
    expectInputError([&] { validate(morph, "t.obj"); }, "morph target 0",
                     "3 deltas for 8 vertices");
    PolygonMesh empty;
    expectInputError([&] { validate(empty, "t.obj"); }, "", "empty mesh");
    PolygonMesh noFaces = fromObj("v 0 0 0\n");
    expectInputError([&] { validate(noFaces, "t.obj"); }, "", "no faces");
}

TEST(Validate, AbsurdSizesAreRefusedBeforeWork) {
    PolygonMesh m = fromObj(sg::test::kCubeObj);
    InputLimits limits;
    limits.maxVertices = 4;
    expectInputError([&] { validate(m, "t.obj", false, nullptr, limits); }, "vertices",
                     "limit is 4");
    limits = InputLimits();
    limits.maxFaceDegree = 3;
    expectInputError([&] { validate(m, "t.obj", false, nullptr, limits); }, "face 0", "limit is 3");
}

TEST(Validate, RepairWeldsExactDuplicates) {
    // A quad split into two triangles whose shared edge uses duplicated
    // vertices (a "triangle soup" seam): welding makes it one surface.
    PolygonMesh m = fromObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 4 5 "
                            "6\nt crease 2/1/0 0 1 3\n");
    MeshInfo before = describe(m);
    EXPECT_EQ(before.boundaryLoops, 2u);
    LoadReport r;
    validate(m, "t.obj", true, &r);
    EXPECT_EQ(r.duplicateVerticesWelded, 2u);
    EXPECT_EQ(m.vertexCount(), 4u);
    EXPECT_EQ(describe(m).boundaryLoops, 1u);
    ASSERT_EQ(m.creases.size(), 1u);
    // Without repair the duplicates stay (they are not an error by themselves).
    PolygonMesh k =
        fromObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 4 5 6\n");
    validate(k, "t.obj");
    EXPECT_EQ(k.vertexCount(), 6u);
}

TEST(Validate, RepairDropsFacesThatWeldingCollapses) {
    // Vertices 1 and 4 coincide: the second triangle becomes degenerate.
    PolygonMesh m = fromObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 0\nf 1 2 3\nf 2 4 1\n");
    LoadReport r;
    validate(m, "t.obj", true, &r);
    EXPECT_EQ(r.duplicateVerticesWelded, 1u);
    EXPECT_EQ(r.degenerateFacesDropped, 1u);
    EXPECT_EQ(m.faceCount(), 1u);
}

TEST(Validate, DescribeCountsBoundaryLoopsAndIsolatedVertices) {
    // A 2x1 strip of quads plus one unused vertex: one boundary loop.
    PolygonMesh m = fromObj(
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 9 9 9\nf 1 2 5 4\nf 2 3 6 5\n");
    LoadReport r;
    validate(m, "t.obj", false, &r);
    EXPECT_EQ(r.isolatedVertices, 1u);
    MeshInfo info = describe(m);
    EXPECT_EQ(info.boundaryLoops, 1u);
    EXPECT_EQ(info.boundaryEdges, 6u);
    EXPECT_EQ(info.isolatedVertices, 1u);
    EXPECT_EQ(info.eulerCharacteristic, 1); // a disk
}

} // namespace
