// Tangent frames for normal/bump mapping, one of three sources per UV set:
//
//  - TangentMethod::MikkTSpace: per-vertex tangents bit-compatible with
//    Morten S. Mikkelsen's MikkTSpace (Mikkelsen 2008, "Simulation of
//    Wrinkled Surfaces Revisited", section 4.2 and the published
//    mikktspace.c algorithm, default 180-degree angular threshold). Our own
//    implementation, written twice: a step-by-step reference (the oracle,
//    slow and simple) and a fast one; both produce the same bits.
//  - TangentMethod::Limit: the exact tangent frame of a subdivision limit
//    surface for one UV set: dP/ds, dP/dt from the limit derivatives
//    dP/du, dP/dv and the Jacobian d(s,t)/d(u,v) of the face-varying limit
//    UVs at the same parametric point (chain rule, see limitTangent()).
//  - TangentMethod::Pixel: nothing is stored; the fragment shader builds the
//    frame from screen-space derivatives of position and UV (Mikkelsen 2019
//    "Surface Gradient Based Bump Mapping Framework", section 2.3, and
//    shaders/sg/frame.glsl). Generating tangents for it is a no-op.
//
// Conventions (shared with surfgrad/mesh/render_mesh.h):
//  - object space, right-handed; UVs with (0,0) at the LOWER-left of the
//    image (t up, OpenGL);
//  - a tangent is vec4(xyz, w): xyz a unit vector along +s (dP/ds direction
//    projected into the tangent plane), w = +1 or -1 the handedness, with
//    bitangent = w * cross(normal, xyz). w = +1 where the UV chart is
//    orientation preserving (ds x dt has the same sense as the normal), -1
//    where it is mirrored.
//
// Errors: the preconditions below are contracts (surfgrad/base/contract.h: abort
// in checked builds, undefined behaviour otherwise). A mesh read from an
// untrusted file may violate them (a coordinate beyond 2^60, a UV set it
// lacks): callers holding one check it first with tangentInputProblem() or
// mikktspaceInputProblem() and raise sg::io::InputError with the reason.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "surfgrad/mesh/render_mesh.h"

namespace sg::mesh {

enum class TangentMethod {
    MikkTSpace, // vertex tangents, MikkTSpace-compatible
    Limit,      // exact tangent frame of the subdivision limit surface
    Pixel,      // none stored: built per pixel by the shader
};

// "mikktspace", "limit", "pixel".
std::string_view tangentMethodName(TangentMethod method);
// Inverse of tangentMethodName(); nullopt for any other string.
std::optional<TangentMethod> parseTangentMethod(std::string_view name);

// ---------------------------------------------------------------------------
// MikkTSpace
// ---------------------------------------------------------------------------

// An indexed polygon mesh as MikkTSpace sees it: faces of 3 or 4 corners,
// each corner an index into per-vertex position, normal and UV arrays.
// Only the VALUES of a corner matter: corners are welded by exact equality
// of (position, normal, uv), so how the caller split its vertices makes no
// difference (as in the reference).
//
// Preconditions (contract checks; mikktspaceInputProblem() names the first
// one an input violates): every value
// finite, |position and uv coordinates| <= 2^60, |normal components| <= 16
// (so no intermediate can become NaN); every index < positions.size();
// normals.size() == uvs.size() == positions.size(); faceSizes either empty
// (all faces are triangles and cornerVertices.size() is a multiple of 3) or
// summing to cornerVertices.size(); fewer than 2^28 triangles. Normals
// should be unit length (the reference assumes it; they are not
// renormalized). Outputs are never NaN; for absurdly large coordinates
// (dP/ds beyond 1e19) a tangent can collapse to 0 and magnitudes to +inf,
// exactly as in the reference.
struct MikkTSpaceInput {
    std::span<const glm::vec3> positions;     // per vertex, object space
    std::span<const glm::vec3> normals;       // per vertex, unit, object space
    std::span<const glm::vec2> uvs;           // per vertex, the UV set (s, t)
    std::span<const uint32_t> cornerVertices; // per face corner: vertex index
    // Per face: number of corners. Faces with other than 3 or 4 corners are
    // ignored, as by the reference: their corners get vec4(0) (triangulate
    // first). Quads are split along the shorter UV diagonal (the shorter
    // position diagonal on a tie, 0-2 on a second tie) and the tangents of
    // the two corners on the diagonal averaged, as in the reference.
    std::span<const uint32_t> faceSizes;
};

// Everything MikkTSpace computes for one face corner (its setTSpace
// callback). `tangent` is what glTF's TANGENT.xyz stores; `sign` its w.
struct MikkTSpaceFrame {
    glm::vec3 tangent{1.0f, 0.0f, 0.0f};   // unit, along +s, in the tangent plane
    float magS = 1.0f;                     // |dP/ds| (object units per UV unit)
    glm::vec3 bitangent{0.0f, 1.0f, 0.0f}; // unit, along +t (NOT cross(n, tangent))
    float magT = 1.0f;                     // |dP/dt|
    float sign = -1.0f;                    // +1 orientation preserving, -1 mirrored
};

// What the reference leaves in a corner it cannot give a frame to (a corner
// of a degenerate triangle that shares no welded vertex with a good one,
// or of a triangle whose UV area is zero and that no group reached):
// tangent (1,0,0), bitangent (0,1,0), magnitudes 1, sign -1. We keep it for
// compatibility; it is finite but need not be orthogonal to the normal.
inline constexpr MikkTSpaceFrame kMikkTSpaceDefaultFrame{};

// The first precondition of MikkTSpaceInput that `input` violates, as a
// sentence naming the vertex or corner; empty when it satisfies them all.
std::string mikktspaceInputProblem(const MikkTSpaceInput& input);

// Wall time of one step of the last MikkTSpaceGenerator::generate() call
// (the steps of docs/tangents.md), for the benchmark.
struct MikkTSpaceStepTime {
    const char* step; // static string
    double ms;
};

// Inputs with fewer triangles than this run on the calling thread whatever
// the thread count: below it the parallel steps cost more than they save
// (tangents_bench --cutover on 2 cores: 2 threads take 0.75x the one-thread
// speed at 2k triangles, 1.04x at 5k, 1.31x at 10k, 1.5-1.7x from 20k).
inline constexpr size_t kMikkTSpaceParallelCutover = 10000;

// The fast implementation: output identical (bit for bit) to the oracle's
// (mikktspaceReferenceFrames, surfgrad/mesh/mikktspace_reference.h), for every
// thread count. Keeps its scratch
// buffers between calls, so reuse one generator for many meshes or frames.
// Not thread-safe (one generator per calling thread); generate() itself
// runs its long steps on several cores (setThreads).
class MikkTSpaceGenerator {
public:
    MikkTSpaceGenerator();
    ~MikkTSpaceGenerator();
    MikkTSpaceGenerator(const MikkTSpaceGenerator&) = delete;
    MikkTSpaceGenerator& operator=(const MikkTSpaceGenerator&) = delete;

    // Fills cornerTangents (resized to cornerVertices.size()) with
    // vec4(frame.tangent, frame.sign) per face corner and, when `frames` is
    // not null, the complete frames. Preconditions: MikkTSpaceInput's.
    void generate(const MikkTSpaceInput& input, std::vector<glm::vec4>& cornerTangents,
                  std::vector<MikkTSpaceFrame>* frames = nullptr);

    // The SIMD kernels run 8 lanes wide with AVX2 when the CPU has it
    // (checked at run time), else 4 lanes (SSE2). The results are the same
    // bits either way; false forces the narrow path, for the tests that
    // check exactly that and for benchmarks.
    void setWideSimd(bool enabled);

    // How many threads generate() may use, by the convention of
    // surfgrad/base/threads.h: 0 (the default) = all cores (still capped by any
    // tbb::global_control the caller holds), 1 = the calling thread only,
    // 2..kMaxThreads (1024) a task arena of that size (sg::runWithThreads,
    // created by each call at or above the cut-over). The output is the
    // same bits for every value. Precondition (contract):
    // 0 <= threads <= kMaxThreads.
    void setThreads(int threads);
    // Inputs with fewer triangles than `triangles` run on the calling
    // thread (default kMikkTSpaceParallelCutover); 0 sends every input
    // through the parallel steps (the tests use it on small meshes).
    void setParallelCutover(size_t triangles);

    // The steps of the last generate() call and their wall times, in order.
    std::span<const MikkTSpaceStepTime> lastStepTimes() const;

private:
    struct Scratch;
    Scratch* scratch_;
    bool wideSimd_ = true;
    int threads_ = 0;
    size_t parallelCutover_ = kMikkTSpaceParallelCutover;
};

// The oracle the fast generator is tested against, a plain step-by-step
// implementation of the published algorithm, is test-only: target
// surfgrad_mesh_oracle, header surfgrad/mesh/mikktspace_reference.h (mesh/oracle/;
// not installed).

// The reference's rounding of a corner angle, (float)acos((double)cosine),
// for cosine in [-1, 1] (clamp first), bit for bit, mostly without calling
// libm's acos (see mesh/src/mikktspace_common.h). Exposed for the
// exhaustive check (bench: tangents_bench --check-acos) and the tests.
float mikktspaceAngleFromCos(float cosine);
// The same for many values in place (what the fast generator uses: four at
// a time with AVX2 when the CPU has it and allowWideSimd, else two with
// SSE2; same bits).
void mikktspaceAnglesFromCos(std::span<float> cosinesToAngles, bool allowWideSimd = true);

// Convenience: MikkTSpace tangents for `uvSet` of a RenderMesh (which must
// have normals), stored into mesh.tangents (replacing any), with
// mesh.tangentUvSet = uvSet. A vertex whose corners received different
// tangents (mirrored-UV seams, a vertex shared by faces whose frames MikkTSpace
// keeps apart, degenerate triangles) is split: the extra copies duplicate
// every per-vertex attribute (normals, all UV sets, morph-target deltas)
// and the index buffer is rewritten; vertices no triangle uses get the
// default frame. Preconditions: the mesh has normals, uvSet indexes
// mesh.uvSets, and MikkTSpaceInput's hold for that set
// (tangentInputProblem(mesh, TangentMethod::MikkTSpace, uvSet) is empty).
// `threads`: MikkTSpaceGenerator::setThreads (0 = all cores, 1 = this
// thread, up to kMaxThreads; meshes below kMikkTSpaceParallelCutover
// triangles stay on this thread); the result is the same bits for every
// count.
void generateMikkTSpaceTangents(RenderMesh& mesh, int uvSet, int threads = 0);

// Triangles of UV set `uvSet` whose UV area is within the rounding of their
// coordinates: |(t1 - t0) x (t2 - t0)| <= 16 * 2^-23 * M * L, M the largest
// |coordinate| of the three UVs, L their longest UV edge (zero areas
// included). MikkTSpace decides such a triangle's frame on its area (zero:
// its neighbours' frame; any non-zero area: the frame of that area's
// Jacobian), so a rounding-size change of one UV turns the frame by up to
// 90 degrees and flips its handedness (docs/tangents.md, "Charts with no
// frame"). The reference algorithm is kept bit for bit; this count tells
// the user that the frames of those triangles follow the rounding of the
// file. Precondition: uvSet indexes mesh.uvSets.
size_t uvAreaWithinRounding(const RenderMesh& mesh, int uvSet);

// Stores per-corner tangents (one per entry of mesh.indices) into
// mesh.tangents, splitting vertices whose corners disagree (bitwise) as
// described above. Corners that agree share one vertex. Returns the number
// of vertices added. Preconditions: cornerTangents.size() ==
// mesh.indices.size(), every index < mesh.vertexCount().
size_t applyCornerTangents(RenderMesh& mesh, int uvSet, std::span<const glm::vec4> cornerTangents);

// ---------------------------------------------------------------------------
// Limit-surface tangents
// ---------------------------------------------------------------------------

// How limitTangent() resolved one point.
enum class LimitTangentCase : uint8_t {
    Regular,           // both charts well conditioned: exact dP/ds
    DegenerateUv,      // UV Jacobian (near) singular: fallback along dP/du
    DegenerateSurface, // dP/du, dP/dv (near) parallel: no reliable chain rule
};

// The tangent frame of a parametric surface P(u,v) carrying UVs (s,t)(u,v),
// at one point, from first derivatives (object space; UV units):
//
//   [dP/du dP/dv] = [dP/ds dP/dt] J,   J = [[ds/du ds/dv], [dt/du dt/dv]]
//   => dP/ds = ( dt/dv dP/du - dt/du dP/dv) / det J
//      dP/dt = (-ds/dv dP/du + ds/du dP/dv) / det J
//
// and N = normalize(dP/du x dP/dv). Returns vec4(T, w) with T the unit
// vector along dP/ds made orthogonal to N (Gram-Schmidt; dP/ds is already
// tangent to the surface, the projection only removes rounding) and
// w = sign(det J) (+1 when the UV chart preserves the orientation of the
// (u,v) chart whose normal is N, -1 when mirrored), so that
// w * cross(N, T) points to the +t side, as MikkTSpace.
//
// Conditioning: the chain rule divides by the sine of the angle between
// the two derivatives of each chart. A point is Regular when both sines
// (|dP/du x dP/dv| / (|dP/du| |dP/dv|) and |det J| / (|J e_u| |J e_v|)) exceed
// 1e-3; float inputs then give T to ~1e-4 rad. Otherwise (never NaN, always
// unit xyz and w = +-1):
//  - DegenerateUv (zero-area or collapsed UVs, surface fine): T = dP/du
//    made orthogonal to N (dP/dv if dP/du vanishes), w = +1;
//  - DegenerateSurface (dP/du, dP/dv parallel or zero, e.g. the collapsed
//    parameterization at a smooth boundary corner of a Catmull-Clark
//    surface): T = normalize(dP/ds) if the UV chart is regular, else
//    normalize(dP/du), else normalize(dP/dv), else (1,0,0); w = sign(det J)
//    if the UV chart is regular, else +1.
// generateLimitTangents() replaces these per-point fallbacks by the mean of
// the regular neighbours when there are any.
glm::vec4 limitTangent(const glm::vec3& dPdu, const glm::vec3& dPdv, const glm::vec2& dSTdu,
                       const glm::vec2& dSTdv, LimitTangentCase* resolved = nullptr);

// limitTangent() over arrays of equal length (one entry per limit point);
// `out` must have the same length (precondition). Returns the number of
// points that were not LimitTangentCase::Regular.
size_t limitTangents(std::span<const glm::vec3> dPdu, std::span<const glm::vec3> dPdv,
                     std::span<const glm::vec2> dSTdu, std::span<const glm::vec2> dSTdv,
                     std::span<glm::vec4> out);

// Limit tangents of a mesh that sg::mesh::Subdivider built with limit
// evaluation (positions, normals and UVs on the limit surface; `frame` its
// limitFrame(), aligned with the vertices): limitTangent() per vertex for
// `uvSet`; a vertex that is not Regular but has regular neighbours
// (sharing a triangle) takes the w of their majority and the normalized sum
// of their tangents with that w; otherwise it keeps limitTangent()'s
// fallback. Then every tangent
// is made orthogonal to the stored vertex normal (the limit normal, or the
// subdivider's fallback where dP/du x dP/dv vanishes; if the tangent is
// parallel to it, any unit vector orthogonal to it). No vertex is split:
// each vertex already has one home location and one UV chart.
// Stores mesh.tangents, mesh.tangentUvSet = uvSet; returns the number of
// vertices that were not LimitTangentCase::Regular. Preconditions: uvSet
// indexes mesh.uvSets and `frame` matches the mesh (one entry per vertex,
// UV derivatives for uvSet).
size_t generateLimitTangents(RenderMesh& mesh, const LimitFrame& frame, int uvSet);

// One entry point for the three methods: MikkTSpace
// (generateMikkTSpaceTangents), Limit (generateLimitTangents; `frame` must
// be the subdivider's limit frame), Pixel (tangents cleared,
// tangentUvSet = -1: the shader builds the frame). Returns the number of
// vertices added (MikkTSpace) or irregular (Limit); 0 for Pixel.
// `threads` goes to generateMikkTSpaceTangents (the other methods run on
// this thread). Preconditions: those of the method's function
// (tangentInputProblem() is empty), 0 <= threads <= kMaxThreads.
size_t generateTangents(RenderMesh& mesh, TangentMethod method, int uvSet,
                        const LimitFrame* frame = nullptr, int threads = 0);

// Why generateTangents(mesh, method, uvSet, frame) would violate its
// preconditions, as a sentence (MikkTSpace: no vertex normals, no UV set
// uvSet, or a value or index MikkTSpaceInput does not allow; Limit: no limit
// frame, no UV set uvSet, or a frame that does not match the mesh); empty
// when it would not (always for Pixel). Meshes read from files are checked
// with this and rejected with sg::io::InputError (`surfgrad mesh tangents`,
// the renderer's assets).
std::string tangentInputProblem(const RenderMesh& mesh, TangentMethod method, int uvSet,
                                const LimitFrame* frame = nullptr);

} // namespace sg::mesh
