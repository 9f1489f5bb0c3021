// Baking a high-resolution mesh onto the limit surface of a Catmull-Clark
// cage: for every texel of one of the cage's UV sets, the point of the
// OpenSubdiv limit surface whose (limit, face-varying) UV is the texel's
// centre, its limit normal and tangent frame; a ray along +- that normal
// finds the high mesh; the hit gives a displacement along the limit normal
// and the high mesh's normal, written as a displacement map and as
// tangent-space and object-space normal maps.
//
// The surface is the one the renderer draws for "mode": "adaptive" meshes:
// OpenSubdiv's feature-adaptive patch table (surfgrad/mesh/adaptive_patches.h)
// evaluated with the shared patch bases (shaders/sg/patch/basis.glsl, the
// tessellation evaluation stage's code), so a baked displacement read back
// by sg/patch/displace.glsl puts each texel's point where the high mesh was.
//
// Math:
//  - limit surface: Catmull & Clark 1978; feature-adaptive patches with
//    Gregory-basis end caps (Niessner, Loop, Meyer & DeRose 2012; Loop,
//    Schaefer, Ni & Castano 2009) as OpenSubdiv's Far builds them;
//  - texel -> surface point: the UV layout of every patch is rasterised from
//    a grid of limit UVs, then Newton's method on the patch's face-varying
//    UV map, (u,v) += J^-1 (st_texel - st(u,v)), J = d(s,t)/d(u,v);
//  - displacement convention: Mikkelsen 2019, section 2.5 (the bump map of
//    a displaced surface is taken in the frame of the surface before
//    displacement): the baked normal map is the high mesh's normal in the
//    limit frame of the undisplaced limit surface;
//  - tangent frame: the limit tangent of sg/patch/limit_tangent.glsl (vec4
//    T, w; T the unit vector along dP/ds in the tangent plane, bitangent
//    w * cross(N, T)), which is also the per-pixel frame (Mikkelsen 2019,
//    listing 6) of the limit surface; normals -> slopes by the shared
//    sgSurfgradFromPerturbedNormal through sg::normalmap::tangentFromObject.
//
// Spaces and units: object space of the two meshes (the same space: no
// transform is applied), right-handed; displacement in object units along
// the unit limit normal, positive outwards (the side cross(dP/du, dP/dv)
// points to); UV (s,t) with t up, texel (i, j) centred at
// ((i + 0.5) / width, (j + 0.5) / height), row 0 at the bottom. Only UVs in
// [0, 1]^2 are baked (no wrapping, no UDIM tiles).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "surfgrad/normalmap/operations.h"
#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/render_mesh.h"

namespace sg::bake {

// Largest map side and texel count bake() accepts.
inline constexpr int kMaxBakeSide = 16384;
inline constexpr size_t kMaxBakeTexels = size_t(1) << 26;

// Empty when a width x height map is within those limits; otherwise a
// sentence saying why not (bake() refuses such a size, the CLI checks its
// --size with it first).
std::string bakeSizeProblem(int width, int height);

// The surface the bake measures from (ray origins and directions, the
// frame of the tangent-space map).
enum class BakeSurface {
    // The Catmull-Clark limit surface of the cage, the exact limit normal
    // and limit frame: what the renderer draws for "mode": "adaptive" and
    // "limit": true meshes.
    Limit,
    // The cage refined uniformly to `refinedLevel` and triangulated (no
    // limit evaluation; any scheme), positions and vertex normals
    // interpolated linearly, MikkTSpace tangents of that mesh: what
    // triangle-mesh bakers measure from, and the frame a renderer drawing
    // that refined mesh with "tangents": "mikktspace" reads.
    Refined,
};

struct BakeSettings {
    int width = 1024, height = 1024; // map size in texels, 1..kMaxBakeSide
    int uvSet = 0;                   // the cage's UV set the maps are laid out in
    BakeSurface surface = BakeSurface::Limit;
    int refinedLevel = 2; // Refined: uniform level, 0..mesh::kMaxSubdivisionLevel
    int isolation = 4;    // Limit: adaptive isolation of the patch table, 1..10
    // How far (object units) the ray looks along +- the limit normal; 0: 5 %
    // of the diagonal of the cage's bounding box. The hit nearest to the
    // limit point wins (outwards on a tie).
    double maxDistance = 0;
    // Texels of padding grown around every chart (the value of the nearest
    // baked texel, found in rings of one texel), so that MIP levels do not
    // mix in the empty background. 0..1024.
    int padTexels = 8;
    // Also bake BakeResult::residualSlopes (the residual after
    // displacement): one more pass over the texels and
    // kBakeResidualBytesPerTexel more per texel.
    bool residual = false;
    int threads = 0; // surfgrad/base/threads.h; a count outside 0..1024 is a contract violation
    // Bytes the maps and their working grids may take (kBakeBytesPerTexel
    // per texel, plus kBakeResidualBytesPerTexel with `residual`); a larger map is refused before
    // anything is allocated. 0: mesh::defaultSubdivisionBudget() (half the physical memory).
    uint64_t memoryBudget = 0;
};

// Peak bytes per texel of bake(): the result's grids (65), the UV cover
// (32) and the padding's queues (13); with BakeSettings::residual also the
// residual's slopes (8) and its object normals while they are converted
// (12).
inline constexpr uint64_t kBakeBytesPerTexel = 110;
inline constexpr uint64_t kBakeResidualBytesPerTexel = 20;

// What each texel became.
enum class TexelState : uint8_t {
    Empty = 0,  // outside every chart (and beyond the padding)
    Hit = 1,    // baked: its ray hit the high mesh
    Miss = 2,   // inside a chart, but its ray found nothing within maxDistance
    Padded = 3, // outside the charts, filled from the nearest baked texel
};

struct BakeStats {
    size_t chartTexels = 0; // texels whose centre lies on the cage's UV layout
    size_t hits = 0, misses = 0;
    size_t padded = 0;
    // Texels whose UV is that of two points of the surface more than half a
    // texel apart (overlapping UV charts; not the two sides of a shared
    // patch edge). The claim deepest inside its patch's UV region keeps the
    // texel; the other point is not baked.
    size_t overlapTexels = 0;
    size_t patches = 0; // primitives of the base surface: patches (Limit), triangles (Refined)
    // Largest |st(u,v) - texel centre| left after Newton's method, in
    // texels (a texel whose preimage lies on another patch keeps the
    // nearest point of its own patch: this is that distance).
    double maxUvResidualTexels = 0;
    double maxDistance = 0; // the distance used (object units)
    double maxAbsDisplacement = 0;
    // Seconds per stage (steady clock).
    // secondsPad: the limit-frame slopes and the padding.
    double secondsPatches = 0, secondsHighMesh = 0, secondsCover = 0, secondsTexels = 0,
           secondsPad = 0;
};

struct BakeResult {
    int width = 0, height = 0;
    normalmap::Grid<uint8_t> state; // TexelState per texel
    // Object units along the base surface's unit normal, + outwards (0
    // where empty or missed, before padding).
    normalmap::ScalarField displacement;
    // The high mesh's unit normal at the hit, object space ((0,0,0) where
    // empty or missed, before padding).
    normalmap::NormalField objectNormal;
    // The same normal as slopes (dh/ds, dh/dt) in the base frame
    // (baseTangent, baseNormal): normalmap::normalsFromSlopes gives the
    // tangent-space map.
    normalmap::DerivField tangentSlopes;
    // The residual after displacement, slopes in the same frame: what a
    // normal map must add to a height layer of `displacement` (scale 1,
    // object units) for the two to resolve to the high mesh's normal
    // (surface gradients add; Mikkelsen 2019, section 2.5). Per hit: the
    // high normal's surface gradient minus the displacement's (listing 8
    // on the texel grid: central differences of the base position and the
    // displacement over neighbouring hits, one-sided at a chart's edge; a
    // hit with no hit neighbour along a texel axis keeps the full slopes).
    // Near zero where the displacement map resolves the high mesh's detail.
    // Empty (0 x 0) unless BakeSettings::residual.
    normalmap::DerivField residualSlopes;
    // The base surface at each texel (Empty, Padded: zero): the point, its
    // unit normal and the tangent frame of tangentSlopes (Limit: the limit
    // tangent of sg/patch/limit_tangent.glsl; Refined: the interpolated
    // MikkTSpace tangent, not normalised, sign in w).
    normalmap::NormalField basePosition;
    normalmap::NormalField baseNormal;
    normalmap::Grid<glm::vec4> baseTangent;
    BakeStats stats;
};

// Progress of bake(): the stage ("cover", "texels") and a fraction in
// [0, 1], called from the calling thread only. May be empty.
using BakeProgress = std::function<void(const char* stage, double fraction)>;

// Bakes `high` (a triangle mesh in the cage's object space; its normals are
// used when present, else area-weighted vertex normals are computed) onto
// the base surface of `cage` (validated; Catmull-Clark for the limit
// surface). Throws
// io::InputError naming the file, element and reason for: a cage whose
// scheme is not Catmull-Clark (file cageFile, element "scheme"), a UV set
// the cage lacks ("uv set K"), a map size or texel count beyond the limits
// or a size whose grids would exceed the memory budget ("size"), an
// isolation outside 1..10, padding outside 0..1024, a max
// distance that is negative or not finite, a high mesh without triangles
// or with a non-finite position or normal (highFile, "vertex N"), no
// texel centre on the cage's UV layout inside [0, 1]^2 (cageFile,
// "uv set K"), and no ray hitting the high mesh at all (highFile: the
// meshes do not overlap within maxDistance; a scale or placement
// mismatch). Misses of some texels are not an error: they are counted and
// marked (TexelState::Miss). Output is the same bits for every thread
// count.
BakeResult bake(const mesh::PolygonMesh& cage, const mesh::RenderMesh& high,
                const BakeSettings& settings, const std::string& cageFile = {},
                const std::string& highFile = {}, const BakeProgress& progress = {});

} // namespace sg::bake
