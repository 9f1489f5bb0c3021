// The blendshape example's claim (examples/blendshape-asset): with the
// per-pixel tangent frame (Mikkelsen 2019, listing 6) a normal map stays
// correct on a morphed mesh, while tangents generated once for the rest pose
// go stale (section 1: per-vertex tangent spaces of blendshapes).
//
// "Correct" is measured against a reference: the same morphed shape baked
// into a static mesh (positions and normals blended by glTF's rule, exactly
// what the renderer does per frame) and rendered with MikkTSpace tangents
// generated for THAT shape, the standard a normal map is baked against.
// All three images see the same triangles from the same camera, so they are
// compared pixel by pixel (normal AOV, linear EXR):
//   pixel frames on the morphed mesh      vs reference: small (the two frame
//                                          constructions differ slightly);
//   rest-pose tangents on the morphed mesh vs reference: large.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <ostream>

#include <glm/glm.hpp>

#include "example_test_util.h"
#include "surfgrad/mesh/mesh_io.h"

namespace {

using namespace sg::examples_test;

const fs::path kSourceDir = SURFGRAD_SOURCE_DIR;
const std::string kCli = SG_SURFGRAD_BIN;

// A scene showing one copy of `meshFile` with the example's material.
std::string sceneJson(const fs::path& meshFile, const std::string& tangents,
                      const std::string& morph) {
    return R"({
  "output": { "width": 320, "height": 320 },
  "camera": { "position": [0.0, 0.9, 3.6], "target": [0.0, 0.0, 0.0], "fov_deg": 40 },
  "materials": [ { "name": "wicker", "layers": [
    { "type": "uv_normal", "uv_set": 0, "map": "data:textures/wicker_normal.png", "green": "gl", "strength": 1.0 } ] } ],
  "meshes": [ { "file": ")" +
           meshFile.string() + R"(", "tangents": ")" + tangents + "\"" + morph +
           R"(, "material": 0 } ]
})";
}

struct Diff {
    size_t compared = 0, coverageMismatch = 0;
    double meanDeg = 0.0, p95Deg = 0.0;
};

Diff compare(const Image& a, const Image& b) {
    Diff d;
    std::vector<double> ang;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            glm::vec3 u(a.at(x, y, 0), a.at(x, y, 1), a.at(x, y, 2)),
                v(b.at(x, y, 0), b.at(x, y, 1), b.at(x, y, 2));
            bool ca = glm::dot(u, u) > 0.0f, cb = glm::dot(v, v) > 0.0f;
            if (ca != cb) ++d.coverageMismatch;
            if (!ca || !cb) continue;
            double c =
                std::clamp(double(glm::dot(glm::normalize(u), glm::normalize(v))), -1.0, 1.0);
            ang.push_back(std::acos(c) * 180.0 / 3.141592653589793);
        }
    }
    d.compared = ang.size();
    if (ang.empty()) return d;
    for (double x : ang) d.meanDeg += x / double(ang.size());
    std::sort(ang.begin(), ang.end());
    d.p95Deg = ang[size_t(0.95 * double(ang.size() - 1))];
    return d;
}

Image renderNormals(const fs::path& dir, const std::string& name, const std::string& json) {
    fs::path scene = dir / (name + ".json"), out = dir / (name + ".exr");
    std::ofstream(scene) << json;
    CommandResult r = runCommand(shellQuote(kCli) + " render " + shellQuote(scene) + " -o " +
                                 shellQuote(out) + " --aov normal");
    EXPECT_EQ(r.exitCode, 0) << r.output();
    return readImage(out);
}

struct Pose {
    float squash, lobes;
};
// For ctest's test names.
void PrintTo(const Pose& p, std::ostream* os) {
    *os << "(" << p.squash << ", " << p.lobes << ")";
}

class BlendshapeFrames : public ::testing::TestWithParam<Pose> {};

TEST_P(BlendshapeFrames, PixelFramesMatchTangentsOfTheMorphedShape) {
    const Pose pose = GetParam();
    fs::path dir = scratchDir("blend_" + std::to_string(int(pose.squash * 100)) + "_" +
                              std::to_string(int(pose.lobes * 100)));
    const fs::path model = kSourceDir / "examples/data/morph_blob.gltf";

    // The reference shape: glTF's morph rule (positions += w * delta,
    // normals += w * delta then renormalized), no targets left.
    sg::mesh::RenderMesh m = sg::mesh::loadRenderMesh(model);
    ASSERT_EQ(m.morphTargets.size(), 2u);
    const float w[2] = {pose.squash, pose.lobes};
    for (size_t t = 0; t < 2; ++t) {
        for (size_t v = 0; v < m.positions.size(); ++v) {
            m.positions[v] += w[t] * m.morphTargets[t].positionDeltas[v];
            m.normals[v] += w[t] * m.morphTargets[t].normalDeltas[v];
        }
    }
    for (auto& n : m.normals) n = glm::normalize(n);
    m.morphTargets.clear();
    m.morphWeights.clear();
    const fs::path baked = dir / "morphed.glb";
    sg::mesh::writeRenderMesh(baked, m);

    char weights[96];
    std::snprintf(weights, sizeof weights, ", \"morph\": { \"weights\": [%g, %g] }", double(w[0]),
                  double(w[1]));
    Image reference = renderNormals(dir, "reference", sceneJson(baked, "mikktspace", ""));
    Image pixel = renderNormals(dir, "pixel", sceneJson(model, "pixel", weights));
    Image stale = renderNormals(dir, "stale", sceneJson(model, "mikktspace", weights));
    ASSERT_EQ(reference.width, 320);
    ASSERT_EQ(pixel.width, 320);
    ASSERT_EQ(stale.width, 320);

    Diff dp = compare(pixel, reference), ds = compare(stale, reference);
    std::printf("weights (%.2f, %.2f): %zu pixels; angle to the reference: per-pixel frames mean "
                "%.3f p95 %.3f deg, "
                "rest-pose tangents mean %.3f p95 %.3f deg\n",
                double(w[0]), double(w[1]), dp.compared, dp.meanDeg, dp.p95Deg, ds.meanDeg,
                ds.p95Deg);
    // Same triangles, same camera: the coverage is identical (a few pixels
    // of slack for rasterisation ties on the silhouette).
    EXPECT_LE(dp.coverageMismatch, 8u);
    EXPECT_GT(dp.compared, size_t(320 * 320 / 8));
    // Per-pixel frames follow the morphed surface: they differ from the
    // reference's vertex tangents only as the two constructions differ on
    // any mesh (orthonormal per-pixel vs interpolated, unnormalized
    // MikkTSpace). Measured means: 0.10 (rest), 0.15 (squash), 0.24 deg
    // (lobes); 1 deg leaves room for driver rounding, not for a wrong frame.
    EXPECT_LT(dp.meanDeg, 1.0);
    // Stale tangents are measurably worse wherever the morph bends the
    // s direction out of the rest pose's tangent plane (the lobes; measured
    // mean 1.56 deg, 6.5x the per-pixel frames'). The squash keeps every
    // latitude circle horizontal, so there the stale tangents stay exact.
    if (pose.lobes > 0.0f) {
        EXPECT_GT(ds.meanDeg, 3.0 * dp.meanDeg);
    }
}

INSTANTIATE_TEST_SUITE_P(Poses, BlendshapeFrames,
                         ::testing::Values(Pose{0.0f, 0.0f}, Pose{1.0f, 0.0f}, Pose{0.6f, 1.0f}),
                         [](const ::testing::TestParamInfo<Pose>& p) {
                             return "squash" + std::to_string(int(p.param.squash * 100)) +
                                    "_lobes" + std::to_string(int(p.param.lobes * 100));
                         });

// The model is also the adaptive-cage example of the blendshape tests and
// the viewer: welded as a cage (exact positions and morph deltas) it must
// be closed, every edge shared by exactly two triangles. The seam column
// and the poles are written bit for bit equal; were they computed with
// sin(pi) = 1.2e-16 the cage would be open along the seam and at the north
// pole, and subdivision would draw a hole there.
TEST(BlendshapeModel, WeldsIntoAClosedCage) {
    const sg::mesh::PolygonMesh cage =
        sg::mesh::loadPolygonMesh(kSourceDir / "examples/data/morph_blob.gltf");
    ASSERT_EQ(cage.faceCount(), 3968u);
    // A closed UV sphere of 64 x 32 segments: 64 * 31 + 2 vertices.
    EXPECT_EQ(cage.vertexCount(), 64u * 31u + 2u);
    std::map<std::pair<uint32_t, uint32_t>, int> edgeUses;
    size_t corner = 0;
    for (uint32_t n : cage.faceSizes) {
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t a = cage.faceVertices[corner + k], b = cage.faceVertices[corner + (k + 1) % n];
            ++edgeUses[{std::min(a, b), std::max(a, b)}];
        }
        corner += n;
    }
    size_t notTwo = 0;
    for (const auto& [edge, uses] : edgeUses) notTwo += uses != 2;
    EXPECT_EQ(notTwo, 0u);
}

} // namespace
