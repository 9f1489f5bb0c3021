// The documented preconditions of the normal-map toolkit (contract checks,
// surfgrad/base/contract.h): each violation aborts with "contract violated" in a
// checked build. Untrusted files never reach these: the CLI checks sizes,
// channels, UV sets and the mesh's tangent input first and reports
// sg::io::InputError (cli_test.cpp).
#include "contract_death.h"
#include "surfgrad/normalmap/operations.h"
#include "surfgrad/mesh/render_mesh.h"

namespace {

using namespace sg::normalmap;
using ContractDeath = sg::test::ContractDeath;

TEST_F(ContractDeath, OpsOnGridsOfDifferentSizes) {
    const DerivField a(8, 8), b(8, 4);
    const ScalarField h(8, 8), small(4, 4);
    SG_EXPECT_CONTRACT_DEATH((void)add(a, 1.0f, b, 1.0f), "grids of different sizes");
    SG_EXPECT_CONTRACT_DEATH((void)modulate(a, h, small, Wrap::Clamp), "grids of different sizes");
    SG_EXPECT_CONTRACT_DEATH((void)blend(a, h, a, h, small, Wrap::Clamp),
                             "grids of different sizes");
    SG_EXPECT_CONTRACT_DEATH((void)applyCurve(a, small, boostCurve(1.0f, 0.5f)),
                             "grids of different sizes");
    SG_EXPECT_CONTRACT_DEATH((void)naive::add(NormalField(8, 8), 1.0f, NormalField(2, 2), 1.0f),
                             "grids of different sizes");
}

TEST_F(ContractDeath, SignedNormalsNeedFloatImages) {
    MapFormat f;
    f.encoding = Encoding::Signed;
    SG_EXPECT_CONTRACT_DEATH((void)encodeSlopes(DerivField(2, 2), f, false),
                             "signed normals need a floating-point image");
}

TEST_F(ContractDeath, FramesNeedAUvSetAndNormals) {
    sg::mesh::RenderMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    m.uvSets = {{{0, 0}, {1, 0}, {0, 1}}};
    m.indices = {0, 1, 2};
    SG_EXPECT_CONTRACT_DEATH((void)rasterizeFrames(m, 1, 8, 8, 0), "uvSet indexes mesh.uvSets");
    m.normals.clear();
    SG_EXPECT_CONTRACT_DEATH((void)rasterizeFrames(m, 0, 8, 8, 0), "the mesh has vertex normals");
}

} // namespace
