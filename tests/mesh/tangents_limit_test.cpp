// Limit-surface tangent frames (surfgrad/mesh/tangents.h: limitTangent,
// generateLimitTangents) on sg::mesh::Subdivider's limit evaluation:
//  - the chain rule on analytic derivatives (known answers, mirrored and
//    degenerate Jacobians);
//  - planes with affine UVs (bilinear and Catmull-Clark): the exact answer
//    is one constant tangent everywhere;
//  - a Catmull-Clark cylinder: by symmetry the tangent is circumferential
//    at every limit point on a mirror plane of the cage;
//  - unit length, orthogonality to the limit normal, handedness on
//    mirrored UVs, finite fallbacks on zero-area UVs;
//  - convergence of MikkTSpace on the refined mesh towards the limit frame.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "hardcase.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"

namespace {

using sg::mesh::limitTangent;
using sg::mesh::LimitTangentCase;

double angleDeg(glm::vec3 a, glm::vec3 b) {
    const glm::dvec3 da(a), db(b);
    return std::atan2(glm::length(glm::cross(da, db)), glm::dot(da, db)) * 180.0 / M_PI;
}

// ---------------------------------------------------------------------------
// The chain rule alone
// ---------------------------------------------------------------------------

TEST(LimitTangent, ScaledAndRotatedCharts) {
    const glm::vec3 du(1, 0, 0), dv(0, 1, 0);
    LimitTangentCase k;
    // s = 2u, t = 3v: dP/ds = (1/2, 0, 0).
    EXPECT_EQ(limitTangent(du, dv, {2, 0}, {0, 3}, &k), glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(k, LimitTangentCase::Regular);
    // s = v, t = -u (a rotation by -90 degrees, orientation preserving):
    // u = -t, v = s, so dP/ds = dP/dv = (0, 1, 0).
    EXPECT_EQ(limitTangent(du, dv, {0, -1}, {1, 0}, &k), glm::vec4(0, 1, 0, 1));
    // s = v, t = u: mirrored (det = -1); dP/ds = dP/dv, w = -1.
    EXPECT_EQ(limitTangent(du, dv, {0, 1}, {1, 0}, &k), glm::vec4(0, 1, 0, -1));
    EXPECT_EQ(k, LimitTangentCase::Regular);
    // s = -u, t = v: mirrored in s: dP/ds = (-1, 0, 0), w = -1.
    EXPECT_EQ(limitTangent(du, dv, {-1, 0}, {0, 1}, &k), glm::vec4(-1, 0, 0, -1));
}

TEST(LimitTangent, RandomChartsSatisfyTheChainRule) {
    // For random derivatives: T is unit, orthogonal to N = dPdu x dPdv, along
    // the part of dP/ds orthogonal to N, and w * (N x T) points to +t.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 du(u(rng), u(rng), u(rng)), dv(u(rng), u(rng), u(rng));
        const glm::vec2 sdu(u(rng), u(rng)), sdv(u(rng), u(rng));
        const double det = double(sdu.x) * sdv.y - double(sdv.x) * sdu.y;
        const glm::vec3 n = glm::cross(du, dv);
        // Well-conditioned charts only (sines of the chart angles > 0.01;
        // limitTangent's threshold is 1e-3).
        if (std::fabs(det) < 1e-2 * glm::length(sdu) * glm::length(sdv) ||
            glm::length(n) < 1e-2f * glm::length(du) * glm::length(dv))
            continue;
        LimitTangentCase k;
        const glm::vec4 t = limitTangent(du, dv, sdu, sdv, &k);
        ASSERT_EQ(k, LimitTangentCase::Regular);
        const glm::vec3 nn = glm::normalize(n), tt(t);
        // dP/ds and dP/dt by the inverse Jacobian, in double.
        const glm::dvec3 dPds =
            (double(sdv.y) * glm::dvec3(du) - double(sdu.y) * glm::dvec3(dv)) / det;
        const glm::dvec3 dPdt =
            (-double(sdv.x) * glm::dvec3(du) + double(sdu.x) * glm::dvec3(dv)) / det;
        EXPECT_NEAR(glm::length(tt), 1.0f, 1e-6f);      // float normalization
        EXPECT_NEAR(glm::dot(tt, nn), 0.0f, 1e-5f);     // float rounding of T and N
        EXPECT_LT(angleDeg(tt, glm::vec3(dPds)), 1e-3); // float rounding of T
        EXPECT_EQ(t.w, det > 0.0 ? 1.0f : -1.0f);
        EXPECT_GT(glm::dot(glm::dvec3(t.w * glm::cross(nn, tt)), dPdt), 0.0);
    }
}

TEST(LimitTangent, DegenerateJacobiansFallBackFinitely) {
    LimitTangentCase k;
    // Zero-area UVs (all derivatives zero, or collapsed to a line):
    // T along dP/du, w = +1.
    EXPECT_EQ(limitTangent({2, 0, 0}, {0, 1, 0}, {0, 0}, {0, 0}, &k), glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(k, LimitTangentCase::DegenerateUv);
    EXPECT_EQ(limitTangent({2, 0, 0}, {0, 1, 0}, {1, 1}, {2, 2}, &k), glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(k, LimitTangentCase::DegenerateUv);
    // dP/du = 0 as well: dP/dv.
    EXPECT_EQ(limitTangent({0, 0, 0}, {0, 3, 0}, {0, 0}, {0, 0}, &k), glm::vec4(0, 1, 0, 1));
    EXPECT_EQ(k, LimitTangentCase::DegenerateSurface);
    // Collapsed surface point (dP/du parallel to dP/dv) with a good chart:
    // normalized dP/ds, w from the chart.
    EXPECT_EQ(limitTangent({1, 0, 0}, {2, 0, 0}, {1, 0}, {0, 1}, &k), glm::vec4(1, 0, 0, 1));
    EXPECT_EQ(k, LimitTangentCase::DegenerateSurface);
    // Everything zero: (1, 0, 0).
    EXPECT_EQ(limitTangent({0, 0, 0}, {0, 0, 0}, {0, 0}, {0, 0}, &k), glm::vec4(1, 0, 0, 1));
    // Huge and tiny magnitudes stay finite and unit.
    for (float s : {1e-30f, 1e-10f, 1e10f, 1e30f}) {
        const glm::vec4 t = limitTangent({s, 0, 0}, {0, s, 0}, {s, 0}, {0, -s}, &k);
        EXPECT_TRUE(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z)) << s;
        EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f) << s;
    }
    sg::test::reportHardCaseHolds(
        "uv-degenerate", "limit tangent of zero or collinear UV and surface derivatives",
        "the tangent and its fallback case", "the documented fallback, exactly",
        "the documented fallback, exactly");
}

// A UV chart whose second derivative is rounding noise (the side walls of a
// planar UV projection: s and t do not change along v, so d(s,t)/dv is
// 1e-7 of the coordinates in a random direction). The chart is degenerate
// relative to its size, whatever the noise's direction: the documented
// fallback, w = +1, for every direction. With the sine of the two
// derivatives' angle as the measure (the rule before), a noise direction
// perpendicular to d(s,t)/du passed as regular and w took the noise's sign.
TEST(LimitTangentHardCases, NoiseDerivativeIsDegenerateInEveryDirection) {
    LimitTangentCase k;
    size_t regular = 0, flipped = 0;
    double worstDeg = 0.0;
    for (int i = 0; i < 360; ++i) {
        const float a = float(i) * float(M_PI / 180.0);
        const glm::vec2 noise = 2.4e-7f * glm::vec2(std::cos(a), std::sin(a));
        const glm::vec4 t = limitTangent({0.3f, 0, 0.1f}, {0, 0.5f, 0}, {0.3f, 0.1f}, noise, &k);
        regular += k == LimitTangentCase::Regular;
        flipped += t.w != 1.0f;
        worstDeg = std::max(worstDeg, angleDeg(glm::vec3(t), glm::vec3(0.3f, 0, 0.1f)));
    }
    EXPECT_EQ(regular, 0u);
    EXPECT_EQ(flipped, 0u);
    // T = dP/du made orthogonal to the normal (dP/du is already): rounding.
    EXPECT_LT(worstDeg, 1e-4);
    sg::test::hardCasePerturbedAtMost(
        "uv-degenerate",
        "limit tangent of a chart whose d(s,t)/dv is rounding noise (2.4e-7 of d(s,t)/du)",
        "the noise's direction turned through 360 deg in 1-deg steps",
        "angle of T to the fallback dP/du (deg); points classified regular or with w = -1 must "
        "be none",
        worstDeg + double(regular + flipped), 1e-4);
}

// ---------------------------------------------------------------------------
// Through the subdivider
// ---------------------------------------------------------------------------

// An n x m grid of quads in the plane z = 0 over [0, n] x [0, m], UVs an
// affine image of (x, y): (s, t) = A (x, y) + b, one UV per vertex.
sg::mesh::PolygonMesh planeCage(int n, int m, glm::mat2 a, glm::vec2 b, sg::mesh::Scheme scheme) {
    sg::mesh::PolygonMesh cage;
    cage.name = "plane";
    sg::mesh::FaceVaryingChannel uv;
    uv.name = "uv";
    for (int y = 0; y <= m; ++y)
        for (int x = 0; x <= n; ++x) {
            cage.positions.push_back({float(x), float(y), 0.0f});
            uv.values.push_back(a * glm::vec2(float(x), float(y)) + b);
        }
    auto id = [&](int x, int y) { return uint32_t(y * (n + 1) + x); };
    for (int y = 0; y < m; ++y)
        for (int x = 0; x < n; ++x) {
            cage.faceSizes.push_back(4);
            for (uint32_t v : {id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)}) {
                cage.faceVertices.push_back(v);
                uv.indices.push_back(v);
            }
        }
    cage.uvSets.push_back(uv);
    cage.options.scheme = scheme;
    // Smooth face-varying interpolation: UVs follow the same rules as
    // positions, so an affine UV map stays affine on the limit surface.
    cage.options.fvar = sg::mesh::FVarInterpolation::Smooth;
    sg::mesh::validate(cage, "plane");
    return cage;
}

struct LimitMesh {
    sg::mesh::Subdivider subdivider;
    sg::mesh::RenderMesh mesh;
    size_t irregular = 0;
};

LimitMesh limitMesh(const sg::mesh::PolygonMesh& cage, int level) {
    sg::mesh::SubdivisionSettings settings;
    settings.level = level;
    settings.options = cage.options;
    settings.limit = true;
    LimitMesh r;
    r.subdivider.build(cage, settings, cage.name);
    r.mesh = r.subdivider.renderMesh();
    r.irregular = sg::mesh::generateLimitTangents(r.mesh, r.subdivider.limitFrame(), 0);
    return r;
}

TEST(LimitTangents, AffinePlaneGivesTheExactConstantTangent) {
    // P = (x, y, 0), (s, t) = A (x, y) + b  =>  dP/ds = first column of
    // A^-1 (in xy), the same at every limit point, w = sign(det A).
    const glm::mat2 charts[] = {
        glm::mat2(0.5f, 0.2f, -0.1f, 0.7f),   // columns: A = [[.5 -.1] [.2 .7]]
        glm::mat2(-0.4f, 0.0f, 0.3f, 0.25f)}; // mirrored (det < 0)
    for (const auto scheme : {sg::mesh::Scheme::Bilinear, sg::mesh::Scheme::Catmark}) {
        for (const glm::mat2& a : charts) {
            const LimitMesh lm = limitMesh(planeCage(4, 3, a, {0.1f, 0.2f}, scheme), 2);
            const glm::mat2 inv = glm::inverse(a);
            const glm::vec3 expected = glm::normalize(glm::vec3(inv[0][0], inv[0][1], 0.0f));
            const float w = glm::determinant(a) > 0.0f ? 1.0f : -1.0f;
            ASSERT_GT(lm.mesh.vertexCount(), 50u);
            // Catmull-Clark: the 4 smooth boundary corners, where the limit
            // parameterization collapses (dP/du parallel to dP/dv); they
            // take their neighbours' frame. Bilinear: none.
            EXPECT_EQ(lm.irregular, scheme == sg::mesh::Scheme::Catmark ? 4u : 0u);
            double worst = 0.0;
            for (const glm::vec4& t : lm.mesh.tangents) {
                worst = std::max(worst, angleDeg(glm::vec3(t), expected));
                EXPECT_EQ(t.w, w);
            }
            std::printf("affine plane, %s, det %.2f: max angle to the exact tangent %.2e deg\n",
                        sg::mesh::toString(scheme), double(glm::determinant(a)), worst);
            // Limit derivatives are evaluated in float (~1e-6 relative after
            // the patch sums); the chain rule divides by the chart sines,
            // which drop towards the collapsed smooth corners (measured max
            // 4.3e-3 deg = 7.6e-5 rad next to them, ~1e-5 deg elsewhere).
            // 0.01 deg bounds that; a wrong chain rule is off by degrees.
            EXPECT_LT(worst, 1e-2) << sg::mesh::toString(scheme) << " det " << glm::determinant(a);
        }
    }
}

// A Catmull-Clark cylinder cage: `ring` vertices around, `rows` + 1 rings
// along z, UV s = around / ring (seam at s = 0 / 1), t = z / rows.
sg::mesh::PolygonMesh cylinderCage(int ring, int rows) {
    sg::mesh::PolygonMesh cage;
    cage.name = "cylinder";
    sg::mesh::FaceVaryingChannel uv;
    uv.name = "uv";
    for (int r = 0; r <= rows; ++r)
        for (int i = 0; i < ring; ++i) {
            const float a = 6.28318530718f * float(i) / float(ring);
            cage.positions.push_back({std::cos(a), std::sin(a), float(r)});
        }
    for (int r = 0; r <= rows; ++r)
        for (int i = 0; i <= ring; ++i)
            uv.values.push_back({float(i) / float(ring), float(r) / float(rows)});
    auto vid = [&](int i, int r) { return uint32_t(r * ring + (i % ring)); };
    auto tid = [&](int i, int r) { return uint32_t(r * (ring + 1) + i); };
    for (int r = 0; r < rows; ++r)
        for (int i = 0; i < ring; ++i) {
            cage.faceSizes.push_back(4);
            // Counter-clockwise seen from outside: around, then up.
            const uint32_t v[4] = {vid(i, r), vid(i + 1, r), vid(i + 1, r + 1), vid(i, r + 1)};
            const uint32_t t[4] = {tid(i, r), tid(i + 1, r), tid(i + 1, r + 1), tid(i, r + 1)};
            for (int k = 0; k < 4; ++k) {
                cage.faceVertices.push_back(v[k]);
                uv.indices.push_back(t[k]);
            }
        }
    cage.uvSets.push_back(uv);
    cage.options.scheme = sg::mesh::Scheme::Catmark;
    sg::mesh::validate(cage, "cylinder");
    return cage;
}

TEST(LimitTangents, CylinderTangentsAreCircumferentialOnMirrorPlanes) {
    // The cage is symmetric under reflection through every plane containing
    // the z axis and a cage vertex or a cage edge midpoint; so is the limit
    // surface. If the UV map is symmetric too (s linear in the angle), dP/ds
    // at a point on such a plane is perpendicular to it: circumferential.
    // The seam breaks the UV symmetry near s = 0, so only points at least
    // one cage face away from it are checked.
    const int ring = 8, level = 3;
    const LimitMesh lm = limitMesh(cylinderCage(ring, 4), level);
    const sg::mesh::RenderMesh& m = lm.mesh;
    size_t checked = 0;
    double worst = 0.0, worstOrtho = 0.0;
    for (size_t v = 0; v < m.vertexCount(); ++v) {
        const glm::vec3 p = m.positions[v];
        const glm::vec4 t = m.tangents[v];
        worstOrtho = std::max(worstOrtho, double(std::fabs(glm::dot(glm::vec3(t), m.normals[v]))));
        EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
        // On a mirror plane: the angle is a multiple of pi / ring.
        const double angle = std::atan2(double(p.y), double(p.x));
        const double steps = angle / (M_PI / ring);
        if (std::fabs(steps - std::round(steps)) > 1e-4) continue;
        const double s = m.uvSets[0][v].x;
        if (s < 1.0 / ring || s > 1.0 - 1.0 / ring) continue; // next to the seam
        const glm::vec3 around = glm::normalize(glm::vec3(-p.y, p.x, 0.0f));
        worst = std::max(worst, angleDeg(glm::vec3(t), around));
        EXPECT_EQ(t.w, 1.0f) << "vertex " << v;
        ++checked;
    }
    std::printf("cylinder L%d: %zu mirror-plane points, max angle to circumferential %.2e deg, max "
                "|t.n| %.2e\n",
                level, checked, worst, worstOrtho);
    EXPECT_GT(checked, 50u);
    // Measured 7.5e-4 deg (1.3e-5 rad): derivatives evaluated in float
    // (~1e-7 relative) divided by the chart sines in the chain rule, and
    // the symmetry planes located from float positions. 5e-3 deg keeps a
    // 6x margin; a wrong chain rule (e.g. using dP/du as the tangent) is
    // off by degrees at these points.
    EXPECT_LT(worst, 5e-3);
    EXPECT_LT(worstOrtho, 1e-6); // made orthogonal to the stored normal
}

TEST(LimitTangents, MirroredUvsGiveNegativeHandedness) {
    // An 8 x 2 plane, left half mapped with s = x, right half with
    // s = 8 - x (mirrored; the mirror line x = 4 is a UV seam with its own
    // UV values on each side). Every point has w = +1 on the left, -1 on
    // the right. The seam is a UV boundary, refined with boundary rules
    // while positions are smooth across it, so UV(P) is exactly affine only
    // beyond the seam faces' support: directions are checked from two cage
    // faces away on.
    sg::mesh::PolygonMesh cage =
        planeCage(8, 2, glm::mat2(1.0f), {0, 0}, sg::mesh::Scheme::Catmark);
    sg::mesh::FaceVaryingChannel& uv = cage.uvSets[0];
    const std::vector<uint32_t> offsets = sg::mesh::faceOffsets(cage);
    std::vector<uint32_t> mirroredValue(cage.vertexCount(), UINT32_MAX); // one per vertex
    for (size_t f = 0; f < cage.faceCount(); ++f) {
        if (f % 8 < 4) continue; // left half keeps s = x
        for (uint32_t c = offsets[f]; c < offsets[f + 1]; ++c) {
            const uint32_t v = cage.faceVertices[c];
            if (mirroredValue[v] == UINT32_MAX) {
                mirroredValue[v] = uint32_t(uv.values.size());
                uv.values.push_back({8.0f - cage.positions[v].x, cage.positions[v].y});
            }
            uv.indices[c] = mirroredValue[v];
        }
    }
    sg::mesh::validate(cage, "mirrored plane");
    const LimitMesh lm = limitMesh(cage, 2);
    size_t left = 0, right = 0;
    sg::test::Worst worst;
    for (size_t v = 0; v < lm.mesh.vertexCount(); ++v) {
        const float x = lm.mesh.positions[v].x, s = lm.mesh.uvSets[0][v].x;
        const glm::vec4 t = lm.mesh.tangents[v];
        // On the seam (x = 4) the vertex is split: s = 4 on both sides;
        // which side a copy belongs to is its UV derivative's business, so
        // only points off the seam are classified by x.
        if (std::fabs(x - 4.0f) < 1e-4f) continue;
        const bool isLeft = x < 4.0f;
        EXPECT_EQ(t.w, isLeft ? 1.0f : -1.0f) << "vertex " << v << " x " << x << " s " << s;
        if (std::fabs(x - 4.0f) >= 2.0f) {
            // Float limit evaluation, as in the affine test (the plane's
            // smooth corners are included here too).
            EXPECT_LT(angleDeg(glm::vec3(t), {isLeft ? 1.0f : -1.0f, 0, 0}), 1e-2)
                << "vertex " << v;
            worst.add(angleDeg(glm::vec3(t), {isLeft ? 1.0f : -1.0f, 0, 0}));
            ++(isLeft ? left : right);
        }
    }
    EXPECT_GT(left, 20u);
    EXPECT_GT(right, 20u);
    sg::test::reportHardCaseHolds("uv-mirrored",
                                  "limit tangents of a plane mirrored at a UV seam, level 2",
                                  "handedness w off the seam", "-1 on the mirrored side, +1 else",
                                  "-1 on the mirrored side, +1 else");
    sg::test::reportHardCase({"uv-mirrored", "the same, two cage faces from the seam",
                              "angle of the tangent to +-x (deg)", "<= 0.01",
                              sg::test::hardCaseNumber(worst.value)});
}

TEST(LimitTangents, ZeroAreaUvsFallBackWithoutNaN) {
    // Every UV of the middle faces collapsed to one point: their limit UV
    // Jacobian vanishes at points inside them.
    sg::mesh::PolygonMesh cage =
        planeCage(4, 4, glm::mat2(0.25f), {0, 0}, sg::mesh::Scheme::Catmark);
    sg::mesh::FaceVaryingChannel& uv = cage.uvSets[0];
    const std::vector<uint32_t> offsets = sg::mesh::faceOffsets(cage);
    const uint32_t point = uint32_t(uv.values.size());
    uv.values.push_back({0.5f, 0.5f});
    for (size_t f : {5u, 6u, 9u, 10u})
        for (uint32_t c = offsets[f]; c < offsets[f + 1]; ++c) uv.indices[c] = point;
    sg::mesh::validate(cage, "collapsed uvs");
    const LimitMesh lm = limitMesh(cage, 2);
    EXPECT_GT(lm.irregular, 0u);
    sg::test::Worst unit, ortho;
    for (size_t v = 0; v < lm.mesh.vertexCount(); ++v) {
        const glm::vec4 t = lm.mesh.tangents[v];
        ASSERT_TRUE(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z)) << v;
        EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
        EXPECT_TRUE(t.w == 1.0f || t.w == -1.0f);
        EXPECT_NEAR(glm::dot(glm::vec3(t), lm.mesh.normals[v]), 0.0f, 1e-6f);
        unit.add(std::fabs(glm::length(glm::vec3(t)) - 1.0f));
        ortho.add(std::fabs(glm::dot(glm::vec3(t), lm.mesh.normals[v])));
    }
    sg::test::reportHardCase({"uv-degenerate",
                              "limit tangents where 4 cage faces' UVs collapse to one point",
                              "| |T| - 1 |", "<= 1e-06", sg::test::hardCaseNumber(unit.value)});
    sg::test::reportHardCase({"uv-degenerate", "the same", "|T . n|", "<= 1e-06",
                              sg::test::hardCaseNumber(ortho.value)});
}

TEST(LimitTangents, MikkTSpaceOnRefinedMeshesApproachesTheLimitFrame) {
    // On spot's cage (quads, pentagons, triangles, UV seams): the limit
    // frame at level L against MikkTSpace computed on the same level-L
    // mesh (limit positions, limit normals, limit UVs). MikkTSpace averages
    // face derivatives, so it differs by O(edge length) and converges as
    // the mesh is refined; the median angle must shrink by level.
    const sg::mesh::PolygonMesh cage = sg::mesh::loadPolygonMesh(
        std::string(SURFGRAD_DATA_DIR) + "/meshes/spot/spot_control_mesh.obj");
    double previousMedian = 1e9;
    for (int level : {1, 2, 3}) {
        const LimitMesh lm = limitMesh(cage, level);
        sg::mesh::RenderMesh mikk = lm.mesh;
        std::vector<glm::vec4> corner;
        sg::mesh::MikkTSpaceInput in;
        in.positions = mikk.positions;
        in.normals = mikk.normals;
        in.uvs = mikk.uvSets[0];
        in.cornerVertices = mikk.indices;
        sg::mesh::MikkTSpaceGenerator g;
        g.generate(in, corner);
        std::vector<double> angles;
        size_t signAgree = 0;
        for (size_t c = 0; c < corner.size(); ++c) {
            const glm::vec4 lt = lm.mesh.tangents[mikk.indices[c]];
            angles.push_back(angleDeg(glm::vec3(corner[c]), glm::vec3(lt)));
            signAgree += corner[c].w == lt.w;
        }
        std::sort(angles.begin(), angles.end());
        const double median = angles[angles.size() / 2];
        std::printf("spot L%d: MikkTSpace vs limit tangents over %zu corners: median %.3f deg, "
                    "p90 %.3f deg, signs agree %.4f\n",
                    level, angles.size(), median, angles[angles.size() * 9 / 10],
                    double(signAgree) / double(angles.size()));
        EXPECT_LT(median, previousMedian);
        // Both frames follow the same UV chart: handedness disagrees only at
        // isolated degenerate spots (zero-area UV corners of the cage).
        EXPECT_GT(double(signAgree) / double(angles.size()), 0.99);
        previousMedian = median;
    }
}

TEST(LimitTangents, DispatchAndErrors) {
    sg::mesh::RenderMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.uvSets = {{{0, 0}, {1, 0}, {0, 1}}};
    m.indices = {0, 1, 2};
    // Calls that would break a precondition are named by
    // tangentInputProblem() (their contract checks: tests/mesh/contract_test.cpp).
    EXPECT_NE(sg::mesh::tangentInputProblem(m, sg::mesh::TangentMethod::Limit, 0), "");
    sg::mesh::LimitFrame frame;
    frame.dPdu = {{1, 0, 0}};
    frame.dPdv = {{0, 1, 0}};
    EXPECT_NE(sg::mesh::tangentInputProblem(m, sg::mesh::TangentMethod::Limit, 0, &frame)
                  .find("does not match"),
              std::string::npos); // size mismatch
    EXPECT_EQ(sg::mesh::tangentInputProblem(m, sg::mesh::TangentMethod::Pixel, 0), "");
    sg::mesh::generateTangents(m, sg::mesh::TangentMethod::MikkTSpace, 0);
    EXPECT_EQ(m.tangents.size(), 3u);
    EXPECT_EQ(sg::mesh::generateTangents(m, sg::mesh::TangentMethod::Pixel, 0), 0u);
    EXPECT_TRUE(m.tangents.empty());
    EXPECT_EQ(m.tangentUvSet, -1);
}

} // namespace
