// The thread-count contract of subdivision (SubdivisionSettings::threads,
// buildAdaptivePatches / updateAdaptivePoints' threads: 0..1024, surfgrad/
// threads.h): a count outside aborts with "contract violated" in a checked
// build. The CLI refuses such counts first (--threads, a usage error:
// subdivision_threads_test.cpp).
#include <vector>

#include "contract_death.h"
#include "mesh_test_util.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

using ContractDeath = sg::test::ContractDeath;

sg::mesh::PolygonMesh cube() {
    sg::mesh::PolygonMesh cage = sg::mesh::parseObj(sg::test::kCubeObj, "cube.obj");
    sg::mesh::validate(cage, "cube.obj");
    return cage;
}

TEST_F(ContractDeath, SubdivisionThreadCountIsZeroTo1024) {
    const sg::mesh::PolygonMesh cage = cube();
    for (int threads : {-1, 1025}) {
        sg::mesh::SubdivisionSettings s;
        s.level = 1;
        s.threads = threads;
        SG_EXPECT_CONTRACT_DEATH(sg::mesh::Subdivider(cage, s), "threads");
        SG_EXPECT_CONTRACT_DEATH(sg::mesh::buildAdaptivePatches(cage, cage.options, 2, "", threads),
                                 "threads");
    }
    sg::mesh::AdaptivePatches patches = sg::mesh::buildAdaptivePatches(cage, cage.options, 2);
    SG_EXPECT_CONTRACT_DEATH(sg::mesh::updateAdaptivePoints(patches, cage.positions, 2000),
                             "threads");
    // The limits themselves are valid.
    for (int threads : {0, 1024}) {
        sg::mesh::SubdivisionSettings s;
        s.level = 1;
        s.threads = threads;
        sg::mesh::Subdivider ok(cage, s);
        EXPECT_EQ(ok.refined().faceCount(), 24u);
    }
}

} // namespace
