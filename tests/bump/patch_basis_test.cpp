// The shared patch basis (shaders/sg/patch/basis.glsl, compiled as C++)
// against OpenSubdiv's own Far::PatchTable::EvaluateBasis on every patch of
// every Catmull-Clark osd-shape, the adaptive patch arrays of
// sg::mesh::buildAdaptivePatches against Far's table and against the limit
// positions of the existing limit evaluation (Subdivider with limit), and
// the shared screen-space tessellation level (shaders/sg/patch/
// tess_level.glsl): symmetric bit for bit, bounded, finite in the hard
// cases (behind the camera, zero length, edge-on, huge and tiny on screen).
#include <gtest/gtest.h>

#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "hardcase.h"
#include "patch_eval_util.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

namespace g = sg::glsl;
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using sg::mesh::PolygonMesh;

std::filesystem::path dataPath(const std::string& rel) {
    return sg::test::patchDataPath(rel);
}

// Far's table for the same cage and options buildAdaptivePatches uses (the
// test builds its own to call EvaluateBasis; the arrays must come out in
// the same order).
std::unique_ptr<Far::PatchTable> farTable(const PolygonMesh& cage, int isolation,
                                          std::unique_ptr<Far::TopologyRefiner>& refiner) {
    std::vector<int> creasePairs, corners;
    std::vector<float> creaseW, cornerW;
    for (const auto& c : cage.creases) {
        creasePairs.push_back(int(c.v0));
        creasePairs.push_back(int(c.v1));
        creaseW.push_back(c.sharpness);
    }
    for (const auto& c : cage.corners) {
        corners.push_back(int(c.vertex));
        cornerW.push_back(c.sharpness);
    }
    std::vector<int> holes(cage.holes.begin(), cage.holes.end());
    Far::TopologyDescriptor d;
    d.numVertices = int(cage.positions.size());
    d.numFaces = int(cage.faceSizes.size());
    d.numVertsPerFace = reinterpret_cast<const int*>(cage.faceSizes.data());
    d.vertIndicesPerFace = reinterpret_cast<const Far::Index*>(cage.faceVertices.data());
    d.numCreases = int(creaseW.size());
    d.creaseVertexIndexPairs = creasePairs.data();
    d.creaseWeights = creaseW.data();
    d.numCorners = int(cornerW.size());
    d.cornerVertexIndices = corners.data();
    d.cornerWeights = cornerW.data();
    d.numHoles = int(holes.size());
    d.holeIndices = holes.data();
    Sdc::Options o;
    static constexpr Sdc::Options::VtxBoundaryInterpolation kVtx[3] = {
        Sdc::Options::VTX_BOUNDARY_NONE, Sdc::Options::VTX_BOUNDARY_EDGE_ONLY,
        Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER};
    o.SetVtxBoundaryInterpolation(kVtx[int(cage.options.boundary)]);
    o.SetCreasingMethod(cage.options.creaseMethod == sg::mesh::CreaseMethod::Chaikin
                            ? Sdc::Options::CREASE_CHAIKIN
                            : Sdc::Options::CREASE_UNIFORM);
    o.SetTriangleSubdivision(cage.options.triangles == sg::mesh::TriangleRule::Smooth
                                 ? Sdc::Options::TRI_SUB_SMOOTH
                                 : Sdc::Options::TRI_SUB_CATMARK);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    refiner.reset(Factory::Create(d, Factory::Options(Sdc::SCHEME_CATMARK, o)));
    Far::PatchTableFactory::Options popt(static_cast<unsigned>(isolation));
    popt.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    popt.useInfSharpPatch = true;
    popt.generateLegacySharpCornerPatches = false;
    refiner->RefineAdaptive(popt.GetRefineAdaptiveOptions());
    return std::unique_ptr<Far::PatchTable>(Far::PatchTableFactory::Create(*refiner, popt));
}

// The Catmull-Clark osd-shapes the mesh module accepts (the others are
// listed with their reasons in tests/mesh/osd_shapes_expected.inc).
std::vector<std::pair<std::string, PolygonMesh>> catmarkShapes() {
    std::vector<std::pair<std::string, PolygonMesh>> out;
    for (const auto& e : std::filesystem::directory_iterator(dataPath("osd-shapes"))) {
        const std::string name = e.path().stem().string();
        if (e.path().extension() != ".obj" || name.rfind("loop_", 0) == 0 ||
            name.rfind("bilinear_", 0) == 0)
            continue;
        try {
            PolygonMesh cage = sg::mesh::loadPolygonMesh(e.path());
            if (cage.options.scheme != sg::mesh::Scheme::Catmark) continue;
            out.emplace_back(name, std::move(cage));
        } catch (const sg::io::InputError&) {
        }
    }
    std::sort(out.begin(), out.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    return out;
}

// Patch-local sample points: corners, edge midpoints, interior.
constexpr float kSamples[][2] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f},
                                 {0.5f, 0.0f}, {0.3f, 0.7f}, {0.5f, 0.5f}, {0.9f, 0.15f}};

TEST(PatchBasis, MatchesFarEvaluateBasisOnEveryCatmarkShape) {
    const auto shapes = catmarkShapes();
    ASSERT_GE(shapes.size(), 35u); // the accepted Catmark shapes of data/osd-shapes
    size_t patchesSeen = 0, gregorySeen = 0, boundarySeen = 0;
    for (const auto& [name, cage] : shapes) {
        SCOPED_TRACE(name);
        const int isolation = 3;
        // Without UV sets: face-varying channels make Far isolate UV seams
        // too (more patches; tests/bump/patch_uv_test.cpp), and farTable
        // builds no channels.
        PolygonMesh noUv = cage;
        noUv.uvSets.clear();
        sg::mesh::AdaptivePatches ours =
            sg::mesh::buildAdaptivePatches(noUv, noUv.options, isolation, name);
        std::unique_ptr<Far::TopologyRefiner> refiner;
        std::unique_ptr<Far::PatchTable> far = farTable(cage, isolation, refiner);
        ASSERT_TRUE(far);
        ASSERT_EQ(ours.patchCount(), size_t(far->GetNumPatchesTotal()));
        ASSERT_EQ(ours.points.size(),
                  size_t(refiner->GetNumVerticesTotal() + far->GetNumLocalPoints()));
        size_t arrayOut = 0;
        for (int a = 0; a < far->GetNumPatchArrays(); ++a) {
            if (far->GetNumPatches(a) == 0) continue;
            const sg::mesh::AdaptivePatchArray& arr = ours.arrays[arrayOut++];
            ASSERT_EQ(arr.type, int(far->GetPatchArrayDescriptor(a).GetType()));
            ASSERT_TRUE(arr.type == SG_PATCH_REGULAR || arr.type == SG_PATCH_GREGORY_BASIS)
                << arr.type;
            for (uint32_t p = 0; p < arr.patchCount; ++p) {
                const glm::uvec2 param = ours.params[arr.firstPatch + p];
                Far::PatchTable::PatchHandle h;
                h.arrayIndex = a;
                h.patchIndex = int(arr.firstPatch + p);
                h.vertIndex = int(arr.firstIndex + p * uint32_t(arr.pointsPerPatch));
                const Far::PatchParam& fp = far->GetPatchParam(h);
                ASSERT_EQ(param.x, fp.field0);
                ASSERT_EQ(param.y, fp.field1);
                // The corner vertices found by descending the refinement are
                // a regular patch's own middle points.
                if (arr.type == SG_PATCH_REGULAR) {
                    const uint32_t* cv = &ours.indices[arr.firstIndex + p * 16u];
                    EXPECT_EQ(ours.cornerVertices[arr.firstPatch + p],
                              glm::uvec4(cv[5], cv[6], cv[10], cv[9]))
                        << "patch " << arr.firstPatch + p;
                }
                boundarySeen += fp.GetBoundary() != 0;
                const float depthScale = float(1 << fp.GetDepth());
                for (const auto& s : kSamples) {
                    float u = s[0], v = s[1];
                    fp.Unnormalize(u, v);
                    float w[20], wu[20], wv[20];
                    far->EvaluateBasis(h, u, v, w, wu, wv);
                    const g::SgPatchBasis b = g::sgPatchBasis(arr.type, param.y, g::vec2(u, v));
                    ASSERT_EQ(b.count, arr.pointsPerPatch);
                    for (int i = 0; i < b.count; ++i) {
                        // Weights are within [-1, 1] (derivatives within
                        // [-3, 3] times 2^depth); the two codes group the
                        // same products differently and Gregory's rational
                        // factors divide once vs multiply by a reciprocal:
                        // a few ulp of the largest term.
                        EXPECT_NEAR(b.pos.v[i], w[i], 2e-6f) << "point weight " << i;
                        EXPECT_NEAR(b.du.v[i], wu[i], 8e-6f * depthScale) << "du weight " << i;
                        EXPECT_NEAR(b.dv.v[i], wv[i], 8e-6f * depthScale) << "dv weight " << i;
                    }
                }
                ++patchesSeen;
                gregorySeen += arr.type == SG_PATCH_GREGORY_BASIS;
            }
        }
    }
    // Both patch kinds and boundary masks were exercised.
    // (14158, 1355 and 1282 at isolation 3 on the shapes of data/.)
    EXPECT_GE(patchesSeen, 14000u);
    EXPECT_GE(gregorySeen, 1300u);
    EXPECT_GE(boundarySeen, 1200u);
}

// Position on a patch from the exported arrays with the shared basis
// (`p` within the array), and optionally its u derivative.
glm::vec3 evalPatch(const sg::mesh::AdaptivePatches& ap, const sg::mesh::AdaptivePatchArray& arr,
                    uint32_t p, glm::vec2 patchUv, glm::vec3* du = nullptr) {
    const sg::test::PatchSample s = sg::test::evalPatchSample(ap, arr, arr.firstPatch + p, patchUv);
    if (du) *du = s.du;
    return s.pos;
}

TEST(PatchBasis, PatchCornersAreTheLimitPointsOfTheExistingLimitEvaluation) {
    // Shapes without semi-sharp features deeper than the isolation (whose
    // unisolated corners are approximations, not limit points: catmark_helmet,
    // sharpness 7, is 3.5e-3 of its size off at isolation 3) and without an
    // infinitely sharp crease ending in an extraordinary vertex
    // (catmark_inf_crease0: Far's Gregory end cap there is 3.8e-4 off).
    for (const char* name :
         {"catmark_cube", "catmark_torus", "catmark_pyramid", "catmark_pole8", "catmark_hole_test1",
          "catmark_xord_interior", "catmark_xord_boundary", "catmark_nonquads",
          "catmark_gregory_test1", "catmark_edgeonly", "catmark_tent"}) {
        SCOPED_TRACE(name);
        const auto path = dataPath(std::string("osd-shapes/") + name + ".obj");
        ASSERT_TRUE(std::filesystem::exists(path));
        PolygonMesh cage = sg::mesh::loadPolygonMesh(path);
        const int isolation = 3;
        sg::mesh::AdaptivePatches ap =
            sg::mesh::buildAdaptivePatches(cage, cage.options, isolation, name);
        sg::mesh::SubdivisionSettings s;
        s.options = cage.options;
        s.level = isolation;
        s.limit = true;
        s.buildRenderMesh = false;
        sg::mesh::Subdivider sub(cage, s, name);
        const std::vector<glm::vec3>& limit = sub.refined().positions;
        const sg::test::PointsByX byX(limit);
        const float extent = sg::test::maxAbsCoordinate(cage.positions);
        // Both are OpenSubdiv's limit in binary32, through different
        // stencil factorisations and isolation depths (5 in the limit
        // evaluation): a few ulp of the coordinates' magnitude, times the
        // sum of |weights| of a Gregory corner (~10).
        const float tol = 2e-5f * extent;
        size_t checked = 0;
        for (const auto& arr : ap.arrays) {
            for (uint32_t p = 0; p < arr.patchCount; ++p) {
                for (glm::vec2 c :
                     {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
                    const glm::vec3 q = evalPatch(ap, arr, p, c);
                    float best = INFINITY;
                    byX.forEachNear(q, tol, [&](uint32_t v) {
                        best = std::min(best, glm::length(limit[v] - q));
                    });
                    EXPECT_LE(best, tol) << "patch " << arr.firstPatch + p << " corner (" << c.x
                                         << "," << c.y << ")";
                    ++checked;
                }
            }
        }
        EXPECT_GT(checked, 0u);
    }
}

TEST(PatchBasis, AnimatedPointsFollowTheCageThroughTheStencils) {
    PolygonMesh cage = sg::mesh::loadPolygonMesh(dataPath("osd-shapes/catmark_torus.obj"));
    sg::mesh::AdaptivePatches ap = sg::mesh::buildAdaptivePatches(cage, cage.options, 3);
    // A rigid motion of the cage moves every control point with it (the
    // rows of the stencil matrix sum to 1 and are linear).
    std::vector<glm::vec3> moved = cage.positions;
    const glm::vec3 shift(0.5f, -2.0f, 3.0f);
    for (glm::vec3& p : moved) p = glm::vec3(-p.y, p.x, p.z) + shift;
    const std::vector<glm::vec3> before = ap.points;
    sg::mesh::updateAdaptivePoints(ap, moved);
    for (size_t i = 0; i < before.size(); ++i) {
        const glm::vec3 want = glm::vec3(-before[i].y, before[i].x, before[i].z) + shift;
        // Rows of up to ~100 weights applied to unit-size coordinates.
        EXPECT_LE(glm::length(ap.points[i] - want), 1e-5f) << i;
    }
}

// A non-rigid motion: every cage vertex moves by a few percent of the
// cage's size along a wave (all control points move differently).
std::vector<glm::vec3> waveCage(const std::vector<glm::vec3>& cage, float extent, float t) {
    std::vector<glm::vec3> out = cage;
    for (size_t k = 0; k < out.size(); ++k) {
        const glm::vec3 p = out[k];
        out[k] += 0.04f * extent *
                  glm::vec3(std::sin(3.1f * p.y / extent + t), std::cos(2.3f * p.z / extent - t),
                            std::sin(0.7f * float(k) + t));
    }
    return out;
}

// Far's table of the same points factorised down to the cage (what the
// stencil rows were before they were applied level by level): the
// refined vertices' stencils with factorizeIntermediateLevels = true and
// the local points' appended.
std::unique_ptr<const Far::StencilTableReal<float>> farFactorised(const Far::TopologyRefiner& r,
                                                                  const Far::PatchTable& t) {
    Far::StencilTableFactoryReal<float>::Options o;
    o.generateIntermediateLevels = true;
    o.factorizeIntermediateLevels = true;
    o.generateControlVerts = true;
    o.generateOffsets = true;
    std::unique_ptr<const Far::StencilTableReal<float>> base(
        Far::StencilTableFactoryReal<float>::Create(r, o));
    if (const Far::StencilTableReal<float>* local = t.GetLocalPointStencilTable<float>())
        return std::unique_ptr<const Far::StencilTableReal<float>>(
            Far::StencilTableFactoryReal<float>::AppendLocalPointStencilTable(r, base.get(), local,
                                                                              true));
    return base;
}

// The stencil passes (AdaptivePatches' declaration): every row reads only
// points of earlier passes; updateAdaptivePoints of a moved cage equals a
// fresh buildAdaptivePatches of that cage bit for bit (the rows depend on
// the topology only and are summed in the same order) and Far's table
// factorised down to the cage within a bound (below); the rows hold far
// fewer entries than the factorised table on the deep cages. Spot (valence
// 3..6: Gregory end caps), bob (a triangle cage: an extraordinary vertex at
// every face centre) and every Catmull-Clark osd-shape (creases, corners,
// boundaries, holes, non-manifold vertices, Gregory patches).
TEST(PatchBasis, StencilPassesMatchFarsFactorisedTable) {
    auto shapes = catmarkShapes();
    shapes.emplace_back("spot",
                        sg::mesh::loadPolygonMesh(dataPath("meshes/spot/spot_control_mesh.obj")));
    shapes.emplace_back("bob", sg::mesh::loadPolygonMesh(dataPath("meshes/bob/bob_tri.obj")));
    size_t gregorySeen = 0, holesSeen = 0, creasesSeen = 0;
    double worstRel = 0.0;
    for (auto& [name, withUv] : shapes) {
        SCOPED_TRACE(name);
        const int isolation = name == "bob" ? 2 : 3;
        // Without UV sets: farTable builds no face-varying channels (which
        // would isolate UV seams too: another refinement).
        PolygonMesh cage = withUv;
        cage.uvSets.clear();
        sg::mesh::AdaptivePatches ap =
            sg::mesh::buildAdaptivePatches(cage, cage.options, isolation, name);
        for (const auto& arr : ap.arrays) gregorySeen += arr.type == 9 ? arr.patchCount : 0;
        holesSeen += !cage.holes.empty();
        creasesSeen += !cage.creases.empty();
        // Layout: passes cover the points past the cage, rows read earlier passes.
        ASSERT_FALSE(ap.stencilPasses.empty()); // a regular cage may need no pass
        EXPECT_EQ(ap.stencilPasses.front(), ap.cagePointCount);
        ASSERT_EQ(ap.stencilPasses.back(), ap.points.size());
        ASSERT_EQ(ap.stencilOffsets.size(), ap.points.size() - ap.cagePointCount + 1);
        size_t readsOwnPass = 0;
        for (size_t p = 0; p + 1 < ap.stencilPasses.size(); ++p) {
            EXPECT_LT(ap.stencilPasses[p], ap.stencilPasses[p + 1]);
            for (uint32_t i = ap.stencilPasses[p]; i < ap.stencilPasses[p + 1]; ++i) {
                const uint32_t r = i - ap.cagePointCount;
                for (uint32_t k = ap.stencilOffsets[r]; k < ap.stencilOffsets[r + 1]; ++k)
                    readsOwnPass += ap.stencilIndices[k] >= ap.stencilPasses[p];
            }
        }
        EXPECT_EQ(readsOwnPass, 0u);

        const float extent = sg::test::maxAbsCoordinate(cage.positions);
        PolygonMesh moved = cage;
        moved.positions = waveCage(cage.positions, extent, 0.8f);
        sg::mesh::updateAdaptivePoints(ap, moved.positions);
        const sg::mesh::AdaptivePatches fresh =
            sg::mesh::buildAdaptivePatches(moved, moved.options, isolation, name);
        ASSERT_EQ(fresh.points.size(), ap.points.size());
        size_t differ = 0;
        for (size_t i = 0; i < ap.points.size(); ++i)
            differ += std::memcmp(&ap.points[i], &fresh.points[i], sizeof(glm::vec3)) != 0;
        EXPECT_EQ(differ, 0u);

        std::unique_ptr<Far::TopologyRefiner> refiner;
        std::unique_ptr<Far::PatchTable> table = farTable(cage, isolation, refiner);
        ASSERT_TRUE(table);
        const auto st = farFactorised(*refiner, *table);
        ASSERT_EQ(size_t(st->GetNumStencils()), ap.points.size());
        // Far's factorised rows applied in double: the points in exact-ish
        // arithmetic, against which the passes' float points are bounded.
        float maxErr = 0.0f, maxFarErr = 0.0f;
        for (int i = 0; i < st->GetNumStencils(); ++i) {
            const auto row = st->GetStencil(Far::Index(i));
            glm::dvec3 want(0.0), farFloat(0.0);
            for (int k = 0; k < row.GetSize(); ++k) {
                want += double(row.GetWeights()[k]) *
                        glm::dvec3(moved.positions[size_t(row.GetVertexIndices()[k])]);
                farFloat += glm::dvec3(row.GetWeights()[k] *
                                       moved.positions[size_t(row.GetVertexIndices()[k])]);
            }
            maxErr = std::max(
                maxErr, float(g::sgMaxAbs3(glm::vec3(glm::dvec3(ap.points[size_t(i)]) - want))));
            maxFarErr = std::max(
                maxFarErr, float(g::sgMaxAbs3(glm::vec3(glm::dvec3(glm::vec3(farFloat)) - want))));
        }
        worstRel = std::max(worstRel, double(maxErr) / double(extent));
        // The passes round at every level (binary32: 2^-24 relative per
        // product and add, on coordinates up to 1.04 extent) and the end
        // caps' rows (sum of |weights| up to a few tens) once more, where
        // the factorised rows round once per row: measured at most
        // 1.3e-6 extent (catmark_smoothtris0; spot 2.5e-7, bob 3.7e-7)
        // against 1e-7 for the factorised rows in float; 4e-6 leaves 3x.
        EXPECT_LE(maxErr, 4e-6f * extent) << "Far factorised in float: " << maxFarErr;

        const size_t passEntries = ap.stencilIndices.size();
        const size_t farEntries = st->GetControlIndices().size();
        std::printf("%-28s isolation %d: %zu points, %zu passes, rows %zu entries (%.2f MiB) vs "
                    "factorised %zu (%.2f MiB), max |error| %.2e extent (factorised in float "
                    "%.2e)\n",
                    name.c_str(), isolation, ap.points.size(), ap.stencilPasses.size() - 1,
                    passEntries, double(ap.stencilBytes()) / 1048576.0, farEntries,
                    double(farEntries * 8 + (ap.points.size() + 1) * 4) / 1048576.0,
                    double(maxErr / extent), double(maxFarErr / extent));
        // Proportional to the points: a few weights per row (Catmull-Clark
        // face, edge and vertex rules with the face points folded in:
        // 4..2n+1 entries; Gregory points: the patch's one-ring): measured
        // at most 7.3 per row on average (bob; spot 6.6), where factorised
        // rows grow with the depth.
        const size_t rows = ap.points.size() - ap.cagePointCount;
        EXPECT_LE(passEntries, 10 * rows);
        if (name == "spot" || name == "bob") {
            EXPECT_LT(passEntries, farEntries);
        }
    }
    EXPECT_GT(gregorySeen, 0u);
    EXPECT_GT(holesSeen, 0u);
    EXPECT_GT(creasesSeen, 0u);
    std::printf("worst |error| %.2e extent\n", worstRel);
}

TEST(PatchBasis, AdaptiveRefusesLoopAndBadIsolation) {
    PolygonMesh cage = sg::mesh::loadPolygonMesh(dataPath("osd-shapes/catmark_cube.obj"));
    sg::mesh::SubdivOptions loop = cage.options;
    loop.scheme = sg::mesh::Scheme::Loop;
    try {
        sg::mesh::buildAdaptivePatches(cage, loop, 3, "cube.obj");
        FAIL() << "Loop accepted";
    } catch (const sg::io::InputError& e) {
        EXPECT_EQ(e.element(), "scheme");
        EXPECT_NE(e.reason().find("uniform"), std::string::npos) << e.what();
    }
    for (int iso : {0, 11}) {
        try {
            sg::mesh::buildAdaptivePatches(cage, cage.options, iso, "cube.obj");
            FAIL() << "isolation " << iso << " accepted";
        } catch (const sg::io::InputError& e) {
            EXPECT_EQ(e.element(), "isolation");
        }
    }
}

// ---- Tessellation levels -------------------------------------------------------

TEST(PatchTessLevel, SymmetricBitForBit) {
    // The two patches of an edge pass its end points in either order.
    uint32_t state = 12345u;
    auto rnd = [&] {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24) * 20.0f - 10.0f;
    };
    for (int i = 0; i < 10000; ++i) {
        const g::vec3 a(rnd(), rnd(), rnd()), b(rnd(), rnd(), rnd());
        const float lab = g::sgPatchEdgeTessLevel(a, b, 800.0f, 3.0f, 64.0f);
        const float lba = g::sgPatchEdgeTessLevel(b, a, 800.0f, 3.0f, 64.0f);
        ASSERT_EQ(lab, lba) << i;
        ASSERT_EQ(lab, std::floor(lab)); // an integer level (equal_spacing)
        ASSERT_GE(lab, 1.0f);
        ASSERT_LE(lab, 64.0f);
    }
}

TEST(PatchTessLevel, FollowsTheScreenLength) {
    // A 1-unit edge 10 units away, focal 1000 px: 100 px; 4 px per edge.
    const float l = g::sgPatchEdgeTessLevel(g::vec3(-0.5f, 0, -10), g::vec3(0.5f, 0, -10), 1000.0f,
                                            4.0f, 64.0f);
    // The midpoint distance is 10, the chord 1: ceil(1 * 1000 / 10 / 4).
    EXPECT_EQ(l, 25.0f);
    // Twice as far: half as many.
    EXPECT_EQ(g::sgPatchEdgeTessLevel(g::vec3(-0.5f, 0, -20), g::vec3(0.5f, 0, -20), 1000.0f, 4.0f,
                                      64.0f),
              13.0f);
    // Very small on screen: 1; very large: the cap.
    EXPECT_EQ(g::sgPatchEdgeTessLevel(g::vec3(0, 0, -1e6f), g::vec3(1e-3f, 0, -1e6f), 1000.0f, 4.0f,
                                      64.0f),
              1.0f);
    EXPECT_EQ(
        g::sgPatchEdgeTessLevel(g::vec3(-100, 0, -1), g::vec3(100, 0, -1), 1000.0f, 4.0f, 64.0f),
        64.0f);
    EXPECT_EQ(g::sgPatchFocalPx(1.0f, 600.0f), 300.0f); // 90 degrees vertical field of view
}

TEST(PatchTessLevel, HardCasesStayBounded) {
    const float big = 1e30f, nan = std::nanf(""), inf = INFINITY;
    struct Case {
        const char* what;
        g::vec3 a, b;
        float expected; // < 0: anything within [1, max]
    };
    const Case cases[] = {
        {"zero length", g::vec3(1, 2, -3), g::vec3(1, 2, -3), 1.0f},
        {"zero length at the camera", g::vec3(0), g::vec3(0), 1.0f},
        {"through the camera", g::vec3(-1, 0, 0), g::vec3(1, 0, 0), 64.0f},
        {"behind the camera", g::vec3(-1, 0, 5), g::vec3(1, 0, 5), -1.0f},
        {"edge-on (along the view ray)", g::vec3(0, 0, -5), g::vec3(0, 0, -6), -1.0f},
        {"huge coordinates", g::vec3(-big, 0, -big), g::vec3(big, 0, -big), -1.0f},
        {"NaN", g::vec3(nan, 0, -1), g::vec3(1, 0, -1), 1.0f},
        {"infinity", g::vec3(inf, 0, -1), g::vec3(1, 0, -1), 1.0f},
    };
    int outside = 0;
    for (const Case& c : cases) {
        SCOPED_TRACE(c.what);
        const float l = g::sgPatchEdgeTessLevel(c.a, c.b, 1000.0f, 4.0f, 64.0f);
        EXPECT_TRUE(std::isfinite(l));
        EXPECT_GE(l, 1.0f);
        EXPECT_LE(l, 64.0f);
        outside += !(l >= 1.0f && l <= 64.0f);
        if (c.expected > 0.0f) {
            EXPECT_EQ(l, c.expected);
        }
    }
    sg::test::hardCaseAtMost("grazing",
                             "patch edge tessellation level: zero length, through, behind and "
                             "along the view ray, 1e30 coordinates, NaN, infinity",
                             "levels not finite or outside [1, 64] (of 8 edges)", outside, 0.0);
}

} // namespace

namespace {

// ---- Evaluation sites of shared edges and corners ---------------------------

TEST(PatchWatertight, EdgeAndCornerPointsGoToTheirOwner) {
    // Patch 5: its edge v = 0 (1) is owned by patch 2's edge v = 1 (3),
    // run the other way; its corner (1,1) by patch 3's corner (0,0).
    const glm::uvec4 edges((5u << 3) | (0u << 1), (2u << 3) | (3u << 1) | 1u, (5u << 3) | (2u << 1),
                           (5u << 3) | (3u << 1));
    const glm::uvec4 corners((5u << 2) | 0u, (5u << 2) | 1u, (3u << 2) | 0u, (5u << 2) | 3u);
    const g::vec4 outer(3.0f, 4.0f, 5.0f, 6.0f);
    const g::SgPatchTransitions none = g::sgPatchNoTransitions();
    // An edge point a tessellator put slightly off 1/4 (fixed point).
    g::SgPatchSite s = g::sgPatchEvalSite(5u, edges, corners, none, outer, g::vec2(0.25002f, 0.0f));
    EXPECT_EQ(s.patchIndex, 2u);
    EXPECT_EQ(s.uv, g::vec2(3.0f / 4.0f, 1.0f)); // i = 1 of 4, flipped: 3/4, exactly
    s = g::sgPatchEvalSite(5u, edges, corners, none, outer, g::vec2(1.0f, 1.0f));
    EXPECT_EQ(s.patchIndex, 3u);
    EXPECT_EQ(s.uv, g::vec2(0.0f, 0.0f));
    // Own edge u = 1, level 5: snapped to 2/5 on the patch itself.
    s = g::sgPatchEvalSite(5u, edges, corners, none, outer, g::vec2(1.0f, 0.39998f));
    EXPECT_EQ(s.patchIndex, 5u);
    EXPECT_EQ(s.uv, g::vec2(1.0f, 2.0f / 5.0f));
    // Interior points stay where they are.
    s = g::sgPatchEvalSite(5u, edges, corners, none, outer, g::vec2(0.3f, 0.7f));
    EXPECT_EQ(s.patchIndex, 5u);
    EXPECT_EQ(s.uv, g::vec2(0.3f, 0.7f));
}

TEST(PatchWatertight, TransitionEdgePointsGoToTheFineHalves) {
    // Patch 7's edge v = 1 (3) is a transition edge: its lower half (from
    // (0,1)) is patch 9's edge u = 0 (0), run the other way, level 3; its
    // upper half patch 12's edge v = 0 (1), level 2; the midpoint patch
    // 12's corner (0,0). Coarse level 3 + 2.
    const glm::uvec4 edges((7u << 3) | (0u << 1), (7u << 3) | (1u << 1), (7u << 3) | (2u << 1),
                           (7u << 3) | (3u << 1));
    const glm::uvec4 corners((7u << 2) | 0u, (7u << 2) | 1u, (7u << 2) | 2u, (7u << 2) | 3u);
    g::SgPatchTransitions tr = g::sgPatchNoTransitions();
    tr.lo[3] = (9u << 3) | (0u << 1) | 1u;
    tr.hi[3] = (12u << 3) | (1u << 1);
    tr.mid[3] = (12u << 2) | 0u;
    tr.loLevel[3] = 3.0f;
    const g::vec4 outer(2.0f, 2.0f, 2.0f, 5.0f);
    // i = 1 of 5 (off by the tessellator's fixed point): point 1 of the
    // lower half's 3, flipped on patch 9: 2/3 along its u = 0 edge.
    g::SgPatchSite s = g::sgPatchEvalSite(7u, edges, corners, tr, outer, g::vec2(0.19998f, 1.0f));
    EXPECT_EQ(s.patchIndex, 9u);
    EXPECT_EQ(s.uv, g::vec2(0.0f, 2.0f / 3.0f));
    // i = 3: the midpoint, at its corner owner.
    s = g::sgPatchEvalSite(7u, edges, corners, tr, outer, g::vec2(0.6f, 1.0f));
    EXPECT_EQ(s.patchIndex, 12u);
    EXPECT_EQ(s.uv, g::vec2(0.0f, 0.0f));
    // i = 4: point 1 of the upper half's 2 on patch 12's v = 0 edge.
    s = g::sgPatchEvalSite(7u, edges, corners, tr, outer, g::vec2(0.80001f, 1.0f));
    EXPECT_EQ(s.patchIndex, 12u);
    EXPECT_EQ(s.uv, g::vec2(0.5f, 0.0f));
    // The other edges are unchanged (level 2 on the patch itself).
    s = g::sgPatchEvalSite(7u, edges, corners, tr, outer, g::vec2(0.5f, 0.0f));
    EXPECT_EQ(s.patchIndex, 7u);
    EXPECT_EQ(s.uv, g::vec2(0.5f, 0.0f));
    // The halves' cap: their sum stays within the maximum.
    EXPECT_EQ(g::sgPatchHalfMaxLevel(64.0f), 32.0f);
    EXPECT_EQ(g::sgPatchHalfMaxLevel(5.0f), 2.0f);
    EXPECT_EQ(g::sgPatchHalfMaxLevel(1.0f), 1.0f);
}

TEST(PatchWatertight, OwnersAreConsistentOnEveryCatmarkShape) {
    // Every shared edge and corner has one owner, seen the same way from
    // each patch that has it (the owner's own entry points to itself).
    for (const auto& [name, cage] : catmarkShapes()) {
        SCOPED_TRACE(name);
        const sg::mesh::AdaptivePatches ap =
            sg::mesh::buildAdaptivePatches(cage, cage.options, 3, name);
        ASSERT_EQ(ap.edgeOwners.size(), ap.patchCount());
        static constexpr int kFrom[4] = {0, 0, 1, 3}, kTo[4] = {3, 1, 2, 2};
        for (uint32_t p = 0; p < ap.patchCount(); ++p) {
            for (int k = 0; k < 4; ++k) {
                const uint32_t e = ap.edgeOwners[p][k], owner = e >> 3, oe = (e >> 1) & 3u;
                ASSERT_LE(owner, p);
                EXPECT_EQ(ap.edgeOwners[owner][int(oe)] >> 1, (owner << 2) | oe);
                const glm::uvec4 c = ap.cornerVertices[p], oc = ap.cornerVertices[owner];
                const bool flip = (e & 1u) != 0u;
                EXPECT_EQ(c[kFrom[k]], flip ? oc[kTo[oe]] : oc[kFrom[oe]]);
                EXPECT_EQ(c[kTo[k]], flip ? oc[kFrom[oe]] : oc[kTo[oe]]);
                // Corner owners are keyed by the refined vertex's root (a
                // vertex and its child vertices): the same vertex at the
                // same depth, or the same limit point at another depth.
                const uint32_t co = ap.cornerOwners[p][k], cp = co >> 2;
                ASSERT_EQ(ap.cornerOwners[cp][int(co & 3u)], co);
                if (g::sgPatchDepth(ap.params[cp].y) == g::sgPatchDepth(ap.params[p].y)) {
                    EXPECT_EQ(ap.cornerVertices[cp][int(co & 3u)], c[k]);
                }
            }
        }
    }
}

// The domain corner (0,0), (1,0), (1,1), (0,1) of corner k.
glm::vec2 cornerUv(int k) {
    return glm::vec2(k == 1 || k == 2 ? 1.0f : 0.0f, k >= 2 ? 1.0f : 0.0f);
}

const sg::mesh::AdaptivePatchArray& arrayOfPatch(const sg::mesh::AdaptivePatches& ap, uint32_t p) {
    for (const auto& a : ap.arrays)
        if (p >= a.firstPatch && p < a.firstPatch + a.patchCount) return a;
    throw std::runtime_error("patch out of range");
}

glm::vec3 evalAt(const sg::mesh::AdaptivePatches& ap, uint32_t p, glm::vec2 uv) {
    const auto& arr = arrayOfPatch(ap, p);
    glm::vec3 du;
    return evalPatch(ap, arr, p - arr.firstPatch, uv, &du);
}

TEST(PatchWatertight, TransitionEdgesFindBothHalvesOnEveryCatmarkShapeAndSpot) {
    // Every edge Far marks as a transition (PatchParam transition mask, bit
    // order from the first corner: v = 0, u = 1, v = 1, u = 0) finds its
    // two halves among the patches one level deeper: each half's owner
    // edge runs (as the flip says) from a vertex with the coarse corner's
    // limit point to the midpoint, whose corner owner is the halves'
    // shared corner; and no edge without the bit is taken as a transition.
    auto shapes = catmarkShapes();
    shapes.emplace_back("spot",
                        sg::mesh::loadPolygonMesh(dataPath("meshes/spot/spot_control_mesh.obj")));
    static constexpr int kFrom[4] = {0, 0, 1, 3}, kTo[4] = {3, 1, 2, 2};
    static constexpr int kFarBit[4] = {3, 0, 1, 2}; // our edge k -> Far's transition bit
    size_t transitions = 0, halves = 0;
    float worst = 0.0f;
    for (const auto& [name, cage] : shapes) {
        SCOPED_TRACE(name);
        for (int isolation : {2, 3}) {
            const sg::mesh::AdaptivePatches ap =
                sg::mesh::buildAdaptivePatches(cage, cage.options, isolation, name);
            ASSERT_EQ(ap.transitionMask.size(), ap.patchCount());
            float extent = 0.0f;
            for (const glm::vec3& q : ap.points) extent = std::max(extent, g::sgMaxAbs3(q));
            for (uint32_t p = 0; p < ap.patchCount(); ++p) {
                const uint32_t farMask = ap.params[p].x >> 28;
                const uint32_t depth = uint32_t(g::sgPatchDepth(ap.params[p].y));
                for (int k = 0; k < 4; ++k) {
                    const bool far = (farMask >> kFarBit[k]) & 1u;
                    const bool ours = (ap.transitionMask[p] >> k) & 1u;
                    EXPECT_EQ(ours, far) << "patch " << p << " edge " << k;
                    halves += (ap.transitionMask[p] >> (4 + k)) & 1u;
                    if (!ours) continue;
                    ++transitions;
                    const uint32_t ends[2] = {ap.cornerVertices[p][kFrom[k]],
                                              ap.cornerVertices[p][kTo[k]]};
                    const glm::vec3 endPos[2] = {evalAt(ap, p, cornerUv(kFrom[k])),
                                                 evalAt(ap, p, cornerUv(kTo[k]))};
                    uint32_t midVertex[2] = {};
                    for (int h = 0; h < 2; ++h) {
                        const uint32_t code =
                            h == 0 ? ap.transitionLo[p][k] : ap.transitionHi[p][k];
                        const uint32_t owner = code >> 3, oe = (code >> 1) & 3u;
                        const bool flip = (code & 1u) != 0u;
                        ASSERT_LT(owner, ap.patchCount());
                        EXPECT_EQ(uint32_t(g::sgPatchDepth(ap.params[owner].y)), depth + 1);
                        EXPECT_EQ((ap.transitionMask[owner] >> (4 + oe)) & 1u, 1u);
                        const glm::uvec4 oc = ap.cornerVertices[owner];
                        // The half from its coarse end (h = 0: the start)
                        // to the midpoint (h = 1: from the midpoint).
                        const int atCoarse = (h == 0) != flip ? kFrom[oe] : kTo[oe];
                        const int atMid = atCoarse == kFrom[oe] ? kTo[oe] : kFrom[oe];
                        midVertex[h] = oc[atMid];
                        EXPECT_NE(oc[atCoarse], ends[h]); // a child, one level down
                        worst = std::max(
                            worst, g::sgMaxAbs3(evalAt(ap, owner, cornerUv(atCoarse)) - endPos[h]));
                    }
                    EXPECT_EQ(midVertex[0], midVertex[1]);
                    const uint32_t mo = ap.transitionMid[p][k];
                    ASSERT_EQ(ap.cornerOwners[mo >> 2][int(mo & 3u)], mo);
                    EXPECT_EQ(ap.cornerVertices[mo >> 2][int(mo & 3u)], midVertex[0]);
                }
            }
            // The far corners' limit points: the coarse corner's (Far's
            // corner evaluation, different patches: a few ulp of the extent).
            EXPECT_LE(worst, 1e-5f * std::max(extent, 1.0f));
        }
    }
    EXPECT_GT(transitions, 100u);
    EXPECT_EQ(halves, 2 * transitions);
    std::printf("%zu transition edges, %zu halves, far-corner limit points within %.3g\n",
                transitions, halves, double(worst));
}

} // namespace

namespace {

// ---- Hard cases ---------------------------------------------------------------

// Every patch of `ap` evaluated at the sample points: all finite.
bool allFinite(const sg::mesh::AdaptivePatches& ap) {
    for (const auto& arr : ap.arrays) {
        for (uint32_t p = 0; p < arr.patchCount; ++p) {
            for (const auto& s : kSamples) {
                glm::vec3 du;
                const glm::vec3 q = evalPatch(ap, arr, p, glm::vec2(s[0], s[1]), &du);
                if (!std::isfinite(q.x + q.y + q.z + du.x + du.y + du.z)) return false;
            }
        }
    }
    return true;
}

TEST(PatchHardCases, ZeroAreaAndFarFromTheOriginStayFinite) {
    const PolygonMesh cube = sg::mesh::loadPolygonMesh(dataPath("osd-shapes/catmark_pole8.obj"));
    // Every cage vertex at one point: every patch has zero area.
    PolygonMesh collapsed = cube;
    for (glm::vec3& p : collapsed.positions) p = glm::vec3(0.25f, -1.0f, 3.0f);
    sg::mesh::AdaptivePatches ap = sg::mesh::buildAdaptivePatches(collapsed, collapsed.options, 3);
    EXPECT_TRUE(allFinite(ap));
    double worstOff = 0.0;
    for (const auto& arr : ap.arrays) {
        for (uint32_t p = 0; p < arr.patchCount; ++p) {
            glm::vec3 du;
            const glm::vec3 q = evalPatch(ap, arr, p, glm::vec2(0.5f), &du);
            const double off = glm::length(q - glm::vec3(0.25f, -1.0f, 3.0f));
            worstOff = std::isfinite(off) ? std::max(worstOff, off) : INFINITY;
            // The normal the TES derives falls back to +z (no direction).
            EXPECT_LE(g::sgMaxAbs3(du), 1e-3f);
        }
    }
    // Weights sum to 1: the point itself, up to rounding of the stencils
    // (rows of ~50 weights) and of the basis.
    sg::test::hardCaseAtMost("zero-area",
                             "adaptive patches of a cage collapsed to one point (catmark_pole8, "
                             "isolation 3): every patch has zero area",
                             "|patch centre - the point| (object units)", worstOff, 2e-5);
    // 1e6 from the origin at a size of 1: finite patches, and a bounded
    // level for an edge seen from 5 units away (camera-relative end points
    // rounded at 1e6: 0.06 steps).
    PolygonMesh far = cube;
    for (glm::vec3& p : far.positions) p += glm::vec3(1e6f, -1e6f, 1e6f);
    ap = sg::mesh::buildAdaptivePatches(far, far.options, 3);
    EXPECT_TRUE(allFinite(ap));
    const glm::vec3 a = ap.points[ap.cornerVertices[0].x], b = ap.points[ap.cornerVertices[0].y];
    const glm::vec3 eye = glm::vec3(1e6f, -1e6f, 1e6f) + glm::vec3(0.0f, 0.0f, 5.0f);
    const float lv = g::sgPatchEdgeTessLevel(a - eye, b - eye, 1000.0f, 4.0f, 64.0f);
    EXPECT_GE(lv, 1.0f);
    EXPECT_LE(lv, 64.0f);
    sg::test::reportHardCaseHolds(
        "far-from-origin", "adaptive patches of catmark_pole8 moved 1e6 from the origin",
        "control points finite, edge level within [1, 64]", "holds", "holds");
}

// A closed cage with two poles of valence `valence`: a sphere of `valence`
// segments and 4 rings, quads between the rings, triangle fans at the poles
// (Catmark turns them into quads around a vertex of the same valence).
// Rotationally symmetric: the limit normal at the north pole is +y.
PolygonMesh poleCage(uint32_t valence) {
    PolygonMesh cage;
    const uint32_t rings = 4;
    cage.positions.push_back(glm::vec3(0.0f, 1.0f, 0.0f)); // north pole: vertex 0
    for (uint32_t r = 1; r < rings; ++r) {
        const float theta = 3.14159265f * float(r) / float(rings);
        for (uint32_t i = 0; i < valence; ++i) {
            const float phi = 6.28318531f * float(i) / float(valence);
            cage.positions.push_back(glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                               -std::sin(theta) * std::sin(phi)));
        }
    }
    const uint32_t south = uint32_t(cage.positions.size());
    cage.positions.push_back(glm::vec3(0.0f, -1.0f, 0.0f));
    auto ring = [&](uint32_t r, uint32_t i) { return 1 + (r - 1) * valence + i % valence; };
    auto face = [&](std::initializer_list<uint32_t> v) {
        cage.faceSizes.push_back(uint32_t(v.size()));
        cage.faceVertices.insert(cage.faceVertices.end(), v);
    };
    for (uint32_t i = 0; i < valence; ++i) { // counter-clockwise seen from outside
        face({0, ring(1, i), ring(1, i + 1)});
        for (uint32_t r = 1; r + 1 < rings; ++r)
            face({ring(r, i), ring(r + 1, i), ring(r + 1, i + 1), ring(r, i + 1)});
        face({south, ring(rings - 1, i + 1), ring(rings - 1, i)});
    }
    return cage;
}

// Hard case: extraordinary vertices of high valence (3 to 1024 patches
// around one point). Gregory end caps surround the pole at every isolation;
// their corner at the pole must be OpenSubdiv's limit point with its limit
// normal, every patch finite. Measured against the uniform path's limit
// evaluation (Far limit stencils at the refined vertices) and against the
// symmetry (+y at the pole).
TEST(PatchHardCases, HighValencePolesKeepTheLimitPointAndNormal) {
    double worstOff = 0.0, worstAngleDeg = 0.0, angle1024Deg = 0.0;
    for (uint32_t valence : {3u, 8u, 64u, 256u, 1024u}) {
        double& angleDeg = valence == 1024u ? angle1024Deg : worstAngleDeg;
        SCOPED_TRACE(valence);
        PolygonMesh cage = poleCage(valence);
        sg::mesh::validate(cage, "pole.obj"); // closed, manifold, consistently oriented
        for (int isolation : {1, 3}) {
            sg::mesh::AdaptivePatches ap =
                sg::mesh::buildAdaptivePatches(cage, cage.options, isolation, "pole.obj");
            ASSERT_TRUE(allFinite(ap));
            sg::mesh::SubdivisionSettings st;
            st.options = cage.options;
            st.level = 1;
            st.limit = true;
            sg::mesh::Subdivider sub(cage, st, "pole.obj");
            const glm::vec3 limitPole = sub.refined().positions[0]; // vertex 0 keeps its index
            size_t atPole = 0;
            for (const auto& arr : ap.arrays) {
                for (uint32_t p = 0; p < arr.patchCount; ++p) {
                    for (glm::vec2 c :
                         {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
                        const sg::test::PatchSample x =
                            sg::test::evalPatchSample(ap, arr, arr.firstPatch + p, c);
                        const glm::vec3 q = x.pos;
                        if (glm::length(q - limitPole) > 1e-3f) continue;
                        const glm::vec3 n = glm::cross(x.du, x.dv);
                        ASSERT_GT(glm::length(n), 0.0f) << "patch " << arr.firstPatch + p;
                        const double cosA = std::clamp(double(glm::normalize(n).y), -1.0, 1.0);
                        angleDeg = std::max(angleDeg, std::acos(cosA) * 57.29577951);
                        worstOff = std::max(worstOff, double(glm::length(q - limitPole)));
                        ++atPole;
                    }
                }
            }
            // Every patch around the pole has it as a corner: at least one
            // per sector of the fan.
            EXPECT_GE(atPole, size_t(valence)) << "isolation " << isolation;
        }
    }
    std::printf("high-valence poles: worst angle to +y %.3g deg (valence 1024: %.3g), worst "
                "distance to the limit point %.3g\n",
                worstAngleDeg, angle1024Deg, worstOff);
    // Both are OpenSubdiv's limit in binary32 through different stencil
    // factorisations: rounding of rows with up to 2 * valence weights of
    // unit-size coordinates (measured 5.8e-6 at valence 64, 3.1e-5 at 1024).
    sg::test::hardCaseAtMost("high-valence",
                             "adaptive patches around poles of valence 3, 8, 64, 256 and 1024 "
                             "(isolation 1 and 3): patch corners at the pole",
                             "|corner - Far's limit point| (object units, cage size 2)", worstOff,
                             1e-4);
    // The normal from the Gregory corner's derivatives against the
    // symmetry's +y. The error grows with the valence (measured 0.02, 0.2
    // and 2.0 degrees at valence 64, 256 and 1024): the corner's
    // derivatives are differences of end-cap points about 2 pi / valence
    // apart, each a float sum of O(valence) weighted points; this test does
    // not separate that rounding from the end cap's own approximation.
    sg::test::hardCaseAtMost("high-valence",
                             "adaptive patches around poles of valence 3, 8, 64 and 256: normal at "
                             "the pole corner",
                             "angle to the exact normal +y (degrees)", worstAngleDeg, 0.5);
    sg::test::hardCaseAtMost("high-valence",
                             "adaptive patches around poles of valence 1024: normal at the pole "
                             "corner",
                             "angle to the exact normal +y (degrees)", angle1024Deg, 4.0);
}

} // namespace
