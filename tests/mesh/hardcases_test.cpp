// Hard cases of the mesh pipeline, reported as rows of docs/hard-cases.md
// (tests/common/hardcase.h):
//  - creases of every sharpness (DeRose, Kass, Truong 1998, semi-sharp
//    creases; OpenSubdiv's uniform and Chaikin creasing): a crease loop and
//    a corner from smooth (0) through fractional values to infinitely sharp
//    at the refinement level, limit evaluation at level 4;
//  - geometry far from the origin: the same cage translated 1e2 to 1e6
//    units, its limit normals and tangents (limit and MikkTSpace) against
//    the untranslated cage's.
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <string>

#include "hardcase.h"
#include "mesh_test_util.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"

namespace {

using namespace sg::mesh;
using sg::test::hardCaseAtMost;
using sg::test::hardCaseNumber;
using sg::test::reportHardCase;
using sg::test::Worst;

PolygonMesh cubeWith(const std::string& tags) {
    PolygonMesh m = parseObj(std::string(sg::test::kCubeObj) + tags, "cube.obj");
    validate(m, "cube.obj");
    return m;
}

double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
    return glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
}
glm::dvec3 d3(const glm::vec3& v) {
    return glm::dvec3(v.x, v.y, v.z);
}

// Non-finite or non-unit normals and tangents of a limit render mesh.
int badFrames(const RenderMesh& m) {
    int bad = 0;
    for (size_t v = 0; v < m.vertexCount(); ++v) {
        const glm::vec3 n = m.normals[v];
        const glm::vec4 t = m.tangents.empty() ? glm::vec4(1, 0, 0, 1) : m.tangents[v];
        const bool ok = std::isfinite(n.x + n.y + n.z) && std::isfinite(t.x + t.y + t.z) &&
                        std::fabs(glm::length(n) - 1.0f) <= 1e-4f &&
                        std::fabs(glm::length(glm::vec3(t)) - 1.0f) <= 1e-4f &&
                        (t.w == 1.0f || t.w == -1.0f);
        bad += !ok;
    }
    return bad;
}

// A crease loop around the top face (cage vertices 4-7, z = 1) and, in a
// second sweep, a corner at cage vertex 4 = (-1, -1, 1), of sharpness s.
// The limit surface moves continuously from the smooth cube's (s = 0) to
// the sharp one as s grows: the highest limit point rises monotonically to
// the top face (z = 1) and the limit point nearest the corner approaches
// it; from s >= the level (4) on the feature is infinitely sharp there
// (the crease's limit curve is the cubic B-spline of the loop, in z = 1;
// the corner interpolates its vertex).
TEST(MeshHardCases, CreasesOfEverySharpness) {
    const double sharpness[] = {0, 0.25, 0.5, 1, 1.5, 2, 2.5, 3, 3.75, 4, 5, 7.5, 10};
    int bad = 0;
    Worst creaseDrop, cornerRise;
    double creaseTop = 0, cornerDist = 0;
    for (CreaseMethod method : {CreaseMethod::Uniform, CreaseMethod::Chaikin}) {
        double prevTop = -1e9, prevDist = 1e9;
        for (double s : sharpness) {
            for (int feature = 0; feature < 2; ++feature) {
                const std::string tag = feature == 0
                                            ? "t crease 5/1/0 4 5 6 7 4 " + std::to_string(s) + "\n"
                                            : "t corner 1/1/0 4 " + std::to_string(s) + "\n";
                PolygonMesh cage = cubeWith(tag);
                SubdivisionSettings set;
                set.level = 4;
                set.limit = true;
                set.options = cage.options;
                set.options.creaseMethod = method;
                Subdivider sub(cage, set, "cube.obj");
                RenderMesh rm = sub.renderMesh();
                generateLimitTangents(rm, sub.limitFrame(), 0);
                bad += badFrames(rm);
                if (feature == 0) {
                    double top = -1e9;
                    for (const auto& p : sub.refined().positions) top = std::max(top, double(p.z));
                    creaseDrop.add(prevTop - top);
                    prevTop = top;
                    if (s == 10) creaseTop = std::max(creaseTop, std::fabs(1.0 - top));
                } else {
                    double dist = 1e9;
                    for (const auto& p : sub.refined().positions)
                        dist = std::min(dist, glm::length(d3(p) - glm::dvec3(-1, -1, 1)));
                    cornerRise.add(dist - prevDist);
                    prevDist = dist;
                    if (s == 10) cornerDist = std::max(cornerDist, dist);
                }
            }
        }
    }
    EXPECT_EQ(bad, 0);
    reportHardCase({"creases",
                    "cube with a crease loop or a corner of sharpness 0 to 10 (13 values, "
                    "fractional ones included), uniform and Chaikin creasing, level 4 limit",
                    "vertices with a non-finite or non-unit limit normal or tangent", "0",
                    std::to_string(bad)});
    // Monotone: binary32 limit evaluation rounds positions by ~1e-7 on unit
    // coordinates, so equal heights may differ by that much.
    hardCaseAtMost("creases", "the crease loop, sharpness growing",
                   "largest decrease of the highest limit point's z", creaseDrop.value, 1e-6);
    hardCaseAtMost("creases", "the corner, sharpness growing",
                   "largest increase of the distance from the corner to the limit surface",
                   cornerRise.value, 1e-6);
    // Infinitely sharp at level 4: the B-spline loop lies in z = 1, the
    // corner limit point is the vertex (float patch evaluation: 2e-6, as
    // Subdivision.InfinitelySharpCreaseFollowsTheCubicBSpline).
    hardCaseAtMost("creases", "sharpness 10 (above the level)", "|1 - highest limit z|", creaseTop,
                   2e-6);
    hardCaseAtMost("creases", "corner sharpness 10 (above the level)",
                   "distance from the corner to the limit surface", cornerDist, 2e-6);
}

// The cube cage translated by d (0.6, -0.48, 0.64) (exact in binary32:
// the corners are integers): limit normals and tangents (both sources)
// against those of the cage at the origin, vertex by vertex (same topology,
// same order). Limit evaluation works relative to the cage's box centre, so
// the limit frames are the same bit for bit (before it did, they were off
// by 0.29 deg at d = 100 and 24 deg at 1e4: derivative weights of deep
// patches cancel terms of size 2^depth |P|). MikkTSpace works on the render
// mesh's binary32 positions, whose rounding d * 6e-8 grows against the
// level-3 edges of 0.25: that is the storage's limit, which a renderer
// avoids with camera-relative positions.
TEST(MeshHardCases, FarFromTheOrigin) {
    const glm::dvec3 dir(0.6, -0.48, 0.64);
    auto build = [&](double d, RenderMesh& limitMesh, RenderMesh& mikk) {
        PolygonMesh cage = cubeWith("");
        for (auto& p : cage.positions) p = glm::vec3(d3(p) + d * dir);
        SubdivisionSettings set;
        set.level = 3;
        set.limit = true;
        set.options = cage.options;
        Subdivider sub(cage, set, "cube.obj");
        limitMesh = sub.renderMesh();
        generateLimitTangents(limitMesh, sub.limitFrame(), 0);
        mikk = sub.renderMesh();
        generateMikkTSpaceTangents(mikk, 0);
    };
    RenderMesh ref, refMikk;
    build(0.0, ref, refMikk);
    const double distances[] = {1e2, 1e4, 1e5, 1e6};
    // Limit frames: identical (measured 0), bound 1e-4 deg. MikkTSpace: the
    // measured worst values (1.2e-3, 0.068, 0.99, 13.9 deg) times about 2.5.
    const double limitBound = 1e-4;
    const double mikkBound[] = {3e-3, 0.17, 2.5, 35};
    for (int k = 0; k < 4; ++k) {
        RenderMesh lm, mk;
        build(distances[k], lm, mk);
        ASSERT_EQ(lm.vertexCount(), ref.vertexCount());
        ASSERT_EQ(mk.vertexCount(), refMikk.vertexCount());
        EXPECT_EQ(badFrames(lm), 0);
        EXPECT_EQ(badFrames(mk), 0);
        Worst n, t, tm;
        for (size_t v = 0; v < lm.vertexCount(); ++v) {
            n.add(angleDeg(d3(lm.normals[v]), d3(ref.normals[v])));
            t.add(angleDeg(d3(glm::vec3(lm.tangents[v])), d3(glm::vec3(ref.tangents[v]))));
        }
        for (size_t v = 0; v < mk.vertexCount(); ++v)
            tm.add(angleDeg(d3(glm::vec3(mk.tangents[v])), d3(glm::vec3(refMikk.tangents[v]))));
        const std::string c = "cube cage (edges 2) at " + hardCaseNumber(distances[k]) +
                              " from the origin, level 3 limit";
        hardCaseAtMost("far-from-origin", c,
                       "angle of the limit normals to the cage at the origin's (deg)", n.value,
                       limitBound);
        hardCaseAtMost("far-from-origin", c, "angle of the limit tangents (deg)", t.value,
                       limitBound);
        hardCaseAtMost("far-from-origin", c, "angle of the MikkTSpace tangents (deg)", tm.value,
                       mikkBound[k]);
    }
}

} // namespace
