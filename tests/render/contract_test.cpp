// The documented preconditions of the renderer (contract checks,
// surfgrad/base/contract.h): textures have width * height >= 1 texels, and plans
// are made for meshes and materials of the scene whose assets they get.
#include <vector>

#include "contract_death.h"
#include "render_test_util.h"

namespace sg::render::test {
namespace {

using ContractDeath = sg::test::ContractDeath;

TEST_F(ContractDeath, TextureSizeMatchesItsTexels) {
    SG_EXPECT_CONTRACT_DEATH(makeTexture(0, 1, {}, Wrap::Repeat), "at least one texel");
    SG_EXPECT_CONTRACT_DEATH(makeTexture(2, 2, std::vector<glm::vec4>(3), Wrap::Clamp),
                             "width \\* height texels");
}

TEST_F(ContractDeath, PlansIndexTheScenesMeshesAndMaterials) {
    const Scene scene = sceneFromJson(oneMaterialScene(R"({"type": "noise"})", kSphere));
    const SceneAssets assets = loadAssets(scene);
    EXPECT_EQ(planMaterial(scene, assets, 0, 0).materialIndex, 0);
    SG_EXPECT_CONTRACT_DEATH(planMaterial(scene, assets, 1, 0), "meshIndex");
    SG_EXPECT_CONTRACT_DEATH(planMaterial(scene, assets, 0, -1), "materialIndex");
    SG_EXPECT_CONTRACT_DEATH(planUberMaterial(scene, SceneAssets{}, 0, 0), "assets loaded");
}

} // namespace
} // namespace sg::render::test
