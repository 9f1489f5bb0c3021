// Threads in subdivision (SubdivisionSettings::threads, buildAdaptivePatches
// and updateAdaptivePoints' threads, `mesh subdivide|morph --threads`): the
// output at 2, 3 and 7 threads is the one-thread output bit for bit (memcmp
// of every float array, equality of every index), on the data/ meshes and
// on random cages (rapidcheck) with creases, corners, UV seams, triangles
// and every boundary and face-varying rule; uniform refinement with the
// specialised refiner and with Far, limit evaluation (positions, normals,
// UVs, the limit frame), stencil updates, rebuilds of the same topology.
// Builds set serialBelowFaces = 0 so that even small cages run every loop
// on TBB, in blocks of 16 elements. Bit-identity needs no tolerance.
//
// Seeds: a fixed rapidcheck seed (kDefaultParams, unless RC_PARAMS is set);
// RC_PARAMS="max_success=2000 seed=7" build/bin/mesh_tests
// --gtest_filter='SubdivisionThreads.*' runs more.
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli.h"
#include "mesh_test_util.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

using namespace sg::mesh;
namespace fs = std::filesystem;

constexpr const char* kDefaultParams = "seed=20260729 max_success=150";
[[maybe_unused]] const bool kSeeded = [] {
    if (!std::getenv("RC_PARAMS")) setenv("RC_PARAMS", kDefaultParams, 0);
    return true;
}();

constexpr int kThreadCounts[] = {2, 3, 7};

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}
template <class T>
bool sameBits(const std::vector<std::vector<T>>& a, const std::vector<std::vector<T>>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
        if (!sameBits(a[i], b[i])) return false;
    }
    return true;
}

// Every array of refined(), renderMesh() and limitFrame(); "" when equal,
// else the first that differs.
std::string firstDifference(const Subdivider& want, const Subdivider& got) {
    const PolygonMesh &a = want.refined(), &b = got.refined();
    if (a.faceSizes != b.faceSizes || a.faceVertices != b.faceVertices) return "refined faces";
    if (!sameBits(a.positions, b.positions)) return "refined positions";
    if (!sameBits(a.normals, b.normals) || a.normalIndices != b.normalIndices)
        return "refined normals";
    if (a.holes != b.holes) return "refined holes";
    if (a.uvSets.size() != b.uvSets.size()) return "UV set count";
    for (size_t s = 0; s < a.uvSets.size(); ++s) {
        if (a.uvSets[s].indices != b.uvSets[s].indices ||
            !sameBits(a.uvSets[s].values, b.uvSets[s].values))
            return "refined UV set " + std::to_string(s);
    }
    if (a.creases.size() != b.creases.size() || a.corners.size() != b.corners.size())
        return "refined tags";
    for (size_t i = 0; i < a.creases.size(); ++i) {
        if (a.creases[i].v0 != b.creases[i].v0 || a.creases[i].v1 != b.creases[i].v1 ||
            std::memcmp(&a.creases[i].sharpness, &b.creases[i].sharpness, sizeof(float)))
            return "refined crease " + std::to_string(i);
    }
    for (size_t t = 0; t < a.morphTargets.size(); ++t) {
        if (!sameBits(a.morphTargets[t].positionDeltas, b.morphTargets[t].positionDeltas))
            return "refined morph target " + std::to_string(t);
    }
    const RenderMesh &ra = want.renderMesh(), &rb = got.renderMesh();
    if (ra.indices != rb.indices) return "render indices";
    if (!sameBits(ra.positions, rb.positions)) return "render positions";
    if (!sameBits(ra.normals, rb.normals)) return "render normals";
    if (!sameBits(ra.uvSets, rb.uvSets)) return "render UVs";
    if (ra.morphTargets.size() != rb.morphTargets.size()) return "render morph targets";
    for (size_t t = 0; t < ra.morphTargets.size(); ++t) {
        if (!sameBits(ra.morphTargets[t].positionDeltas, rb.morphTargets[t].positionDeltas))
            return "render morph target " + std::to_string(t);
    }
    if (want.renderToRefinedVertex() != got.renderToRefinedVertex()) return "render -> refined";
    const LimitFrame &fa = want.limitFrame(), &fb = got.limitFrame();
    if (!sameBits(fa.dPdu, fb.dPdu) || !sameBits(fa.dPdv, fb.dPdv)) return "limit dP";
    if (!sameBits(fa.dUVdu, fb.dUVdu) || !sameBits(fa.dUVdv, fb.dUVdv)) return "limit dUV";
    if (fa.ptexFace != fb.ptexFace || !sameBits(fa.ptexUV, fb.ptexUV)) return "limit homes";
    if (!sameBits(fa.morphDPdu, fb.morphDPdu) || !sameBits(fa.morphDPdv, fb.morphDPdv))
        return "limit morph dP";
    if (want.usedSpecializedRefiner() != got.usedSpecializedRefiner()) return "refiner choice";
    if (want.stencilWeightCount() != got.stencilWeightCount()) return "stencil weights";
    return {};
}

// The cage moved (an animation frame).
std::vector<glm::vec3> moved(const PolygonMesh& cage) {
    std::vector<glm::vec3> p = cage.positions;
    for (size_t i = 0; i < p.size(); ++i)
        p[i] = glm::vec3(p[i].x * (1.0f + 0.01f * float(i % 7)), p[i].y + 0.02f * float(i % 3),
                         p[i].z);
    return p;
}

// Builds `cage` at 1 thread and at each of kThreadCounts (a build, an
// update() with animate, and a same-topology rebuild for uniform builds);
// "" when everything is the same bits, else what differs.
std::string compareThreads(const PolygonMesh& cage, SubdivisionSettings s) {
    s.serialBelowFaces = 0;
    s.threads = 1;
    Subdivider one(cage, s);
    RenderMesh oneFrame;
    LimitFrame oneLimit;
    if (s.animate && s.buildRenderMesh) {
        oneFrame = one.renderMesh();
        one.update(moved(cage), oneFrame, &oneLimit);
    }
    PolygonMesh again = cage;
    again.positions = moved(cage);
    Subdivider oneAgain(cage, s);
    oneAgain.build(again, s);
    for (int threads : kThreadCounts) {
        const std::string at = " at " + std::to_string(threads) + " threads";
        s.threads = threads;
        Subdivider many(cage, s);
        std::string d = firstDifference(one, many);
        if (!d.empty()) return d + at;
        if (s.animate && s.buildRenderMesh) {
            RenderMesh frame = many.renderMesh();
            LimitFrame limit;
            many.update(moved(cage), frame, &limit);
            if (!sameBits(frame.positions, oneFrame.positions) ||
                !sameBits(frame.normals, oneFrame.normals))
                return "update()" + at;
            if (!sameBits(limit.dPdu, oneLimit.dPdu) || !sameBits(limit.dPdv, oneLimit.dPdv))
                return "update() limit frame" + at;
        }
        many.build(again, s); // a rebuild of the same topology (stencils when uniform)
        d = firstDifference(oneAgain, many);
        if (!d.empty()) return "rebuild: " + d + at;
    }
    return {};
}

PolygonMesh load(const std::string& rel) {
    return loadPolygonMesh(sg::test::dataPath(rel));
}

// Spot to level 4 (47k quads) and bob (10.7k triangles) to level 2 (128k
// quads); then spot at level 5 (187k quads) at the default cut-over.
TEST(SubdivisionThreads, SpotAndBobUniformAreTheSameBitsAtEveryCount) {
    struct Case {
        const char* rel;
        int level;
        bool far;
    };
    for (const Case& c :
         {Case{"meshes/spot/spot_control_mesh.obj", 1, true},
          Case{"meshes/spot/spot_control_mesh.obj", 3, true},
          Case{"meshes/spot/spot_control_mesh.obj", 4, false},
          Case{"meshes/bob/bob_tri.obj", 1, true}, Case{"meshes/bob/bob_tri.obj", 2, false}}) {
        const PolygonMesh cage = load(c.rel);
        SubdivisionSettings s;
        s.level = c.level;
        s.animate = c.level != 4;
        EXPECT_EQ(compareThreads(cage, s), "") << c.rel << " level " << c.level;
        if (!c.far) continue;
        s.specializedRefiner = false; // Far's refinement, our render mesh and stencils
        EXPECT_EQ(compareThreads(cage, s), "") << c.rel << " level " << c.level << " (Far)";
    }
    // The default cut-over at level 5 (threads without serialBelowFaces = 0).
    const PolygonMesh spot = load("meshes/spot/spot_control_mesh.obj");
    SubdivisionSettings s;
    s.level = 5;
    s.threads = 1;
    Subdivider one(spot, s);
    for (int threads : {0, 2, 3, 7}) {
        s.threads = threads;
        Subdivider many(spot, s);
        EXPECT_EQ(firstDifference(one, many), "") << threads << " threads";
    }
}

TEST(SubdivisionThreads, LimitEvaluationIsTheSameBitsAtEveryCount) {
    // (bob's 10.7k triangles are all irregular: its limit build takes
    // tens of seconds; the random cages cover triangles.)
    for (const char* rel : {"meshes/spot/spot_control_mesh.obj",
                            "gltf/AnimatedMorphSphere/glTF/AnimatedMorphSphere.gltf"}) {
        const PolygonMesh cage = load(rel);
        SubdivisionSettings s;
        s.level = 2;
        s.limit = true;
        s.animate = true;
        EXPECT_EQ(compareThreads(cage, s), "") << rel;
    }
}

// Creases and corners (semi-sharp and infinite, both creasing methods),
// every face-varying rule, UV seams, holes, and Loop on a triangle cage.
TEST(SubdivisionThreads, OsdShapesWithTagsAndFaceVaryingRules) {
    for (const char* name : {"catmark_torus_creases1", "catmark_fvar_bound1", "catmark_fvar_bound2",
                             "catmark_cube_corner3", "catmark_hole_test1", "catmark_chaikin1",
                             "loop_triangle_edgeonly", "catmark_edgecorner"}) {
        const fs::path path = sg::test::dataPath(std::string("osd-shapes/") + name + ".obj");
        if (!fs::exists(path)) {
            ADD_FAILURE() << path << " missing";
            continue;
        }
        const PolygonMesh cage = loadPolygonMesh(path);
        for (int fvar : {0, 2, 5}) {
            SubdivisionSettings s;
            s.options = cage.options;
            s.options.fvar = FVarInterpolation(fvar);
            s.level = 3;
            s.animate = true;
            EXPECT_EQ(compareThreads(cage, s), "") << name << " fvar " << fvar;
            s.level = 2;
            s.limit = true;
            EXPECT_EQ(compareThreads(cage, s), "") << name << " fvar " << fvar << " limit";
        }
    }
}

TEST(SubdivisionThreads, AdaptivePatchesAreTheSameBitsAtEveryCount) {
    // Spot's level-3 mesh as a cage: 11.7k faces, patches above the serial
    // cut-over at isolation 2.
    const PolygonMesh spot = load("meshes/spot/spot_control_mesh.obj");
    SubdivisionSettings s;
    s.level = 3;
    s.buildRenderMesh = false;
    Subdivider sub(spot, s);
    PolygonMesh cage = sub.refined();
    cage.creases.clear();
    cage.corners.clear();
    const AdaptivePatches one = buildAdaptivePatches(cage, cage.options, 2, "spot2", 1);
    ASSERT_GE(one.patchCount(), kAdaptiveSerialBelowPatches);
    const std::vector<glm::vec3> next = moved(cage);
    AdaptivePatches oneNext = one;
    updateAdaptivePoints(oneNext, next, 1);
    for (int threads : {0, 2, 3, 7}) {
        AdaptivePatches many = buildAdaptivePatches(cage, cage.options, 2, "spot2", threads);
        EXPECT_TRUE(sameBits(one.points, many.points)) << threads;
        EXPECT_TRUE(sameBits(one.cornerVertices, many.cornerVertices)) << threads;
        EXPECT_TRUE(sameBits(one.edgeOwners, many.edgeOwners)) << threads;
        EXPECT_EQ(one.indices, many.indices) << threads;
        updateAdaptivePoints(many, next, threads);
        EXPECT_TRUE(sameBits(oneNext.points, many.points)) << threads;
    }
}

// ---- Random cages ----------------------------------------------------------------

// A cols x rows grid of quads, closed into a torus or open (a boundary),
// some quads split into triangles (all of them for Loop), the corners'
// positions jittered, UVs from the grid (a torus gets seams where it
// wraps, and `seams` cuts more), random semi-sharp and infinite creases on
// grid edges and random corners.
struct RandomCage {
    PolygonMesh cage;
    SubdivisionSettings settings;
};

rc::Gen<RandomCage> randomCage() {
    return rc::gen::exec([] {
        const int cols = *rc::gen::inRange(3, 9), rows = *rc::gen::inRange(3, 9);
        const bool torus = *rc::gen::arbitrary<bool>();
        const bool loop =
            *rc::gen::weightedOneOf<bool>({{1, rc::gen::just(true)}, {4, rc::gen::just(false)}});
        const int splitPercent = loop ? 100 : *rc::gen::inRange(0, 60);
        const uint32_t seed = *rc::gen::arbitrary<uint32_t>();
        uint32_t state = seed | 1u;
        auto next = [&] { // xorshift: many draws without a generator each
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            return state;
        };
        auto unit = [&] { return float(next() % 10000) / 10000.0f; };
        RandomCage out;
        PolygonMesh& m = out.cage;
        m.name = "random";
        const int vCols = torus ? cols : cols + 1, vRows = torus ? rows : rows + 1;
        for (int j = 0; j < vRows; ++j) {
            for (int i = 0; i < vCols; ++i) {
                const float a = 6.2831853f * float(i) / float(cols),
                            b = 6.2831853f * float(j) / float(rows);
                glm::vec3 p = torus ? glm::vec3((2.0f + std::cos(b)) * std::cos(a),
                                                (2.0f + std::cos(b)) * std::sin(a), std::sin(b))
                                    : glm::vec3(float(i), float(j), 0.3f * std::sin(a + b));
                p += 0.15f * glm::vec3(unit() - 0.5f, unit() - 0.5f, unit() - 0.5f);
                m.positions.push_back(p);
            }
        }
        auto vid = [&](int i, int j) { return uint32_t((j % vRows) * vCols + (i % vCols)); };
        FaceVaryingChannel uv;
        uv.name = "uv";
        for (int j = 0; j <= rows; ++j) {
            for (int i = 0; i <= cols; ++i)
                uv.values.push_back(glm::vec2(float(i) / float(cols), float(j) / float(rows)));
        }
        const int seamCol = int(next() % uint32_t(cols)); // faces right of it get their own UVs
        auto uid = [&](int i, int j, bool shifted) {
            const uint32_t base = uint32_t(j * (cols + 1) + i);
            return shifted ? base + uint32_t((rows + 1) * (cols + 1)) : base;
        };
        const bool seams = *rc::gen::arbitrary<bool>();
        if (seams) { // a second copy of the values, offset (a seam at seamCol)
            const size_t n = uv.values.size();
            for (size_t k = 0; k < n; ++k) uv.values.push_back(uv.values[k] + glm::vec2(0.5f));
        }
        for (int j = 0; j < rows; ++j) {
            for (int i = 0; i < cols; ++i) {
                const uint32_t q[4] = {vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)};
                const bool shifted = seams && i > seamCol;
                const uint32_t t[4] = {uid(i, j, shifted), uid(i + 1, j, shifted),
                                       uid(i + 1, j + 1, shifted), uid(i, j + 1, shifted)};
                if (int(next() % 100) < splitPercent) {
                    const int tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
                    for (const auto& tri : tris) {
                        m.faceSizes.push_back(3);
                        for (int k : tri) {
                            m.faceVertices.push_back(q[k]);
                            uv.indices.push_back(t[k]);
                        }
                    }
                } else {
                    m.faceSizes.push_back(4);
                    for (int k = 0; k < 4; ++k) {
                        m.faceVertices.push_back(q[k]);
                        uv.indices.push_back(t[k]);
                    }
                }
            }
        }
        m.uvSets.push_back(uv);
        const float kSharp[] = {0.5f, 1.0f, 1.7f, 3.2f, kInfiniteSharpness};
        const int creasePercent = *rc::gen::inRange(0, 30);
        for (size_t f = 0, c = 0; f < m.faceSizes.size(); c += m.faceSizes[f], ++f) {
            if (int(next() % 100) < creasePercent)
                m.creases.push_back({m.faceVertices[c], m.faceVertices[c + 1], kSharp[next() % 5]});
        }
        const int cornerPercent = *rc::gen::inRange(0, 10);
        for (uint32_t v = 0; v < m.positions.size(); ++v) {
            if (int(next() % 100) < cornerPercent) m.corners.push_back({v, kSharp[next() % 5]});
        }
        m.options.scheme = loop ? Scheme::Loop : Scheme::Catmark;
        m.options.boundary = BoundaryInterpolation(*rc::gen::inRange(0, 3));
        m.options.fvar = FVarInterpolation(*rc::gen::inRange(0, 6));
        m.options.creaseMethod =
            *rc::gen::arbitrary<bool>() ? CreaseMethod::Chaikin : CreaseMethod::Uniform;
        validate(m, "random");
        SubdivisionSettings& s = out.settings;
        s.options = m.options;
        s.limit =
            *rc::gen::weightedOneOf<bool>({{1, rc::gen::just(true)}, {2, rc::gen::just(false)}});
        s.level = *rc::gen::inRange(1, s.limit ? 3 : 4);
        s.animate = *rc::gen::arbitrary<bool>();
        s.specializedRefiner =
            *rc::gen::weightedOneOf<bool>({{3, rc::gen::just(true)}, {1, rc::gen::just(false)}});
        return out;
    });
}

RC_GTEST_PROP(SubdivisionThreads, RandomCagesAreTheSameBitsAtEveryCount, ()) {
    const RandomCage c = *randomCage();
    RC_TAG(c.settings.limit ? "limit" : "uniform");
    RC_TAG(c.cage.options.scheme == Scheme::Loop ? "loop" : "catmark");
    const std::string d = compareThreads(c.cage, c.settings);
    RC_ASSERT(d == std::string());
}

// ---- CLI ---------------------------------------------------------------------------

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(SubdivisionThreads, CliOutputIsTheSameBytesAtEveryCount) {
    sg::test::TempDir dir;
    const std::string spot =
        sg::test::shellQuote(sg::test::dataPath("meshes/spot/spot_control_mesh.obj"));
    for (const std::string& extra : {std::string("--level 4"), std::string("--level 2 --limit")}) {
        for (const char* ext : {".obj", ".glb"}) {
            std::vector<std::string> outputs;
            for (int threads : {1, 3}) {
                const fs::path out = dir / ("t" + std::to_string(threads) + ext);
                const sg::test::CommandResult r = sg::test::runSurfgrad(
                    "mesh subdivide " + spot + " " + extra + " --threads " +
                    std::to_string(threads) + " -o " + sg::test::shellQuote(out));
                ASSERT_EQ(r.exitCode, 0) << r.err;
                outputs.push_back(readBytes(out));
            }
            EXPECT_FALSE(outputs[0].empty());
            EXPECT_TRUE(outputs[0] == outputs[1]) << extra << " " << ext;
        }
    }
}

TEST(SubdivisionThreads, CliThreadCountOutOfRangeIsAUsageError) {
    sg::test::TempDir dir;
    const std::string spot =
        sg::test::shellQuote(sg::test::dataPath("meshes/spot/spot_control_mesh.obj"));
    const std::string out = sg::test::shellQuote(dir / "o.obj");
    for (const std::string& cmd : {"mesh subdivide " + spot + " --level 1 -o " + out,
                                   "mesh morph " + spot + " --weights 1 --level 1 -o " + out}) {
        for (const char* count : {"0", "2000", "-3"}) {
            const sg::test::CommandResult r = sg::test::runSurfgrad(cmd + " --threads " + count);
            EXPECT_EQ(r.exitCode, 2) << cmd << " --threads " << count << ": " << r.err;
            EXPECT_NE(r.err.find("--threads"), std::string::npos) << r.err;
            EXPECT_FALSE(fs::exists(dir / "o.obj"));
        }
    }
}

} // namespace
