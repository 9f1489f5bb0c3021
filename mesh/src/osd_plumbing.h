// OpenSubdiv plumbing shared by the subdivision (subdivision.cpp) and the
// adaptive patches (adaptive_patches.cpp), internal to mesh/: Far's error
// callbacks, the Sdc options of a SubdivOptions, a cage's
// Far::TopologyDescriptor with the refiner made from it, and face-varying
// values through an adaptive refiner's levels.
#pragma once

#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <glm/vec2.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/subdivision.h"

namespace sg::mesh::detail {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

// Far's error messages of the current thread's last refiner or table
// (collected by the callback installFarCallbacks installs; at most about
// 400 characters).
extern thread_local std::string tFarError;
void installFarCallbacks();

Sdc::SchemeType sdcScheme(Scheme s);
Sdc::Options sdcOptions(const SubdivOptions& o);

// Descriptor arrays for one cage (the descriptor points into them).
struct Descriptor {
    std::vector<int> creasePairs, corners, holes;
    std::vector<float> creaseWeights, cornerWeights;
    std::vector<Far::TopologyDescriptor::FVarChannel> channels;
    Far::TopologyDescriptor desc;

    void build(const PolygonMesh& cage);
};

// Far::TopologyRefinerFactory on the descriptor; throws io::InputError
// (file, "topology") with Far's messages when OpenSubdiv rejects the mesh.
std::unique_ptr<Far::TopologyRefiner> createRefiner(const Descriptor& d, const SubdivOptions& o,
                                                    const std::string& file);

// Face-varying channel ch's values at every point of an adaptive refiner
// and its patch table: the cage's values (cageValues) interpolated once
// through all adaptive levels (concatenated, as the patch table indexes
// them), plus the table's local points.
std::vector<glm::vec2> fvarPatchPoints(const Far::TopologyRefiner& adaptive,
                                       const Far::PatchTable& table,
                                       const std::vector<glm::vec2>& cageValues, int ch);

} // namespace sg::mesh::detail
