// Subdivision of a control cage with OpenSubdiv: uniform refinement to level
// N (Far::TopologyRefiner + PrimvarRefiner, UV sets as face-varying
// channels), optional limit evaluation at the refined vertices (positions,
// normals, UVs and their first derivatives, Far::LimitStencilTable on an
// adaptively refined copy), and per-frame updates of an animated cage
// through stencil tables built once.
//
// Math: Catmull & Clark 1978, Loop 1987, semi-sharp creases DeRose, Kass &
// Truong 1998, as implemented by OpenSubdiv 3.5 Sdc/Vtr/Far; limit
// evaluation by feature-adaptive patches (Niessner et al. 2012) with
// Gregory-basis end caps.
//
// Every (u,v) handed to OpenSubdiv's patch evaluation is finite and clamped
// to [0,1] first: PatchTable::EvaluateBasis spins forever outside the
// domain (docs/platform.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/render_mesh.h"

namespace sg::mesh {

inline constexpr int kMaxSubdivisionLevel = 8;

// Serial cut-over of SubdivisionSettings::threads: a build whose level-N
// face count (estimated from the cage, before refining) is below this runs
// on the calling thread whatever the count, and so do its update() calls.
// Measured (mesh_bench --threads-only, idle 2-core machine): with every
// loop on TBB, refinement of spot at 2,880 faces took 2.3x one thread's time
// and at 46,080 faces 1.17x, but the stencil updates of a build of 46,080
// faces already gain 1.7x (and refinement itself from ~184k faces up):
// the cut-over sits at 2^15, for the per-frame updates.
inline constexpr uint64_t kSerialBelowFaces = 32768;

struct SubdivisionSettings {
    int level = 2;         // uniform refinement level, 0..kMaxSubdivisionLevel
    SubdivOptions options; // scheme and rules (start from cage.options, apply flags)
    // Evaluate the limit surface at the refined vertices: refined() and
    // renderMesh() then hold limit positions, limit normals and limit UVs,
    // and limitFrame() the derivatives (see LimitFrame in render_mesh.h).
    bool limit = false;
    bool buildRenderMesh = true; // false: refined() only (benchmarks, OBJ/PLY output)
    // Build the stencil tables update() needs (costs about as much as one
    // more refinement; only worth it for animated cages).
    bool animate = false;
    // Refused (InputError) before refining when the level-N face count
    // would exceed this (keeps every index within 32 bits).
    size_t maxRefinedFaces = size_t(1) << 24;
    // Bytes build() may take at its peak (estimateSubdivisionCost): a build
    // that needs more is refused before anything is allocated, with an
    // InputError naming the level, the face count and the bytes needed.
    // 0: defaultSubdivisionBudget().
    uint64_t memoryBudget = 0;
    // How the caller's user raises memoryBudget, quoted in that refusal
    // ("--max-memory SIZE"); empty: not quoted.
    std::string memoryBudgetHint;
    // A build whose cage has the same topology, tags, level and options as
    // the previous uniform build of this Subdivider reuses its refiner and
    // applies factored stencils to the new positions/UVs (recorded on the
    // first repeat). false: always refine from scratch.
    bool reuseTopology = true;
    // Uniform Catmull-Clark builds without limit evaluation of a manifold
    // cage without holes take surfgrad's specialised refiner (mesh/src/
    // uniform_refiner.h): the same refined() as OpenSubdiv's
    // TopologyRefiner::RefineUniform + PrimvarRefiner bit for bit (same
    // numbering, weights and order of operations; tested on every accepted
    // osd-shape), 3-4x faster. Other cages, and UV seams through a vertex
    // with semi-sharp creasing, take OpenSubdiv's Far (see
    // Subdivider::usedSpecializedRefiner). false: always Far.
    bool specializedRefiner = true;
    // Threads (surfgrad/base/threads.h): 0 all cores, 1 the calling thread only,
    // 2..1024 a task arena of that many; a count outside 0..1024 is a
    // contract violation (surfgrad/base/contract.h). build() and update() give
    // the same refined(), renderMesh() and limitFrame() bit for bit for
    // every count: the parallel loops write disjoint outputs, each
    // element's sums run in the serial order, and lists gathered per
    // element are cut in fixed blocks. On TBB: the specialised refiner's
    // topology and interpolation per level, factored stencil application
    // (update(), rebuilds of the same topology), render vertices and
    // normals, and with limit the home locations, the per-sample basis
    // weights, positions, derivatives and UVs. Serial: OpenSubdiv's own
    // steps (the level-0 factory, Far's RefineUniform/RefineAdaptive,
    // PrimvarRefiner for cages the specialised refiner declines, the
    // PatchTableFactory, stencil recording), the render-vertex split and the
    // offsets (prefix sums). Builds below serialBelowFaces stay serial.
    int threads = 0;
    // Level-N faces below which a build (and its update() calls) stays on
    // the calling thread whatever `threads` says. Default: the measured
    // cut-over; 0 runs every build's loops on TBB in blocks of 16 elements
    // (tests: small cages then cross many block boundaries).
    uint64_t serialBelowFaces = kSerialBelowFaces;
};

// Seconds spent in each stage of the last build() (steady clock).
struct SubdivisionTimings {
    double convertIn = 0;   // PolygonMesh -> Far::TopologyDescriptor arrays
    double topology = 0;    // level 0 (TopologyRefinerFactory) + uniform topology refinement
    double interpolate = 0; // PrimvarRefiner: positions, UVs, morph deltas
    double convertOut = 0;  // level-N topology -> refined() polygons
    double limit = 0;       // limit stencils + evaluation (limit only)
    double render = 0;      // triangulation, vertex split, normals
    double stencils = 0;    // stencil tables for update() (animate only)
};

class Subdivider {
public:
    Subdivider();
    // Same as build(cage, settings, file).
    Subdivider(const PolygonMesh& cage, const SubdivisionSettings& settings,
               const std::string& file = {});
    ~Subdivider();
    Subdivider(Subdivider&&) noexcept;
    Subdivider& operator=(Subdivider&&) noexcept;

    // Refines `cage` (which must have passed validate()). Reuses this
    // object's buffers from the previous build (call it again instead of
    // constructing a new Subdivider to avoid page faults on big levels), and
    // its refined topology when only values changed (see reuseTopology).
    // Throws InputError (file, element, reason) when OpenSubdiv cannot take
    // the cage: Loop with a non-triangle face, a level outside
    // 0..kMaxSubdivisionLevel, a refined size above maxRefinedFaces, an
    // estimated peak memory above memoryBudget (element "level N"). Holes:
    // hole faces and their descendants are left out of every output.
    void build(const PolygonMesh& cage, const SubdivisionSettings& settings,
               const std::string& file = {});

    const SubdivisionSettings& settings() const;

    // Level-N polygons (quads for Catmark/bilinear, triangles for Loop; holes
    // removed), positions (refined points, or limit points with limit), UV
    // sets (face-varying, refined or limit), per-vertex normals
    // (normalIndices == faceVertices), crease/corner tags of level N (the
    // sharpness left after N levels), options of the cage, morph targets'
    // refined position deltas.
    const PolygonMesh& refined() const;

    // Triangulated refined mesh (each quad split along its 0-2 diagonal),
    // vertices split at UV seams and at infinitely sharp creases, normals:
    // limit normals with limit, else area-weighted face normals per smooth
    // sector. morphTargets hold refined position deltas. Empty when
    // settings.buildRenderMesh is false.
    const RenderMesh& renderMesh() const;
    // Render vertex -> vertex of refined() (several render vertices share
    // one refined vertex across seams).
    const std::vector<uint32_t>& renderToRefinedVertex() const;

    // Limit derivatives aligned with renderMesh() (empty unless limit).
    const LimitFrame& limitFrame() const;

    // Animated cage (settings.animate): recomputes out.positions and
    // out.normals (and frame->dPdu/dPdv with limit) for new cage positions
    // (cage.vertexCount() entries, object space) by applying stencil tables;
    // nothing else is touched and nothing is allocated once `out` has been
    // filled once. `out` must have renderMesh()'s vertex count (start from a
    // copy of renderMesh()). Positions must be finite. Preconditions
    // (contract checks, surfgrad/base/contract.h): settings.animate, and the two
    // sizes above.
    // recomputeNormals = false leaves out.normals alone (callers that
    // morph or shade without them). Not safe to call concurrently on one
    // Subdivider (it keeps scratch buffers).
    void update(std::span<const glm::vec3> cagePositions, RenderMesh& out,
                LimitFrame* frame = nullptr, bool recomputeNormals = true) const;

    const SubdivisionTimings& timings() const;
    // Whether the last build refined with the specialised refiner (see
    // SubdivisionSettings::specializedRefiner) and, when it did not, why
    // ("non-manifold or isolated vertex 12", "holes", "limit evaluation", ...).
    bool usedSpecializedRefiner() const;
    const std::string& specializedRefinerDeclined() const;
    size_t cageVertexCount() const;
    // Weights in the stencil tables update() applies (its memory traffic):
    // the uniform levels, or with limit the adaptive levels, local points and
    // per-sample patch weights. 0 before they are built.
    size_t stencilWeightCount() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// What Subdivider::build(cage, settings) will take, estimated from the
// cage alone before anything is allocated (mesh/src/subdivision_budget.cpp).
// The counts of level N are exact for every scheme, face kind and UV
// layout (each scheme's growth per level); `bytes` is the peak of live heap
// bytes of build(), from per-element coefficients of every stage (all
// levels' topology, level N's values, the render mesh, the limit patches,
// stencils and samples, the animation stencils): on the test cages within
// [1, 2.5] times the measured peak (tests/mesh/subdivision_budget_test.cpp).
// Costs O(C log C) for a cage of C face corners.
struct SubdivisionCost {
    int level = 0;
    int isolation = 0; // limit: adaptive isolation level (0 without limit)
    // Level N of the uniform refinement (faces: before holes are removed).
    uint64_t faces = 0, vertices = 0, edges = 0, corners = 0;
    uint64_t fvarValues = 0;     // level-N UV values, all sets
    uint64_t renderVertices = 0; // vertices of renderMesh() (split at UV seams)
    uint64_t irregular = 0;      // limit: cage features isolated adaptively
    uint64_t bytes = 0;          // peak heap bytes of build()
    // Sums over levels 0..N (the topology every refiner keeps).
    double sumV = 0, sumE = 0, sumF = 0, sumC = 0, sumFV = 0;
};
SubdivisionCost estimateSubdivisionCost(const PolygonMesh& cage,
                                        const SubdivisionSettings& settings);

// The memory budget of a build when SubdivisionSettings::memoryBudget is 0:
// half the machine's physical memory, and at most three quarters of the
// process's address-space or data limit (ulimit -v / -d) when one is set.
uint64_t defaultSubdivisionBudget();

// "1.5 GiB", "640 MiB", "12 KiB", "100 B": byte counts in messages.
std::string formatByteSize(uint64_t bytes);

// Area-weighted vertex normals of a triangle mesh, accumulated over all
// render vertices that share `smoothGroup[v]` (pass an empty span to treat
// every render vertex on its own). A vertex whose accumulated normal
// vanishes gets the normal of its first non-degenerate triangle, else +z.
// Precondition (contract check): smoothGroup is empty or has one entry per
// vertex.
void computeVertexNormals(RenderMesh& mesh, std::span<const uint32_t> smoothGroup = {});

} // namespace sg::mesh
