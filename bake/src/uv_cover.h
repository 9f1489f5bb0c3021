// Which patch and which point of it each texel centre of a UV layout lies
// on: every patch's face-varying UV map is sampled on a grid of limit UVs
// (cells of at most about one texel), each cell split into two triangles
// and rasterised over the texel centres with the patch coordinates
// interpolated linearly; the bake then refines that point by Newton's
// method (LimitPatches::invertUv).
//
// Claims: a texel centre within kClaimTolTexels outside a triangle is
// claimed too (the two sides of a shared patch edge evaluate it with
// different rounding: neither may leave a crack); of several claims the one
// deepest inside its triangle wins (signed distance to the nearest edge,
// in texels), and the deepest claim of another patch is kept as the
// runner-up. The bake evaluates both: the same surface point (a texel on a
// shared patch edge) or two different ones (overlapping UV charts).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "limit_patches.h"
#include "surfgrad/mesh/render_mesh.h"

namespace sg::bake::detail {

inline constexpr float kClaimTolTexels = 1e-3f;
// Grid cells per patch side: the smallest power of two that makes each
// cell at most kCellTexels texels along the patch's longest side in UV,
// capped at kMaxCellsPerSide. Newton's method refines the linear estimate
// inside a cell, so cells need not be smaller than a texel; two texels
// keep the chords of curved chart edges far below the claim tolerance
// (checked by the known-answer tests' residuals).
inline constexpr float kCellTexels = 2.0f;
inline constexpr int kMaxCellsPerSide = 1024;
// Rows of texels per rasterisation task.
inline constexpr int kBandRows = 32;

struct TexelClaim {
    uint32_t patch = UINT32_MAX;      // UINT32_MAX: no patch covers the texel
    float depthTexels = 0.0f;         // signed distance inside its triangle
    glm::vec2 patchUv{0.0f};          // linear estimate, before Newton
    uint32_t otherPatch = UINT32_MAX; // runner-up of another patch (UINT32_MAX: none)
    float otherDepthTexels = 0.0f;
    glm::vec2 otherUv{0.0f};
};

struct UvCover {
    std::vector<TexelClaim> claims; // width * height, row 0 at the bottom
    size_t chartTexels = 0;
};

// threads: the grids of limit UVs are evaluated on TBB (one task per
// block of patches), then bands of kBandRows rows are rasterised on TBB,
// each visiting the patches and cells in order, so every texel receives
// its claims in the same order and the cover is the same for every count.
UvCover coverTexels(const LimitPatches& patches, int width, int height);

// The same for a triangle mesh's UV set `uvSet`: each claim's `patch` is a
// triangle and its patchUv the barycentric weights (b1, b2) of the
// triangle's second and third corner (exact: nothing to refine).
UvCover coverTriangles(const mesh::RenderMesh& mesh, int uvSet, int width, int height);

} // namespace sg::bake::detail
