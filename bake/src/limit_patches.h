// The limit surface of a Catmull-Clark cage as the bake reads it: the
// feature-adaptive patch table (surfgrad/mesh/adaptive_patches.h, OpenSubdiv's
// Far::PatchTable with Gregory-basis end caps) evaluated with the shared
// patch bases (shaders/sg/patch/basis.glsl, the tessellation evaluation
// stage's code), one UV set's face-varying patches beside it, and the
// inverse of that UV map on one patch by Newton's method.
//
// Parameters: patchUv in the patch's own unit square ([0,1]^2; values
// outside are clamped, as sgPatchBasis clamps); derivatives with respect to
// the ptex face's (u,v) (the depth scale applied), for positions and UVs
// alike, so dP/ds follows from the chain rule (sg/patch/limit_tangent.glsl).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/mesh/polygon_mesh.h"

namespace sg::bake::detail {

struct SurfaceSample {
    glm::vec3 pos{0.0f}, dPdu{0.0f}, dPdv{0.0f};  // object space
    glm::vec2 st{0.0f}, dSTdu{0.0f}, dSTdv{0.0f}; // the UV set (t up)
};

class LimitPatches {
public:
    // Builds the patch table of `cage` (validated; Catmull-Clark: other
    // schemes are refused by buildAdaptivePatches with an InputError naming
    // `file`) and keeps UV set `uvSet` (which must exist). threads as in
    // buildAdaptivePatches.
    LimitPatches(const mesh::PolygonMesh& cage, int isolation, int uvSet, const std::string& file,
                 int threads);

    uint32_t patchCount() const { return uint32_t(ap_.patchCount()); }
    // The UV set's value at patchUv of patch p.
    glm::vec2 st(uint32_t p, glm::vec2 patchUv) const;
    // Position, UV and both sets of derivatives at patchUv of patch p.
    SurfaceSample sample(uint32_t p, glm::vec2 patchUv) const;
    // The point of patch p whose UV is `target`, by Newton's method on
    // patchUv from `start` (at most kNewtonSteps steps, each clamped to the
    // patch's square; stops when the UV is within 1e-7 of the UV set's
    // scale or the chart is singular). Returns the sample at the last
    // iterate (no second evaluation); `residual` receives
    // |st(result) - target|.
    SurfaceSample invertUv(uint32_t p, glm::vec2 target, glm::vec2 start, float& residual) const;
    static constexpr int kNewtonSteps = 4;

private:
    mesh::AdaptivePatches ap_;
    std::vector<uint32_t> arrayOf_; // patch -> its array in ap_.arrays
    int uvSet_ = 0;
};

} // namespace sg::bake::detail
