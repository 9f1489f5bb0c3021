// MikkTSpace tangents on several threads (MikkTSpaceGenerator::setThreads):
// the output at 2, 3 and 7 threads is the one-thread output bit for bit
// (memcmp of the tangent and frame arrays), and both are the step-by-step
// oracle's (mikktspaceReferenceFrames). Small meshes go through the
// parallel steps with setParallelCutover(0); their loops then split into
// blocks of a few elements, so block boundaries fall everywhere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "surfgrad/mesh/mikktspace_reference.h"
#include "surfgrad/mesh/tangents.h"
#include "tangents_test_util.h"

namespace {

using sg::mesh::MikkTSpaceFrame;
using sg::mesh::MikkTSpaceGenerator;
using sg::mesh::MikkTSpaceInput;

const std::string kData = SURFGRAD_DATA_DIR;

using sg::test::inputOf;

// Every corner its own vertex (same values): the weld does all the merging.
sg::test::SoupMesh unwelded(const sg::test::SoupMesh& m) {
    sg::test::SoupMesh r;
    r.faceSizes = m.faceSizes;
    for (size_t c = 0; c < m.corners.size(); ++c) {
        const uint32_t v = m.corners[c];
        r.positions.push_back(m.positions[v]);
        r.normals.push_back(m.normals[v]);
        r.uvs.push_back(m.uvs[v]);
        r.corners.push_back(uint32_t(c));
    }
    return r;
}

template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

struct Output {
    std::vector<glm::vec4> tangents;   // without frames (the direct path)
    std::vector<glm::vec4> withFrames; // with frames (the per-corner spaces path)
    std::vector<MikkTSpaceFrame> frames;
};

Output run(MikkTSpaceGenerator& g, const MikkTSpaceInput& in) {
    Output o;
    g.generate(in, o.tangents);
    g.generate(in, o.withFrames, &o.frames);
    return o;
}

// The number of thread counts in {2, 3, 7} (wide and narrow SIMD) whose
// output differs in any bit from the one-thread output; adds a failure
// when the one-thread output differs from the oracle.
int countThreadMismatches(const MikkTSpaceInput& in, size_t cutover = 0) {
    MikkTSpaceGenerator one;
    one.setThreads(1);
    const Output expected = run(one, in);
    const std::vector<MikkTSpaceFrame> ref = sg::mesh::mikktspaceReferenceFrames(in);
    EXPECT_TRUE(sameBits(expected.frames, ref)) << "one thread against the oracle";
    int bad = 0;
    for (const bool wide : {true, false}) {
        for (const int threads : {2, 3, 7}) {
            MikkTSpaceGenerator g;
            g.setWideSimd(wide);
            g.setThreads(threads);
            g.setParallelCutover(cutover);
            const Output got = run(g, in);
            const bool same = sameBits(got.tangents, expected.tangents) &&
                              sameBits(got.withFrames, expected.withFrames) &&
                              sameBits(got.frames, expected.frames);
            EXPECT_TRUE(same) << threads << " threads, " << (wide ? "wide" : "narrow") << " SIMD";
            bad += !same;
        }
    }
    return bad;
}

TEST(MikkTSpaceThreads, EqualsOneThreadOnRandomSoups) {
    // Seeded random meshes with seams, mirrored UVs, degenerate and
    // zero-UV-area triangles, quads, inconsistent winding, 3+ faces per
    // edge, pentagons; each also unwelded (every corner its own vertex).
    std::vector<sg::test::SoupOptions> cases;
    sg::test::SoupOptions o;
    o.gridX = 17;
    o.gridY = 13;
    cases.push_back(o);
    o.quadFraction = 0.6f;
    o.flipFraction = 0.15f;
    o.duplicateFraction = 0.1f;
    cases.push_back(o);
    o.otherPolygonFraction = 0.1f;
    cases.push_back(o);
    sg::test::SoupOptions heavy;
    heavy.degenerateFraction = heavy.zeroUvFraction = heavy.mirrorFraction = 0.4f;
    heavy.quantize = 1; // coarse values: ties everywhere
    heavy.gridX = 12;
    cases.push_back(heavy);
    sg::test::SoupOptions clean;
    clean.mirrorFraction = clean.seamFraction = clean.degenerateFraction = clean.zeroUvFraction = 0;
    clean.quantize = 1024;
    clean.gridX = 30;
    clean.gridY = 20;
    cases.push_back(clean);
    size_t meshes = 0;
    for (const sg::test::SoupOptions& c : cases) {
        for (uint32_t seed = 1; seed <= 12; ++seed) {
            const sg::test::SoupMesh m = sg::test::randomSoup(seed * 104729u + uint32_t(meshes), c);
            EXPECT_EQ(countThreadMismatches(inputOf(m)), 0)
                << "case " << meshes / 12 << ", seed " << seed;
            EXPECT_EQ(countThreadMismatches(inputOf(unwelded(m))), 0)
                << "unwelded, case " << meshes / 12 << ", seed " << seed;
            ++meshes;
        }
    }
}

TEST(MikkTSpaceThreads, EqualsOneThreadOnHighValenceFans) {
    // Fans around one vertex (the longest incidence list), mirrored and
    // zero-UV-area sectors, one triangle twice.
    for (int n : {3, 9, 64, 200}) {
        sg::test::SoupMesh m;
        m.positions.push_back({0, 0, 1});
        m.normals.push_back({0, 0, 1});
        m.uvs.push_back({0.5f, 0.5f});
        for (int i = 0; i < n; ++i) {
            const float a = 6.2831853f * float(i) / float(n);
            m.positions.push_back({std::cos(a), std::sin(a), 0.0f});
            m.normals.push_back(glm::normalize(glm::vec3(std::cos(a), std::sin(a), 1.0f)));
            glm::vec2 uv(0.5f + 0.5f * std::cos(a), 0.5f + 0.5f * std::sin(a));
            if (i % 5 == 3) uv.x = 1.0f - uv.x;
            if (i % 11 == 4) uv = {0.5f, 0.5f};
            m.uvs.push_back(uv);
        }
        for (int i = 0; i < n; ++i) {
            const uint32_t a = uint32_t(1 + i), b = uint32_t(1 + (i + 1) % n);
            m.corners.insert(m.corners.end(), {0u, a, b});
            if (i == n / 2) m.corners.insert(m.corners.end(), {0u, a, b});
        }
        EXPECT_EQ(countThreadMismatches(inputOf(m)), 0) << n << " triangles";
    }
}

TEST(MikkTSpaceThreads, EqualsOneThreadOnGltfSamples) {
    for (const char* file : {"/gltf/NormalTangentMirrorTest/glTF/NormalTangentMirrorTest.gltf",
                             "/gltf/NormalTangentTest/glTF/NormalTangentTest.gltf"}) {
        const auto p = sg::test::readGltfPrimitive(kData + file);
        EXPECT_EQ(countThreadMismatches(inputOf(p)), 0) << file;
    }
}

TEST(MikkTSpaceThreads, EqualsOneThreadAboveTheDefaultCutover) {
    // A mesh above kMikkTSpaceParallelCutover through the default settings
    // (all cores) and explicit thread counts.
    sg::test::SoupOptions o;
    o.gridX = 160;
    o.gridY = 100;
    o.quantize = 64;
    const sg::test::SoupMesh m = sg::test::randomSoup(29, o);
    const MikkTSpaceInput in = inputOf(m);
    ASSERT_GE(m.corners.size() / 3, sg::mesh::kMikkTSpaceParallelCutover);
    EXPECT_EQ(countThreadMismatches(in, sg::mesh::kMikkTSpaceParallelCutover), 0);
    MikkTSpaceGenerator one, all;
    one.setThreads(1);
    std::vector<glm::vec4> a, b;
    one.generate(in, a);
    all.generate(in, b); // default: threads 0 (all cores), default cut-over
    EXPECT_TRUE(sameBits(a, b));
}

TEST(MikkTSpaceThreads, GeneratorReuseAcrossThreadCounts) {
    // Per-thread scratch is kept between calls; results must not depend on
    // which thread count or mesh came before.
    sg::test::SoupOptions o;
    o.quadFraction = 0.5f;
    const auto a = sg::test::randomSoup(5, o);
    o.gridX = 40;
    o.gridY = 30;
    o.quadFraction = 0.0f;
    const auto b = sg::test::randomSoup(6, o);
    MikkTSpaceGenerator one;
    one.setThreads(1);
    std::vector<glm::vec4> expectA, expectB, got;
    one.generate(inputOf(a), expectA);
    one.generate(inputOf(b), expectB);
    MikkTSpaceGenerator g;
    g.setParallelCutover(0);
    for (const int threads : {7, 1, 2, 0, 3}) {
        g.setThreads(threads);
        g.generate(inputOf(b), got);
        EXPECT_TRUE(sameBits(got, expectB)) << threads << " threads";
        g.generate(inputOf(a), got);
        EXPECT_TRUE(sameBits(got, expectA)) << threads << " threads";
    }
}

TEST(MikkTSpaceThreads, StepTimesNameEveryStep) {
    sg::test::SoupOptions o;
    const auto m = sg::test::randomSoup(3, o);
    MikkTSpaceGenerator g;
    std::vector<glm::vec4> t;
    g.generate(inputOf(m), t);
    const auto steps = g.lastStepTimes();
    ASSERT_FALSE(steps.empty());
    for (const auto& s : steps) {
        EXPECT_NE(s.step, nullptr);
        EXPECT_GE(s.ms, 0.0);
    }
}

} // namespace
