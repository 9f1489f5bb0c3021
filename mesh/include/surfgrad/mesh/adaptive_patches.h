// Feature-adaptive patches of a Catmull-Clark cage for GPU tessellation:
// OpenSubdiv's Far::PatchTable (Niessner, Loop, Meyer & DeRose,
// "Feature-adaptive GPU rendering of Catmull-Clark subdivision surfaces",
// ACM TOG 31(1), 2012; Gregory-basis end caps, Loop et al. 2009) as plain
// arrays, the refined face each patch covers, and which patch evaluates the
// points of shared edges and corners (crack-freedom). The bases are
// shaders/sg/patch/*.glsl (shared GLSL/C++ subset, surfgrad/bump/patch_basis.h
// of the bump module); the mesh module has no shader math.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "surfgrad/mesh/polygon_mesh.h"

namespace sg::mesh {

// ---- Adaptive patches (GPU tessellation) ----------------------------------

// Far feature-adaptive refinement of a Catmull-Clark cage into a patch table
// as plain arrays, for drawing the limit surface with hardware tessellation
// (and the CPU reference of that path). Patches: regular bicubic B-spline
// (16 points, boundaries through PatchParam's boundary mask; creases and
// corners isolated to `isolation` and infinitely sharp ones as regular
// patches, Far's useInfSharpPatch), Gregory-basis end caps (20 points)
// around extraordinary vertices and unisolated semi-sharp features. The
// bases are shaders/sg/patch/basis.glsl (shared GLSL/C++ subset).
struct AdaptivePatchArray {
    int type = 0;            // Far::PatchDescriptor::Type: 6 regular, 9 Gregory basis
    int pointsPerPatch = 0;  // 16 or 20
    uint32_t firstPatch = 0; // into params (and patchFace)
    uint32_t patchCount = 0;
    uint32_t firstIndex = 0; // into indices: patchCount * pointsPerPatch entries
};

// One UV set on the patches: OpenSubdiv's face-varying patch table of the
// set's channel (Far::PatchTable::GetPatchFVarValues / GetPatchFVarPatchParam),
// built under the cage's face-varying interpolation rule
// (SubdivOptions::fvar, as the uniform path refines UVs). Each patch of
// the position table has one face-varying patch over the same part of the
// same ptex face, with its own type: bilinear (type 3, 4 values) when the
// rule makes the channel linear ("all"), else regular B-spline (type 6, 16
// values, boundary folds from its own PatchParam: UV seams are boundaries
// of the channel) or Gregory basis (type 9, 20 values) where the channel is
// irregular, exactly as Far::PatchTable::EvaluateBasisFaceVarying chooses.
// The bases are the positions' (shaders/sg/patch/basis.glsl); a UV is the
// weighted sum of the patch's values, evaluated at the ptex (u,v) of the
// position patch's domain point. UVs are static: no stencils.
struct AdaptiveUvSet {
    std::vector<glm::vec2> values; // every level's face-varying values, then Far's local points
    std::vector<uint32_t> field1;  // per patch: face-varying PatchParam field1
    std::vector<uint32_t> types;   // per patch: Far::PatchDescriptor::Type (3, 6 or 9)
    // Per patch kUvValuesPerPatch entries (indices into values; the first 4,
    // 16 or 20 are used, the rest 0).
    std::vector<uint32_t> indices;
    static constexpr uint32_t kUvValuesPerPatch = 20;
};

struct AdaptivePatches {
    int isolation = 0;
    uint32_t cagePointCount = 0; // points[0, cagePointCount) are the cage's vertices
    // Every control point, object space: the vertices of all adaptive levels
    // (level 0 = the cage) then Far's local points (Gregory end caps).
    std::vector<glm::vec3> points;
    std::vector<AdaptivePatchArray> arrays;
    std::vector<uint32_t> indices;  // control points of each patch, Far's order per type
    std::vector<glm::uvec2> params; // Far::PatchParam (field0, field1) per patch
    // Per patch, the refined vertices (indices into points) at its domain's
    // corners (0,0), (1,0), (1,1), (0,1), at the patch's depth: the vertices
    // of the refined face the patch covers. Two patches of the same depth
    // that share an edge share its two vertices, so anything computed from
    // them alone (the edge's tessellation level) is the same bit for bit on
    // both sides. For a regular patch these are its control points 5, 6,
    // 10, 9; for a Gregory patch they are not among its control points.
    std::vector<glm::uvec4> cornerVertices;
    // Crack-freedom between patches of the same depth: every point on a
    // shared edge (or corner) is evaluated from one patch, its owner (the
    // patch of lowest index among those that have it, by cornerVertices),
    // at a parameter both sides derive from the same integers. Per patch and
    // edge (0: u = 0, 1: v = 0, 2: u = 1, 3: v = 1; the edge runs along +v
    // or +u): (owner << 3) | (owner's edge << 1) | flip, flip = 1 when the
    // owner runs the edge the other way. Per patch and corner ((0,0), (1,0),
    // (1,1), (0,1)): (owner << 2) | owner's corner. A patch owns its
    // unshared edges and corners. Corners are keyed by the vertex they
    // refine (a vertex's child vertex at the next level is the same limit
    // point), so patches of different depths that meet at a corner share
    // its owner too.
    std::vector<glm::uvec4> edgeOwners;
    std::vector<glm::uvec4> cornerOwners;
    // Transition edges (Far's PatchParam transition mask): an edge of a
    // patch at depth d whose other side is two patches at depth d + 1, each
    // covering one half (from the child vertex of one end to the edge's
    // child vertex, its midpoint). The coarse side tessellates the edge
    // with the sum of the halves' levels (each computed from the half's
    // own two corner vertices, as the fine patch computes it) and evaluates
    // every point on it from the fine owner of its half, at the parameter
    // the fine owner uses: bitwise equal from both sides. Per patch:
    // bit k (0..3) set when edge k is a transition edge of this (coarse)
    // patch, bit 4 + k when edge k is a half of a coarser patch's
    // transition edge (its level is capped at half the maximum, so the
    // coarse side's sum stays within GL's maximum; sgPatchHalfMaxLevel).
    std::vector<uint32_t> transitionMask;
    // Per patch and transition edge k (0 elsewhere): the owner of the half
    // at the edge's start (the corner it runs from: (0,0) for edges 0 and
    // 1, (1,0) for 2, (0,1) for 3) and of the half at its end, each encoded
    // as edgeOwners ((owner << 3) | (owner's edge << 1) | flip, flip = 1
    // when the owner runs the half from the midpoint towards the coarse
    // corner), and the midpoint's corner owner (as cornerOwners).
    std::vector<glm::uvec4> transitionLo;
    std::vector<glm::uvec4> transitionHi;
    std::vector<glm::uvec4> transitionMid;
    // Stencils: every point past the cage is a fixed linear combination of
    // points before it, applied in passes (what an animated cage needs per
    // frame besides its own positions; the GPU runs the same passes,
    // render/src/gpu_stencils.h). One row per point past the cage, in
    // point order: row r computes point i = cagePointCount + r as
    //   points[i] = sum over k in [stencilOffsets[r], stencilOffsets[r + 1])
    //               of stencilWeights[k] * points[stencilIndices[k]],
    // summed from 0 in increasing k, each product rounded to float before
    // its add (no fused multiply-add). That order is the contract: the
    // GPU's compute stage performs the same operations and its points equal
    // updateAdaptivePoints' bit for bit. stencilOffsets has
    // points.size() - cagePointCount + 1 entries.
    // Passes: pass p computes points [stencilPasses[p], stencilPasses[p + 1])
    // (stencilPasses[0] = cagePointCount, stencilPasses.back() =
    // points.size(); empty passes are left out). Each adaptive refinement
    // level is one pass whose rows read the level above (OpenSubdiv's
    // Far::StencilTable with factorizeIntermediateLevels = false: a few
    // weights per point), then one pass for Far's local points (Gregory end
    // caps) whose rows read refined points of any level. Every row reads
    // only points of earlier passes (checked when built), so the rows of a
    // pass are independent and the passes run in order. The rows are not
    // factorised down to the cage, so their size is proportional to the
    // number of points, not growing with the depth.
    std::vector<uint32_t> stencilOffsets;
    std::vector<uint32_t> stencilIndices;
    std::vector<float> stencilWeights;
    std::vector<uint32_t> stencilPasses;
    // The cage's UV sets, in its order (empty for a cage without UVs).
    std::vector<AdaptiveUvSet> uvSets;

    size_t patchCount() const { return params.size(); }
    // Bytes of the stencil arrays (offsets, indices, weights, passes).
    size_t stencilBytes() const {
        return 4 * (stencilOffsets.size() + stencilIndices.size() + stencilWeights.size() +
                    stencilPasses.size());
    }
};

// Builds the adaptive patches of `cage` (validated) at the given isolation
// level (1..10, OpenSubdiv's limit). Throws InputError (file, element,
// reason) for a scheme other than Catmark (element "scheme": Loop and
// bilinear cages take the uniform path), an isolation outside 1..10
// (element "isolation"), or a cage OpenSubdiv refuses. Holes: hole faces
// get no patches. Every UV set of the cage becomes an AdaptiveUvSet.
// threads (surfgrad/base/threads.h: 0 all cores, 1..1024; outside is a contract
// violation): the corner vertices of every patch and the stencil passes
// run on TBB for cages of at least kAdaptiveSerialBelowPatches patches,
// with the same result for every count; OpenSubdiv's refinement, patch
// table and stencil tables, and the owner maps, stay serial.
AdaptivePatches buildAdaptivePatches(const PolygonMesh& cage, const SubdivOptions& options,
                                     int isolation, const std::string& file = {}, int threads = 0);
// Patches (and stencil rows) below which buildAdaptivePatches and
// updateAdaptivePoints stay on the calling thread. Not measured on its own:
// a guess of the order of kSerialBelowFaces (subdivision.h; one patch's
// corner descent costs more than one refined face's loops, hence lower).
inline constexpr size_t kAdaptiveSerialBelowPatches = 8192;

// Recomputes patches.points from new cage positions (cagePointCount
// entries): copies the cage into points[0, cagePointCount), then applies
// the stencil passes in order (the layout and summation order above): what
// an animated cage needs per frame (the GPU applies the same passes in a
// compute stage, bit for bit the same points). threads as in
// buildAdaptivePatches: the rows of a pass on TBB (each row's sum in the
// order above, so the points are the same bits for every count), serial
// below kAdaptiveSerialBelowPatches rows.
void updateAdaptivePoints(AdaptivePatches& patches, std::span<const glm::vec3> cagePositions,
                          int threads = 0);

} // namespace sg::mesh
