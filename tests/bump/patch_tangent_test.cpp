// "limit" tangents on adaptive patches (shaders/sg/patch/limit_tangent.glsl,
// what the tessellation evaluation stage and the CPU tessellator write)
// against the uniform path's limit tangents (sg::mesh::generateLimitTangents
// on the Subdivider's limit frame) at the same limit points, and their hard
// cases (zero-area UV patches, a collapsed cage, non-finite and extreme
// derivatives): finite, unit, orthogonal to the normal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "hardcase.h"
#include "patch_eval_util.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"

namespace {

namespace g = sg::glsl;
using sg::mesh::AdaptivePatches;
using sg::mesh::PolygonMesh;

using sg::test::patchArrayOf;

std::filesystem::path dataPath(const std::string& rel) {
    return sg::test::patchDataPath(rel);
}

// A tessellated point as the evaluation stage computes it from patch p's
// own control points and its UV set `set`: position, normal, UV and the
// limit tangent (patch_tes.glsl's patchTangent, object space).
struct PatchPoint {
    glm::vec3 pos, normal;
    glm::vec2 st;
    glm::vec4 tangent;
    int resolved = 0;
};

PatchPoint evalPatchPoint(const AdaptivePatches& ap, const std::vector<uint32_t>& arrayOf,
                          uint32_t p, size_t set, glm::vec2 patchUv) {
    const sg::test::PatchSample x =
        sg::test::evalPatchSample(ap, ap.arrays[arrayOf[p]], p, patchUv);
    const sg::test::PatchUvSample uv = sg::test::evalPatchUvSample(ap, set, p, patchUv);
    PatchPoint r;
    r.pos = x.pos;
    r.st = uv.st;
    r.normal = g::sgSafeNormalize(glm::cross(x.du, x.dv), glm::vec3(0.0f, 0.0f, 1.0f));
    r.tangent = g::sgPatchLimitTangent(x.du, x.dv, uv.du, uv.dv, r.normal, r.resolved);
    return r;
}

// In double (atan2 of |a x b| and a . b: no acos rounding near 0).
double angleDeg(glm::vec3 af, glm::vec3 bf) {
    const glm::dvec3 a(af), b(bf);
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * 180.0 / M_PI;
}

struct Stats {
    double worstDeg = 0.0;
    std::vector<double> angles;
    double at(double q) {
        std::sort(angles.begin(), angles.end());
        return angles.empty() ? 0.0 : angles[size_t(q * double(angles.size() - 1))];
    }
};
struct TangentAgreement {
    size_t checked = 0, skipped = 0, otherFace = 0, unmatched = 0, signMismatch = 0;
    Stats bspline; // position and UV patches both B-spline: exact limit
    Stats gregory; // either a Gregory end cap (Loop et al. 2009: approximate)
};

// Every patch point that is a vertex of the uniform refinement at `level`
// (corners, and for a patch of depth d < level the grid of step
// 2^(d - level)): the patch's limit tangent of UV set 0 against the uniform
// path's at the render vertex with the same position (within posTol) and
// the closest UV (a vertex on a UV seam is split, one copy per side). Points
// where either side is not LimitTangentCase::Regular (collapsed
// parameterisations: the uniform path averages neighbours there) are
// skipped and counted, and so are points whose uniform vertex has its home
// in another ptex face (below).
TangentAgreement compareWithUniformLimit(const PolygonMesh& cage, int level, float posTol,
                                         const char* name) {
    const AdaptivePatches ap = sg::mesh::buildAdaptivePatches(cage, cage.options, level, name);
    sg::mesh::SubdivisionSettings st;
    st.options = cage.options;
    st.level = level;
    st.limit = true;
    sg::mesh::Subdivider sub(cage, st, name);
    sg::mesh::RenderMesh ref = sub.renderMesh();
    const sg::mesh::LimitFrame& frame = sub.limitFrame();
    TangentAgreement r;
    if (ap.uvSets.empty() || ref.uvSets.empty()) {
        ADD_FAILURE() << "no UV set";
        return r;
    }
    sg::mesh::generateLimitTangents(ref, frame, 0);
    const sg::test::PointsByX byX(ref.positions);
    const std::vector<uint32_t> arrays = patchArrayOf(ap);
    sg::test::forEachLevelGridPoint(ap, level, [&](uint32_t p, glm::vec2 at) {
        const PatchPoint q = evalPatchPoint(ap, arrays, p, 0, at);
        uint32_t best = UINT32_MAX;
        float bestUv = 1e-3f; // UVs agree to 2e-5 (PatchUv tests)
        byX.forEachNear(q.pos, posTol, [&](uint32_t v) {
            if (glm::length(ref.positions[v] - q.pos) > posTol) return;
            const float d = glm::length(ref.uvSets[0][v] - q.st);
            if (d <= bestUv) bestUv = d, best = v;
        });
        if (best == UINT32_MAX) {
            ++r.unmatched;
            return;
        }
        // The UV chart of a vertex can have a kink there (a face-varying
        // corner: the UVs are C0 only, each face has its own Jacobian); the
        // uniform vertex's derivatives are those of its home ptex face:
        // compare in that face only.
        if (frame.ptexFace[best] != (ap.params[p].x & 0x0fffffffu)) {
            ++r.otherFace;
            return;
        }
        sg::mesh::LimitTangentCase kase;
        sg::mesh::limitTangent(frame.dPdu[best], frame.dPdv[best], frame.dUVdu[0][best],
                               frame.dUVdv[0][best], &kase);
        if (kase != sg::mesh::LimitTangentCase::Regular || q.resolved != SG_LIMIT_TANGENT_REGULAR) {
            ++r.skipped;
            return;
        }
        const glm::vec4 u = ref.tangents[best];
        const double a = angleDeg(glm::vec3(q.tangent), glm::vec3(u));
        r.signMismatch += q.tangent.w != u.w;
        const bool gregory = ap.arrays[arrays[p]].type == SG_PATCH_GREGORY_BASIS ||
                             ap.uvSets[0].types[p] == SG_PATCH_GREGORY_BASIS;
        Stats& into = gregory ? r.gregory : r.bspline;
        into.worstDeg = std::max(into.worstDeg, std::isfinite(a) ? a : INFINITY);
        into.angles.push_back(a);
        ++r.checked;
    });
    return r;
}

TEST(PatchTangent, MatchesTheUniformLimitTangentsAtTheSameLimitPoints) {
    // Spot (UV seams, extraordinary vertices) and osd-shapes with UV seams
    // and boundaries under several face-varying rules.
    const char* shapes[] = {
        "meshes/spot/spot_control_mesh.obj",  "osd-shapes/catmark_cube.obj",
        "osd-shapes/catmark_fvar_bound0.obj", "osd-shapes/catmark_fvar_bound1.obj",
        "osd-shapes/catmark_fvar_bound2.obj", "osd-shapes/catmark_gregory_test1.obj"};
    for (const char* rel : shapes) {
        SCOPED_TRACE(rel);
        const auto path = dataPath(rel);
        ASSERT_TRUE(std::filesystem::exists(path));
        PolygonMesh cage = sg::mesh::loadPolygonMesh(path);
        ASSERT_FALSE(cage.uvSets.empty());
        const float extent = sg::test::maxAbsCoordinate(cage.positions);
        // Positions: PatchUv's bound, to find the vertex.
        TangentAgreement r = compareWithUniformLimit(cage, 3, 2e-5f * extent, rel);
        std::printf("%s: %zu points (%zu not regular, %zu in another ptex face: skipped), "
                    "%zu handedness differences; B-spline patches: %zu points, p50 %.2e p99 "
                    "%.2e worst %.2e deg; Gregory: %zu points, p50 %.2e p90 %.2e worst %.2e deg\n",
                    rel, r.checked, r.skipped, r.otherFace, r.signMismatch, r.bspline.angles.size(),
                    r.bspline.at(0.5), r.bspline.at(0.99), r.bspline.worstDeg,
                    r.gregory.angles.size(), r.gregory.at(0.5), r.gregory.at(0.9),
                    r.gregory.worstDeg);
        EXPECT_GT(r.checked, 0u);
        EXPECT_EQ(r.unmatched, 0u);
        // Same handedness everywhere the chain rule is well conditioned.
        EXPECT_EQ(r.signMismatch, 0u);
        // B-spline patches are the exact limit surface and UVs: both sides
        // are the chain rule on the same limit derivatives in binary32
        // (~1e-6 relative, through different factorisations), divided by
        // the charts' sines (above 1e-3 at worst): bound 0.5 degree
        // (measured: p99 below 4e-3 degree, worst 0.23 at one boundary
        // corner of catmark_fvar_bound2; a wrong chart, side or sign is
        // tens of degrees).
        EXPECT_LE(r.bspline.worstDeg, 0.5);
        // Gregory end caps (isolation 3 here, 5 on the uniform path's limit
        // evaluation) approximate the limit: the tangent plane is exact at
        // their corners but the derivative magnitudes along each edge are
        // not, for positions and UVs alike, and the chain rule takes their
        // ratios: degrees at a few irregular corners. Bounds: median 1
        // degree, worst 30 (measured below 23 on spot).
        EXPECT_LE(r.gregory.at(0.5), 1.0);
        EXPECT_LE(r.gregory.worstDeg, 30.0);
    }
}

// Hard cases of sgPatchLimitTangent itself: degenerate and non-finite
// inputs give finite, unit tangents orthogonal to the normal and w = +-1.
TEST(PatchTangentHardCases, DegenerateInputsGiveFiniteUnitOrthogonalTangents) {
    const float inf = INFINITY, nan = NAN;
    struct In {
        glm::vec3 du, dv;
        glm::vec2 su, sv;
    };
    const In cases[] = {
        {{1, 0, 0}, {0, 1, 0}, {0, 0}, {0, 0}},                   // zero UV Jacobian
        {{1, 0, 0}, {0, 1, 0}, {1, 1}, {2, 2}},                   // collapsed UVs (rank 1)
        {{0, 0, 0}, {0, 0, 0}, {1, 0}, {0, 1}},                   // collapsed surface
        {{1, 0, 0}, {2, 0, 0}, {1, 0}, {0, 1}},                   // parallel derivatives
        {{0, 0, 0}, {0, 0, 0}, {0, 0}, {0, 0}},                   // everything zero
        {{1e30f, 0, 0}, {0, 1e30f, 0}, {1e-30f, 0}, {0, 1e-30f}}, // extreme scales
        {{1e-30f, 0, 0}, {0, 1e-30f, 0}, {1e30f, 0}, {0, -1e30f}},
        {{inf, 0, 0}, {0, 1, 0}, {1, 0}, {0, 1}}, // non-finite
        {{nan, 0, 0}, {0, 1, 0}, {1, 0}, {0, nan}},
        {{1, 0, 0}, {0, 1, 0}, {inf, 0}, {0, 1}},
        {{0, 0, 1}, {0, 0, 2}, {1, 0}, {0, 1}}, // along the normal
    };
    const glm::vec3 normals[] = {
        {0, 0, 1}, {0, 1, 0}, {1, 0, 0}, glm::normalize(glm::vec3(1, 1, 1))};
    sg::test::Worst offUnit, offPlane;
    size_t nonFinite = 0;
    for (const In& c : cases) {
        for (const glm::vec3& n : normals) {
            int resolved = -1;
            const glm::vec4 t = g::sgPatchLimitTangent(c.du, c.dv, c.su, c.sv, n, resolved);
            const bool finite = std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z) &&
                                (t.w == 1.0f || t.w == -1.0f);
            nonFinite += !finite;
            offUnit.add(std::abs(double(glm::length(glm::vec3(t))) - 1.0));
            offPlane.add(std::abs(double(glm::dot(glm::vec3(t), n))));
            EXPECT_TRUE(resolved >= 0 && resolved <= 2);
        }
    }
    // The regular cases keep the exact answer.
    int resolved = -1;
    EXPECT_EQ(
        g::sgPatchLimitTangent({1, 0, 0}, {0, 1, 0}, {1e-30f, 0}, {0, 1e-30f}, {0, 0, 1}, resolved),
        glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(resolved, SG_LIMIT_TANGENT_REGULAR);
    // Mirrored UVs (t runs along -v): w = -1, T still along +s.
    EXPECT_EQ(g::sgPatchLimitTangent({2, 0, 0}, {0, 3, 0}, {1, 0}, {0, -1}, {0, 0, 1}, resolved),
              glm::vec4(1, 0, 0, -1));
    EXPECT_EQ(nonFinite, 0u);
    // Unit: one rounding of a normalisation (a few ulp of 1).
    sg::test::hardCaseAtMost("uv-degenerate",
                             "patch limit tangent: zero, rank-1 or non-finite UV Jacobians, "
                             "collapsed or non-finite surface derivatives, scales 1e-30..1e30",
                             "| |T| - 1 |", offUnit.value, 1e-6);
    // Orthogonal: the Gram-Schmidt step in binary32 (a few ulp).
    sg::test::hardCaseAtMost("uv-degenerate", "patch limit tangent: the same inputs, four normals",
                             "|T . N|", offPlane.value, 1e-6);
}

// Real patches: a cube cage whose UVs are all one point (every UV patch
// has zero area) and a cage collapsed to one point (every position patch
// has zero area): every tessellated point's tangent is finite, unit and
// orthogonal to the normal the evaluation stage outputs.
TEST(PatchTangentHardCases, ZeroAreaUvPatchesAndCollapsedCage) {
    PolygonMesh cube = sg::mesh::loadPolygonMesh(dataPath("osd-shapes/catmark_cube.obj"));
    ASSERT_FALSE(cube.uvSets.empty());
    PolygonMesh oneUv = cube;
    for (glm::vec2& v : oneUv.uvSets[0].values) v = glm::vec2(0.5f, 0.5f);
    PolygonMesh collapsed = cube;
    for (glm::vec3& p : collapsed.positions) p = glm::vec3(0.25f, -1.0f, 3.0f);
    sg::test::Worst offUnit, offPlane;
    size_t nonFinite = 0, points = 0, degenerate = 0;
    for (const PolygonMesh* cage : {&oneUv, &collapsed}) {
        for (int isolation : {1, 3}) {
            const AdaptivePatches ap =
                sg::mesh::buildAdaptivePatches(*cage, cage->options, isolation, "cube");
            const std::vector<uint32_t> arrays = patchArrayOf(ap);
            for (uint32_t p = 0; p < ap.patchCount(); ++p) {
                for (int j = 0; j <= 4; ++j) {
                    for (int i = 0; i <= 4; ++i) {
                        const PatchPoint q =
                            evalPatchPoint(ap, arrays, p, 0, glm::vec2(i / 4.0f, j / 4.0f));
                        const glm::vec4 t = q.tangent;
                        nonFinite += !(std::isfinite(t.x) && std::isfinite(t.y) &&
                                       std::isfinite(t.z) && (t.w == 1.0f || t.w == -1.0f));
                        offUnit.add(std::abs(double(glm::length(glm::vec3(t))) - 1.0));
                        offPlane.add(std::abs(double(glm::dot(glm::vec3(t), q.normal))));
                        degenerate += q.resolved != SG_LIMIT_TANGENT_REGULAR;
                        ++points;
                    }
                }
            }
        }
    }
    // Most points resolve as degenerate; a few may not: the derivatives of
    // a zero chart are rounding residues of the basis sums (the weights'
    // derivatives sum to 0 only up to rounding), to which the scale-free
    // rule gives some direction. The contract holds either way.
    std::printf("%zu points, %zu not regular\n", points, degenerate);
    EXPECT_GT(degenerate, points / 2);
    EXPECT_EQ(nonFinite, 0u);
    // As above: one normalisation, one projection in binary32.
    sg::test::hardCaseAtMost("uv-degenerate",
                             "adaptive patches (catmark_cube, isolation 1 and 3) with every UV at "
                             "one point, and the cage collapsed to one point: limit tangents",
                             "| |T| - 1 | and |T . N|", std::max(offUnit.value, offPlane.value),
                             1e-6);
}

// The patch version of the same rule (sg/patch/limit_tangent.glsl): a UV
// chart whose d(s,t)/dv is rounding noise is degenerate in every direction
// of the noise (w = +1, T along dP/du), as tests/mesh/tangents_limit_test
// checks for the uniform path; with the sine rule a perpendicular noise
// direction passed as regular and w followed its sign on the GPU and the
// CPU alike, differently (41 deg apart on an adaptive cylinder).
TEST(PatchTangentHardCases, NoiseUvDerivativeIsDegenerateInEveryDirection) {
    size_t regular = 0, flipped = 0;
    double worst = 0.0;
    const glm::vec3 du(0.3f, 0.0f, 0.1f), dv(0.0f, 0.5f, 0.0f);
    const glm::vec3 n = glm::normalize(glm::cross(du, dv));
    for (int i = 0; i < 360; ++i) {
        const float a = glm::radians(float(i));
        const glm::vec2 noise = 2.4e-7f * glm::vec2(std::cos(a), std::sin(a));
        int resolved = 0;
        const glm::vec4 t =
            g::sgPatchLimitTangent(du, dv, glm::vec2(0.3f, 0.1f), noise, n, resolved);
        regular += resolved == SG_LIMIT_TANGENT_REGULAR;
        flipped += t.w != 1.0f;
        const glm::dvec3 a3{glm::vec3(t)}, b3{glm::normalize(du)};
        worst = std::max(worst, std::atan2(glm::length(glm::cross(a3, b3)), glm::dot(a3, b3)));
    }
    EXPECT_EQ(regular, 0u);
    EXPECT_EQ(flipped, 0u);
    sg::test::hardCasePerturbedAtMost(
        "uv-degenerate", "patch limit tangent of a chart whose d(s,t)/dv is rounding noise",
        "the noise's direction turned through 360 deg in 1-deg steps",
        "angle of T to dP/du (rad); regular points or w = -1 must be none",
        worst + double(regular + flipped), 1e-6);
}

} // namespace
