// The documented preconditions of features/ (contract checks,
// surfgrad/base/contract.h): texel coordinates inside the maps, for the C++
// emulation of the evaluator's texelFetch and for the packing helpers; a
// thread count within 0..kMaxThreads for the bake and the packing.
#include <array>
#include <vector>

#include "contract_death.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/base/threads.h"

namespace {

using ContractDeath = sg::test::ContractDeath;

TEST_F(ContractDeath, TexelFetchInsideTheMap) {
    const std::vector<uint32_t> texels(2 * 3 * 4, 0u); // 2 x 3 texels, 4 words each
    const sg::glsl::SgFeatCornerSampler corners{texels.data(), 2, 3};
    const sg::glsl::SgFeatEdgeSampler edges{texels.data(), 2, 3};
    EXPECT_EQ(sg::glsl::texelFetch(corners, sg::glsl::ivec2(1, 2), 0).x, 0u);
    SG_EXPECT_CONTRACT_DEATH(sg::glsl::texelFetch(corners, sg::glsl::ivec2(2, 0), 0),
                             "texel inside the map");
    SG_EXPECT_CONTRACT_DEATH(sg::glsl::texelFetch(edges, sg::glsl::ivec2(0, -1), 0),
                             "texel inside the map");
}

TEST_F(ContractDeath, PackingHelpersTakeTexelsInsideTheMap) {
    sg::features::FeatureMaps maps; // size 0: no texel at all
    SG_EXPECT_CONTRACT_DEATH(maps.configWord(0, 0), "inside the map");
    sg::features::GpuFeatureMaps gpu;
    std::array<float, 64> record{};
    SG_EXPECT_CONTRACT_DEATH(
        sg::features::packEvalRecord(gpu, 0, 0, glm::vec2(0.5f), record.data()), "inside the map");
}

TEST_F(ContractDeath, ThreadCountsOutsideZeroTo1024) {
    sg::features::CurveNetwork net;
    net.curves.resize(1);
    sg::features::Segment s;
    s.p0 = {0.0, 0.0};
    s.p2 = {1.0, 1.0};
    s.p1 = {0.5, 0.5};
    net.segments.push_back(s);
    sg::features::BakeOptions o;
    o.size = 16;
    o.marginTexels = 2.0;
    o.threads = sg::kMaxThreads;
    const sg::features::FeatureMaps maps = sg::features::bake(net, o); // the largest count
    (void)maps.packGpu(sg::kMaxThreads);
    for (int threads : {-1, sg::kMaxThreads + 1}) {
        o.threads = threads;
        SG_EXPECT_CONTRACT_DEATH(sg::features::bake(net, o), "BakeOptions::threads is 0");
        SG_EXPECT_CONTRACT_DEATH(maps.packGpu(threads), "threads is 0");
    }
}

} // namespace
