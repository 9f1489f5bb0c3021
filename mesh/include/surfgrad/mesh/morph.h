// Blendshapes (glTF 2.0 morph targets, sec. 3.7.2.2): P = P0 + sum_i w_i dP_i.
// Applied either to the cage (then refined through the Subdivider's
// stencils: Subdivider::update) or to the final mesh (the refined position
// deltas the Subdivider stores in RenderMesh::morphTargets): subdivision and
// limit evaluation are linear in the control points, so both give the same
// positions; the final-mesh path costs one multiply-add per target per
// vertex. Normals are either recomputed from the morphed geometry or blended
// from the targets' normal deltas (the caller chooses).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/render_mesh.h"

namespace sg::mesh {

enum class MorphNormals : uint8_t {
    // From the morphed geometry: normalize(dPdu x dPdv) when a LimitFrame is
    // given (exact limit normals), else area-weighted triangle normals,
    // shared by render vertices that coincide in the base mesh and in every
    // target (so UV seams stay smooth). Tangents are cleared: they must be
    // regenerated for the new geometry (surfgrad/mesh/tangents.h).
    Recompute,
    // normalize(n0 + sum_i w_i dN_i) (glTF's rule); tangents likewise
    // (xyz blended and normalized, w kept). Targets without normal/tangent
    // deltas contribute nothing. Falls back to Recompute for a vertex whose
    // blended normal vanishes.
    Blend,
};

// out = cage.positions + sum_i weights[i] * cage.morphTargets[i].positionDeltas.
// Preconditions (contract checks, surfgrad/base/contract.h): weights.size() ==
// cage.morphTargets.size() and every weight finite (callers check user
// input first). `out` is resized and reused.
void morphCagePositions(const PolygonMesh& cage, std::span<const float> weights,
                        std::vector<glm::vec3>& out);

// Per-frame morphing of a RenderMesh with reused buffers.
class Morpher {
public:
    // `base` (and `baseFrame`, when given: the LimitFrame of the same mesh,
    // with morphDPdu/morphDPdv) must outlive the Morpher.
    explicit Morpher(const RenderMesh& base, const LimitFrame* baseFrame = nullptr);

    // Writes the morphed positions and normals (and tangents, and with a
    // frame dPdu/dPdv) into `out`; on the first call `out` becomes a copy of
    // base, later calls overwrite only the arrays that change. Preconditions
    // (contract checks): weights.size() == base.morphTargets.size() and every
    // weight finite.
    void apply(std::span<const float> weights, MorphNormals normals, RenderMesh& out,
               LimitFrame* outFrame = nullptr) const;

    // Smooth group of each vertex used by MorphNormals::Recompute (the
    // smallest render vertex index that coincides with it in the base mesh
    // and in every target).
    const std::vector<uint32_t>& smoothGroups() const { return smoothGroup_; }

private:
    const RenderMesh* base_;
    const LimitFrame* baseFrame_;
    std::vector<uint32_t> smoothGroup_;
    mutable std::vector<glm::vec3> scratchU_, scratchV_; // derivatives when no outFrame is given
};

} // namespace sg::mesh
