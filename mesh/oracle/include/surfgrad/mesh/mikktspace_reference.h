// The MikkTSpace oracle (mesh/oracle/mikktspace_reference.cpp): a plain,
// step-by-step implementation of the published algorithm (Mikkelsen 2008,
// section 4.2; the mikktspace.c reference), against which the fast
// generator of surfgrad/mesh/tangents.h is tested bit for bit. Test-only: the
// target surfgrad_mesh_oracle is linked by the tests, the fuzz target and
// tangents_bench, and is not installed.
#pragma once

#include <vector>

#include "surfgrad/mesh/tangents.h"

namespace sg::mesh {

// The oracle: a plain, step-by-step implementation of the published
// algorithm (see docs/tangents.md for the steps). Slow (std::map welding,
// per-group allocations) but simple; used by the tests and the benchmark to
// check the fast path. Same preconditions.
std::vector<MikkTSpaceFrame> mikktspaceReferenceFrames(const MikkTSpaceInput& input);

} // namespace sg::mesh
