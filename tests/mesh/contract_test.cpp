// The documented preconditions of mesh/ (contract checks, surfgrad/base/contract.h):
// each violation aborts with "contract violated" in a checked build.
// Untrusted meshes never reach these: loaders and the callers of the tangent
// generators reject them with sg::io::InputError first (tests of
// tangentInputProblem() and mikktspaceInputProblem() in tangents_*_test.cpp).
#include <cmath>
#include <limits>
#include <vector>

#include "contract_death.h"
#include "mesh_test_util.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/morph.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/mikktspace_reference.h"
#include "surfgrad/mesh/tangents.h"

namespace {

using sg::mesh::MikkTSpaceGenerator;
using sg::mesh::MikkTSpaceInput;
using sg::mesh::RenderMesh;
using sg::mesh::TangentMethod;
using ContractDeath = sg::test::ContractDeath;

const float kNaN = std::numeric_limits<float>::quiet_NaN();

// One triangle with normals and one UV set: satisfies every precondition.
RenderMesh triangle() {
    RenderMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.uvSets = {{{0, 0}, {1, 0}, {0, 1}}};
    m.indices = {0, 1, 2};
    return m;
}

MikkTSpaceInput inputOf(const RenderMesh& m) {
    MikkTSpaceInput in;
    in.positions = m.positions;
    in.normals = m.normals;
    in.uvs = m.uvSets[0];
    in.cornerVertices = m.indices;
    return in;
}

sg::mesh::PolygonMesh cube() {
    sg::mesh::PolygonMesh cage = sg::mesh::parseObj(sg::test::kCubeObj, "cube.obj");
    sg::mesh::validate(cage, "cube.obj");
    return cage;
}

TEST_F(ContractDeath, MorphWeightsOnePerTargetAndFinite) {
    sg::mesh::PolygonMesh cage = cube();
    cage.morphTargets.resize(1);
    cage.morphTargets[0].positionDeltas.assign(cage.positions.size(), glm::vec3(0.1f));
    std::vector<glm::vec3> out;
    const std::vector<float> two{0.5f, 0.5f}, nan{kNaN};
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::morphCagePositions(cage, two, out), "one weight per");
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::morphCagePositions(cage, nan, out), "finite");

    RenderMesh base = triangle();
    base.morphTargets.resize(1);
    base.morphTargets[0].positionDeltas.assign(3, glm::vec3(0.1f));
    sg::mesh::Morpher morpher(base);
    RenderMesh morphed;
    SG_EXPECT_CONTRACT_DEATH(morpher.apply(two, sg::mesh::MorphNormals::Recompute, morphed),
                             "one weight per");
    SG_EXPECT_CONTRACT_DEATH(morpher.apply(nan, sg::mesh::MorphNormals::Blend, morphed), "finite");
}

TEST_F(ContractDeath, SubdividerUpdateNeedsAnimateAndMatchingSizes) {
    const sg::mesh::PolygonMesh cage = cube();
    sg::mesh::SubdivisionSettings settings;
    settings.level = 1;
    sg::mesh::Subdivider still(cage, settings);
    RenderMesh out = still.renderMesh();
    SG_EXPECT_CONTRACT_DEATH(still.update(cage.positions, out), "animate");
    settings.animate = true;
    sg::mesh::Subdivider animated(cage, settings);
    out = animated.renderMesh();
    const std::vector<glm::vec3> fewer(cage.positions.begin(), cage.positions.end() - 1);
    SG_EXPECT_CONTRACT_DEATH(animated.update(fewer, out), "one position per cage vertex");
    RenderMesh other = triangle();
    SG_EXPECT_CONTRACT_DEATH(animated.update(cage.positions, other), "copy of renderMesh");
}

TEST_F(ContractDeath, VertexNormalSmoothGroupsOnePerVertex) {
    RenderMesh m = triangle();
    const std::vector<uint32_t> groups{0, 1};
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::computeVertexNormals(m, groups), "smoothGroup");
}

TEST_F(ContractDeath, MikkTSpaceThreadCountInRange) {
    MikkTSpaceGenerator generator;
    generator.setThreads(0);
    generator.setThreads(1024);
    SG_EXPECT_CONTRACT_DEATH(generator.setThreads(-1), "threads");
    SG_EXPECT_CONTRACT_DEATH(generator.setThreads(1025), "threads");
    RenderMesh m = triangle();
    SG_EXPECT_CONTRACT_DEATH(
        sg::mesh::generateTangents(m, sg::mesh::TangentMethod::MikkTSpace, 0, nullptr, -1),
        "threads");
    SG_EXPECT_CONTRACT_DEATH(
        sg::mesh::generateTangents(m, sg::mesh::TangentMethod::MikkTSpace, 0, nullptr, 1025),
        "threads");
}

TEST_F(ContractDeath, ObjReaderThreadCountInRange) {
    sg::mesh::parseObj(sg::test::kCubeObj, "cube.obj", {}, nullptr, 1024);
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::parseObj(sg::test::kCubeObj, "cube.obj", {}, nullptr, -1),
                             "threads");
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::parseObj(sg::test::kCubeObj, "cube.obj", {}, nullptr, 1025),
                             "threads");
    sg::mesh::LoadOptions options;
    options.threads = 2000;
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::loadRenderMesh("cube.obj", options), "threads");
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::loadPolygonMesh("cube.obj", options), "threads");
}

TEST_F(ContractDeath, MikkTSpaceInputPreconditions) {
    const RenderMesh good = triangle();
    MikkTSpaceGenerator generator;
    std::vector<glm::vec4> out;
    {
        RenderMesh bad = good;
        bad.positions[1].y = kNaN;
        SG_EXPECT_CONTRACT_DEATH(generator.generate(inputOf(bad), out), "MikkTSpaceInput");
        SG_EXPECT_CONTRACT_DEATH(sg::mesh::mikktspaceReferenceFrames(inputOf(bad)),
                                 "MikkTSpaceInput");
        bad = good;
        bad.positions[2].x = 1e30f; // beyond 2^60
        SG_EXPECT_CONTRACT_DEATH(generator.generate(inputOf(bad), out), "MikkTSpaceInput");
        bad = good;
        bad.normals[0] = {0, 0, 1e5f}; // not a unit normal
        SG_EXPECT_CONTRACT_DEATH(generator.generate(inputOf(bad), out), "MikkTSpaceInput");
    }
    {
        RenderMesh bad = good;
        bad.indices = {0, 1, 3};
        SG_EXPECT_CONTRACT_DEATH(generator.generate(inputOf(bad), out), "MikkTSpaceInput");
        bad.indices = {0, 1};
        SG_EXPECT_CONTRACT_DEATH(generator.generate(inputOf(bad), out), "MikkTSpaceInput");
    }
    {
        MikkTSpaceInput in = inputOf(good);
        const std::vector<uint32_t> sizes{4};
        in.faceSizes = sizes;
        SG_EXPECT_CONTRACT_DEATH(generator.generate(in, out), "MikkTSpaceInput");
    }
}

TEST_F(ContractDeath, MikkTSpaceOnAMeshNeedsNormalsAndTheUvSet) {
    RenderMesh noNormals = triangle();
    noNormals.normals.clear();
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::generateMikkTSpaceTangents(noNormals, 0), "normals");
    RenderMesh m = triangle();
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::generateMikkTSpaceTangents(m, 1), "uvSet");
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::generateTangents(m, TangentMethod::MikkTSpace, -1), "uvSet");
    const std::vector<glm::vec4> two(2, glm::vec4(1, 0, 0, 1));
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::applyCornerTangents(m, 0, two), "one tangent per");
}

TEST_F(ContractDeath, LimitTangentsNeedAMatchingFrame) {
    RenderMesh m = triangle();
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::generateTangents(m, TangentMethod::Limit, 0), "limit frame");
    sg::mesh::LimitFrame frame;
    frame.dPdu = {{1, 0, 0}};
    frame.dPdv = {{0, 1, 0}};
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::generateLimitTangents(m, frame, 0), "frame");
    const std::vector<glm::vec3> one(1, glm::vec3(1, 0, 0)), two(2, glm::vec3(0, 1, 0));
    const std::vector<glm::vec2> st(1, glm::vec2(1, 0));
    std::vector<glm::vec4> out(1);
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::limitTangents(one, two, st, st, out), "equal length");
}

} // namespace
