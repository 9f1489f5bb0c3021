// The bake against answers known without it: a plane cage (limit surface
// = the square, UV = (x, y)) under an analytic height field, a cube cage
// under a sphere (displacement and normal from a double-precision
// ray-sphere intersection at the baked limit point and normal), seams,
// misses, bad input, and the same bits at every thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "bake_meshes.h"
#include "hardcase.h"
#include "surfgrad/bake/baker.h"
#include "surfgrad/base/io.h"

namespace sg::test {
namespace {

using bake::BakeResult;
using bake::BakeSettings;
using bake::TexelState;

constexpr double kPi = std::numbers::pi;

// h = A sin(2 pi x) cos(2 pi y) and its gradient.
constexpr double kAmp = 0.02;
double planeHeight(double x, double y) {
    return kAmp * std::sin(2 * kPi * x) * std::cos(2 * kPi * y);
}
glm::dvec2 planeGrad(double x, double y) {
    return {kAmp * 2 * kPi * std::cos(2 * kPi * x) * std::cos(2 * kPi * y),
            -kAmp * 2 * kPi * std::sin(2 * kPi * x) * std::sin(2 * kPi * y)};
}

bool hit(const BakeResult& r, int i, int j) {
    return r.state.at(i, j) == uint8_t(TexelState::Hit);
}

// Both base surfaces: the limit surface and the cage refined to level 2
// (on the plane both are the square with UV = (x, y); on the cube the
// expected values follow the baked point and normal, whichever surface
// they are on).
class BakeBoth : public ::testing::TestWithParam<bake::BakeSurface> {
protected:
    BakeSettings settings() const {
        BakeSettings s;
        s.surface = GetParam();
        s.refinedLevel = 2;
        return s;
    }
};

INSTANTIATE_TEST_SUITE_P(Surfaces, BakeBoth,
                         ::testing::Values(bake::BakeSurface::Limit, bake::BakeSurface::Refined),
                         [](const auto& param) {
                             return param.param == bake::BakeSurface::Limit ? "Limit" : "Refined";
                         });

TEST_P(BakeBoth, PlaneUnderAHeightFieldGivesItsHeightsAndSlopes) {
    const int n = 256;
    const float lo = -0.1f, hi = 1.1f;
    const mesh::RenderMesh high = heightFieldMesh(n, lo, hi, planeHeight, planeGrad);
    BakeSettings s = settings();
    s.width = s.height = 128;
    s.maxDistance = 0.1;
    s.residual = true;
    const BakeResult r = bake::bake(planeCage(4), high, s, "plane.obj", "height.obj");
    // Every texel centre lies on the square.
    EXPECT_EQ(r.stats.chartTexels, size_t(128 * 128));
    EXPECT_EQ(r.stats.hits, size_t(128 * 128));
    EXPECT_EQ(r.stats.overlapTexels, 0u);
    // Linear interpolation of h over triangles of diameter d errs by at most
    // M d^2 / 2 (M: the largest second derivative along a line, at most
    // 2 A (2 pi)^2 here); slopes of the interpolated vertex normals by
    // d^2 / 2 times the third derivatives (2 A (2 pi)^3); plus binary32
    // rounding of values of order 1 (1e-6).
    const double d = std::sqrt(2.0) * (hi - lo) / n;
    const double heightTol = 0.5 * d * d * 2 * kAmp * std::pow(2 * kPi, 2) + 1e-6;
    const double slopeTol = 0.5 * d * d * 2 * kAmp * std::pow(2 * kPi, 3) + 1e-5;
    double worstPos = 0, worstH = 0, worstSlope = 0;
    for (int j = 0; j < r.height; ++j)
        for (int i = 0; i < r.width; ++i) {
            ASSERT_TRUE(hit(r, i, j)) << i << "," << j;
            const double x = (i + 0.5) / r.width, y = (j + 0.5) / r.height;
            const glm::vec3 p = r.basePosition.at(i, j);
            worstPos =
                std::max({worstPos, std::abs(p.x - x), std::abs(p.y - y), double(std::abs(p.z))});
            worstH = std::max(worstH, std::abs(r.displacement.at(i, j) - planeHeight(x, y)));
            const glm::dvec2 g = planeGrad(x, y);
            const glm::vec2 sl = r.tangentSlopes.at(i, j);
            worstSlope = std::max({worstSlope, std::abs(sl.x - g.x), std::abs(sl.y - g.y)});
        }
    // The texel's limit point is the texel centre itself: Newton on the UV
    // map leaves binary32 rounding of coordinates of order 1.
    EXPECT_LE(worstPos, 2e-6);
    EXPECT_LE(worstH, heightTol);
    EXPECT_LE(worstSlope, slopeTol);
    std::printf("plane: position %.3g, height %.3g (tol %.3g), slope %.3g (tol %.3g)\n", worstPos,
                worstH, heightTol, worstSlope, slopeTol);

    // The residual after displacement: the high mesh IS the displaced
    // plane, so a height layer of the displacement explains all of its
    // normal and the residual is the error of the texel differences. With
    // texel size D and each height off by at most heightTol: a central
    // difference errs by D^2 / 6 max|h_xxx| (<= A (2 pi)^3 along an axis)
    // + heightTol / D; a one-sided one on the map's border by D / 2
    // max|h_xx| (<= A (2 pi)^2) + 2 heightTol / D; plus the slopes' own
    // error.
    const double texel = 1.0 / r.width;
    const double residualTol =
        slopeTol + texel * texel / 6 * kAmp * std::pow(2 * kPi, 3) + heightTol / texel;
    const double borderTol =
        slopeTol + texel / 2 * kAmp * std::pow(2 * kPi, 2) + 2 * heightTol / texel;
    double worstResidual = 0, worstBorder = 0, largestSlope = 0;
    for (int j = 0; j < r.height; ++j)
        for (int i = 0; i < r.width; ++i) {
            const glm::vec2 res = r.residualSlopes.at(i, j);
            const double e = std::max(std::abs(res.x), std::abs(res.y));
            const bool border = i == 0 || j == 0 || i == r.width - 1 || j == r.height - 1;
            double& worst = border ? worstBorder : worstResidual;
            worst = std::max(worst, e);
            largestSlope = std::max(largestSlope, double(glm::length(r.tangentSlopes.at(i, j))));
        }
    EXPECT_LE(worstResidual, residualTol);
    EXPECT_LE(worstBorder, borderTol);
    std::printf("plane residual: interior %.3g (tol %.3g), border %.3g (tol %.3g), full slopes up "
                "to %.3g\n",
                worstResidual, residualTol, worstBorder, borderTol, largestSlope);
}

// The residual keeps what the displacement map cannot hold: a ripple finer
// than the map's texels (period 1/64 on a 32^2 map) stays whole in the
// residual, while the smooth field under it goes into the height layer.
TEST(BakePlane, ResidualKeepsDetailFinerThanTheMap) {
    constexpr double kRipple = 0.0004, kFreq = 2 * kPi * 64;
    const auto h = [&](double x, double y) {
        return planeHeight(x, y) + kRipple * std::sin(kFreq * x);
    };
    const auto g = [&](double x, double y) {
        return planeGrad(x, y) + glm::dvec2(kRipple * kFreq * std::cos(kFreq * x), 0.0);
    };
    // The high mesh's vertices fall on every texel centre ((16 i + 8) / 512
    // with spacing 1/512 from -64/512), so each ray meets a vertex: its
    // height and normal are the analytic ones there (no interpolation).
    const int n = 640;
    const mesh::RenderMesh high = heightFieldMesh(n, -0.125f, 1.125f, h, g);
    BakeSettings s;
    s.width = s.height = 32;
    s.maxDistance = 0.1;
    s.residual = true;
    const BakeResult r = bake::bake(planeCage(4), high, s, "plane.obj", "ripple.obj");
    // At x = (i + 0.5) / 32, sin(kFreq x) = 0 and cos(kFreq x) = 1: the
    // sampled ripple is flat (nothing of it enters the height differences)
    // and its slope there is kRipple kFreq = 0.16 (the smooth field's slopes
    // reach 0.25). Expected residual: (0.16, 0) up to the smooth part's
    // central-difference error, D^2 / 6 max|h_xxx| with D = 1/32, and
    // binary32 rounding of positions of order 1 divided by D (2e-6; 1e-5
    // allowed).
    const double texel = 1.0 / 32;
    const double tol = texel * texel / 6 * kAmp * std::pow(2 * kPi, 3) + 1e-5;
    double worst = 0;
    for (int j = 1; j < 31; ++j)
        for (int i = 1; i < 31; ++i) {
            const glm::vec2 res = r.residualSlopes.at(i, j);
            worst = std::max({worst, std::abs(res.x - kRipple * kFreq), double(std::abs(res.y))});
        }
    EXPECT_LE(worst, tol);
    std::printf("ripple residual: worst %.3g (tol %.3g) of a ripple slope %.3g\n", worst, tol,
                kRipple * kFreq);
}

TEST(BakePlane, HighMeshCoveringHalfTheSquareReportsTheOtherHalfAsMisses) {
    // The high mesh spans x in [-0.1, 0.5]: texel columns whose centre is
    // beyond 0.5 miss.
    const mesh::RenderMesh high = heightFieldMesh(
        64, -0.1f, 1.1f, [](double, double) { return 0.01; },
        [](double, double) { return glm::dvec2(0.0); });
    mesh::RenderMesh half;
    half.positions = high.positions;
    half.normals = high.normals;
    for (size_t t = 0; t < high.indices.size(); t += 3) {
        float xmax = -1;
        for (int k = 0; k < 3; ++k) xmax = std::max(xmax, high.positions[high.indices[t + k]].x);
        if (xmax <= 0.5f + 1e-6f)
            for (int k = 0; k < 3; ++k) half.indices.push_back(high.indices[t + k]);
    }
    BakeSettings s;
    s.width = s.height = 64;
    s.maxDistance = 0.05;
    const BakeResult r = bake::bake(planeCage(2), half, s);
    EXPECT_EQ(r.stats.hits, size_t(32 * 64));
    EXPECT_EQ(r.stats.misses, size_t(32 * 64));
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            EXPECT_EQ(r.state.at(i, j), uint8_t(i < 32 ? TexelState::Hit : TexelState::Miss));
            // Misses take the nearest hit's value (reported, never zero).
            EXPECT_FLOAT_EQ(r.displacement.at(i, j), 0.01f);
        }
}

TEST(BakePlane, HighMeshOutOfReachIsAnError) {
    const mesh::RenderMesh high = heightFieldMesh(
        8, 0.0f, 1.0f, [](double, double) { return 5.0; },
        [](double, double) { return glm::dvec2(0.0); });
    BakeSettings s;
    s.width = s.height = 16;
    try {
        bake::bake(planeCage(2), high, s, "cage.obj", "high.obj");
        FAIL() << "expected an InputError";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.file(), "high.obj");
        EXPECT_NE(e.reason().find("same space and scale"), std::string::npos) << e.what();
    }
}

// The cube cage's limit surface under a sphere of radius R: every texel's
// expected displacement is the double-precision intersection of the ray
// from its baked limit point along its baked limit normal with the exact
// sphere, its expected normal the sphere's there.
struct SphereCheck {
    double worstT = 0, worstNormal = 0, worstNormalRad = 0, tolWorst = 0;
};

SphereCheck checkSphere(const BakeResult& r, double radius, double sagTol) {
    SphereCheck c;
    for (int j = 0; j < r.height; ++j)
        for (int i = 0; i < r.width; ++i) {
            if (!hit(r, i, j)) continue;
            const glm::dvec3 p(r.basePosition.at(i, j)), nn(r.baseNormal.at(i, j));
            // |p + t n|^2 = R^2: the root nearest 0.
            const double b = glm::dot(p, nn), cc = glm::dot(p, p) - radius * radius;
            const double disc = std::sqrt(b * b - cc);
            const double t1 = -b + disc, t2 = -b - disc;
            const double t = std::abs(t1) < std::abs(t2) ? t1 : t2;
            const glm::dvec3 q = p + t * nn;
            // A chord of the tessellated sphere lies up to sagTol inside it,
            // measured radially: along a ray at angle a to the radius that
            // is sagTol / cos a.
            const double cosA = std::abs(glm::dot(nn, q / radius));
            const double tol = sagTol / cosA + 2e-6;
            c.tolWorst = std::max(c.tolWorst, tol);
            c.worstT = std::max(c.worstT, std::abs(r.displacement.at(i, j) - t) / tol);
            // The angle by atan2 (acos loses half the digits near 0).
            const glm::dvec3 on(r.objectNormal.at(i, j)), sn = q / radius;
            const double ang = std::atan2(glm::length(glm::cross(on, sn)), glm::dot(on, sn));
            // The high mesh's interpolated normal at its hit h is h's own
            // direction (its vertices are radius times their normals); h
            // lies on the ray within the sagitta bound of q, so the angle
            // between them is at most that distance times sin a / R; plus
            // binary32 rounding of unit vectors (1e-6 rad).
            const double sinA = std::sqrt(std::max(0.0, 1 - cosA * cosA));
            const double normalTol = sagTol / cosA * sinA / radius + 1e-6;
            c.worstNormal = std::max(c.worstNormal, ang / normalTol);
            c.worstNormalRad = std::max(c.worstNormalRad, ang);
        }
    return c;
}

TEST_P(BakeBoth, CubeUnderASphereGivesTheExactIntersection) {
    const double radius = 0.7;
    const int rings = 256;
    BakeSettings s = settings();
    s.width = s.height = 256;
    s.maxDistance = 0.5;
    const BakeResult r = bake::bake(cubeCage(), sphereMesh(rings, radius), s);
    EXPECT_EQ(r.stats.misses, 0u);
    EXPECT_EQ(r.stats.overlapTexels, 0u);
    // Every texel centre inside one of the six UV squares is baked (a lone
    // face's chart is its square: its UV boundary is linear).
    size_t inSquares = 0;
    for (int f = 0; f < 6; ++f)
        for (int j = 0; j < 256; ++j)
            for (int i = 0; i < 256; ++i) {
                const double x = (i + 0.5) / 256 - (0.05 + 0.32 * (f % 3)),
                             y = (j + 0.5) / 256 - (0.05 + 0.5 * (f / 3));
                inSquares += x >= 0 && x <= 0.28 && y >= 0 && y <= 0.4 ? 1 : 0;
            }
    EXPECT_EQ(r.stats.hits, inSquares);
    // Sagitta of a chord spanning the widest cell: R (1 - cos(dphi / 2)),
    // dphi = pi / rings (the cells' diagonal is below sqrt(2) of that).
    const double dphi = std::sqrt(2.0) * kPi / rings;
    const double sag = radius * (1 - std::cos(dphi / 2));
    const SphereCheck c = checkSphere(r, radius, sag);
    EXPECT_LE(c.worstT, 1.0) << "displacement error beyond the sagitta bound (ratio)";
    EXPECT_LE(c.worstNormal, 1.0) << "normal error beyond its bound (ratio)";
    std::printf("cube->sphere: hits %zu, displacement error / bound %.3g (bound up to %.3g), "
                "normal %.3g rad, max uv residual %.3g texels\n",
                r.stats.hits, c.worstT, c.tolWorst, c.worstNormalRad, r.stats.maxUvResidualTexels);
    // Newton leaves a UV residual only where a texel's preimage lies on a
    // neighbouring patch: a few thousandths of a texel (the claim
    // tolerance and the grid's chords).
    EXPECT_LE(r.stats.maxUvResidualTexels, 0.05);
}

// Texels beside a seam: a chart's outermost texels lie half a texel from
// the chart's edge, whose limit curve the neighbouring chart shares. Each
// such texel's limit point has a point of another chart's outermost
// texels within about one texel of surface length.
TEST(BakeCube, TexelsOnBothSidesOfASeamMeetOnTheSurface) {
    BakeSettings s;
    s.width = s.height = 128;
    s.maxDistance = 0.5;
    s.padTexels = 0;
    const BakeResult r = bake::bake(cubeCage(), sphereMesh(128, 0.7), s);
    // Chart of a texel: which of the 3 x 2 atlas cells its centre is in.
    auto chart = [&](int i, int j) {
        return int(3.0 * (i + 0.5) / r.width) + 3 * int(2.0 * (j + 0.5) / r.height);
    };
    struct Edge {
        glm::vec3 p;
        int chart;
    };
    std::vector<Edge> edge;
    float texelLen = 0; // largest distance between neighbouring texels' points
    for (int j = 0; j < r.height; ++j)
        for (int i = 0; i < r.width; ++i) {
            if (!hit(r, i, j)) continue;
            bool border = false;
            for (auto [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                const int ni = i + di, nj = j + dj;
                if (ni < 0 || nj < 0 || ni >= r.width || nj >= r.height || !hit(r, ni, nj)) {
                    border = true;
                } else {
                    texelLen = std::max(
                        texelLen, glm::length(r.basePosition.at(i, j) - r.basePosition.at(ni, nj)));
                }
            }
            if (border) edge.push_back({r.basePosition.at(i, j), chart(i, j)});
        }
    ASSERT_GT(edge.size(), 100u);
    float worst = 0;
    for (const Edge& e : edge) {
        float best = INFINITY;
        for (const Edge& o : edge)
            if (o.chart != e.chart) best = std::min(best, glm::length(o.p - e.p));
        worst = std::max(worst, best);
    }
    // Half a texel from each side plus the texel spacing along the seam:
    // at most about 1.2 texel lengths apart.
    EXPECT_LE(worst, 1.2f * texelLen) << "texel length " << texelLen;
}

TEST(BakeThreads, SameBitsAtEveryThreadCount) {
    BakeSettings s;
    s.width = 96;
    s.height = 80;
    s.maxDistance = 0.5;
    s.residual = true;
    s.threads = 1;
    const mesh::RenderMesh high = sphereMesh(64, 0.7);
    const BakeResult one = bake::bake(cubeCage(), high, s);
    ASSERT_EQ(one.residualSlopes.v.size(), one.displacement.v.size());
    for (int threads : {2, 3, 7}) {
        s.threads = threads;
        const BakeResult r = bake::bake(cubeCage(), high, s);
        EXPECT_EQ(r.state.v, one.state.v) << threads;
        EXPECT_EQ(0, std::memcmp(r.displacement.v.data(), one.displacement.v.data(),
                                 one.displacement.v.size() * sizeof(float)))
            << threads;
        EXPECT_EQ(0, std::memcmp(r.tangentSlopes.v.data(), one.tangentSlopes.v.data(),
                                 one.tangentSlopes.v.size() * sizeof(glm::vec2)))
            << threads;
        EXPECT_EQ(0, std::memcmp(r.residualSlopes.v.data(), one.residualSlopes.v.data(),
                                 one.residualSlopes.v.size() * sizeof(glm::vec2)))
            << threads;
        EXPECT_EQ(0, std::memcmp(r.objectNormal.v.data(), one.objectNormal.v.data(),
                                 one.objectNormal.v.size() * sizeof(glm::vec3)))
            << threads;
    }
}

void expectInputError(const mesh::PolygonMesh& cage, const mesh::RenderMesh& high,
                      const BakeSettings& s, const std::string& file, const std::string& element) {
    try {
        bake::bake(cage, high, s, "cage.obj", "high.obj");
        ADD_FAILURE() << "expected an InputError about " << file << ": " << element;
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.file(), file) << e.what();
        EXPECT_EQ(e.element(), element) << e.what();
    }
}

TEST(BakeInput, BadInputIsRefusedNamingFileAndElement) {
    const mesh::RenderMesh high = sphereMesh(16, 0.7);
    BakeSettings s;
    s.width = s.height = 32;
    mesh::PolygonMesh noUv = cubeCage();
    noUv.uvSets.clear();
    expectInputError(noUv, high, s, "cage.obj", "uv set 0");
    BakeSettings set1 = s;
    set1.uvSet = 1;
    expectInputError(cubeCage(), high, set1, "cage.obj", "uv set 1");
    mesh::PolygonMesh loop = cubeCage();
    loop.options.scheme = mesh::Scheme::Bilinear;
    expectInputError(loop, high, s, "cage.obj", "scheme");
    BakeSettings big = s;
    big.width = bake::kMaxBakeSide + 1;
    expectInputError(cubeCage(), high, big, "cage.obj", "size");
    BakeSettings budget = s;
    budget.memoryBudget = 32 * 32 * bake::kBakeBytesPerTexel - 1;
    expectInputError(cubeCage(), high, budget, "cage.obj", "size");
    // The residual's grids count too: a budget that holds the bake without
    // them refuses the bake with them.
    BakeSettings residualBudget = s;
    residualBudget.residual = true;
    residualBudget.memoryBudget = 32 * 32 * bake::kBakeBytesPerTexel;
    expectInputError(cubeCage(), high, residualBudget, "cage.obj", "size");
    BakeSettings iso = s;
    iso.isolation = 11;
    expectInputError(cubeCage(), high, iso, "cage.obj", "isolation");
    BakeSettings dist = s;
    dist.maxDistance = std::nan("");
    expectInputError(cubeCage(), high, dist, "cage.obj", "max distance");
    mesh::RenderMesh nan = high;
    nan.positions[5].y = std::nanf("");
    expectInputError(cubeCage(), nan, s, "high.obj", "vertex 5");
    mesh::RenderMesh empty;
    expectInputError(cubeCage(), empty, s, "high.obj", "");
    // UVs entirely outside [0, 1]^2: nothing to bake.
    mesh::PolygonMesh away = cubeCage();
    for (glm::vec2& uv : away.uvSets[0].values) uv += glm::vec2(3.0f, 0.0f);
    expectInputError(away, high, s, "cage.obj", "uv set 0");
}

TEST(BakeInput, OverlappingChartsAreCountedOnce) {
    // Two faces of the cube on the same UV square.
    mesh::PolygonMesh cage = cubeCage();
    for (int c = 0; c < 4; ++c)
        cage.uvSets[0].values[size_t(4 + c)] = cage.uvSets[0].values[size_t(c)];
    BakeSettings s;
    s.width = s.height = 64;
    s.maxDistance = 0.5;
    const BakeResult r = bake::bake(cage, sphereMesh(32, 0.7), s);
    // Chart 0's texel centres: those in [0.05, 0.33] x [0.05, 0.45] of the
    // 64 x 64 map. Every one is on both faces.
    size_t chartTexels = 0;
    for (int j = 0; j < 64; ++j)
        for (int i = 0; i < 64; ++i) {
            const double x = (i + 0.5) / 64, y = (j + 0.5) / 64;
            chartTexels += x >= 0.05 && x <= 0.33 && y >= 0.05 && y <= 0.45 ? 1 : 0;
        }
    EXPECT_EQ(r.stats.overlapTexels, chartTexels);
}

// Stability: every position of the high mesh moved by -2..2 ulps moves
// each baked displacement by a rounding-size amount, and never turns a
// hit into a miss.
TEST(BakeHardCase, HighMeshMovedByUlpsMovesDisplacementByRounding) {
    const mesh::RenderMesh high = sphereMesh(64, 0.7);
    mesh::RenderMesh moved = high;
    uint32_t state = 12345u;
    for (glm::vec3& p : moved.positions)
        for (int k = 0; k < 3; ++k) {
            state = state * 1664525u + 1013904223u;
            const int ulps = int(state >> 29) % 5 - 2;
            for (int u = 0; u < std::abs(ulps); ++u)
                p[k] = std::nextafter(p[k], ulps > 0 ? INFINITY : -INFINITY);
        }
    BakeSettings s;
    s.width = s.height = 128;
    s.residual = true;
    s.maxDistance = 0.5;
    const BakeResult a = bake::bake(cubeCage(), high, s), b = bake::bake(cubeCage(), moved, s);
    EXPECT_EQ(a.state.v, b.state.v);
    double worst = 0;
    for (size_t k = 0; k < a.displacement.v.size(); ++k)
        if (a.state.v[k] == uint8_t(TexelState::Hit))
            worst = std::max(worst, double(std::abs(a.displacement.v[k] - b.displacement.v[k])));
    // Positions of order 1 moved by 2 ulps (2.4e-7) move the surface by as
    // much; the ray's hit distance follows, plus its own rounding: 8 ulps
    // of 1 (about 1e-6).
    const double bound = 8 * std::numeric_limits<float>::epsilon();
    hardCasePerturbedAtMost("generated", "bake: sphere high mesh (24k triangles) onto a cube cage",
                            "every high-mesh coordinate moved by -2..2 ulps",
                            "displacement change (object units)", worst, bound);

    // The residual after displacement differentiates the displacement over
    // the texel grid: a height change of at most `bound` moves a central
    // difference by bound / L (L the shortest texel length on the surface,
    // from the base points: the difference spans two texels), and the high
    // normal's own change (its rounding, ~1e-6) moves the slopes by about
    // as much; 2x for the two terms' worst alignment.
    double texelLength = INFINITY, worstResidual = 0;
    for (int j = 0; j < a.height; ++j)
        for (int i = 0; i + 1 < a.width; ++i) {
            if (a.state.at(i, j) != uint8_t(TexelState::Hit)) continue;
            const glm::vec2 d = a.residualSlopes.at(i, j) - b.residualSlopes.at(i, j);
            worstResidual = std::max({worstResidual, double(std::abs(d.x)), double(std::abs(d.y))});
            if (a.state.at(i + 1, j) == uint8_t(TexelState::Hit))
                texelLength = std::min(texelLength, double(glm::length(a.basePosition.at(i + 1, j) -
                                                                       a.basePosition.at(i, j))));
        }
    const double residualBound = 2.0 * (bound / texelLength + bound);
    hardCasePerturbedAtMost("generated", "bake: sphere high mesh onto a cube cage, residual map",
                            "every high-mesh coordinate moved by -2..2 ulps",
                            "residual slope change", worstResidual, residualBound);
}

} // namespace
} // namespace sg::test
