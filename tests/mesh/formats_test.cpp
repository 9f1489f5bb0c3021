// OFF/PLY/STL through OpenMesh's readers (nothing dropped silently, header
// counts checked), the writers (round trips), and the OpenMesh view.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <fstream>

#include "hardcase.h"
#include "mesh_test_util.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/polymesh.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

using namespace sg::mesh;
using sg::test::expectInputError;
using sg::test::TempDir;
using sg::test::writeText;

const char* kCubeOff =
    "OFF\n8 6 12\n-1 -1 -1\n1 -1 -1\n1 1 -1\n-1 1 -1\n-1 -1 1\n1 -1 1\n1 1 1\n-1 1 1\n"
    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

TEST(Formats, OffThroughOpenMesh) {
    TempDir dir;
    writeText(dir / "cube.off", kCubeOff);
    PolygonMesh m = loadPolygonMesh(dir / "cube.off");
    EXPECT_EQ(m.vertexCount(), 8u);
    EXPECT_EQ(m.faceCount(), 6u);
    EXPECT_EQ(m.positions[6], glm::vec3(1, 1, 1));
    EXPECT_EQ(describe(m).eulerCharacteristic, 2);
}

// Binary STL of `triangles` (3 corners each), little-endian.
std::string binaryStl(const std::vector<std::array<glm::vec3, 3>>& triangles) {
    std::string b(80, '\0');
    const uint32_t n = uint32_t(triangles.size());
    b.append(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : triangles) {
        const float normal[3] = {0, 0, 1};
        b.append(reinterpret_cast<const char*>(normal), 12);
        for (const glm::vec3& v : t) b.append(reinterpret_cast<const char*>(&v), 12);
        b.append(2, '\0');
    }
    return b;
}

// Binary PLY of a square (4 vertices, 2 triangles) whose vertex 2 has x = `x2`.
std::string binaryPly(bool bigEndian, double x2, bool doubles) {
    std::string h = std::string("ply\nformat ") +
                    (bigEndian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 4\n";
    for (const char* c : {"x", "y", "z"})
        h += std::string("property ") + (doubles ? "double " : "float ") + c + "\n";
    h += "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
    auto put = [&](const void* p, size_t n) {
        std::string bytes(static_cast<const char*>(p), n);
        if (bigEndian) std::reverse(bytes.begin(), bytes.end());
        h += bytes;
    };
    const double v[4][3] = {{0, 0, 0}, {1, 0, 0}, {x2, 1, 0}, {0, 1, 0}};
    for (const auto& p : v) {
        for (double c : p) {
            if (doubles) {
                put(&c, 8);
            } else {
                const float f = float(c);
                put(&f, 4);
            }
        }
    }
    for (const auto& f : {std::array<int32_t, 3>{0, 1, 2}, std::array<int32_t, 3>{0, 2, 3}}) {
        h += char(3);
        for (int32_t i : f) put(&i, 4);
    }
    return h;
}

// NaN, infinite or out-of-float-range coordinates are refused in every
// format as "vertex N: non-finite coordinate", N the file's own vertex
// number. OpenMesh's readers take them as zeros (ASCII: `stream >> float`
// fails on "nan") or weld them away (STL), so they used to surface as a
// degenerate face, a face of 0 corners, a bad index or a silently dropped
// facet.
TEST(Formats, NonFiniteCoordinatesAreNamedInEveryFormat) {
    TempDir dir;
    const double nan = std::numeric_limits<double>::quiet_NaN(),
                 inf = std::numeric_limits<double>::infinity();
    for (const char* value : {"nan", "inf", "-inf", "1e39", "-NaN", "infinity"}) {
        SCOPED_TRACE(value);
        const std::string v = value;
        writeText(dir / "a.off",
                  "OFF\n4 2 0\n0 0 0\n1 0 0\n" + v + " 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
        expectInputError([&] { loadPolygonMesh(dir / "a.off"); }, "vertex 2",
                         "non-finite coordinate '" + v + "' (line 5)");
        writeText(dir / "a.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                                 "property float y\nproperty float z\nelement face 2\n"
                                 "property list uchar int vertex_indices\nend_header\n"
                                 "0 0 0\n1 0 0\n1 " +
                                     v + " 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
        expectInputError([&] { loadPolygonMesh(dir / "a.ply"); }, "vertex 2",
                         "non-finite coordinate y = '" + v + "'");
        writeText(dir / "a.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                 "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
                                 "facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
                                 "   vertex 0 1 " +
                                     v +
                                     "\n   vertex -1 0 0\n  endloop\n"
                                     "endfacet\nendsolid t\n");
        expectInputError([&] { loadPolygonMesh(dir / "a.stl"); }, "vertex 4",
                         "non-finite coordinate '" + v + "' (facet 1, line 12)");
    }
    // A normal of an NOFF file, and any other PLY property.
    writeText(dir / "n.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 nan\n0 1 0 0 0 1\n3 0 1 2\n");
    expectInputError([&] { loadPolygonMesh(dir / "n.off"); }, "vertex 1",
                     "non-finite normal component 'nan'");
    writeText(dir / "n.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                             "property float y\nproperty float z\nproperty float nx\n"
                             "element face 1\nproperty list uchar int vertex_indices\n"
                             "end_header\n0 0 0 0\n1 0 0 inf\n0 1 0 0\n3 0 1 2\n");
    expectInputError([&] { loadPolygonMesh(dir / "n.ply"); }, "vertex 1",
                     "non-finite value 'inf' of property 'nx'");
    // Binary PLY, both byte orders, float and double (a double beyond float
    // range would become inf).
    for (bool big : {false, true}) {
        for (bool doubles : {false, true}) {
            SCOPED_TRACE(std::to_string(big) + std::to_string(doubles));
            writeText(dir / "b.ply", binaryPly(big, nan, doubles));
            expectInputError([&] { loadPolygonMesh(dir / "b.ply"); }, "vertex 2",
                             "non-finite coordinate x = 'nan'");
            writeText(dir / "b.ply", binaryPly(big, doubles ? 1e300 : -inf, doubles));
            expectInputError([&] { loadPolygonMesh(dir / "b.ply"); }, "vertex 2",
                             doubles ? "x = '1e+300'" : "x = '-inf'");
            writeText(dir / "b.ply", binaryPly(big, 1.0, doubles));
            EXPECT_EQ(loadPolygonMesh(dir / "b.ply").positions[2], glm::vec3(1, 1, 0));
        }
    }
    // Binary STL: vertices numbered 3 per facet in file order.
    const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(-1, 0, 0);
    writeText(dir / "b.stl", binaryStl({{a, b, c}, {a, c, glm::vec3(float(nan), 0, 0)}}));
    expectInputError([&] { loadPolygonMesh(dir / "b.stl"); }, "vertex 5",
                     "non-finite coordinate 'nan' (facet 1)");
    writeText(dir / "b.stl", binaryStl({{a, b, c}, {a, c, d}}));
    EXPECT_EQ(loadPolygonMesh(dir / "b.stl").faceCount(), 2u);
    // Underflow is a zero, not an error.
    writeText(dir / "u.off", "OFF\n3 1 0\n0 0 1e-999\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_EQ(loadPolygonMesh(dir / "u.off").positions[0], glm::vec3(0.0f));
}

// OpenMesh's STL reader drops facets whose corners coincide without a
// word; the loader counts and notes them.
TEST(Formats, StlFacetsDroppedByOpenMeshAreNoted) {
    TempDir dir;
    const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    writeText(dir / "d.stl", binaryStl({{a, b, c}, {a, b, b}}));
    LoadReport report;
    EXPECT_EQ(loadPolygonMesh(dir / "d.stl", {}, &report).faceCount(), 1u);
    ASSERT_EQ(report.notes.size(), 1u);
    EXPECT_EQ(report.notes[0], "1 degenerate facets (two equal corners) dropped by the STL reader");
}

TEST(Formats, NonManifoldOffIsNamedNotDropped) {
    // OpenMesh's own importer would drop the third face on edge (0,1)
    // ("complex edge"); the recording importer keeps it for validation.
    TempDir dir;
    writeText(dir / "fin.off",
              "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
    expectInputError([&] { loadPolygonMesh(dir / "fin.off"); }, "edge (0, 1)", "shared by 3 faces");
    LoadOptions o;
    o.allowNonManifold = true;
    PolygonMesh m = loadPolygonMesh(dir / "fin.off", o);
    EXPECT_EQ(m.faceCount(), 3u);
    // The OpenMesh view refuses it too, by name.
    PolyMeshProperties props;
    expectInputError([&] { toPolyMesh(m, props, "fin.off"); }, "face 2",
                     "OpenMesh cannot insert it");
    sg::test::reportHardCaseHolds("non-manifold", "three faces on one edge (OFF, OpenMesh reader)",
                                  "loading; loading with non-manifold input allowed",
                                  "InputError naming the edge; all 3 faces kept",
                                  "InputError naming the edge; all 3 faces kept");
}

TEST(Formats, PlyWithUvsThroughOpenMesh) {
    TempDir dir;
    writeText(dir / "quad.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float "
                                "x\nproperty float y\nproperty float z\n"
                                "property float u\nproperty float v\nelement face 1\nproperty list "
                                "uchar int vertex_indices\nend_header\n"
                                "0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n");
    PolygonMesh m = loadPolygonMesh(dir / "quad.ply");
    ASSERT_EQ(m.faceCount(), 1u);
    ASSERT_EQ(m.uvSets.size(), 1u);
    EXPECT_EQ(m.uvSets[0].values[2], glm::vec2(1, 1));
}

TEST(Formats, LyingHeadersAreRefused) {
    TempDir dir;
    writeText(
        dir / "big.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float "
        "x\nproperty float y\n"
        "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n");
    expectInputError([&] { loadPolygonMesh(dir / "big.ply"); }, "header",
                     "declares 4000000000 vertex elements");
    writeText(dir / "big.off", "OFF\n900000000 1 0\n0 0 0\n");
    expectInputError([&] { loadPolygonMesh(dir / "big.off"); }, "header",
                     "declares 900000000 vertices");
    // Binary STL: 80-byte header, triangle count, 50 bytes per triangle.
    std::string stl(84, '\0');
    uint32_t n = 1000000;
    std::memcpy(stl.data() + 80, &n, 4);
    writeText(dir / "big.stl", stl);
    expectInputError([&] { loadPolygonMesh(dir / "big.stl"); }, "header",
                     "declares 1000000 triangles");
}

// PLY headers are parsed in full before OpenMesh's reader sees them: its
// header code indexes the element list unchecked (a property line before
// any element, as in this mutated file found by fuzz_mesh_openmesh,
// crashed it). Each malformed line is named by its number.
TEST(Formats, MalformedPlyHeadersAreNamedByLine) {
    TempDir dir;
    struct Case {
        const char* text;
        const char* element;
        const char* reason;
    };
    const std::string props = "property float x\nproperty float y\nproperty float z\n";
    const Case cases[] = {
        {"ply\nformat ascii 1.0\neement vertex 4\nproperty float x\nend_header\n", "header line 3",
         "unknown header keyword 'eement'"},
        {"ply\nformat ascii 1.0\nproperty float x\nelement vertex 1\nend_header\n", "header line 3",
         "property before any element"},
        {"ply\nelement vertex 1\nend_header\n", "header line 2", "element before the format line"},
        {"ply\nformat ascii 2.0\nend_header\n", "header line 2", "expected 'format ascii"},
        {"ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", "header line 3",
         "non-negative integer count"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", "header line 4",
         "PLY types"},
        {"ply\nformat ascii 1.0\nelement face 1\nproperty list uchar vertex_indices\nend_header\n",
         "header line 4", "property list TYPE TYPE NAME"},
        {"ply\nformat ascii 1.0\nformat ascii 1.0\nend_header\n", "header line 3",
         "a second format line"},
        {"ply\nformat ascii 1.0\nelement vertex 1\n", "header", "no end_header"},
        {"plyx\nformat ascii 1.0\nend_header\n", "header line 1", "not a PLY file"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        writeText(dir / "bad.ply", c.text);
        expectInputError([&] { loadPolygonMesh(dir / "bad.ply"); }, c.element, c.reason);
    }
    // The body, item by item (OpenMesh resizes to a list's size before
    // reading it: a size of -30 read as unsigned asked for 2^31 handles;
    // found by fuzz_mesh_openmesh and kept in its corpus).
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\n" + props +
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const Case bodies[] = {
        {"0 0 0\n1 0 0\n0 1 0\n-30 0 1 2\n", "face 0", "list size '-30' is not an integer in [0, "},
        {"0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "face 0", "too few values"},
        {"0 0 0\n1 0 0\n0 1 0\n3 0 1 2 7\n", "face 0", "more values on its line"},
        {"0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n", "vertex 1", "expected a number, found 'x'"},
        {"0 0 0\n1 0 0\n0 1 0\n", "face 0", "the file ends before face 0 of 1"},
    };
    for (const Case& c : bodies) {
        SCOPED_TRACE(c.text);
        writeText(dir / "bad.ply", head + c.text);
        expectInputError([&] { loadPolygonMesh(dir / "bad.ply"); }, c.element, c.reason);
    }
    // Binary: a signed list size below zero, and one that runs past the end.
    auto binary = [&](int8_t count, int indices, const char* countType = "char") {
        std::string b = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + props +
                        "element face 1\nproperty list " + countType +
                        " int vertex_indices\nend_header\n";
        const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        b.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
        b.push_back(char(count));
        for (int32_t k = 0; k < indices; ++k) b.append(reinterpret_cast<const char*>(&k), 4);
        return b;
    };
    writeText(dir / "negbin.ply", binary(-3, 3));
    expectInputError([&] { loadPolygonMesh(dir / "negbin.ply"); }, "face 0", "negative list size");
    writeText(dir / "shortbin.ply", binary(3, 2));
    expectInputError([&] { loadPolygonMesh(dir / "shortbin.ply"); }, "face 0",
                     "the file ends inside the item");
    writeText(dir / "okbin.ply", binary(3, 3, "uchar"));
    EXPECT_EQ(loadPolygonMesh(dir / "okbin.ply").faceCount(), 1u);

    // Comments, obj_info, CRLF line ends and both list forms are accepted.
    writeText(
        dir / "ok.ply",
        "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info x\r\nelement vertex 3\r\n" +
            props +
            "element face 1\r\nproperty list uint8 int32 vertex_indices\r\nend_header\r\n0 0 "
            "0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n");
    EXPECT_EQ(loadPolygonMesh(dir / "ok.ply").faceCount(), 1u);
}

// ASCII OFF is checked token by token before OpenMesh's reader, whose face
// loop trusts each face's vertex count (a count of -10 read as unsigned
// spun for billions of iterations: found by fuzz_mesh_openmesh, kept in
// its corpus). Each case names the element and the line.
TEST(Formats, MalformedOffIsNamedBeforeOpenMeshReadsIt) {
    TempDir dir;
    struct Case {
        const char* text;
        const char* element;
        const char* reason;
    };
    const Case cases[] = {
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n-10 0 1 2\n", "face 0",
         "line 6: a vertex count in [1, "},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", "face 0",
         "the file ends inside the face (2 of 3 indices)"},
        {"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "face 1",
         "the file ends before face 1 of 2"},
        {"OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n", "vertex 1",
         "line 4: expected a number, found 'x'"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", "face 0",
         "expected 3 vertex indices, found '1.5'"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n0\n", "face 0", "at least one vertex"},
        {"OFF BINARY\n", "header", "binary OFF is not supported"},
        {"4OFF\n1 0 0\n0 0 0 1\n", "header", "dimension other than 3"},
        {"OFF4 1 5\n", "header", "not an OFF file"},
        {"XOFF\n", "header", "unknown OFF keyword 'XOFF'"},
        {"OFF 3 1 0\n", "header", "the OFF keyword alone on line 1"},
        {"OFF\n3 -1 0\n", "header", "expected a face count"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.text);
        writeText(dir / "bad.off", c.text);
        expectInputError([&] { loadPolygonMesh(dir / "bad.off"); }, c.element, c.reason);
    }
    // Normals (NOFF: 6 numbers per vertex), colours after the coordinates
    // (skipped with the rest of the line) and CRLF line ends are accepted.
    writeText(dir / "ok.off",
              "NOFF\r\n3 1 0\r\n0 0 0 0 0 1\r\n1 0 0 0 0 1 255 0 0\r\n0 1 0 0 0 1\r\n3 0 1 2\r\n");
    EXPECT_EQ(loadPolygonMesh(dir / "ok.off").faceCount(), 1u);
}

TEST(Formats, BinaryStlIsWeldedByOpenMesh) {
    // Two triangles of a square, each with its own copies of the corners.
    TempDir dir;
    std::string stl(80, ' ');
    uint32_t n = 2;
    stl.append(reinterpret_cast<const char*>(&n), 4);
    auto tri = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        float nrm[3] = {0, 0, 1};
        stl.append(reinterpret_cast<const char*>(nrm), 12);
        for (const glm::vec3& p : {a, b, c}) stl.append(reinterpret_cast<const char*>(&p), 12);
        stl.append(2, '\0');
    };
    tri({0, 0, 0}, {1, 0, 0}, {1, 1, 0});
    tri({0, 0, 0}, {1, 1, 0}, {0, 1, 0});
    writeText(dir / "sq.stl", stl);
    PolygonMesh m = loadPolygonMesh(dir / "sq.stl");
    EXPECT_EQ(m.faceCount(), 2u);
    EXPECT_EQ(m.vertexCount(), 4u);
    EXPECT_EQ(describe(m).boundaryLoops, 1u);
}

TEST(Formats, ObjRoundTripKeepsTagsAndUvs) {
    TempDir dir;
    PolygonMesh m = parseObj(std::string(sg::test::kCubeObj) +
                                 "t crease 2/1/0 0 1 2.5\nt corner 1/1/0 6 10\nt hole 1/0/0 2\n"
                                 "t facevaryinginterpolateboundary 1/0/0 4\n",
                             "c.obj");
    validate(m, "c.obj");
    auto notes = writePolygonMesh(dir / "out.obj", m);
    EXPECT_TRUE(notes.empty());
    PolygonMesh back = loadPolygonMesh(dir / "out.obj");
    EXPECT_EQ(back.positions, m.positions);
    EXPECT_EQ(back.faceVertices, m.faceVertices);
    EXPECT_EQ(back.uvSets[0].values, m.uvSets[0].values);
    EXPECT_EQ(back.uvSets[0].indices, m.uvSets[0].indices);
    ASSERT_EQ(back.creases.size(), 1u);
    EXPECT_EQ(back.creases[0].sharpness, 2.5f);
    ASSERT_EQ(back.corners.size(), 1u);
    EXPECT_EQ(back.holes, m.holes);
    EXPECT_EQ(back.options.fvar, FVarInterpolation::Boundaries);
    // OpenSubdiv's refinement of both agrees exactly.
    SubdivisionSettings s;
    s.level = 2;
    s.options = m.options;
    EXPECT_EQ(Subdivider(m, s).refined().positions, Subdivider(back, s).refined().positions);
}

TEST(Formats, PlyAndGltfWritersRoundTrip) {
    TempDir dir;
    PolygonMesh cube = parseObj(sg::test::kCubeObj, "c.obj");
    validate(cube, "c.obj");
    SubdivisionSettings s;
    s.level = 2;
    s.limit = true;
    Subdivider sub(cube, s);
    RenderMesh rm = sub.renderMesh();
    rm.tangents.assign(rm.vertexCount(), glm::vec4(1, 0, 0, -1));
    rm.tangentUvSet = 0;
    for (const char* name : {"out.gltf", "out.glb"}) {
        writeRenderMesh(dir / name, rm);
        RenderMesh back = loadRenderMesh(dir / name);
        ASSERT_EQ(back.vertexCount(), rm.vertexCount()) << name;
        EXPECT_EQ(back.indices, rm.indices);
        EXPECT_EQ(back.positions, rm.positions); // float32 in, float32 out
        ASSERT_EQ(back.uvSets.size(), 1u);
        for (size_t i = 0; i < rm.vertexCount(); ++i) {
            // t -> 1 - t -> 1 - (1 - t): exact for t in [0,1] on a 2^-k grid; 1 ulp otherwise.
            EXPECT_NEAR(back.uvSets[0][i].y, rm.uvSets[0][i].y, 1e-7f);
            EXPECT_LT(glm::length(back.normals[i] - rm.normals[i]), 1e-6f); // renormalized on load
        }
        ASSERT_EQ(back.tangents.size(), rm.vertexCount());
        EXPECT_EQ(back.tangents[0], glm::vec4(1, 0, 0, -1));
    }
    // OBJ and PLY (render mesh): the split vertices are welded back, so the
    // surface reads back closed (no repair needed), one vertex per refined
    // vertex, with the same triangles.
    for (const char* name : {"out.obj", "out.ply"}) {
        SCOPED_TRACE(name);
        writeRenderMesh(dir / name, rm);
        PolygonMesh back = loadPolygonMesh(dir / name);
        EXPECT_EQ(back.faceCount(), rm.triangleCount());
        EXPECT_EQ(back.vertexCount(), sub.refined().vertexCount());
        const MeshInfo info = describe(back);
        EXPECT_EQ(info.boundaryEdges, 0u);
        EXPECT_EQ(info.eulerCharacteristic, 2);
        EXPECT_TRUE(info.manifold);
    }
    // OBJ keeps the UVs and normals per corner: loaded for rendering, every
    // corner has its position, UV and normal back (vertex numbering may
    // differ: copies with equal attributes are merged).
    RenderMesh obj = loadRenderMesh(dir / "out.obj");
    ASSERT_EQ(obj.triangleCount(), rm.triangleCount());
    for (size_t c = 0; c < rm.indices.size(); ++c) {
        const uint32_t a = rm.indices[c], b = obj.indices[c];
        ASSERT_EQ(obj.positions[b], rm.positions[a]) << c; // shortest round-trip text
        ASSERT_EQ(obj.uvSets[0][b], rm.uvSets[0][a]) << c;
        // Normals are renormalized on load: an ulp or two.
        ASSERT_LT(glm::length(obj.normals[b] - rm.normals[a]), 1e-6f) << c;
    }
    // PLY (polygons) keeps quads.
    writePolygonMesh(dir / "quads.ply", sub.refined());
    PolygonMesh quads = loadPolygonMesh(dir / "quads.ply");
    EXPECT_EQ(quads.faceCount(), sub.refined().faceCount());
    EXPECT_EQ(quads.positions, sub.refined().positions);
}

TEST(Formats, WritersRefuseInputsAndUnknownFormats) {
    TempDir dir;
    writeText(dir / "in.obj", sg::test::kCubeObj);
    PolygonMesh m = loadPolygonMesh(dir / "in.obj");
    WriteOptions o;
    o.inputs = {dir / "in.obj"};
    expectInputError([&] { writePolygonMesh(dir / "in.obj", m, o); }, "",
                     "would overwrite the input");
    expectInputError([&] { writePolygonMesh(dir / "out.fbx", m, o); }, "",
                     "unknown output format '.fbx'");
    expectInputError([&] { writePolygonMesh(dir / "no_such_dir" / "out.obj", m, o); }, "",
                     "does not exist");
    // Nothing half-written is left behind.
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir.path()))
        files += e.is_regular_file();
    EXPECT_EQ(files, 1u);
}

TEST(Formats, PolyMeshViewRoundTrip) {
    PolygonMesh m = parseObj(std::string(sg::test::kCubeObj) +
                                 "t crease 2/1/0 0 1 3\nt corner 1/1/0 7 2\nt hole 1/0/0 4\n",
                             "c.obj");
    validate(m, "c.obj");
    PolyMeshProperties props;
    PolyMesh pm = toPolyMesh(m, props, "c.obj");
    EXPECT_EQ(pm.n_faces(), 6u);
    EXPECT_EQ(pm.n_edges(), 12u);
    PolygonMesh back = fromPolyMesh(pm, props);
    EXPECT_EQ(back.positions, m.positions);
    EXPECT_EQ(back.faceCount(), 6u);
    ASSERT_EQ(back.creases.size(), 1u);
    EXPECT_EQ(back.creases[0].sharpness, 3.0f);
    ASSERT_EQ(back.corners.size(), 1u);
    EXPECT_EQ(back.corners[0].vertex, 7u);
    EXPECT_EQ(back.holes, std::vector<uint32_t>{4});
    // Same UV per corner (up to the face's starting corner, which OpenMesh may rotate).
    validate(back, "back");
    for (size_t f = 0; f < 6; ++f) {
        for (uint32_t k = 0; k < 4; ++k) {
            uint32_t v = back.faceVertices[4 * f + k];
            glm::vec2 uv = back.uvSets[0].values[back.uvSets[0].indices[4 * f + k]];
            bool found = false;
            for (uint32_t j = 0; j < 4; ++j) {
                found |= m.faceVertices[4 * f + j] == v &&
                         m.uvSets[0].values[m.uvSets[0].indices[4 * f + j]] == uv;
            }
            EXPECT_TRUE(found) << "face " << f << " corner " << k;
        }
    }
}

} // namespace
