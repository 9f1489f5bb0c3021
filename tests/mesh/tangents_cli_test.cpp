// `surfgrad mesh tangents` from outside: runs the built binary
// (SURFGRAD_BINARY_DIR/bin/surfgrad), reads the glTF it writes with
// tinygltf, and checks TANGENT against what the input says (MikkTSpace
// tangents of NormalTangentMirrorTest), or against the invariants of the
// limit frame (unit, orthogonal to NORMAL, |w| = 1); plus the errors: no
// output and exit status 1 for bad arguments.
#include <gtest/gtest.h>

#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <unistd.h>

#include <glm/geometric.hpp>

#include "cli.h"
#include "surfgrad/mesh/mesh_io.h"
#include "tangents_test_util.h"

namespace {

namespace fs = std::filesystem;

const std::string kData = SURFGRAD_DATA_DIR;

using CliRun = sg::test::CommandResult;

CliRun surfgrad(const std::string& args) {
    return sg::test::runSurfgrad(args);
}

class TangentsCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("surfgrad_tangents_cli_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    fs::path dir_;
};

// A written .glb's first primitive: positions, normals, tangents, UVs
// (flipped to t up, as the reader of the input does).
struct Written {
    std::vector<glm::vec3> positions, normals;
    std::vector<glm::vec4> tangents;
    std::vector<glm::vec2> uvs;
};

template <typename T>
std::vector<T> accessorData(const tinygltf::Model& m, int index) {
    const tinygltf::Accessor& a = m.accessors.at(size_t(index));
    const tinygltf::BufferView& bv = m.bufferViews.at(size_t(a.bufferView));
    const auto& data = m.buffers.at(size_t(bv.buffer)).data;
    const size_t stride = bv.byteStride ? bv.byteStride : sizeof(T);
    std::vector<T> out(a.count);
    for (size_t i = 0; i < a.count; ++i)
        std::memcpy(&out[i], data.data() + bv.byteOffset + a.byteOffset + i * stride, sizeof(T));
    return out;
}

Written readGlb(const std::string& file) {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    EXPECT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, file)) << err;
    Written w;
    if (model.meshes.empty()) return w;
    const tinygltf::Primitive& p = model.meshes[0].primitives.at(0);
    auto attr = [&](const char* name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -1 : it->second;
    };
    EXPECT_GE(attr("TANGENT"), 0) << file << " has no TANGENT";
    if (attr("TANGENT") < 0) return w;
    EXPECT_EQ(model.accessors.at(size_t(attr("TANGENT"))).type, TINYGLTF_TYPE_VEC4);
    w.positions = accessorData<glm::vec3>(model, attr("POSITION"));
    w.normals = accessorData<glm::vec3>(model, attr("NORMAL"));
    w.tangents = accessorData<glm::vec4>(model, attr("TANGENT"));
    w.uvs = accessorData<glm::vec2>(model, attr("TEXCOORD_0"));
    for (glm::vec2& t : w.uvs) t.y = 1.0f - t.y;
    return w;
}

double angleDeg(glm::vec3 a, glm::vec3 b) {
    const glm::dvec3 da(a), db(b);
    return std::atan2(glm::length(glm::cross(da, db)), glm::dot(da, db)) * 180.0 / M_PI;
}

TEST_F(TangentsCli, MikkTSpaceGlbMatchesTheSampleTangents) {
    const std::string in =
        kData + "/gltf/NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf";
    const CliRun r = surfgrad("mesh tangents '" + in + "' -o '" + path("out.glb") + "' --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("\"method\":\"mikktspace\""), std::string::npos) << r.out;
    const Written w = readGlb(path("out.glb"));
    ASSERT_FALSE(w.tangents.empty());
    // Match output vertices to input vertices by position and uv (the
    // loader may reorder or merge primitives), then compare with the
    // file's MikkTSpace tangents.
    const sg::test::GltfPrimitive ref = sg::test::readGltfPrimitive(in);
    std::map<std::array<float, 5>, size_t> byValue;
    for (size_t v = 0; v < ref.positions.size(); ++v)
        byValue[{ref.positions[v].x, ref.positions[v].y, ref.positions[v].z, ref.uvs[v].x,
                 ref.uvs[v].y}] = v;
    size_t matched = 0, signAgree = 0;
    double maxAngle = 0.0;
    for (size_t v = 0; v < w.positions.size(); ++v) {
        auto it = byValue.find(
            {w.positions[v].x, w.positions[v].y, w.positions[v].z, w.uvs[v].x, w.uvs[v].y});
        if (it == byValue.end()) continue;
        const glm::vec4 file = ref.tangents[it->second];
        maxAngle = std::max(maxAngle, angleDeg(glm::vec3(w.tangents[v]), glm::vec3(file)));
        signAgree += w.tangents[v].w == file.w;
        ++matched;
    }
    // Positions and UVs survive the glTF round trip bit for bit (float in,
    // float out; the t flip is exact for these values or the match fails
    // and the vertex is skipped); nearly all must match.
    EXPECT_GT(matched, w.positions.size() * 9 / 10);
    EXPECT_EQ(signAgree, matched);
    // As the library test: 0.0029 deg measured; rounding of the exporter's
    // inputs, not the algorithm (docs/tangents.md).
    EXPECT_LT(maxAngle, 0.01);
}

TEST_F(TangentsCli, LimitFramesAreUnitAndOrthogonalToTheNormal) {
    const std::string in = kData + "/meshes/spot/spot_control_mesh.obj";
    const CliRun r = surfgrad("mesh tangents '" + in + "' --method limit --level 2 -o '" +
                              path("spot.glb") + "'");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("limit tangents"), std::string::npos) << r.out;
    const Written w = readGlb(path("spot.glb"));
    ASSERT_GT(w.tangents.size(), 2000u);
    ASSERT_EQ(w.normals.size(), w.tangents.size());
    for (size_t v = 0; v < w.tangents.size(); ++v) {
        const glm::vec4 t = w.tangents[v];
        ASSERT_TRUE(t.w == 1.0f || t.w == -1.0f) << v;
        // Written as float: a few ulps of length and orthogonality.
        ASSERT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-5f) << v;
        ASSERT_NEAR(glm::dot(glm::vec3(t), glm::normalize(w.normals[v])), 0.0f, 1e-5f) << v;
    }
}

TEST_F(TangentsCli, BadArgumentsFailWithoutOutput) {
    const std::string in = kData + "/meshes/spot/spot_control_mesh.obj";
    // Exit status 2 for a wrong command line, 1 for bad input.
    struct Case {
        std::string args, message;
        int exitCode;
    };
    const std::vector<Case> cases = {
        {"mesh tangents '" + in + "' --uv-set 2 -o '" + path("a.glb") + "'", "UV set", 1},
        {"mesh tangents '" + in + "' -o '" + path("a.obj") + "'", "glTF output", 2},
        {"mesh tangents '" + in + "' --method pixel -o '" + path("a.glb") + "'",
         "built by the shader", 2},
        {"mesh tangents '" + in + "' --method nope -o '" + path("a.glb") + "'",
         "expected mikktspace or limit", 2},
        {"mesh tangents '" + in + "' --level 99 -o '" + path("a.glb") + "'", "--level", 2},
        {"mesh tangents '" + path("missing.obj") + "' -o '" + path("a.glb") + "'", "missing.obj",
         1},
        {"mesh tangents '" + in + "' -o '" + in + "'", "", 2}, // .obj (and never over the input)
    };
    for (const Case& c : cases) {
        const CliRun r = surfgrad(c.args);
        EXPECT_EQ(r.exitCode, c.exitCode) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find("surfgrad: error:"), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_FALSE(fs::exists(path("a.glb"))) << c.args;
    }
}

// A mesh file whose values MikkTSpace cannot take (a coordinate beyond
// 2^60: products of differences could overflow to NaN) is bad input: an
// InputError naming the file and the vertex, exit status 1, no output.
TEST_F(TangentsCli, ValuesMikkTSpaceCannotTakeFailNamingTheFile) {
    const std::string in = path("huge.obj");
    std::ofstream(in) << "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                         "f 1/1 2/2 3/3\n";
    const CliRun r = surfgrad("mesh tangents '" + in + "' -o '" + path("a.glb") + "'");
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.err.find("surfgrad: error: " + in + ": MikkTSpace: vertex 1"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("a.glb")));
}

// A chart with no frame: two triangles of a quad, the second with its UVs
// collinear (its area is 0), then one of them moved by a rounding-size
// amount. MikkTSpace keeps its rule (the reference algorithm); the command
// counts the triangles whose frame follows the rounding and says what to
// do, in its notes and its JSON.
TEST_F(TangentsCli, MikkTSpaceNamesChartsWithNoFrame) {
    const std::string in = path("chart.obj");
    std::ofstream(in) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0.5 0.5\nvt 0.25 0.25\n"
                         "vn 0 0 1\n"
                         "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
    const CliRun r = surfgrad("mesh tangents '" + in + "' -o '" + path("a.glb") + "' --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // Triangle 2's UVs (0,0), (1,1), (0.5,0.5) are collinear: counted.
    EXPECT_NE(r.out.find("\"rounding_area_triangles\":1"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("MikkTSpace gives them the frame of that rounding"), std::string::npos)
        << r.out;
    // Moved by one ulp (0.5 -> 0.50000006): still within the rounding.
    std::ofstream(in) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0.50000006 0.5\n"
                         "vn 0 0 1\n"
                         "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
    const CliRun r2 = surfgrad("mesh tangents '" + in + "' -o '" + path("b.glb") + "' --json");
    ASSERT_EQ(r2.exitCode, 0) << r2.err;
    EXPECT_NE(r2.out.find("\"rounding_area_triangles\":1"), std::string::npos) << r2.out;
    // A chart with area: nothing to say.
    std::ofstream(in) << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                         "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n";
    const CliRun r3 = surfgrad("mesh tangents '" + in + "' -o '" + path("c.glb") + "' --json");
    ASSERT_EQ(r3.exitCode, 0) << r3.err;
    EXPECT_NE(r3.out.find("\"rounding_area_triangles\":0"), std::string::npos) << r3.out;
    EXPECT_EQ(r3.out.find("MikkTSpace gives them"), std::string::npos) << r3.out;
}

TEST_F(TangentsCli, ThreadCountOutOfRangeIsAUsageError) {
    const std::string in = kData + "/meshes/spot/spot_control_mesh.obj";
    for (const char* n : {"0", "2000", "-1"}) {
        const CliRun r =
            surfgrad("mesh tangents '" + in + "' --threads " + n + " -o '" + path("a.glb") + "'");
        EXPECT_EQ(r.exitCode, 2) << n << "\n" << r.err;
        EXPECT_NE(r.err.find("--threads"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("a.glb")));
    }
}

// A height-field grid of n x n quads (2 n^2 triangles) with mirrored UVs
// (u folds at x = 1/2: MikkTSpace splits the vertices there) and vertex
// normals, as OBJ text: shared v/vt/vn indices, or every corner with its
// own v, vt and vn lines (as many exporters write).
std::string gridObj(int n, bool cornerOwnIndices) {
    std::string obj;
    auto point = [&](int i, int j, std::string& v, std::string& vt, std::string& vn) {
        const float x = float(i) / float(n), y = float(j) / float(n);
        const float z = 0.1f * std::sin(6.0f * x) * std::cos(5.0f * y);
        const glm::vec3 nrm =
            glm::normalize(glm::vec3(-0.6f * std::cos(6.0f * x) * std::cos(5.0f * y),
                                     0.5f * std::sin(6.0f * x) * std::sin(5.0f * y), 1.0f));
        const float u = x < 0.5f ? 2.0f * x : 2.0f - 2.0f * x;
        char buf[128];
        std::snprintf(buf, sizeof buf, "v %.7g %.7g %.7g\n", x, y, z);
        v = buf;
        std::snprintf(buf, sizeof buf, "vt %.7g %.7g\n", u, y);
        vt = buf;
        std::snprintf(buf, sizeof buf, "vn %.7g %.7g %.7g\n", nrm.x, nrm.y, nrm.z);
        vn = buf;
    };
    std::string v, vt, vn;
    if (!cornerOwnIndices) {
        std::string vs, vts, vns;
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                point(i, j, v, vt, vn);
                vs += v, vts += vt, vns += vn;
            }
        obj = vs + vts + vns;
    }
    auto id = [&](int i, int j) { return std::to_string(j * (n + 1) + i + 1); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int tri[2][3][2] = {{{i, j}, {i + 1, j}, {i + 1, j + 1}},
                                      {{i, j}, {i + 1, j + 1}, {i, j + 1}}};
            for (const auto& t : tri) {
                if (cornerOwnIndices) {
                    std::string vs, vts, vns;
                    for (const auto& c : t) {
                        point(c[0], c[1], v, vt, vn);
                        vs += v, vts += vt, vns += vn;
                    }
                    obj += vs + vts + vns + "f -3/-3/-3 -2/-2/-2 -1/-1/-1\n";
                } else {
                    obj += "f";
                    for (const auto& c : t) {
                        const std::string k = id(c[0], c[1]);
                        obj += " " + k + "/" + k + "/" + k;
                    }
                    obj += "\n";
                }
            }
        }
    return obj;
}

// Above the generator's parallel cut-over (2 * 110^2 = 24200 triangles),
// the OBJ reader's (every corner its own v/vt/vn: a file of more than
// kObjParallelMinBytes) and the weld's (72,600 corners welded by value):
// the written file is the same bytes at 1 and 3 threads (and all cores).
TEST_F(TangentsCli, OutputIsTheSameBytesForEveryThreadCount) {
    const std::string in = path("grid.obj");
    std::ofstream(in) << gridObj(110, true);
    ASSERT_GT(std::filesystem::file_size(in), sg::mesh::kObjParallelMinBytes);
    std::vector<std::string> bytes;
    for (const char* threads : {"1", "3", ""}) {
        const std::string out = path(std::string("grid") + threads + ".glb");
        const std::string opt = *threads ? std::string(" --threads ") + threads : "";
        const CliRun r = surfgrad("mesh tangents '" + in + "'" + opt + " -o '" + out + "'");
        ASSERT_EQ(r.exitCode, 0) << r.err;
        std::ifstream f(out, std::ios::binary);
        bytes.emplace_back(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    }
    ASSERT_GT(bytes[0].size(), 100000u);
    EXPECT_TRUE(bytes[0] == bytes[1]) << "--threads 1 and --threads 3 differ";
    EXPECT_TRUE(bytes[0] == bytes[2]) << "--threads 1 and all cores differ";
}

// Every corner with its own v/vt/vn indices: the output has only the
// distinct vertices, the same arrays (order: first occurrence) and the
// same tangents as the file with shared indices.
TEST_F(TangentsCli, CornersWithTheirOwnIndicesAreWeldedByValue) {
    const int n = 40;
    std::ofstream(path("shared.obj")) << gridObj(n, false);
    std::ofstream(path("corners.obj")) << gridObj(n, true);
    const CliRun a =
        surfgrad("mesh tangents '" + path("shared.obj") + "' -o '" + path("a.glb") + "' --json");
    const CliRun b =
        surfgrad("mesh tangents '" + path("corners.obj") + "' -o '" + path("b.glb") + "' --json");
    ASSERT_EQ(a.exitCode, 0) << a.err;
    ASSERT_EQ(b.exitCode, 0) << b.err;
    EXPECT_NE(a.out.find("\"welded_vertices\":0"), std::string::npos) << a.out;
    // 6 n^2 corners, (n + 1)^2 distinct points.
    EXPECT_NE(b.out.find("\"welded_vertices\":" + std::to_string(6 * n * n - (n + 1) * (n + 1))),
              std::string::npos)
        << b.out;
    const Written wa = readGlb(path("a.glb")), wb = readGlb(path("b.glb"));
    // (n + 1)^2 points plus the copies MikkTSpace splits at the fold.
    ASSERT_GT(wa.positions.size(), size_t((n + 1) * (n + 1)));
    ASSERT_EQ(wa.positions.size(), wb.positions.size());
    auto same = [](const auto& x, const auto& y) {
        return x.size() == y.size() &&
               std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
    };
    EXPECT_TRUE(same(wa.positions, wb.positions));
    EXPECT_TRUE(same(wa.normals, wb.normals));
    EXPECT_TRUE(same(wa.uvs, wb.uvs));
    EXPECT_TRUE(same(wa.tangents, wb.tangents));
}

} // namespace
