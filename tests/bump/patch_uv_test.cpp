// UV sets on adaptive patches (sg::mesh::AdaptiveUvSet): OpenSubdiv's
// face-varying patch tables evaluated with the shared basis
// (shaders/sg/patch/basis.glsl) against the uniform path's limit UVs at
// the same limit points, and UV seams against the positions' crack-freedom.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unordered_map>
#include <vector>

#include "patch_eval_util.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

namespace g = sg::glsl;
using sg::mesh::AdaptivePatches;
using sg::mesh::PolygonMesh;

using sg::test::patchArrayOf;

std::filesystem::path dataPath(const std::string& rel) {
    return sg::test::patchDataPath(rel);
}

// Position of patch p at (u,v) of its square (the tessellator's evaluation).
glm::vec3 evalPosition(const AdaptivePatches& ap, const std::vector<uint32_t>& arrays, uint32_t p,
                       glm::vec2 patchUv) {
    return sg::test::evalPatchSample(ap, ap.arrays[arrays[p]], p, patchUv).pos;
}

// UV of set `s` on patch p at (u,v) of the position patch's square.
glm::vec2 evalUv(const AdaptivePatches& ap, size_t s, uint32_t p, glm::vec2 patchUv) {
    return sg::test::evalPatchUvSample(ap, s, p, patchUv).st;
}

struct UvAgreement {
    size_t checked = 0, unmatched = 0;
    float worst = 0.0f;
    int types[10] = {};
};

// Every patch's points that are vertices of the uniform refinement at
// `level` (its corners, and for a patch of depth d < level the grid of
// step 2^(d - level) in its square), each found among the uniform limit
// positions within posTol; the patch's UV there against the closest of the
// limit UVs of that vertex (a vertex on a UV seam has one per side).
UvAgreement compareWithUniformLimit(const PolygonMesh& cage, int level, float posTol,
                                    const char* name) {
    const AdaptivePatches ap = sg::mesh::buildAdaptivePatches(cage, cage.options, level, name);
    sg::mesh::SubdivisionSettings st;
    st.options = cage.options;
    st.level = level;
    st.limit = true;
    st.buildRenderMesh = false;
    sg::mesh::Subdivider sub(cage, st, name);
    const PolygonMesh& ref = sub.refined();
    UvAgreement r;
    if (ap.uvSets.size() != cage.uvSets.size() || ref.uvSets.empty()) {
        ADD_FAILURE() << "UV sets: " << ap.uvSets.size() << " vs " << cage.uvSets.size();
        return r;
    }
    // Uniform limit vertices, each with its UV values.
    std::vector<std::vector<glm::vec2>> uvOf(ref.positions.size());
    for (size_t c = 0; c < ref.faceVertices.size(); ++c)
        uvOf[ref.faceVertices[c]].push_back(ref.uvSets[0].values[ref.uvSets[0].indices[c]]);
    const sg::test::PointsByX byX(ref.positions);
    const std::vector<uint32_t> arrays = patchArrayOf(ap);
    for (uint32_t p = 0; p < ap.patchCount(); ++p)
        ++r.types[std::clamp(int(ap.uvSets[0].types[p]), 0, 9)];
    sg::test::forEachLevelGridPoint(ap, level, [&](uint32_t p, glm::vec2 at) {
        const glm::vec3 q = evalPosition(ap, arrays, p, at);
        uint32_t best = UINT32_MAX;
        float bestDist = posTol;
        byX.forEachNear(q, posTol, [&](uint32_t v) {
            const float d = glm::length(ref.positions[v] - q);
            if (d <= bestDist) bestDist = d, best = v;
        });
        if (best == UINT32_MAX) {
            ++r.unmatched;
            return;
        }
        const glm::vec2 w = evalUv(ap, 0, p, at);
        float e = INFINITY;
        for (const glm::vec2& u : uvOf[best]) e = std::min(e, glm::length(u - w));
        r.worst = std::max(r.worst, e);
        ++r.checked;
    });
    return r;
}

TEST(PatchUv, MatchTheUniformLimitUvsAtTheSameLimitPoints) {
    // Spot (seams, extraordinary vertices; fvar rule from its OBJ: the
    // default) and osd-shapes with UVs under several face-varying rules and
    // boundaries, without semi-sharp features deeper than the isolation
    // (whose unisolated points are approximations: see
    // PatchBasis.PatchCornersAreTheLimitPointsOfTheExistingLimitEvaluation).
    const char* shapes[] = {
        "meshes/spot/spot_control_mesh.obj",    "osd-shapes/catmark_cube.obj",
        "osd-shapes/catmark_fvar_bound0.obj",   "osd-shapes/catmark_fvar_bound1.obj",
        "osd-shapes/catmark_fvar_bound2.obj",   "osd-shapes/catmark_fvar_bound3.obj",
        "osd-shapes/catmark_gregory_test1.obj", "osd-shapes/catmark_hole_test1.obj",
        "osd-shapes/catmark_edgeonly.obj",      "osd-shapes/catmark_fvar_bound4.obj"};
    size_t total = 0;
    int types[10] = {};
    for (const char* rel : shapes) {
        SCOPED_TRACE(rel);
        const auto path = dataPath(rel);
        ASSERT_TRUE(std::filesystem::exists(path));
        PolygonMesh cage = sg::mesh::loadPolygonMesh(path);
        ASSERT_FALSE(cage.uvSets.empty());
        const float extent = sg::test::maxAbsCoordinate(cage.positions);
        // Positions: the bound of the position test (a few ulp times the
        // sum of |weights| of a Gregory corner), to find the vertex.
        const UvAgreement r = compareWithUniformLimit(cage, 3, 2e-5f * extent, rel);
        std::printf("%s: %zu points, %zu unmatched, worst UV difference %.3g\n", rel, r.checked,
                    r.unmatched, double(r.worst));
        // Both are OpenSubdiv's limit UVs in binary32 (UVs within [0, 1]),
        // through different levels, factorisations and end-cap depths (the
        // limit path isolates to 5): a few ulp of 1 times the sum of
        // |weights| of a Gregory corner (~10): 2e-5.
        EXPECT_LE(r.worst, 2e-5f);
        EXPECT_GT(r.checked, 0u);
        // Every patch point is a vertex of the uniform refinement.
        EXPECT_EQ(r.unmatched, 0u);
        total += r.checked;
        for (int t = 0; t < 10; ++t) types[t] += r.types[t];
    }
    // Regular and Gregory face-varying patches were both exercised.
    std::printf("UV patches: %d bilinear, %d regular, %d Gregory; %zu points\n", types[3], types[6],
                types[9], total);
    EXPECT_GT(types[6], 0);
    EXPECT_GT(types[9], 0);
}

TEST(PatchUv, LinearRuleGivesBilinearUvPatches) {
    // "fvar": "all" (FVAR_LINEAR_ALL): every UV patch is bilinear (type 3),
    // and its corners are the cage's UVs refined linearly: at a patch
    // corner the value of one of the refined face-varying values there.
    PolygonMesh cage = sg::mesh::loadPolygonMesh(dataPath("meshes/spot/spot_control_mesh.obj"));
    cage.options.fvar = sg::mesh::FVarInterpolation::All;
    const UvAgreement r = compareWithUniformLimit(cage, 2, 1e-4f, "spot linear");
    EXPECT_EQ(r.types[3], int(r.types[3] + r.types[6] + r.types[9]));
    EXPECT_EQ(r.unmatched, 0u);
    EXPECT_LE(r.worst, 2e-5f); // as above
}

TEST(PatchUv, SeamsDoNotTearPositions) {
    PolygonMesh cage = sg::mesh::loadPolygonMesh(dataPath("meshes/spot/spot_control_mesh.obj"));
    ASSERT_FALSE(cage.uvSets.empty());
    const AdaptivePatches withUv = sg::mesh::buildAdaptivePatches(cage, cage.options, 3, "spot");
    // The face-varying channels are considered by the adaptive refinement
    // (Far's RefineAdaptive options from generateFVarTables): UV seams are
    // isolated like creases, so the cage with UVs has more, deeper patches
    // than without; both describe the same limit surface (the patch points
    // against the uniform limit: MatchTheUniformLimitUvsAtTheSameLimitPoints).
    PolygonMesh noUv = cage;
    noUv.uvSets.clear();
    const AdaptivePatches without = sg::mesh::buildAdaptivePatches(noUv, noUv.options, 3, "spot");
    std::printf("spot, isolation 3: %zu patches with its UV set, %zu without\n",
                withUv.patchCount(), without.patchCount());
    EXPECT_GE(withUv.patchCount(), without.patchCount());
    // Shared edges whose two sides have different UVs (seams): their points
    // go to one site from both sides (the owner's, sg/patch/watertight.glsl),
    // so the positions are equal bit for bit while the UVs differ.
    const std::vector<uint32_t> arrays = patchArrayOf(withUv);
    size_t seamEdges = 0, sharedEdges = 0, torn = 0;
    const int n = 4;
    for (uint32_t p = 0; p < withUv.patchCount(); ++p) {
        for (int k = 0; k < 4; ++k) {
            const uint32_t owner = withUv.edgeOwners[p][k] >> 3;
            if (owner == p) continue;
            ++sharedEdges;
            const int ownerEdge = int((withUv.edgeOwners[p][k] >> 1) & 3u);
            const bool flip = (withUv.edgeOwners[p][k] & 1u) != 0;
            const glm::vec2 mine = g::sgPatchEdgeUv(k, 0.25f);
            const glm::vec2 theirs = g::sgPatchEdgeUv(ownerEdge, flip ? 0.75f : 0.25f);
            const float uvGap =
                glm::length(evalUv(withUv, 0, p, mine) - evalUv(withUv, 0, owner, theirs));
            if (uvGap < 1e-3f) continue; // the same UVs: not a seam
            ++seamEdges;
            const glm::vec4 outer = glm::vec4(float(n));
            const g::SgPatchTransitions none = g::sgPatchNoTransitions();
            for (int i = 1; i < n; ++i) {
                const glm::vec2 a = g::sgPatchEdgeUv(k, float(i) / float(n));
                const glm::vec2 b = g::sgPatchEdgeUv(ownerEdge, float(flip ? n - i : i) / float(n));
                const g::SgPatchSite sa = g::sgPatchEvalSite(
                    p, withUv.edgeOwners[p], withUv.cornerOwners[p], none, outer, a);
                const g::SgPatchSite sb = g::sgPatchEvalSite(
                    owner, withUv.edgeOwners[owner], withUv.cornerOwners[owner], none, outer, b);
                const glm::vec3 pa = evalPosition(withUv, arrays, sa.patchIndex, sa.uv);
                const glm::vec3 pb = evalPosition(withUv, arrays, sb.patchIndex, sb.uv);
                torn += std::memcmp(&pa, &pb, sizeof pa) != 0;
            }
        }
    }
    std::printf("spot: %zu shared patch edges, %zu on UV seams, %zu torn points\n", sharedEdges,
                seamEdges, torn);
    EXPECT_GT(seamEdges, 10u); // spot's unwrap has seams
    EXPECT_EQ(torn, 0u);
}

} // namespace
