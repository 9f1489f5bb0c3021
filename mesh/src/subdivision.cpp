// Subdivision with OpenSubdiv 3.5 (surfgrad/subdivision.h).
//
// build():
//  1. PolygonMesh -> Far::TopologyDescriptor (arrays are used in place;
//     creases, corners, holes and one face-varying channel per UV set);
//  2. uniform refinement to level N; positions (and morph deltas)
//     through PrimvarRefiner::Interpolate, UVs through
//     InterpolateFaceVarying, ping-pong buffers kept between builds. A
//     manifold Catmull-Clark cage (without a limit evaluation) takes the
//     specialised refiner of uniform_refiner.h instead: the same numbers
//     bit for bit from OpenSubdiv's level 0, 3-4x faster;
//  3. level-N faces (holes dropped) -> refined() polygons;
//  4. limit (optional): a second, adaptively refined TopologyRefiner
//     (isolation >= N, so every level-N vertex is a patch corner and patch
//     corners are exact limit points, Gregory-basis end caps included), a
//     PatchTable with face-varying patches, and for every render vertex its
//     home location (ptex face, u, v) found by following the uniform
//     refinement's parent/child relations (see locateCorners). Each location
//     is evaluated once into per-sample basis weights (PatchTable::
//     EvaluateBasis / EvaluateBasisFaceVarying), so positions, normals and
//     derivatives come from one weight table that update() reuses;
//  5. render mesh: vertices split at UV seams and at infinitely sharp
//     edges (convert.cpp), quads split along 0-2.
//
// update(): the refined points are linear in the cage, so both the uniform
// refinement and the adaptive points are applied as "factored stencils":
// one sparse matrix per refinement level recorded from PrimvarRefiner (a few
// weights per point: ~3x fewer than Far's flattened StencilTable at level 4
// on spot, and no 50 ms StencilTableFactory build), applied level by level
// with plain loops (Osd's CpuEvaluator takes a slow path for stride-3 data,
// docs/platform.md).
#include "surfgrad/subdivision.h"
#include "surfgrad/adaptive_patches.h"

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <unordered_map>

#include "mesh_internal.h"
#include "surfgrad/contract.h"
#include "surfgrad/mesh_io.h"
#include "surfgrad/osd_primvar.h"
#include "surfgrad/threads.h"
#include "subdivision_parallel.h"
#include "uniform_refiner.h"

namespace sg::mesh {

using io::InputError;
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

namespace {

// ---- OpenSubdiv plumbing -----------------------------------------------------

thread_local std::string tFarError;

void farError(Far::ErrorType, const char* message) {
    if (tFarError.size() < 400) tFarError += (tFarError.empty() ? "" : "; ") + std::string(message);
}
void farWarning(const char*) {} // warnings are about topology we validated already

void installFarCallbacks() {
    static std::once_flag once;
    std::call_once(once, [] {
        Far::SetErrorCallback(&farError);
        Far::SetWarningCallback(&farWarning);
    });
}

// Records PrimvarRefiner's weights: each child's Clear() starts a row, the
// AddWithWeight calls that follow fill it.
struct Token {
    uint32_t index;
};
struct TokenView {
    uint32_t base;
    Token operator[](int i) const { return {base + uint32_t(i)}; }
};
struct RecordedRows {
    uint32_t dstBase = 0;           // global index of the child level's first point
    std::vector<uint32_t> rowOf;    // per recorded row: its child index
    std::vector<uint32_t> rowStart; // per recorded row: first entry
    std::vector<uint32_t> src;      // global point indices
    std::vector<float> weight;
};
struct RecorderRef {
    RecordedRows* rows;
    uint32_t child;
    void Clear() {
        rows->rowOf.push_back(child);
        rows->rowStart.push_back(uint32_t(rows->src.size()));
    }
    void AddWithWeight(const Token& t, float w) {
        rows->src.push_back(t.index);
        rows->weight.push_back(w);
    }
    // PrimvarRefiner reuses child points it computed before (face points in
    // edge and vertex points): a reference into the child level itself.
    void AddWithWeight(const RecorderRef& c, float w) {
        rows->src.push_back(rows->dstBase + c.child);
        rows->weight.push_back(w);
    }
};
struct RecorderView {
    RecordedRows* rows;
    RecorderRef operator[](int i) const { return {rows, uint32_t(i)}; }
};

Sdc::SchemeType sdcScheme(Scheme s) {
    switch (s) {
    case Scheme::Loop:
        return Sdc::SCHEME_LOOP;
    case Scheme::Bilinear:
        return Sdc::SCHEME_BILINEAR;
    default:
        return Sdc::SCHEME_CATMARK;
    }
}

Sdc::Options sdcOptions(const SubdivOptions& o) {
    Sdc::Options opt;
    static constexpr Sdc::Options::VtxBoundaryInterpolation kVtx[3] = {
        Sdc::Options::VTX_BOUNDARY_NONE, Sdc::Options::VTX_BOUNDARY_EDGE_ONLY,
        Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER};
    static constexpr Sdc::Options::FVarLinearInterpolation kFVar[6] = {
        Sdc::Options::FVAR_LINEAR_NONE,          Sdc::Options::FVAR_LINEAR_CORNERS_ONLY,
        Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1, Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2,
        Sdc::Options::FVAR_LINEAR_BOUNDARIES,    Sdc::Options::FVAR_LINEAR_ALL};
    opt.SetVtxBoundaryInterpolation(kVtx[int(o.boundary)]);
    opt.SetFVarLinearInterpolation(kFVar[int(o.fvar)]);
    opt.SetCreasingMethod(o.creaseMethod == CreaseMethod::Chaikin ? Sdc::Options::CREASE_CHAIKIN
                                                                  : Sdc::Options::CREASE_UNIFORM);
    opt.SetTriangleSubdivision(o.triangles == TriangleRule::Smooth ? Sdc::Options::TRI_SUB_SMOOTH
                                                                   : Sdc::Options::TRI_SUB_CATMARK);
    return opt;
}

// Descriptor arrays for one cage (the descriptor points into them).
struct Descriptor {
    std::vector<int> creasePairs, corners, holes;
    std::vector<float> creaseWeights, cornerWeights;
    std::vector<Far::TopologyDescriptor::FVarChannel> channels;
    Far::TopologyDescriptor desc;

    void build(const PolygonMesh& cage) {
        creasePairs.clear();
        creaseWeights.clear();
        for (const EdgeCrease& c : cage.creases) {
            creasePairs.push_back(int(c.v0));
            creasePairs.push_back(int(c.v1));
            creaseWeights.push_back(c.sharpness);
        }
        corners.clear();
        cornerWeights.clear();
        for (const VertexCorner& c : cage.corners) {
            corners.push_back(int(c.vertex));
            cornerWeights.push_back(c.sharpness);
        }
        holes.assign(cage.holes.begin(), cage.holes.end());
        channels.resize(cage.uvSets.size());
        for (size_t s = 0; s < cage.uvSets.size(); ++s) {
            channels[s].numValues = int(cage.uvSets[s].values.size());
            // uint32_t and int may alias (same type, other signedness).
            channels[s].valueIndices =
                reinterpret_cast<const Far::Index*>(cage.uvSets[s].indices.data());
        }
        desc = Far::TopologyDescriptor();
        desc.numVertices = int(cage.positions.size());
        desc.numFaces = int(cage.faceSizes.size());
        desc.numVertsPerFace = reinterpret_cast<const int*>(cage.faceSizes.data());
        desc.vertIndicesPerFace = reinterpret_cast<const Far::Index*>(cage.faceVertices.data());
        desc.numCreases = int(creaseWeights.size());
        desc.creaseVertexIndexPairs = creasePairs.data();
        desc.creaseWeights = creaseWeights.data();
        desc.numCorners = int(corners.size());
        desc.cornerVertexIndices = corners.data();
        desc.cornerWeights = cornerWeights.data();
        desc.numHoles = int(holes.size());
        desc.holeIndices = holes.data();
        desc.numFVarChannels = int(channels.size());
        desc.fvarChannels = channels.empty() ? nullptr : channels.data();
        desc.isLeftHanded = false;
    }
};

std::unique_ptr<Far::TopologyRefiner> createRefiner(const Descriptor& d, const SubdivOptions& o,
                                                    const std::string& file) {
    installFarCallbacks();
    tFarError.clear();
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> r(
        Factory::Create(d.desc, Factory::Options(sdcScheme(o.scheme), sdcOptions(o))));
    if (!r)
        throw InputError(file, "topology",
                         "OpenSubdiv rejected the mesh: " +
                             (tFarError.empty() ? std::string("no reason given") : tFarError));
    return r;
}

// ---- Factored stencils -------------------------------------------------------

// One sparse matrix per refinement step; all points of all levels (and the
// local points of a patch table) live in one array, level after level.
// Rows are kept in the order PrimvarRefiner computed them (face points
// before the edge and vertex points that reuse them), each with its
// destination.
//
// Waves (for threads): rows [waves[i], waves[i + 1]) read no point that a
// row of the same wave writes, so a wave's rows can run in any order and
// the waves run in order; each row's sum runs in its recorded order, so the
// result is the same bits as the serial loop. A PrimvarRefiner level has
// two waves (face points; edge and vertex points, which read face points).
struct StencilBlock {
    uint32_t dstBase = 0, count = 0;
    std::vector<uint32_t> dst;     // per row: destination offset from dstBase (empty: row i -> i)
    std::vector<uint32_t> offsets; // count + 1
    std::vector<uint32_t> src;     // global point indices
    std::vector<float> weight;
    std::vector<uint32_t> waves; // row boundaries, waves.front() = 0, waves.back() = count

    uint32_t dstOf(uint32_t row) const { return dst.empty() ? row : dst[row]; }
    // Splits the rows into waves (serial, O(weights)). A row that reads a
    // point this block writes only later (never seen in OpenSubdiv's
    // tables: it would read the previous apply's value) makes the whole
    // block one serial wave.
    void computeWaves() {
        constexpr uint32_t kUnwritten = UINT32_MAX, kLater = UINT32_MAX - 1;
        uint32_t span = 0;
        for (uint32_t i = 0; i < count; ++i) span = std::max(span, dstOf(i) + 1);
        std::vector<uint32_t> waveOf(span, kUnwritten);
        for (uint32_t i = 0; i < count; ++i) waveOf[dstOf(i)] = kLater;
        waves.assign(1, 0);
        uint32_t wave = 0;
        for (uint32_t i = 0; i < count; ++i) {
            bool newWave = false;
            for (uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
                if (src[k] < dstBase || src[k] - dstBase >= span) continue;
                const uint32_t w = waveOf[src[k] - dstBase];
                if (w == kLater) {
                    waves.assign({0, count}); // read before write: serial
                    serial = true;
                    return;
                }
                newWave |= w == wave;
            }
            if (newWave) {
                waves.push_back(i);
                ++wave;
            }
            waveOf[dstOf(i)] = wave;
        }
        waves.push_back(count);
        serial = false;
    }
    bool serial = false;
};

struct FactoredStencils {
    uint32_t numControl = 0, numPoints = 0;
    std::vector<StencilBlock> blocks;

    // Records refinement step `level` (1-based) of `refiner` as a block
    // reading the previous level at srcBase and writing at dstBase.
    // fvarChannel >= 0 records InterpolateFaceVarying of that channel.
    void recordLevel(const Far::TopologyRefiner& refiner, int level, uint32_t srcBase,
                     uint32_t dstBase, int fvarChannel = -1) {
        const int nChild = fvarChannel < 0 ? refiner.GetLevel(level).GetNumVertices()
                                           : refiner.GetLevel(level).GetNumFVarValues(fvarChannel);
        record(uint32_t(nChild), srcBase, dstBase, [&](const TokenView& src, RecorderView& dst) {
            Far::PrimvarRefiner primvar(refiner);
            if (fvarChannel < 0)
                primvar.Interpolate(level, src, dst);
            else
                primvar.InterpolateFaceVarying(level, src, dst, fvarChannel);
        });
    }
    // The same from the specialised refiner (uniform_refiner.h), through
    // its writer protocol.
    void recordLevel(const detail::UniformRefiner& refiner, int level, uint32_t srcBase,
                     uint32_t dstBase, int fvarChannel = -1) {
        const uint32_t nChild = fvarChannel < 0 ? refiner.level(level).numVerts
                                                : refiner.numFVarValues(level, fvarChannel);
        record(nChild, srcBase, dstBase, [&](const TokenView& src, RecorderView& dst) {
            struct Writer {
                RecordedRows* rows;
                uint32_t srcBase;
                void begin(uint32_t child) {
                    rows->rowOf.push_back(child);
                    rows->rowStart.push_back(uint32_t(rows->src.size()));
                }
                void add(uint32_t parent, float w) {
                    rows->src.push_back(srcBase + parent);
                    rows->weight.push_back(w);
                }
                void addChild(uint32_t child, float w) {
                    rows->src.push_back(rows->dstBase + child);
                    rows->weight.push_back(w);
                }
                void end() {}
            } writer{dst.rows, src.base};
            if (fvarChannel < 0)
                refiner.interpolate(level, writer);
            else
                refiner.interpolateFaceVarying(level, writer, fvarChannel);
        });
    }
    template <class Interpolate>
    void record(uint32_t nChild, uint32_t srcBase, uint32_t dstBase, Interpolate&& interpolate) {
        RecordedRows rows;
        rows.dstBase = dstBase;
        rows.rowOf.reserve(size_t(nChild));
        rows.rowStart.reserve(size_t(nChild));
        TokenView src{srcBase};
        RecorderView dst{&rows};
        interpolate(src, dst);
        StencilBlock b;
        b.dstBase = dstBase;
        b.count = uint32_t(rows.rowOf.size());
        b.dst = std::move(rows.rowOf);
        b.offsets = std::move(rows.rowStart);
        b.offsets.push_back(uint32_t(rows.src.size()));
        b.src = std::move(rows.src);
        b.weight = std::move(rows.weight);
        b.computeWaves();
        blocks.push_back(std::move(b));
    }

    // A Far stencil table whose control indices are global point indices.
    // (StencilTableReal<float>, not StencilTable: PatchTable creates its
    // local-point tables as the former, and its non-template getters
    // static_cast them to the latter, a downcast UBSan rejects.)
    void appendTable(const Far::StencilTableReal<float>& table, uint32_t dstBase) {
        StencilBlock b;
        b.dstBase = dstBase;
        b.count = uint32_t(table.GetNumStencils());
        const auto& sizes = table.GetSizes();
        const auto& idx = table.GetControlIndices();
        const auto& w = table.GetWeights();
        b.offsets.resize(size_t(b.count) + 1);
        uint32_t at = 0;
        for (uint32_t s = 0; s < b.count; ++s) {
            b.offsets[s] = at;
            at += uint32_t(sizes[s]);
        }
        b.offsets[b.count] = at;
        b.src.assign(idx.begin(), idx.begin() + at);
        b.weight.assign(w.begin(), w.begin() + at);
        b.computeWaves();
        blocks.push_back(std::move(b));
    }

    size_t weightCount() const {
        size_t n = 0;
        for (const StencilBlock& b : blocks) n += b.src.size();
        return n;
    }

    // points[0, numControl) must hold the control values. Blocks in order,
    // each block's waves in order, a wave's rows on TBB with par.on (each
    // row's sum in its recorded order: the same bits for any thread count).
    template <class V>
    void apply(V* points, const detail::Parallel& par = {}) const {
        for (const StencilBlock& b : blocks) {
            const uint32_t* off = b.offsets.data();
            const uint32_t* src = b.src.data();
            const float* w = b.weight.data();
            V* dst = points + b.dstBase;
            const uint32_t* row = b.dst.empty() ? nullptr : b.dst.data();
            auto rows = [&](size_t begin, size_t end) {
                for (size_t i = begin; i < end; ++i) {
                    V acc(0.0f);
                    for (uint32_t k = off[i]; k < off[i + 1]; ++k) acc += w[k] * points[src[k]];
                    dst[row ? row[i] : i] = acc;
                }
            };
            for (size_t v = 0; v + 1 < b.waves.size(); ++v) {
                const uint32_t first = b.waves[v];
                (b.serial ? detail::Parallel{} : par)
                    .blocks(b.waves[v + 1] - first,
                            [&](size_t lo, size_t hi) { rows(first + lo, first + hi); });
            }
        }
    }
};

// ---- Limit samples -----------------------------------------------------------

// Basis weights per sample: the value at the home location and the two
// first derivatives (at the same point for B-spline patches, a hair inside
// the home face for end caps, see evaluateLimit). One list of patch points
// per sample with three weights each, so a point shared by the value and
// the derivatives is read once per frame; exact zero weights are dropped
// (a B-spline patch evaluated at a corner has 9 non-zero of 16).
struct SampleTable {
    std::vector<uint32_t> offsets, point;
    std::vector<glm::vec3> weight; // (value, d/du, d/dv)

    void clear() {
        offsets.assign(1, 0);
        point.clear();
        weight.clear();
    }
    // Value weights from one patch, derivative weights from another (or the
    // same) patch.
    void add(const Far::ConstIndexArray& cvsP, const float* p, const Far::ConstIndexArray& cvsD,
             const float* du, const float* dv) {
        const size_t first = point.size();
        for (int k = 0; k < cvsP.size(); ++k) {
            if (p[k] == 0.0f) continue;
            point.push_back(uint32_t(cvsP[k]));
            weight.push_back(glm::vec3(p[k], 0.0f, 0.0f));
        }
        const size_t valueEnd = point.size();
        for (int k = 0; k < cvsD.size(); ++k) {
            if (du[k] == 0.0f && dv[k] == 0.0f) continue;
            size_t at = valueEnd;
            for (size_t j = first; j < valueEnd; ++j) {
                if (point[j] == uint32_t(cvsD[k])) at = j;
            }
            if (at == valueEnd) {
                point.push_back(uint32_t(cvsD[k]));
                weight.push_back(glm::vec3(0.0f, du[k], dv[k]));
            } else {
                weight[at].y = du[k];
                weight[at].z = dv[k];
            }
        }
        offsets.push_back(uint32_t(point.size()));
    }
    // V: the points' type (glm::vec3, or glm::vec4 with xyz in the first
    // three lanes, the arithmetic then done on 4 lanes); Out: the results'.
    // With par.on, samples on TBB (each writes its own three outputs).
    template <class V, class Out>
    void evaluate(const V* points, Out* value, Out* du, Out* dv,
                  const detail::Parallel& par = {}) const {
        par.each(offsets.size() - 1, [&](size_t s) {
            V a(0.0f), b(0.0f), c(0.0f);
            for (uint32_t k = offsets[s]; k < offsets[s + 1]; ++k) {
                const V& x = points[point[k]];
                const glm::vec3& w = weight[k];
                a += w.x * x;
                b += w.y * x;
                c += w.z * x;
            }
            value[s] = Out(a);
            du[s] = Out(b);
            dv[s] = Out(c);
        });
    }
    // Appends `block`'s samples (a table of consecutive samples built on
    // its own, offsets from 0).
    void append(const SampleTable& block) {
        const uint32_t base = uint32_t(point.size());
        point.insert(point.end(), block.point.begin(), block.point.end());
        weight.insert(weight.end(), block.weight.begin(), block.weight.end());
        for (size_t i = 1; i < block.offsets.size(); ++i)
            offsets.push_back(base + block.offsets[i]);
    }
};

// The middle of the bounding box of `p` (0 for none): limit evaluation runs
// on positions relative to it. Its derivative weights are in ptex units, so
// on the deep patches of adaptive isolation they reach 2^depth, and
// dP/du = sum w_i P_i cancels terms of size 2^depth |P_i|: the rounding
// then scales with the distance from the origin instead of the cage's size
// (a 2-unit cube 100 units from the origin had limit normals off by 0.29
// degrees, 24 at 1e4; tests/mesh/hardcases_test.cpp,
// MeshHardCases.FarFromTheOrigin). Positions are translated back after
// evaluation; derivatives do not change under a translation.
glm::vec3 boxCentre(const glm::vec3* p, size_t n) {
    if (n == 0) return glm::vec3(0.0f);
    glm::vec3 lo = p[0], hi = p[0];
    for (size_t i = 1; i < n; ++i) {
        lo = glm::min(lo, p[i]);
        hi = glm::max(hi, p[i]);
    }
    return 0.5f * lo + 0.5f * hi;
}

// The patch-table hang (docs/platform.md): PatchTable::EvaluateBasis
// spins forever for parameters outside [0,1]. Every evaluation goes through
// here.
inline float clampParam(float x) {
    SG_ASSERT(std::isfinite(x), "patch parameters are finite");
    return std::isfinite(x) ? std::clamp(x, 0.0f, 1.0f) : 0.0f;
}

// OpenSubdiv 3.5 scales patch derivatives by 2^depth, but a patch of a
// non-quad base face lives in a ptex sub-face that is already one level
// down (PatchParam::GetParamFraction uses depth - NonQuadRoot()), so its
// derivatives come out per half a ptex unit. Rescale to per ptex unit (the
// finite-difference test in tests/mesh/subdivision_test.cpp checks it).
void toPtexUnits(const Far::PatchParam& param, int n, float* du, float* dv) {
    if (!param.NonQuadRoot()) return;
    for (int k = 0; k < n; ++k) {
        du[k] *= 0.5f;
        dv[k] *= 0.5f;
    }
}

glm::vec3 safeNormal(const glm::vec3& du, const glm::vec3& dv, const glm::vec3& fallback) {
    glm::vec3 n = glm::cross(du, dv);
    float len = glm::length(n);
    if (len > 0.0f && std::isfinite(len)) return n / len;
    len = glm::length(fallback);
    return len > 0.0f && std::isfinite(len) ? fallback / len : glm::vec3(0.0f, 0.0f, 1.0f);
}

// The limit surface's patches (evaluateLimit): an adaptively refined copy
// of the cage, its patch table, and the map from (ptex face, u, v) to patch.
struct LimitPatches {
    std::unique_ptr<Far::TopologyRefiner> adaptive;
    std::unique_ptr<Far::PatchTable> patches;
    std::unique_ptr<Far::PatchMap> patchMap;
};

// Where the limit is evaluated: each corner of refined() at its home
// location, each render vertex's derivatives at a point moved slightly
// into its home face.
struct LimitHomes {
    std::vector<uint32_t> offsets;    // refined() face offsets
    std::vector<uint32_t> cornerPtex; // per corner: ptex face
    std::vector<glm::vec2> cornerUV;  // per corner: (u, v) in it, clamped to [0, 1]
    std::vector<const Far::PatchMap::Handle*> cornerHandle; // per corner: its patch, or null
    std::vector<glm::vec2> derivUV; // per render vertex: where derivatives are taken
    std::vector<const Far::PatchMap::Handle*> derivHandle; // per render vertex: that patch
};

} // namespace

// ---- Impl ----------------------------------------------------------------------

struct Subdivider::Impl {
    SubdivisionSettings settings;
    std::string file;
    size_t cageVertices = 0;
    PolygonMesh refined;
    RenderMesh render;
    LimitFrame frame;
    detail::RenderSplit split;
    std::vector<uint32_t> renderToRefined;
    std::vector<uint32_t>
        smoothGroup; // per render vertex: first copy with the same (vertex, sector)
    std::vector<uint32_t> positionRep; // per render vertex: first copy of the same refined vertex
    SubdivisionTimings timings;
    // Whether this build's loops (and update()'s) run on TBB: settings.threads
    // != 1 and the refined mesh at or above kSerialBelowFaces (build()).
    detail::Parallel par;

    // Reused between builds.
    Descriptor descriptor;
    std::vector<glm::vec3> bufA, bufB;
    std::vector<glm::vec2> uvA, uvB;
    std::vector<std::vector<glm::vec4>> levelPoints; // specialised refiner: levels 1..N-1
    std::vector<std::vector<glm::vec2>> levelValues; // specialised refiner: UV levels 1..N-1

    // Level-N vertex -> refined() vertex (UINT32_MAX: unused, e.g. in holes),
    // and render vertex -> level-N vertex (for update()).
    std::vector<uint32_t> levelToRefined, renderToLevel;
    bool cageHasHoles = false;

    // Kept from the last uniform build: the refiner and, once the same
    // topology comes again (or for animation), factored stencils for
    // positions and every UV set, so a rebuild with new values is a few
    // sparse matrix products (see sameTopology / rebuildValues).
    std::unique_ptr<Far::TopologyRefiner> keptRefiner; // Far builds
    detail::UniformRefiner fast; // specialised builds (its levels stay until the next build)
    bool fastBuilt = false;      // the last uniform build used `fast`
    std::string fastDeclined;    // why `fast` declined the last cage
    bool keyValid = false, stencilsRecorded = false, renderValid = false;
    PolygonMesh key; // topology, tags and value counts of the kept build (values not used)
    int keyLevel = -1;
    SubdivOptions keyOptions;
    std::vector<FactoredStencils> fvarStencils;
    std::vector<glm::vec2> uvPoints;

    // Animation / limit.
    FactoredStencils uniformStencils;      // cage -> every uniform level (positions, morph deltas)
    FactoredStencils limitStencils;        // limit: cage -> adaptive points + local points
    SampleTable samples;                   // limit: per render vertex
    mutable std::vector<glm::vec3> points; // build scratch (all stencil points)
    // update() scratch: xyz in 4 floats (4th lane 0), so
    // each weighted add of FactoredStencils::apply is one 4-lane multiply
    // and add whose x, y, z lanes are the scalar operations of the vec3
    // version (no FMA in this build): bitwise the same, about a third faster.
    mutable std::vector<glm::vec4> points4;

    void build(const PolygonMesh& cage);
    void update(std::span<const glm::vec3> cagePositions, RenderMesh& out, LimitFrame* outFrame,
                bool recomputeNormals) const;
    void checkBuildable(const PolygonMesh& cage) const;
    void keepTopologyKey(const PolygonMesh& cage);
    void checkMemoryBudget(const PolygonMesh& cage) const;
    bool sameTopology(const PolygonMesh& cage) const;
    // far: the uniform Far refiner, or nullptr for the specialised one.
    void recordUniformStencils(const Far::TopologyRefiner* far, const PolygonMesh& cage);
    void rebuildValues(const PolygonMesh& cage);
    void refineUniform(const PolygonMesh& cage, Far::TopologyRefiner& refiner);
    void refineUniformFast(const PolygonMesh& cage);
    void collectCreases(const Far::TopologyRefiner& refiner);
    std::vector<uint32_t> sectors(const std::vector<uint32_t>& offsets) const;
    void locateCorners(const Far::TopologyRefiner& refiner, std::vector<uint32_t>& cornerPtex,
                       std::vector<glm::vec2>& cornerUV) const;
    void evaluateLimit(const PolygonMesh& cage, const Far::TopologyRefiner& uniform,
                       std::vector<uint8_t>& dropFace);
    // The steps of evaluateLimit.
    LimitPatches buildPatches(const PolygonMesh& cage) const;
    void recordLimitStencils(const PolygonMesh& cage, const LimitPatches& lp);
    void locateHomes(const Far::TopologyRefiner& uniform, const LimitPatches& lp, LimitHomes& homes,
                     std::vector<uint8_t>& dropFace);
    void buildSamples(const LimitPatches& lp, LimitHomes& homes);
    void addSample(const LimitPatches& lp, LimitHomes& homes, const std::vector<uint32_t>& faceOf,
                   size_t r, SampleTable& table);
    void evaluatePositions(const PolygonMesh& cage);
    void evaluateUvSets(const PolygonMesh& cage, const LimitPatches& lp, const LimitHomes& homes);
    void copyLimitToRefined(const PolygonMesh& cage);
    void buildRender();
    // render.positions and render.uvSets (sized) from refined().
    void copyToRender() {
        const size_t nR = renderToRefined.size();
        par.each(nR,
                 [&](size_t r) { render.positions[r] = refined.positions[renderToRefined[r]]; });
        for (size_t s = 0; s < refined.uvSets.size(); ++s) {
            const FaceVaryingChannel& set = refined.uvSets[s];
            par.each(nR, [&](size_t r) {
                render.uvSets[s][r] = set.values[set.indices[split.renderFirstCorner[r]]];
            });
        }
    }
    // Copies of one vertex evaluated from different home faces differ in the
    // last bits; make them bitwise equal (no cracks): positions per refined
    // vertex, normals per smooth group.
    // Area-weighted normals of the refined polygons (Newell normal per face,
    // for a quad the cross product of its diagonals: the sum of its two
    // triangles' normals, whichever diagonal splits it), summed per smooth
    // group (vertex and sector) and normalized; the same for a build and
    // every update(). `scratch` holds the sums.
    //
    // Threads: each face's normal, then each group's sum over its faces in
    // corner order (normalGroups: the order in which the serial loop over
    // faces and corners adds them), so the sums are the same bits for every
    // thread count.
    void polygonNormals(const glm::vec3* pos, glm::vec3* nrm,
                        std::vector<glm::vec3>& scratch) const {
        const size_t nR = smoothGroup.size();
        const size_t nF = refined.faceSizes.size();
        const uint32_t* crv = split.cornerRenderVertex.data();
        const uint32_t* off = normalFaceOffsets.data();
        faceNormals.resize(nF);
        par.each(nF, [&](size_t f) {
            const uint32_t c = off[f], k = off[f + 1] - c;
            if (crv[c] == UINT32_MAX) return; // holes of refined() (limit builds)
            glm::vec3 n;
            if (k == 4) {
                n = glm::cross(pos[crv[c + 2]] - pos[crv[c]], pos[crv[c + 3]] - pos[crv[c + 1]]);
            } else {
                n = glm::vec3(0.0f);
                for (uint32_t j = 0; j < k; ++j)
                    n += glm::cross(pos[crv[c + j]], pos[crv[c + (j + 1) % k]]);
            }
            faceNormals[f] = n;
        });
        scratch.resize(nR);
        par.each(nR, [&](size_t g) {
            glm::vec3 sum(0.0f);
            for (uint32_t i = groupOffsets[g]; i < groupOffsets[g + 1]; ++i)
                sum += faceNormals[groupFaces[i]];
            scratch[g] = sum;
        });
        par.each(nR, [&](size_t r) {
            const glm::vec3& a = scratch[smoothGroup[r]];
            float len = glm::length(a);
            // A vanishing sum (a fin whose faces cancel, or degenerate faces)
            // keeps the previous normal, or +z.
            if (len > 0.0f && std::isfinite(len))
                nrm[r] = a / len;
            else if (!(glm::length(nrm[r]) > 0.5f))
                nrm[r] = glm::vec3(0.0f, 0.0f, 1.0f);
        });
    }
    // smoothGroup (after positionRep): per render vertex the first render
    // vertex of the same (refined vertex, sector of its first corner).
    // Without sectors that is positionRep. With them, each render vertex
    // scans its refined vertex's render vertices in increasing order (a
    // handful) for the first with its sector: the same first-of-key for
    // every thread count.
    void smoothGroups(const uint32_t* cornerSector) {
        if (!cornerSector) {
            smoothGroup = positionRep;
            return;
        }
        const size_t nR = positionRep.size(), nV = refined.positions.size();
        std::vector<uint32_t> start(nV + 1, 0), list(nR);
        for (size_t r = 0; r < nR; ++r) ++start[renderToRefined[r] + 1];
        for (size_t v = 0; v < nV; ++v) start[v + 1] += start[v];
        {
            std::vector<uint32_t> at(start.begin(), start.end() - 1);
            for (size_t r = 0; r < nR; ++r) list[at[renderToRefined[r]]++] = uint32_t(r);
        }
        smoothGroup.resize(nR);
        const uint32_t* firstCorner = split.renderFirstCorner.data();
        par.each(nR, [&](size_t r) {
            const uint32_t v = renderToRefined[r], key = cornerSector[firstCorner[r]];
            uint32_t g = uint32_t(r);
            for (uint32_t i = start[v]; i < start[v + 1]; ++i)
                if (cornerSector[firstCorner[list[i]]] == key) {
                    g = list[i];
                    break;
                }
            smoothGroup[r] = g;
        });
    }
    // polygonNormals' gather lists (after smoothGroup and the split): per
    // smooth group (indexed by its first render vertex) the face of each of
    // its corners, in corner order.
    void normalGroups() {
        const size_t nR = smoothGroup.size();
        normalFaceOffsets = faceOffsets(refined);
        const uint32_t* crv = split.cornerRenderVertex.data();
        const size_t nF = refined.faceSizes.size();
        groupOffsets.assign(nR + 1, 0);
        for (size_t f = 0; f < nF; ++f) {
            for (uint32_t c = normalFaceOffsets[f]; c < normalFaceOffsets[f + 1]; ++c) {
                if (crv[c] != UINT32_MAX) ++groupOffsets[smoothGroup[crv[c]] + 1];
            }
        }
        for (size_t g = 0; g < nR; ++g) groupOffsets[g + 1] += groupOffsets[g];
        groupFaces.resize(groupOffsets[nR]);
        std::vector<uint32_t> at(groupOffsets.begin(), groupOffsets.end() - 1);
        for (size_t f = 0; f < nF; ++f) {
            for (uint32_t c = normalFaceOffsets[f]; c < normalFaceOffsets[f + 1]; ++c) {
                if (crv[c] != UINT32_MAX) groupFaces[at[smoothGroup[crv[c]]]++] = uint32_t(f);
            }
        }
    }
    std::vector<uint32_t> normalFaceOffsets, groupOffsets, groupFaces;
    mutable std::vector<glm::vec3> faceNormals;
    mutable std::vector<glm::vec3> normalScratch;

    // (A first copy is never written, so copies can run in any order.)
    void unifyCopies(glm::vec3* pos, glm::vec3* nrm) const {
        par.each(positionRep.size(), [&](size_t r) {
            if (positionRep[r] != r) pos[r] = pos[positionRep[r]];
            if (smoothGroup[r] != r) nrm[r] = nrm[smoothGroup[r]];
        });
    }
};

namespace {

// Refined face count of level N, for the size check before refining.
long double refinedFaceEstimate(const PolygonMesh& cage, Scheme scheme, int level) {
    long double total = 0, grow = std::pow(4.0L, level);
    for (uint32_t k : cage.faceSizes) {
        if (level == 0)
            total += 1;
        else if (scheme == Scheme::Loop || k == 4)
            total += grow;
        else
            total += (long double)k * grow / 4; // N-gon: N quads after one level
    }
    return total;
}

// Positions and every morph target's position deltas (vertex data: the
// same masks), through `interpolate(cageValues, refinedValues)`.
template <class Interpolate>
void refineVertexData(const PolygonMesh& cage, PolygonMesh& refined, Interpolate&& interpolate) {
    interpolate(cage.positions, refined.positions);
    refined.morphTargets.resize(cage.morphTargets.size());
    for (size_t t = 0; t < cage.morphTargets.size(); ++t) {
        refined.morphTargets[t].name = cage.morphTargets[t].name;
        interpolate(cage.morphTargets[t].positionDeltas, refined.morphTargets[t].positionDeltas);
    }
}

} // namespace

void Subdivider::Impl::refineUniform(const PolygonMesh& cage, Far::TopologyRefiner& refiner) {
    const int N = settings.level;
    const size_t nSets = cage.uvSets.size();
    detail::Stopwatch sw;
    // Ping-pong through levels 1..N-1, level N straight into refined()'s
    // arrays: every buffer keeps its capacity from the previous build, so a
    // rebuild touches no fresh pages.
    const Far::TopologyLevel& last = refiner.GetLevel(N);
    auto interpolateVec3 = [&](const std::vector<glm::vec3>& control, std::vector<glm::vec3>& out) {
        Far::PrimvarRefiner primvar(refiner);
        if (N == 0) {
            out = control;
            return;
        }
        const glm::vec3* src = control.data();
        for (int l = 1; l <= N; ++l) {
            std::vector<glm::vec3>& dstBuf = l == N ? out : (l % 2 ? bufA : bufB);
            dstBuf.resize(size_t(refiner.GetLevel(l).GetNumVertices()));
            PrimvarView<const glm::vec3> s{src};
            PrimvarView<glm::vec3> d{dstBuf.data()};
            primvar.Interpolate(l, s, d);
            src = dstBuf.data();
        }
    };
    refineVertexData(cage, refined, interpolateVec3);
    refined.uvSets.resize(nSets);
    for (size_t s = 0; s < nSets; ++s) {
        if (N == 0) {
            refined.uvSets[s].values = cage.uvSets[s].values;
            continue;
        }
        Far::PrimvarRefiner primvar(refiner);
        const glm::vec2* src = cage.uvSets[s].values.data();
        for (int l = 1; l <= N; ++l) {
            std::vector<glm::vec2>& dstBuf =
                l == N ? refined.uvSets[s].values : (l % 2 ? uvA : uvB);
            dstBuf.resize(size_t(refiner.GetLevel(l).GetNumFVarValues(int(s))));
            PrimvarView<const glm::vec2> sv{src};
            PrimvarView<glm::vec2> dv{dstBuf.data()};
            primvar.InterpolateFaceVarying(l, sv, dv, int(s));
            src = dstBuf.data();
        }
    }
    timings.interpolate = sw.lap();

    // Level-N polygons without holes; vertices compacted to those used.
    const int nF = last.GetNumFaces();
    refined.faceSizes.clear();
    refined.faceVertices.clear();
    refined.faceSizes.reserve(size_t(nF));
    refined.faceVertices.reserve(size_t(nF) * (settings.options.scheme == Scheme::Loop ? 3 : 4));
    for (size_t s = 0; s < nSets; ++s) {
        refined.uvSets[s].name = cage.uvSets[s].name;
        refined.uvSets[s].indices.clear();
    }
    const bool anyHole = !cage.holes.empty();
    levelToRefined.assign(size_t(last.GetNumVertices()), anyHole ? UINT32_MAX : 0);
    uint32_t used = 0;
    if (!anyHole) {
        for (uint32_t v = 0; v < levelToRefined.size(); ++v) levelToRefined[v] = v;
        used = uint32_t(levelToRefined.size());
    }
    for (int f = 0; f < nF; ++f) {
        if (anyHole && last.IsFaceHole(f)) continue;
        Far::ConstIndexArray fv = last.GetFaceVertices(f);
        refined.faceSizes.push_back(uint32_t(fv.size()));
        for (int k = 0; k < fv.size(); ++k) {
            uint32_t& m = levelToRefined[size_t(fv[k])];
            if (m == UINT32_MAX) m = used++;
            refined.faceVertices.push_back(m);
        }
        for (size_t s = 0; s < nSets; ++s) {
            Far::ConstIndexArray fvv = last.GetFaceFVarValues(f, int(s));
            for (int k = 0; k < fvv.size(); ++k)
                refined.uvSets[s].indices.push_back(uint32_t(fvv[k]));
        }
    }
    auto compact = [&](std::vector<glm::vec3>& values) {
        if (!anyHole) return;
        bufA.resize(used);
        for (size_t v = 0; v < levelToRefined.size(); ++v) {
            if (levelToRefined[v] != UINT32_MAX) bufA[levelToRefined[v]] = values[v];
        }
        values.swap(bufA);
    };
    compact(refined.positions);
    for (size_t t = 0; t < cage.morphTargets.size(); ++t)
        compact(refined.morphTargets[t].positionDeltas);
    refined.morphWeights = cage.morphWeights;
    timings.convertOut = sw.lap();
}

void Subdivider::Impl::refineUniformFast(const PolygonMesh& cage) {
    // As refineUniform, from the specialised refiner: no holes, every level-N
    // vertex is used, so refined() numbers them as level N does.
    const int N = settings.level;
    const size_t nSets = cage.uvSets.size();
    detail::Stopwatch sw;
    // Levels 1..N-1 as 4-float values (detail::Vec4Writer), one buffer per
    // level so none is shrunk and re-zeroed between builds.
    if (levelPoints.size() < size_t(N)) levelPoints.resize(size_t(N));
    auto interpolateVec3 = [&](const std::vector<glm::vec3>& control, std::vector<glm::vec3>& out) {
        out.resize(fast.level(N).numVerts);
        if (N == 1) {
            fast.interpolate(
                1, detail::Vec4Writer<glm::vec3, glm::vec3>{control.data(), out.data()}, par);
            return;
        }
        levelPoints[1].resize(fast.level(1).numVerts);
        fast.interpolate(
            1, detail::Vec4Writer<glm::vec3, glm::vec4>{control.data(), levelPoints[1].data()},
            par);
        for (int l = 2; l < N; ++l) {
            levelPoints[size_t(l)].resize(fast.level(l).numVerts);
            fast.interpolate(l,
                             detail::Vec4Writer<glm::vec4, glm::vec4>{
                                 levelPoints[size_t(l) - 1].data(), levelPoints[size_t(l)].data()},
                             par);
        }
        fast.interpolate(
            N,
            detail::Vec4Writer<glm::vec4, glm::vec3>{levelPoints[size_t(N) - 1].data(), out.data()},
            par);
    };
    refineVertexData(cage, refined, interpolateVec3);
    refined.uvSets.resize(nSets);
    for (size_t s = 0; s < nSets; ++s) {
        refined.uvSets[s].name = cage.uvSets[s].name;
        const glm::vec2* src = cage.uvSets[s].values.data();
        if (levelValues.size() < size_t(N)) levelValues.resize(size_t(N));
        for (int l = 1; l <= N; ++l) {
            std::vector<glm::vec2>& dstBuf =
                l == N ? refined.uvSets[s].values : levelValues[size_t(l)];
            dstBuf.resize(fast.numFVarValues(l, int(s)));
            fast.interpolateFaceVarying(
                l, detail::ArrayWriter<glm::vec2>{src, dstBuf.data(), glm::vec2(0.0f)}, int(s),
                par);
            src = dstBuf.data();
        }
    }
    timings.interpolate = sw.lap();
    const detail::RefineLevel& last = fast.level(N);
    refined.faceSizes.assign(last.numFaces, 4u);
    fast.takeLastFaceVertices(refined.faceVertices);
    for (size_t s = 0; s < nSets; ++s) fast.takeLastFaceValues(int(s), refined.uvSets[s].indices);
    levelToRefined.resize(last.numVerts);
    par.each(last.numVerts, [&](size_t v) { levelToRefined[v] = uint32_t(v); });
    refined.morphWeights = cage.morphWeights;
    timings.convertOut = sw.lap();
}

void Subdivider::Impl::collectCreases(const Far::TopologyRefiner& refiner) {
    // The sharpness left after N levels, on interior edges (boundary edges
    // carry the boundary rule, not a tag) and on vertices that are tagged
    // corners (a boundary corner under EdgeAndCorner is the rule again).
    const Far::TopologyLevel& last = refiner.GetLevel(settings.level);
    refined.creases.clear();
    refined.corners.clear();
    for (int e = 0; e < last.GetNumEdges(); ++e) {
        float s = last.GetEdgeSharpness(e);
        if (s <= 0.0f || last.IsEdgeBoundary(e)) continue;
        Far::ConstIndexArray ev = last.GetEdgeVertices(e);
        uint32_t a = levelToRefined[size_t(ev[0])], b = levelToRefined[size_t(ev[1])];
        if (a == UINT32_MAX || b == UINT32_MAX) continue;
        refined.creases.push_back({a, b, s});
    }
    const bool ruleCorners = settings.options.boundary == BoundaryInterpolation::EdgeAndCorner;
    for (int v = 0; v < last.GetNumVertices(); ++v) {
        float s = last.GetVertexSharpness(v);
        if (s <= 0.0f || (ruleCorners && last.IsVertexBoundary(v))) continue;
        uint32_t m = levelToRefined[size_t(v)];
        if (m != UINT32_MAX) refined.corners.push_back({m, s});
    }
}

std::vector<uint32_t> Subdivider::Impl::sectors(const std::vector<uint32_t>& offsets) const {
    // Union-find over corners across interior edges that are not infinitely
    // sharp: each root is one smooth sector around a vertex. The infinitely
    // sharp interior edges of level N are refined().creases with infinite
    // sharpness (collectCreases / UniformRefiner::lastLevelCreases).
    std::vector<uint64_t> sharp;
    for (const EdgeCrease& c : refined.creases) {
        if (c.sharpness >= kInfiniteSharpness) sharp.push_back(detail::edgeKey(c.v0, c.v1));
    }
    std::vector<uint32_t> sector(refined.faceVertices.size());
    if (sharp.empty()) {
        for (size_t c = 0; c < sector.size(); ++c) sector[c] = refined.faceVertices[c];
        return sector; // one sector per vertex
    }
    std::sort(sharp.begin(), sharp.end());
    std::vector<detail::FaceEdge> edges = detail::sortedFaceEdges(refined, offsets);
    detail::UnionFind uf(refined.faceVertices.size());
    for (size_t i = 0; i + 1 < edges.size(); ++i) {
        const detail::FaceEdge &a = edges[i], &b = edges[i + 1];
        if (a.key != b.key || (i + 2 < edges.size() && edges[i + 2].key == a.key))
            continue; // manifold pairs only
        if (a.forward == b.forward || std::binary_search(sharp.begin(), sharp.end(), a.key))
            continue;
        uf.unite(a.corner, b.next);
        uf.unite(a.next, b.corner);
    }
    for (uint32_t c = 0; c < sector.size(); ++c) sector[c] = uf.find(c);
    return sector;
}

void Subdivider::Impl::locateCorners(const Far::TopologyRefiner& refiner,
                                     std::vector<uint32_t>& cornerPtex,
                                     std::vector<glm::vec2>& cornerUV) const {
    // Home location of every level-N face corner: ptex face and (u,v).
    // Level 0: a quad (or a Loop triangle) is one ptex face with corners at
    // (0,0),(1,0),(1,1),(0,1) ((0,0),(1,0),(0,1)); any other polygon has one
    // ptex sub-face per corner: sub-face j has (0,0) at corner j, (1,0) at
    // the midpoint of the edge to corner j+1, (1,1) at the centre and (0,1)
    // at the midpoint of the edge from corner j-1 (OpenSubdiv's quad
    // sub-face parameterization; the tests check it against PrimvarRefiner::
    // Limit). Each further level places child vertices at the parameter of
    // their parent vertex, the midpoint of their parent edge or the centre of
    // their parent face.
    const bool loop = settings.options.scheme == Scheme::Loop;
    const Far::TopologyLevel& base = refiner.GetLevel(0);
    Far::PtexIndices ptex(refiner);
    const int N = settings.level;
    // Per face of the current level: ptex face and corner params (flat).
    std::vector<uint32_t> facePtex, faceFirst;
    std::vector<glm::vec2> uv;
    std::vector<uint32_t> nextPtex, nextFirst;
    std::vector<glm::vec2> nextUV;
    const glm::vec2 kQuad[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const glm::vec2 kTri[3] = {{0, 0}, {1, 0}, {0, 1}};
    // Level 0 (N-gons keep their corners' sub-face ids in cornerSub).
    std::vector<uint32_t> cornerSub; // level 0 only: ptex face per corner
    for (int f = 0; f < base.GetNumFaces(); ++f) {
        int k = base.GetFaceVertices(f).size();
        faceFirst.push_back(uint32_t(uv.size()));
        facePtex.push_back(uint32_t(ptex.GetFaceId(f)));
        bool regular = loop ? k == 3 : k == 4;
        for (int j = 0; j < k; ++j) {
            uv.push_back(regular ? (loop ? kTri[j] : kQuad[j]) : glm::vec2(0.0f));
            cornerSub.push_back(uint32_t(ptex.GetFaceId(f) + (regular ? 0 : j)));
        }
    }
    for (int l = 0; l < N; ++l) {
        const Far::TopologyLevel& P = refiner.GetLevel(l);
        const Far::TopologyLevel& C = refiner.GetLevel(l + 1);
        nextPtex.assign(size_t(C.GetNumFaces()), 0);
        nextFirst.assign(size_t(C.GetNumFaces()), 0);
        nextUV.assign(size_t(C.GetNumFaces()) * (loop ? 3 : 4), glm::vec2(0.0f));
        for (int f = 0; f < P.GetNumFaces(); ++f) {
            Far::ConstIndexArray fv = P.GetFaceVertices(f), fe = P.GetFaceEdges(f),
                                 children = P.GetFaceChildFaces(f);
            const int k = fv.size();
            const bool nonQuad = l == 0 && !loop && k != 4;
            const uint32_t first = faceFirst[size_t(f)];
            glm::vec2 centre(0.0f);
            for (int j = 0; j < k; ++j) centre += uv[first + uint32_t(j)];
            centre /= float(k);
            const int faceChild = loop ? -1 : P.GetFaceChildVertex(f);
            for (int ci = 0; ci < children.size(); ++ci) {
                const int c = children[ci];
                Far::ConstIndexArray cv = C.GetFaceVertices(c);
                // Which corner of the parent does this child touch (N-gon sub-face)?
                int sub = 0;
                if (nonQuad) {
                    for (int j = 0; j < k; ++j) {
                        for (int m = 0; m < cv.size(); ++m) {
                            if (cv[m] == P.GetVertexChildVertex(fv[j])) sub = j;
                        }
                    }
                }
                nextPtex[size_t(c)] =
                    nonQuad ? cornerSub[first + uint32_t(sub)] : facePtex[size_t(f)];
                nextFirst[size_t(c)] = uint32_t(c) * (loop ? 3u : 4u);
                for (int m = 0; m < cv.size(); ++m) {
                    const int v = cv[m];
                    glm::vec2 p(0.0f);
                    if (v == faceChild) {
                        p = nonQuad ? glm::vec2(1.0f, 1.0f) : centre;
                    } else {
                        for (int j = 0; j < k; ++j) {
                            const int jn = (j + 1) % k;
                            if (v == P.GetVertexChildVertex(fv[j])) {
                                p = nonQuad ? glm::vec2(0.0f) : uv[first + uint32_t(j)];
                                break;
                            }
                            if (v == P.GetEdgeChildVertex(fe[j])) {
                                // Edge j joins corners j and j+1.
                                // Sub-face `sub` touches edge sub (to its (1,0)) and edge sub-1 (to
                                // its (0,1)).
                                if (nonQuad)
                                    p = j == sub ? glm::vec2(1.0f, 0.0f) : glm::vec2(0.0f, 1.0f);
                                else
                                    p = 0.5f * (uv[first + uint32_t(j)] + uv[first + uint32_t(jn)]);
                                break;
                            }
                        }
                    }
                    nextUV[nextFirst[size_t(c)] + uint32_t(m)] = p;
                }
            }
        }
        facePtex.swap(nextPtex);
        faceFirst.swap(nextFirst);
        uv.swap(nextUV);
    }
    // Flatten onto refined() corners (non-hole faces in order).
    const Far::TopologyLevel& last = refiner.GetLevel(N);
    cornerPtex.clear();
    cornerUV.clear();
    cornerPtex.reserve(refined.faceVertices.size());
    cornerUV.reserve(refined.faceVertices.size());
    const bool anyHole = cageHasHoles;
    uint32_t level0Corner = 0;
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        const int k = last.GetFaceVertices(f).size();
        if (!(anyHole && last.IsFaceHole(f))) {
            for (int m = 0; m < k; ++m) {
                cornerPtex.push_back(N == 0 ? cornerSub[level0Corner + uint32_t(m)]
                                            : facePtex[size_t(f)]);
                cornerUV.push_back(uv[faceFirst[size_t(f)] + uint32_t(m)]);
            }
        }
        level0Corner += uint32_t(k);
    }
}

// Isolation: at least N (every level-N vertex on a patch corner, where
// patches interpolate the limit exactly) and at least the largest finite
// crease/corner sharpness (semi-sharp features are exact only when isolated
// that deep); OpenSubdiv caps it at 10. At least 5: Gregory end caps
// approximate the tangent plane around extraordinary vertices, better the
// deeper they sit, while float patch points lose precision the deeper they
// sit. On spot, vs OpenSubdiv's limit masks, the worst normal is off by
// 4.5e-3 rad at isolation 3, 1.6e-3 at 4, 9.7e-4 at 5 and 3.4e-3 at 6
// (tests/mesh/subdivision_test.cpp).
LimitPatches Subdivider::Impl::buildPatches(const PolygonMesh& cage) const {
    float maxSharp = 0.0f;
    for (const EdgeCrease& c : cage.creases) {
        if (c.sharpness < kInfiniteSharpness) maxSharp = std::max(maxSharp, c.sharpness);
    }
    for (const VertexCorner& c : cage.corners) {
        if (c.sharpness < kInfiniteSharpness) maxSharp = std::max(maxSharp, c.sharpness);
    }
    const int isolation =
        std::clamp(std::max({settings.level, 5, int(std::ceil(maxSharp))}), 5, 10);
    LimitPatches lp;
    lp.adaptive = createRefiner(descriptor, settings.options, file);
    Far::PatchTableFactory::Options popt(static_cast<unsigned>(isolation));
    popt.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    popt.useInfSharpPatch = true;
    popt.generateFVarTables = !cage.uvSets.empty();
    popt.generateFVarLegacyLinearPatches = false; // smooth UV patches where the rules say smooth
    popt.generateLegacySharpCornerPatches = false;
    popt.generateVaryingTables = false;
    lp.adaptive->RefineAdaptive(popt.GetRefineAdaptiveOptions());
    lp.patches.reset(Far::PatchTableFactory::Create(*lp.adaptive, popt));
    if (!lp.patches)
        throw InputError(file, "limit", "OpenSubdiv could not build patches: " + tFarError);
    lp.patchMap = std::make_unique<Far::PatchMap>(*lp.patches);
    return lp;
}

// Cage -> every adaptive point, then the patch table's local points.
void Subdivider::Impl::recordLimitStencils(const PolygonMesh& cage, const LimitPatches& lp) {
    const Far::TopologyRefiner& adaptive = *lp.adaptive;
    limitStencils = FactoredStencils();
    limitStencils.numControl = uint32_t(cage.positions.size());
    std::vector<uint32_t> levelBase(size_t(adaptive.GetNumLevels()) + 1, 0);
    for (int l = 0; l < adaptive.GetNumLevels(); ++l) {
        levelBase[size_t(l) + 1] =
            levelBase[size_t(l)] + uint32_t(adaptive.GetLevel(l).GetNumVertices());
    }
    for (int l = 1; l < adaptive.GetNumLevels(); ++l)
        limitStencils.recordLevel(adaptive, l, levelBase[size_t(l) - 1], levelBase[size_t(l)]);
    const uint32_t refinedTotal = levelBase.back();
    uint32_t localCount = 0;
    if (const Far::StencilTableReal<float>* local =
            lp.patches->GetLocalPointStencilTable<float>()) {
        limitStencils.appendTable(*local, refinedTotal);
        localCount = uint32_t(local->GetNumStencils());
    }
    limitStencils.numPoints = refinedTotal + localCount;
}

// Home location (ptex face, (u,v) clamped, patch) of each corner of
// refined(); faces with a corner off every patch (boundary faces under
// BoundaryInterpolation::None) leave the limit mesh: dropFace, and holes of
// refined() so the render split skips them.
void Subdivider::Impl::locateHomes(const Far::TopologyRefiner& uniform, const LimitPatches& lp,
                                   LimitHomes& homes, std::vector<uint8_t>& dropFace) {
    locateCorners(uniform, homes.cornerPtex, homes.cornerUV);
    homes.offsets = faceOffsets(refined);
    dropFace.assign(refined.faceSizes.size(), 0);
    homes.cornerHandle.assign(homes.cornerPtex.size(), nullptr);
    par.each(refined.faceSizes.size(), [&](size_t f) {
        for (uint32_t c = homes.offsets[f]; c < homes.offsets[f + 1]; ++c) {
            glm::vec2& uv = homes.cornerUV[c];
            uv = glm::vec2(clampParam(uv.x), clampParam(uv.y));
            homes.cornerHandle[c] = lp.patchMap->FindPatch(int(homes.cornerPtex[c]), uv.x, uv.y);
            if (!homes.cornerHandle[c]) dropFace[f] = 1;
        }
    });
    refined.holes.clear();
    for (uint32_t f = 0; f < dropFace.size(); ++f) {
        if (dropFace[f]) refined.holes.push_back(f);
    }
}

// Per render vertex: the derivative location and the sample's basis
// weights (value at the home corner, derivatives at the derivative
// location), and the LimitFrame's home location.
//
// Derivative locations: the corner moved kInward of the way to its face's
// centre. At the corner itself the derivatives of an end-cap patch can be
// singular (Gregory weights are 0/0 there; a sharp corner of a one-face
// sector came out with a flipped normal), and a corner on a sharp crease
// belongs to patches on both sides: a point just inside the home face picks
// that face's side. The shift is 2^-12 of the face's size, so derivatives
// move by O(2^-12 h |P''|), far below float noise in the tangent plane.
void Subdivider::Impl::buildSamples(const LimitPatches& lp, LimitHomes& homes) {
    const std::vector<uint32_t>& offsets = homes.offsets;
    const size_t nR = split.renderFirstCorner.size();
    const std::vector<uint32_t> faceOf = detail::cornerFaces(offsets);
    homes.derivUV.resize(nR);
    homes.derivHandle.resize(nR);
    samples.clear();
    frame = LimitFrame();
    frame.ptexFace.resize(nR);
    frame.ptexUV.resize(nR);
    // Fixed blocks of render vertices, each its own table, appended in
    // block order: the same table for every thread count.
    std::vector<SampleTable> block((nR + detail::kFixedBlock - 1) / detail::kFixedBlock);
    par.fixedBlocks(nR, [&](size_t k, size_t begin, size_t end) {
        SampleTable& t = block[k];
        t.clear();
        for (size_t r = begin; r < end; ++r) addSample(lp, homes, faceOf, r, t);
    });
    for (const SampleTable& t : block) samples.append(t);
}

// buildSamples for render vertex r, appended to `table`.
void Subdivider::Impl::addSample(const LimitPatches& lp, LimitHomes& homes,
                                 const std::vector<uint32_t>& faceOf, size_t r,
                                 SampleTable& table) {
    constexpr float kInward = 1.0f / 4096.0f;
    const Far::PatchTable& patches = *lp.patches;
    const std::vector<uint32_t>& offsets = homes.offsets;
    float wP[20], wDu[20], wDv[20];
    uint32_t c = split.renderFirstCorner[r];
    uint32_t f = faceOf[c];
    glm::vec2 centre(0.0f);
    bool onePtex = true;
    for (uint32_t k = offsets[f]; k < offsets[f + 1]; ++k) {
        centre += homes.cornerUV[k];
        onePtex &= homes.cornerPtex[k] == homes.cornerPtex[c];
    }
    centre /= float(offsets[f + 1] - offsets[f]);
    // A level-0 polygon that is not a quad spans one ptex sub-face per
    // corner; the corner sits at (0,0) of its sub-face, whose centre is (0.5,0.5).
    if (!onePtex) centre = glm::vec2(0.5f);
    glm::vec2 d = homes.cornerUV[c] + kInward * (centre - homes.cornerUV[c]);
    glm::vec2& derivUV = homes.derivUV[r];
    const Far::PatchMap::Handle*& derivHandle = homes.derivHandle[r];
    derivUV = glm::vec2(clampParam(d.x), clampParam(d.y));
    derivHandle = lp.patchMap->FindPatch(int(homes.cornerPtex[c]), derivUV.x, derivUV.y);
    if (!derivHandle)
        derivHandle = homes.cornerHandle[c]; // cannot happen inside a face with patches

    const Far::PatchMap::Handle* h = homes.cornerHandle[c];
    float u = clampParam(homes.cornerUV[c].x), v = clampParam(homes.cornerUV[c].y);
    float wValue[20];
    patches.EvaluateBasis(*h, u, v, wValue, wDu, wDv);
    // A regular (B-spline) patch has well-defined derivatives at its
    // corners: evaluate the home face's patch at the corner itself (fewer
    // non-zero weights, no shift); end caps keep the shifted point.
    glm::vec2 at = derivUV;
    if (patches.GetPatchDescriptor(*derivHandle).GetType() == Far::PatchDescriptor::REGULAR)
        at = glm::vec2(u, v);
    patches.EvaluateBasis(*derivHandle, at.x, at.y, wP, wDu, wDv);
    int n = patches.GetPatchVertices(*derivHandle).size();
    toPtexUnits(patches.GetPatchParam(*derivHandle), n, wDu, wDv);
    table.add(patches.GetPatchVertices(*h), wValue, patches.GetPatchVertices(*derivHandle), wDu,
              wDv);
    frame.ptexFace[r] = homes.cornerPtex[c];
    frame.ptexUV[r] = glm::vec2(u, v);
}

// Limit positions, dP/du, dP/dv and normals of the render vertices, and the
// same for every morph target's deltas.
void Subdivider::Impl::evaluatePositions(const PolygonMesh& cage) {
    const size_t nR = split.renderFirstCorner.size();
    points.resize(limitStencils.numPoints);
    // Positions relative to `origin` (boxCentre: morph deltas need none).
    auto evalVec3 = [&](const std::vector<glm::vec3>& control, glm::vec3 origin, glm::vec3* value,
                        std::vector<glm::vec3>& du, std::vector<glm::vec3>& dv) {
        par.each(control.size(), [&](size_t v) { points[v] = control[v] - origin; });
        limitStencils.apply(points.data(), par);
        du.resize(nR);
        dv.resize(nR);
        samples.evaluate(points.data(), value, du.data(), dv.data(), par);
        par.each(nR, [&](size_t r) { value[r] += origin; });
    };
    evalVec3(cage.positions, boxCentre(cage.positions.data(), cage.positions.size()),
             render.positions.data(), frame.dPdu, frame.dPdv);
    render.normals.resize(nR);
    par.each(nR, [&](size_t r) {
        // Fallback for a degenerate limit point: the refined face normal.
        render.normals[r] = safeNormal(frame.dPdu[r], frame.dPdv[r], render.normals[r]);
    });
    unifyCopies(render.positions.data(), render.normals.data());
    frame.morphDPdu.resize(cage.morphTargets.size());
    frame.morphDPdv.resize(cage.morphTargets.size());
    for (size_t t = 0; t < cage.morphTargets.size(); ++t) {
        evalVec3(cage.morphTargets[t].positionDeltas, glm::vec3(0.0f),
                 render.morphTargets[t].positionDeltas.data(), frame.morphDPdu[t],
                 frame.morphDPdv[t]);
        std::vector<glm::vec3>& d = render.morphTargets[t].positionDeltas;
        par.each(nR, [&](size_t r) {
            if (positionRep[r] != r) d[r] = d[positionRep[r]];
        });
    }
}

namespace {

// Face-varying channel ch's values at every point of an adaptive refiner
// and its patch table: the cage's values (cageValues) interpolated once
// through all adaptive levels (concatenated, as the patch table indexes
// them), plus the table's local points.
std::vector<glm::vec2> fvarPatchPoints(const Far::TopologyRefiner& adaptive,
                                       const Far::PatchTable& table,
                                       const std::vector<glm::vec2>& cageValues, int ch) {
    std::vector<uint32_t> fvBase(size_t(adaptive.GetNumLevels()) + 1, 0);
    for (int l = 0; l < adaptive.GetNumLevels(); ++l) {
        fvBase[size_t(l) + 1] =
            fvBase[size_t(l)] + uint32_t(adaptive.GetLevel(l).GetNumFVarValues(ch));
    }
    const Far::StencilTableReal<float>* local =
        table.GetLocalPointFaceVaryingStencilTable<float>(ch);
    std::vector<glm::vec2> values(fvBase.back() + (local ? size_t(local->GetNumStencils()) : 0));
    std::copy(cageValues.begin(), cageValues.end(), values.begin());
    Far::PrimvarRefiner primvar(adaptive);
    for (int l = 1; l < adaptive.GetNumLevels(); ++l) {
        PrimvarView<const glm::vec2> src{values.data() + fvBase[size_t(l) - 1]};
        PrimvarView<glm::vec2> dst{values.data() + fvBase[size_t(l)]};
        primvar.InterpolateFaceVarying(l, src, dst, ch);
    }
    if (local) {
        FactoredStencils localPoints;
        localPoints.appendTable(*local, fvBase.back());
        localPoints.apply(values.data());
    }
    return values;
}

// UV set s's values at every adaptive point: UVs are static, so they are
// interpolated once.
std::vector<glm::vec2> limitUvPoints(const PolygonMesh& cage, const LimitPatches& lp, size_t s) {
    return fvarPatchPoints(*lp.adaptive, *lp.patches, cage.uvSets[s].values, int(s));
}

} // namespace

// Every UV set's limit value at each render vertex's home corner and its
// derivatives at the derivative location (same locations as the
// positions').
void Subdivider::Impl::evaluateUvSets(const PolygonMesh& cage, const LimitPatches& lp,
                                      const LimitHomes& homes) {
    const Far::PatchTable& patches = *lp.patches;
    const size_t nR = split.renderFirstCorner.size();
    frame.dUVdu.assign(cage.uvSets.size(), {});
    frame.dUVdv.assign(cage.uvSets.size(), {});
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        const int ch = int(s);
        const std::vector<glm::vec2> values = limitUvPoints(cage, lp, s);
        auto evalUv = [&](const Far::PatchMap::Handle* h, glm::vec2 at, glm::vec2& value,
                          glm::vec2& du, glm::vec2& dv) {
            float wP[20], wDu[20], wDv[20];
            patches.EvaluateBasisFaceVarying(*h, at.x, at.y, wP, wDu, wDv, nullptr, nullptr,
                                             nullptr, ch);
            Far::ConstIndexArray cvs = patches.GetPatchFVarValues(*h, ch);
            toPtexUnits(patches.GetPatchFVarPatchParam(*h, ch), cvs.size(), wDu, wDv);
            value = du = dv = glm::vec2(0.0f);
            for (int k = 0; k < cvs.size(); ++k) {
                const glm::vec2& x = values[size_t(cvs[k])];
                value += wP[k] * x;
                du += wDu[k] * x;
                dv += wDv[k] * x;
            }
        };
        std::vector<glm::vec2>& outUV = render.uvSets[s];
        frame.dUVdu[s].resize(nR);
        frame.dUVdv[s].resize(nR);
        par.each(nR, [&](size_t r) {
            uint32_t c = split.renderFirstCorner[r];
            glm::vec2 q, du, dv, unused;
            evalUv(homes.cornerHandle[c],
                   glm::vec2(clampParam(homes.cornerUV[c].x), clampParam(homes.cornerUV[c].y)), q,
                   unused, unused);
            evalUv(homes.derivHandle[r], homes.derivUV[r], unused, du, dv);
            outUV[r] = q;
            frame.dUVdu[s][r] = du;
            frame.dUVdv[s][r] = dv;
        });
    }
}

// refined() gets the limit positions and UVs too (per refined vertex / per
// UV value: from the render vertex that is home to it).
void Subdivider::Impl::copyLimitToRefined(const PolygonMesh& cage) {
    for (size_t r = 0; r < split.renderFirstCorner.size(); ++r) {
        uint32_t c = split.renderFirstCorner[r];
        refined.positions[refined.faceVertices[c]] = render.positions[r];
        refined.normals[refined.faceVertices[c]] = render.normals[r];
        for (size_t t = 0; t < cage.morphTargets.size(); ++t) {
            refined.morphTargets[t].positionDeltas[refined.faceVertices[c]] =
                render.morphTargets[t].positionDeltas[r];
        }
        for (size_t s = 0; s < cage.uvSets.size(); ++s)
            refined.uvSets[s].values[refined.uvSets[s].indices[c]] = render.uvSets[s][r];
    }
}

// Limit evaluation (docs/mesh.md, "Limit evaluation"): patches of an
// adaptively refined copy of the cage, the stencils from the cage to their
// points, every corner's home location, the render mesh over the faces
// that have patches, one sample per render vertex, then positions,
// normals, morph deltas and UVs with their derivatives.
void Subdivider::Impl::evaluateLimit(const PolygonMesh& cage, const Far::TopologyRefiner& uniform,
                                     std::vector<uint8_t>& dropFace) {
    detail::Stopwatch sw;
    const LimitPatches lp = buildPatches(cage);
    recordLimitStencils(cage, lp);
    LimitHomes homes;
    locateHomes(uniform, lp, homes, dropFace);
    timings.limit += sw.lap();
    // Render vertices over the surviving faces (the split needs dropFace).
    buildRender();
    timings.render = sw.lap();
    buildSamples(lp, homes);
    evaluatePositions(cage);
    evaluateUvSets(cage, lp, homes);
    copyLimitToRefined(cage);
    timings.limit += sw.lap();
}

void Subdivider::Impl::buildRender() {
    std::vector<uint32_t> offsets = faceOffsets(refined);
    std::vector<uint32_t> sector;
    const bool needSectors = !refined.creases.empty();
    if (needSectors) sector = sectors(offsets);
    detail::splitRenderVertices(refined, offsets, needSectors ? sector.data() : nullptr, split);
    const size_t nR = split.renderSourceVertex.size();
    renderToRefined = split.renderSourceVertex;
    render.name = refined.name;
    render.positions.resize(nR);
    render.uvSets.resize(refined.uvSets.size());
    for (size_t s = 0; s < refined.uvSets.size(); ++s) render.uvSets[s].resize(nR);
    copyToRender();
    render.indices = split.indices;
    render.tangents.clear();
    render.tangentUvSet = -1;
    positionRep.resize(nR);
    {
        std::vector<uint32_t> first(refined.positions.size(), UINT32_MAX);
        for (uint32_t r = 0; r < nR; ++r) {
            uint32_t& f = first[renderToRefined[r]];
            if (f == UINT32_MAX) f = r;
            positionRep[r] = f;
        }
    }
    smoothGroups(needSectors ? sector.data() : nullptr);
    render.normals.assign(nR, glm::vec3(0.0f));
    normalGroups();
    polygonNormals(render.positions.data(), render.normals.data(), normalScratch);
    render.morphTargets.resize(refined.morphTargets.size());
    for (size_t t = 0; t < refined.morphTargets.size(); ++t) {
        render.morphTargets[t].name = refined.morphTargets[t].name;
        render.morphTargets[t].normalDeltas.clear();
        render.morphTargets[t].tangentDeltas.clear();
        render.morphTargets[t].positionDeltas.resize(nR);
        par.each(nR, [&](size_t r) {
            render.morphTargets[t].positionDeltas[r] =
                refined.morphTargets[t].positionDeltas[renderToRefined[r]];
        });
    }
    render.morphWeights = refined.morphWeights;
    if (!render.morphTargets.empty() && render.morphWeights.empty())
        render.morphWeights.assign(render.morphTargets.size(), 0.0f);
    std::vector<uint32_t> refinedToLevel(refined.positions.size(), 0);
    for (uint32_t v = 0; v < levelToRefined.size(); ++v) {
        if (levelToRefined[v] != UINT32_MAX) refinedToLevel[levelToRefined[v]] = v;
    }
    renderToLevel.resize(nR);
    par.each(nR, [&](size_t r) { renderToLevel[r] = refinedToLevel[renderToRefined[r]]; });
    // refined() normals: per vertex, from the first render vertex using it.
    refined.normals.assign(refined.positions.size(), glm::vec3(0.0f, 0.0f, 1.0f));
    for (size_t r = nR; r-- > 0;) refined.normals[renderToRefined[r]] = render.normals[r];
    refined.normalIndices = refined.faceVertices;
}

bool Subdivider::Impl::sameTopology(const PolygonMesh& cage) const {
    const SubdivOptions& o = settings.options;
    if (!keyValid || keyLevel != settings.level || keyOptions.scheme != o.scheme ||
        keyOptions.boundary != o.boundary || keyOptions.fvar != o.fvar ||
        keyOptions.creaseMethod != o.creaseMethod || keyOptions.triangles != o.triangles) {
        return false;
    }
    auto sameCreases = [](const std::vector<EdgeCrease>& a, const std::vector<EdgeCrease>& b) {
        return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(),
                                                  [](const EdgeCrease& x, const EdgeCrease& y) {
                                                      return x.v0 == y.v0 && x.v1 == y.v1 &&
                                                             x.sharpness == y.sharpness;
                                                  });
    };
    auto sameCorners = [](const std::vector<VertexCorner>& a, const std::vector<VertexCorner>& b) {
        return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(),
                                                  [](const VertexCorner& x, const VertexCorner& y) {
                                                      return x.vertex == y.vertex &&
                                                             x.sharpness == y.sharpness;
                                                  });
    };
    if (cage.positions.size() != key.positions.size() || cage.faceSizes != key.faceSizes ||
        cage.faceVertices != key.faceVertices || cage.holes != key.holes ||
        !sameCreases(cage.creases, key.creases) || !sameCorners(cage.corners, key.corners) ||
        cage.uvSets.size() != key.uvSets.size() ||
        cage.morphTargets.size() != key.morphTargets.size()) {
        return false;
    }
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        if (cage.uvSets[s].indices != key.uvSets[s].indices ||
            cage.uvSets[s].values.size() != key.uvSets[s].values.size())
            return false;
    }
    return true;
}

void Subdivider::Impl::recordUniformStencils(const Far::TopologyRefiner* far,
                                             const PolygonMesh& cage) {
    const int N = settings.level;
    auto numVerts = [&](int l) {
        return far ? uint32_t(far->GetLevel(l).GetNumVertices()) : fast.level(l).numVerts;
    };
    // Level 0 holds the cage's UV values (Far indexes them as given).
    auto numValues = [&](int l, int s) {
        if (l == 0) return uint32_t(cage.uvSets[size_t(s)].values.size());
        return far ? uint32_t(far->GetLevel(l).GetNumFVarValues(s)) : fast.numFVarValues(l, s);
    };
    auto record = [&](FactoredStencils& f, int l, uint32_t srcBase, uint32_t dstBase, int channel) {
        if (far)
            f.recordLevel(*far, l, srcBase, dstBase, channel);
        else
            f.recordLevel(fast, l, srcBase, dstBase, channel);
    };
    uniformStencils = FactoredStencils();
    uniformStencils.numControl = uint32_t(cage.positions.size());
    uint32_t base = 0;
    for (int l = 1; l <= N; ++l) {
        uint32_t next = base + numVerts(l - 1);
        record(uniformStencils, l, base, next, -1);
        base = next;
    }
    uniformStencils.numPoints = base + numVerts(N);
    fvarStencils.assign(cage.uvSets.size(), FactoredStencils());
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        FactoredStencils& f = fvarStencils[s];
        f.numControl = uint32_t(cage.uvSets[s].values.size());
        uint32_t b = 0;
        for (int l = 1; l <= N; ++l) {
            uint32_t next = b + numValues(l - 1, int(s));
            record(f, l, b, next, int(s));
            b = next;
        }
        f.numPoints = b + numValues(N, int(s));
    }
    stencilsRecorded = true;
}

void Subdivider::Impl::rebuildValues(const PolygonMesh& cage) {
    // Same topology as the kept build: only values change. refined()'s
    // faces, UV indices, tags and the render split stay as they are.
    detail::Stopwatch sw;
    if (!stencilsRecorded) recordUniformStencils(fastBuilt ? nullptr : keptRefiner.get(), cage);
    timings.stencils = sw.lap();
    const size_t nLevel = levelToRefined.size();
    auto refineVec3 = [&](const std::vector<glm::vec3>& control, std::vector<glm::vec3>& out) {
        points.resize(uniformStencils.numPoints);
        std::copy(control.begin(), control.end(), points.begin());
        uniformStencils.apply(points.data(), par);
        const glm::vec3* levelN = points.data() + (uniformStencils.numPoints - nLevel);
        out.resize(refined.positions.size());
        par.each(nLevel, [&](size_t v) {
            if (levelToRefined[v] != UINT32_MAX) out[levelToRefined[v]] = levelN[v];
        });
    };
    refineVec3(cage.positions, refined.positions);
    for (size_t t = 0; t < cage.morphTargets.size(); ++t)
        refineVec3(cage.morphTargets[t].positionDeltas, refined.morphTargets[t].positionDeltas);
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        const FactoredStencils& f = fvarStencils[s];
        uvPoints.resize(f.numPoints);
        std::copy(cage.uvSets[s].values.begin(), cage.uvSets[s].values.end(), uvPoints.begin());
        f.apply(uvPoints.data(), par);
        std::vector<glm::vec2>& values = refined.uvSets[s].values;
        values.assign(uvPoints.end() - std::ptrdiff_t(values.size()), uvPoints.end());
    }
    refined.morphWeights = cage.morphWeights;
    timings.interpolate = sw.lap();
    if (!settings.buildRenderMesh) {
        // As in a fresh build without a render mesh: no normals (the kept
        // ones belong to the old positions).
        refined.normals.clear();
        refined.normalIndices.clear();
        renderValid = false;
    } else {
        if (renderValid) {
            const size_t nR = renderToRefined.size();
            copyToRender();
            for (size_t t = 0; t < refined.morphTargets.size(); ++t) {
                par.each(nR, [&](size_t r) {
                    render.morphTargets[t].positionDeltas[r] =
                        refined.morphTargets[t].positionDeltas[renderToRefined[r]];
                });
            }
            render.morphWeights = refined.morphWeights;
            polygonNormals(render.positions.data(), render.normals.data(), normalScratch);
            for (size_t r = nR; r-- > 0;) refined.normals[renderToRefined[r]] = render.normals[r];
        } else {
            buildRender();
            renderValid = true;
        }
        timings.render = sw.lap();
    }
}

// Refuses a build whose estimated peak memory is above the budget, before
// OpenSubdiv or the specialised refiner allocates (the estimate and its
// test: subdivision_budget.cpp, tests/mesh/subdivision_budget_test.cpp).
void Subdivider::Impl::checkMemoryBudget(const PolygonMesh& cage) const {
    const uint64_t budget =
        settings.memoryBudget ? settings.memoryBudget : defaultSubdivisionBudget();
    const SubdivisionCost cost = estimateSubdivisionCost(cage, settings);
    if (cost.bytes <= budget) return;
    std::string what = std::to_string(cost.faces) + " faces";
    if (settings.limit) what += " with limit evaluation";
    if (settings.animate) what += " and animation stencils";
    throw InputError(file, "level " + std::to_string(settings.level),
                     "would make " + what + " and need about " + formatByteSize(cost.bytes) +
                         " of memory; the limit is " + formatByteSize(budget) +
                         (settings.memoryBudgetHint.empty()
                              ? std::string()
                              : " (raise it with " + settings.memoryBudgetHint + ")"));
}

// What build() refuses before refining: a level out of range, an empty
// cage, non-triangles under Loop, and refinements beyond
// settings.maxRefinedFaces.
void Subdivider::Impl::checkBuildable(const PolygonMesh& cage) const {
    const SubdivOptions& o = settings.options;
    const int N = settings.level;
    if (N < 0 || N > kMaxSubdivisionLevel) {
        throw InputError(file, "level",
                         std::to_string(N) + " is outside 0.." +
                             std::to_string(kMaxSubdivisionLevel));
    }
    if (cage.faceSizes.empty()) throw InputError(file, "", "empty mesh: no faces");
    if (o.scheme == Scheme::Loop) {
        for (size_t f = 0; f < cage.faceSizes.size(); ++f) {
            if (cage.faceSizes[f] != 3) {
                throw InputError(
                    file, "face " + std::to_string(f),
                    "has " + std::to_string(cage.faceSizes[f]) +
                        " corners; the Loop scheme takes triangles only (use catmark or bilinear)");
            }
        }
    }
    long double estimate = refinedFaceEstimate(cage, o.scheme, N);
    if (estimate > (long double)settings.maxRefinedFaces) {
        throw InputError(file, "level " + std::to_string(N),
                         "would make about " + std::to_string((unsigned long long)estimate) +
                             " faces; the limit is " + std::to_string(settings.maxRefinedFaces));
    }
}

// What a rebuild of the same topology needs (sameTopology): the topology,
// tags and value counts of this cage (its values are not kept).
void Subdivider::Impl::keepTopologyKey(const PolygonMesh& cage) {
    keyValid = true;
    keyLevel = settings.level;
    keyOptions = settings.options;
    renderValid = settings.buildRenderMesh;
    key.positions.resize(cage.positions.size());
    key.faceSizes = cage.faceSizes;
    key.faceVertices = cage.faceVertices;
    key.holes = cage.holes;
    key.creases = cage.creases;
    key.corners = cage.corners;
    key.morphTargets.resize(cage.morphTargets.size());
    key.uvSets.resize(cage.uvSets.size());
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        key.uvSets[s].indices = cage.uvSets[s].indices;
        key.uvSets[s].values.resize(cage.uvSets[s].values.size());
    }
}

void Subdivider::Impl::build(const PolygonMesh& cage) {
    timings = SubdivisionTimings();
    const SubdivOptions& o = settings.options;
    const int N = settings.level;
    checkBuildable(cage);
    cageVertices = cage.positions.size();
    if (!settings.limit && settings.reuseTopology && sameTopology(cage)) {
        rebuildValues(cage);
        return;
    }
    checkMemoryBudget(cage);
    keyValid = false;
    stencilsRecorded = false;
    renderValid = false;
    fastBuilt = false;
    fastDeclined.clear();
    // Free the previous refiner before OpenSubdiv allocates the next one, so
    // malloc hands the same pages back instead of faulting in new ones.
    keptRefiner.reset();
    detail::Stopwatch sw;
    descriptor.build(cage);
    timings.convertIn = sw.lap();
    // Level 0 (OpenSubdiv's factory: validation, edges, tags, face-varying
    // channels) is shared by both refiners.
    std::unique_ptr<Far::TopologyRefiner> refiner = createRefiner(descriptor, o, file);
    const bool tags = !cage.creases.empty() || !cage.corners.empty();
    refined.name = cage.name;
    refined.options = o;
    refined.explicitTags = cage.explicitTags;
    refined.holes.clear();
    refined.normals.clear();
    refined.normalIndices.clear();
    cageHasHoles = !cage.holes.empty();
    if (settings.specializedRefiner && !settings.limit && N >= 1) {
        fastBuilt = fast.accept(*refiner, cage, fastDeclined);
    } else {
        fastDeclined = settings.limit ? "limit evaluation" : (N < 1 ? "level 0" : "not asked");
    }
    if (fastBuilt) {
        fast.refine(N, par);
        timings.topology = sw.lap();
        refineUniformFast(cage);
        sw.lap();
        if (tags)
            fast.lastLevelCreases(refined.creases, refined.corners,
                                  o.boundary == BoundaryInterpolation::EdgeAndCorner);
        else {
            refined.creases.clear();
            refined.corners.clear();
        }
        timings.convertOut += sw.lap();
    } else {
        Far::TopologyRefiner::UniformOptions uo(N);
        // Edges of the last level are needed only for crease tags and sharp sectors.
        uo.fullTopologyInLastLevel = tags;
        refiner->RefineUniform(uo);
        timings.topology = sw.lap();
        refineUniform(cage, *refiner);
        sw.lap();
        if (tags)
            collectCreases(*refiner);
        else {
            refined.creases.clear();
            refined.corners.clear();
        }
        timings.convertOut += sw.lap();
    }

    render = RenderMesh();
    frame = LimitFrame();
    split = detail::RenderSplit();
    renderToRefined.clear();
    if (settings.limit) {
        std::vector<uint8_t> drop;
        // evaluateLimit builds the render mesh over faces that have patches.
        evaluateLimit(cage, *refiner, drop);
        // Faces without patches (only boundary faces under
        // BoundaryInterpolation::None, which OpenSubdiv leaves out of the limit
        // surface) are now refined().holes.
        if (!settings.buildRenderMesh) {
            render = RenderMesh();
            frame = LimitFrame();
        }
    } else if (settings.buildRenderMesh) {
        sw.lap();
        buildRender();
        timings.render = sw.lap();
    }
    if (settings.animate && !settings.limit) {
        sw.lap();
        recordUniformStencils(fastBuilt ? nullptr : refiner.get(), cage);
        timings.stencils = sw.lap();
    }
    // Keep what a rebuild of the same topology needs (uniform builds only:
    // a limit build turns faces without patches into holes of refined()).
    // A specialised build keeps its levels in `fast`.
    if (!settings.limit && settings.reuseTopology) {
        if (!fastBuilt) keptRefiner = std::move(refiner);
        keepTopologyKey(cage);
    }
}

// ---- Public ----------------------------------------------------------------------

Subdivider::Subdivider() : impl_(std::make_unique<Impl>()) {}
Subdivider::Subdivider(const PolygonMesh& cage, const SubdivisionSettings& settings,
                       const std::string& file)
    : Subdivider() {
    build(cage, settings, file);
}
Subdivider::~Subdivider() = default;
Subdivider::Subdivider(Subdivider&&) noexcept = default;
Subdivider& Subdivider::operator=(Subdivider&&) noexcept = default;

// Elements per task with serialBelowFaces = 0: small cages then exercise
// many block boundaries.
constexpr size_t kTestGrain = 16;

void Subdivider::build(const PolygonMesh& cage, const SubdivisionSettings& settings,
                       const std::string& file) {
    SG_EXPECTS(settings.threads >= 0 && settings.threads <= kMaxThreads,
               "SubdivisionSettings::threads is 0 (all cores) or 1..1024");
    impl_->settings = settings;
    impl_->file = file.empty() ? (cage.name.empty() ? std::string("(mesh)") : cage.name) : file;
    // Threads only where they pay: a refined mesh below serialBelowFaces
    // stays on the calling thread (the estimate is the budget check's).
    const long double faces =
        settings.level >= 0 && settings.level <= kMaxSubdivisionLevel
            ? refinedFaceEstimate(cage, settings.options.scheme, settings.level)
            : 0.0L;
    impl_->par.on = settings.threads != 1 && faces >= (long double)settings.serialBelowFaces;
    impl_->par.grain = settings.serialBelowFaces == 0 ? kTestGrain : detail::kGrain;
    if (impl_->par.on)
        runWithThreads(settings.threads, [&] { impl_->build(cage); });
    else
        impl_->build(cage);
}

const SubdivisionSettings& Subdivider::settings() const {
    return impl_->settings;
}
const PolygonMesh& Subdivider::refined() const {
    return impl_->refined;
}
const RenderMesh& Subdivider::renderMesh() const {
    return impl_->render;
}
const std::vector<uint32_t>& Subdivider::renderToRefinedVertex() const {
    return impl_->renderToRefined;
}
const LimitFrame& Subdivider::limitFrame() const {
    return impl_->frame;
}
const SubdivisionTimings& Subdivider::timings() const {
    return impl_->timings;
}
bool Subdivider::usedSpecializedRefiner() const {
    return impl_->fastBuilt;
}
const std::string& Subdivider::specializedRefinerDeclined() const {
    return impl_->fastDeclined;
}
size_t Subdivider::cageVertexCount() const {
    return impl_->cageVertices;
}
size_t Subdivider::stencilWeightCount() const {
    const Impl& m = *impl_;
    if (m.settings.limit) return m.limitStencils.weightCount() + m.samples.point.size();
    return m.uniformStencils.weightCount();
}

void Subdivider::update(std::span<const glm::vec3> cagePositions, RenderMesh& out,
                        LimitFrame* frame, bool recomputeNormals) const {
    const Impl& m = *impl_;
    SG_EXPECTS(m.settings.animate, "the Subdivider was built with SubdivisionSettings::animate");
    SG_EXPECTS(cagePositions.size() == m.cageVertices, "one position per cage vertex");
    SG_EXPECTS(out.positions.size() == m.render.positions.size(),
               "`out` starts as a copy of renderMesh()");
    if (m.par.on)
        runWithThreads(m.settings.threads,
                       [&] { m.update(cagePositions, out, frame, recomputeNormals); });
    else
        m.update(cagePositions, out, frame, recomputeNormals);
}

void Subdivider::Impl::update(std::span<const glm::vec3> cagePositions, RenderMesh& out,
                              LimitFrame* outFrame, bool recomputeNormals) const {
    const size_t nR = out.positions.size();
    if (settings.limit) {
        // Relative to the box centre, as a build evaluates them.
        const glm::vec3 origin = boxCentre(cagePositions.data(), cagePositions.size());
        points4.resize(limitStencils.numPoints);
        par.each(cagePositions.size(),
                 [&](size_t v) { points4[v] = glm::vec4(cagePositions[v] - origin, 0.0f); });
        limitStencils.apply(points4.data(), par);
        glm::vec3 *du, *dv;
        std::vector<glm::vec3> tmpU, tmpV;
        if (outFrame) {
            outFrame->dPdu.resize(nR);
            outFrame->dPdv.resize(nR);
            du = outFrame->dPdu.data();
            dv = outFrame->dPdv.data();
        } else {
            tmpU.resize(nR);
            tmpV.resize(nR);
            du = tmpU.data();
            dv = tmpV.data();
        }
        samples.evaluate(points4.data(), out.positions.data(), du, dv, par);
        par.each(nR, [&](size_t r) { out.positions[r] += origin; });
        out.normals.resize(nR);
        if (recomputeNormals) {
            par.each(nR,
                     [&](size_t r) { out.normals[r] = safeNormal(du[r], dv[r], out.normals[r]); });
        }
        unifyCopies(out.positions.data(), out.normals.data());
        return;
    }
    points4.resize(uniformStencils.numPoints);
    par.each(cagePositions.size(),
             [&](size_t v) { points4[v] = glm::vec4(cagePositions[v], 0.0f); });
    uniformStencils.apply(points4.data(), par);
    const glm::vec4* levelN = points4.data() + (uniformStencils.numPoints - levelToRefined.size());
    par.each(nR, [&](size_t r) { out.positions[r] = glm::vec3(levelN[renderToLevel[r]]); });
    if (recomputeNormals) polygonNormals(out.positions.data(), out.normals.data(), normalScratch);
}

} // namespace sg::mesh

// ---- Adaptive patches ----------------------------------------------------------

namespace sg::mesh {

namespace {

// The refined vertices at the corners of a patch's domain: descends from
// the patch's ptex face (a base quad, or the level-1 child k of a non-quad
// base face) through the child faces that contain the patch's square,
// tracking every vertex's position in the ptex face in integer units of
// the patch's size (2^depth per face side; exact). The child of a face
// containing the square is found by those positions, not by the order of
// child faces or of their vertices. Returns false if the descent leaves
// the refined hierarchy (a contract of Far's tables, never seen).
bool patchCorners(const Far::TopologyRefiner& refiner, const std::vector<int>& ptexToFace,
                  const Far::PtexIndices& ptex, const std::vector<uint32_t>& levelBase,
                  const Far::PatchParam& pp, glm::uvec4& out) {
    const int depth = pp.GetDepth();
    const int ptexId = pp.GetFaceId();
    if (ptexId < 0 || size_t(ptexId) >= ptexToFace.size()) return false;
    const int base = ptexToFace[size_t(ptexId)];
    int level = 0, face = base;
    const int res = 1 << (depth - (pp.NonQuadRoot() ? 1 : 0)); // face side in patch units
    std::array<Far::Index, 4> fv{};
    std::array<glm::ivec2, 4> pc = {glm::ivec2(0, 0), glm::ivec2(res, 0), glm::ivec2(res, res),
                                    glm::ivec2(0, res)};
    const Far::TopologyLevel& l0 = refiner.GetLevel(0);
    if (pp.NonQuadRoot()) {
        const int k = ptexId - ptex.GetFaceId(base);
        Far::ConstIndexArray cv = l0.GetFaceVertices(base), ce = l0.GetFaceEdges(base);
        const int n = cv.size();
        if (refiner.GetNumLevels() < 2 || k < 0 || k >= n) return false;
        face = l0.GetFaceChildFaces(base)[k];
        fv = {l0.GetVertexChildVertex(cv[k]), l0.GetEdgeChildVertex(ce[k]),
              l0.GetFaceChildVertex(base), l0.GetEdgeChildVertex(ce[(k + n - 1) % n])};
        level = 1;
    } else {
        Far::ConstIndexArray cv = l0.GetFaceVertices(base);
        if (cv.size() != 4) return false;
        for (int j = 0; j < 4; ++j) fv[size_t(j)] = cv[j];
    }
    const glm::ivec2 lo(int(pp.GetU()), int(pp.GetV()));
    for (; level < depth; ++level) {
        if (face == Far::INDEX_INVALID || level + 1 >= refiner.GetNumLevels()) return false;
        const Far::TopologyLevel& lv = refiner.GetLevel(level);
        const Far::TopologyLevel& next = refiner.GetLevel(level + 1);
        Far::ConstIndexArray fe = lv.GetFaceEdges(face);
        // The nine level+1 vertices of this face and their positions.
        std::array<std::pair<Far::Index, glm::ivec2>, 9> known;
        for (int j = 0; j < 4; ++j) {
            known[size_t(j)] = {lv.GetVertexChildVertex(fv[size_t(j)]), pc[size_t(j)]};
            known[size_t(4 + j)] = {lv.GetEdgeChildVertex(fe[j]),
                                    (pc[size_t(j)] + pc[size_t((j + 1) % 4)]) / 2};
        }
        known[8] = {lv.GetFaceChildVertex(face), (pc[0] + pc[2]) / 2};
        bool found = false;
        for (Far::Index child : lv.GetFaceChildFaces(face)) {
            if (child == Far::INDEX_INVALID) continue;
            Far::ConstIndexArray cv = next.GetFaceVertices(child);
            std::array<glm::ivec2, 4> cp{};
            glm::ivec2 mn(INT32_MAX), mx(INT32_MIN);
            bool ok = cv.size() == 4;
            for (int j = 0; ok && j < 4; ++j) {
                auto it = std::find_if(known.begin(), known.end(),
                                       [&](const auto& k) { return k.first == cv[j]; });
                ok = it != known.end();
                if (ok) cp[size_t(j)] = it->second;
                if (ok) mn = glm::min(mn, it->second), mx = glm::max(mx, it->second);
            }
            if (!ok || lo.x < mn.x || lo.y < mn.y || lo.x + 1 > mx.x || lo.y + 1 > mx.y) continue;
            face = child;
            for (int j = 0; j < 4; ++j) fv[size_t(j)] = cv[j];
            pc = cp;
            found = true;
            break;
        }
        if (!found) return false;
    }
    const glm::ivec2 want[4] = {lo, lo + glm::ivec2(1, 0), lo + glm::ivec2(1, 1),
                                lo + glm::ivec2(0, 1)};
    for (int c = 0; c < 4; ++c) {
        int j = 0;
        while (j < 4 && pc[size_t(j)] != want[c]) ++j;
        if (j == 4) return false;
        out[c] = levelBase[size_t(depth)] + uint32_t(fv[size_t(j)]);
    }
    return true;
}

// Face-varying channel ch of the patch table as an AdaptiveUvSet, patches
// in the order of the position arrays. The type of each patch is the one
// Far::PatchTable::EvaluateBasisFaceVarying uses: the channel's regular
// descriptor where the patch's face-varying PatchParam says regular, else
// its irregular one.
AdaptiveUvSet adaptiveUvSet(const Far::TopologyRefiner& refiner, const Far::PatchTable& table,
                            const std::vector<glm::vec2>& cageValues, int ch) {
    AdaptiveUvSet out;
    out.values = fvarPatchPoints(refiner, table, cageValues, ch);
    const int regular = int(table.GetFVarPatchDescriptorRegular(ch).GetType());
    const int irregular = int(table.GetFVarPatchDescriptorIrregular(ch).GetType());
    const uint32_t stride = AdaptiveUvSet::kUvValuesPerPatch;
    for (int a = 0; a < table.GetNumPatchArrays(); ++a) {
        for (int k = 0; k < table.GetNumPatches(a); ++k) {
            const Far::PatchParam pp = table.GetPatchFVarPatchParam(a, k, ch);
            const Far::ConstIndexArray cvs = table.GetPatchFVarValues(a, k, ch);
            out.field1.push_back(pp.field1);
            out.types.push_back(uint32_t(pp.IsRegular() ? regular : irregular));
            const size_t at = out.indices.size();
            out.indices.resize(at + stride, 0u);
            for (int i = 0; i < cvs.size() && uint32_t(i) < stride; ++i)
                out.indices[at + size_t(i)] = uint32_t(cvs[i]);
        }
    }
    return out;
}

// Edge k of a patch runs from corner kEdgeFrom[k] to corner kEdgeTo[k].
constexpr int kEdgeFrom[4] = {0, 0, 1, 3}, kEdgeTo[4] = {3, 1, 2, 2};

uint64_t edgeKey(uint32_t a, uint32_t b) {
    return (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

// The first patch (and its edge or corner) that has each edge (by its two
// vertices) and each corner (by the vertex it refines), in patch order.
struct OwnerMaps {
    std::unordered_map<uint64_t, uint32_t> edgeFirst;   // vertex pair -> (patch << 2) | edge
    std::unordered_map<uint64_t, uint32_t> edgeCount;   // vertex pair -> patches with it
    std::unordered_map<uint32_t, uint32_t> cornerFirst; // root vertex -> (patch << 2) | corner
};

// AdaptivePatches::edgeOwners and cornerOwners from cornerVertices; root[v]
// is the coarsest vertex whose chain of child vertices ends at point v.
OwnerMaps assignOwners(AdaptivePatches& ap, const std::vector<uint32_t>& root) {
    const size_t n = ap.cornerVertices.size();
    OwnerMaps m;
    ap.edgeOwners.assign(n, glm::uvec4(0));
    ap.cornerOwners.assign(n, glm::uvec4(0));
    for (uint32_t p = 0; p < uint32_t(n); ++p) {
        const glm::uvec4 c = ap.cornerVertices[p];
        for (int k = 0; k < 4; ++k) {
            const uint32_t a = c[kEdgeFrom[k]], b = c[kEdgeTo[k]];
            const uint64_t key = edgeKey(a, b);
            const uint32_t first =
                m.edgeFirst.try_emplace(key, (p << 2) | uint32_t(k)).first->second;
            ++m.edgeCount[key];
            const uint32_t owner = first >> 2, ownerEdge = first & 3u;
            const uint32_t ownerFrom = ap.cornerVertices[owner][kEdgeFrom[ownerEdge]];
            ap.edgeOwners[p][k] = (owner << 3) | (ownerEdge << 1) | (ownerFrom != a ? 1u : 0u);
            ap.cornerOwners[p][k] =
                m.cornerFirst.try_emplace(root[c[k]], (p << 2) | uint32_t(k)).first->second;
        }
    }
    return m;
}

// AdaptivePatches::transition*: for each edge of a patch at depth d that no
// other patch of its depth shares, the level-d edge between its two
// vertices, its child vertex (the midpoint) and its ends' child vertices at
// level d + 1; when patches have both halves as edges, it is a transition.
void assignTransitions(AdaptivePatches& ap, const OwnerMaps& m, const Far::TopologyRefiner& refiner,
                       const std::vector<uint32_t>& levelBase, const std::vector<uint32_t>& root) {
    const size_t n = ap.cornerVertices.size();
    ap.transitionMask.assign(n, 0u);
    ap.transitionLo.assign(n, glm::uvec4(0));
    ap.transitionHi.assign(n, glm::uvec4(0));
    ap.transitionMid.assign(n, glm::uvec4(0));
    std::vector<uint64_t> halves;
    // (owner << 3) | (owner's edge << 1) | flip of the half from `from` to `to`.
    auto halfOwner = [&](uint32_t from, uint32_t to, uint32_t& code) {
        const auto it = m.edgeFirst.find(edgeKey(from, to));
        if (it == m.edgeFirst.end()) return false;
        const uint32_t owner = it->second >> 2, ownerEdge = it->second & 3u;
        const uint32_t ownerFrom = ap.cornerVertices[owner][kEdgeFrom[ownerEdge]];
        code = (owner << 3) | (ownerEdge << 1) | (ownerFrom != from ? 1u : 0u);
        return true;
    };
    for (uint32_t p = 0; p < uint32_t(n); ++p) {
        Far::PatchParam pp;
        pp.field0 = ap.params[p].x;
        pp.field1 = ap.params[p].y;
        const int depth = pp.GetDepth();
        if (depth + 1 >= refiner.GetNumLevels()) continue;
        const Far::TopologyLevel& lv = refiner.GetLevel(depth);
        // Level d's vertices are points [lo, next), level d + 1's from next.
        const uint32_t lo = levelBase[size_t(depth)], next = levelBase[size_t(depth) + 1];
        const glm::uvec4 c = ap.cornerVertices[p];
        for (int k = 0; k < 4; ++k) {
            const uint32_t a = c[kEdgeFrom[k]], b = c[kEdgeTo[k]];
            if (a < lo || a >= next || b < lo || b >= next) continue; // not a level-d vertex
            if (m.edgeCount.at(edgeKey(a, b)) != 1) continue;         // shared at its own depth
            const Far::Index e = lv.FindEdge(Far::Index(a - lo), Far::Index(b - lo));
            if (e == Far::INDEX_INVALID) continue;
            const Far::Index ca = lv.GetVertexChildVertex(Far::Index(a - lo));
            const Far::Index cb = lv.GetVertexChildVertex(Far::Index(b - lo));
            const Far::Index cm = lv.GetEdgeChildVertex(e);
            if (ca == Far::INDEX_INVALID || cb == Far::INDEX_INVALID || cm == Far::INDEX_INVALID)
                continue; // the edge was not refined: no finer neighbour
            const uint32_t pa = next + uint32_t(ca), pb = next + uint32_t(cb),
                           pm = next + uint32_t(cm);
            uint32_t codeLo = 0, codeHi = 0;
            if (!halfOwner(pa, pm, codeLo) || !halfOwner(pm, pb, codeHi)) continue;
            const auto mid = m.cornerFirst.find(root[pm]);
            if (mid == m.cornerFirst.end()) continue;
            ap.transitionMask[p] |= 1u << k;
            ap.transitionLo[p][k] = codeLo;
            ap.transitionHi[p][k] = codeHi;
            ap.transitionMid[p][k] = mid->second;
            halves.push_back(edgeKey(pa, pm));
            halves.push_back(edgeKey(pm, pb));
        }
    }
    std::sort(halves.begin(), halves.end());
    for (uint32_t p = 0; p < uint32_t(n); ++p) {
        const glm::uvec4 c = ap.cornerVertices[p];
        for (int k = 0; k < 4; ++k)
            if (std::binary_search(halves.begin(), halves.end(),
                                   edgeKey(c[kEdgeFrom[k]], c[kEdgeTo[k]])))
                ap.transitionMask[p] |= 1u << (4 + k);
    }
}

// The stencil passes of AdaptivePatches (its declaration has the layout):
// one pass per refinement level from Far's StencilTable with
// factorizeIntermediateLevels = false (each level's rows read the level
// above, by its own vertex indices: rebased here onto the global point
// index; Far folds the face points its edge and vertex rules reuse into
// them), then one pass of the patch table's local points (Gregory end
// caps), whose rows read refined points of any level by global index.
// Checks that every row reads only points of earlier passes: the contract
// that lets the GPU run a pass's rows in parallel.
void recordAdaptiveStencils(const Far::TopologyRefiner& refiner, const Far::PatchTable& table,
                            AdaptivePatches& out, const std::string& file) {
    Far::StencilTableFactoryReal<float>::Options sopt;
    sopt.generateIntermediateLevels = true;
    sopt.factorizeIntermediateLevels = false;
    sopt.generateControlVerts = false;
    sopt.generateOffsets = true;
    std::unique_ptr<const Far::StencilTableReal<float>> levels(
        Far::StencilTableFactoryReal<float>::Create(refiner, sopt));
    const Far::StencilTableReal<float>* local = table.GetLocalPointStencilTable<float>();
    out.stencilOffsets.assign(1, 0);
    out.stencilIndices.clear();
    out.stencilWeights.clear();
    out.stencilPasses.assign(1, out.cagePointCount);
    // Rows [first, first + count) of `st`, reading points srcBase + index.
    auto appendRows = [&](const Far::StencilTableReal<float>& st, int first, int count,
                          uint32_t srcBase) {
        const auto& sizes = st.GetSizes();
        const auto& offsets = st.GetOffsets();
        const auto& idx = st.GetControlIndices();
        const auto& w = st.GetWeights();
        const uint32_t passStart = out.stencilPasses.back();
        for (int s = first; s < first + count; ++s) {
            const size_t at = size_t(offsets[size_t(s)]);
            for (int k = 0; k < sizes[size_t(s)]; ++k) {
                const uint32_t src = srcBase + uint32_t(idx[at + size_t(k)]);
                if (idx[at + size_t(k)] < 0 || src >= passStart)
                    throw InputError(file, "stencils",
                                     "a stencil row reads a point of its own pass (OpenSubdiv "
                                     "layout not as expected)");
                out.stencilIndices.push_back(src);
                out.stencilWeights.push_back(w[at + size_t(k)]);
            }
            out.stencilOffsets.push_back(uint32_t(out.stencilIndices.size()));
        }
        if (count > 0) out.stencilPasses.push_back(passStart + uint32_t(count));
    };
    int row = 0;
    uint32_t levelAbove = 0; // global index of the level above's first point
    for (int l = 1; l < refiner.GetNumLevels(); ++l) {
        const int n = refiner.GetLevel(l).GetNumVertices();
        appendRows(*levels, row, n, levelAbove);
        row += n;
        levelAbove += uint32_t(refiner.GetLevel(l - 1).GetNumVertices());
    }
    SG_ASSERT(row == levels->GetNumStencils(), "one stencil per refined vertex");
    if (local) appendRows(*local, 0, local->GetNumStencils(), 0);
    out.points.resize(out.stencilPasses.back());
}

// root[v] for every refined vertex (levels only, not the local points):
// the level-0 or edge/face child vertex whose chain of vertex children
// reaches v (they all have v's limit position).
std::vector<uint32_t> rootVertices(const Far::TopologyRefiner& refiner,
                                   const std::vector<uint32_t>& levelBase) {
    std::vector<uint32_t> root(levelBase.back());
    for (uint32_t i = 0; i < uint32_t(root.size()); ++i) root[i] = i;
    for (int l = 0; l + 1 < refiner.GetNumLevels(); ++l) {
        const Far::TopologyLevel& lv = refiner.GetLevel(l);
        for (int v = 0; v < lv.GetNumVertices(); ++v) {
            const Far::Index child = lv.GetVertexChildVertex(v);
            if (child != Far::INDEX_INVALID)
                root[levelBase[size_t(l) + 1] + uint32_t(child)] =
                    root[levelBase[size_t(l)] + uint32_t(v)];
        }
    }
    return root;
}

} // namespace

AdaptivePatches buildAdaptivePatches(const PolygonMesh& cage, const SubdivOptions& options,
                                     int isolation, const std::string& file, int threads) {
    SG_EXPECTS(threads >= 0 && threads <= kMaxThreads, "threads is 0 (all cores) or 1..1024");
    if (options.scheme != Scheme::Catmark)
        throw InputError(file, "scheme",
                         std::string("adaptive patches need Catmull-Clark (catmark), not ") +
                             toString(options.scheme) + "; use the uniform mode");
    if (isolation < 1 || isolation > 10)
        throw InputError(file, "isolation",
                         "adaptive isolation " + std::to_string(isolation) + " is outside 1..10");
    Descriptor d;
    d.build(cage); // one face-varying channel per UV set
    std::unique_ptr<Far::TopologyRefiner> refiner = createRefiner(d, options, file);
    Far::PatchTableFactory::Options popt(static_cast<unsigned>(isolation));
    popt.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    popt.useInfSharpPatch = true;
    // UV patches as the uniform path's limit evaluation builds them
    // (buildPatches): smooth where the face-varying rule says smooth.
    popt.generateFVarTables = !cage.uvSets.empty();
    popt.generateFVarLegacyLinearPatches = false;
    popt.generateVaryingTables = false;
    popt.generateLegacySharpCornerPatches = false;
    refiner->RefineAdaptive(popt.GetRefineAdaptiveOptions());
    std::unique_ptr<Far::PatchTable> table(Far::PatchTableFactory::Create(*refiner, popt));
    if (!table) throw InputError(file, "limit", "OpenSubdiv could not build patches: " + tFarError);

    AdaptivePatches out;
    out.isolation = isolation;
    out.cagePointCount = uint32_t(cage.positions.size());
    recordAdaptiveStencils(*refiner, *table, out, file);
    updateAdaptivePoints(out, cage.positions, threads);

    for (int a = 0; a < table->GetNumPatchArrays(); ++a) {
        AdaptivePatchArray arr;
        arr.type = int(table->GetPatchArrayDescriptor(a).GetType());
        arr.pointsPerPatch = table->GetPatchArrayDescriptor(a).GetNumControlVertices();
        arr.patchCount = uint32_t(table->GetNumPatches(a));
        arr.firstPatch = uint32_t(out.params.size());
        arr.firstIndex = uint32_t(out.indices.size());
        if (arr.patchCount == 0) continue;
        for (Far::Index i : table->GetPatchArrayVertices(a)) out.indices.push_back(uint32_t(i));
        for (const Far::PatchParam& p : table->GetPatchParams(a))
            out.params.push_back(glm::uvec2(p.field0, p.field1));
        out.arrays.push_back(arr);
    }
    // Corner vertices of every patch.
    Far::PtexIndices ptex(*refiner);
    std::vector<int> ptexToFace(size_t(ptex.GetNumFaces()), -1);
    for (int f = 0; f < refiner->GetLevel(0).GetNumFaces(); ++f) {
        const int sides = refiner->GetLevel(0).GetFaceVertices(f).size();
        for (int k = 0; k < (sides == 4 ? 1 : sides); ++k)
            ptexToFace[size_t(ptex.GetFaceId(f) + k)] = f;
    }
    std::vector<uint32_t> levelBase(size_t(refiner->GetNumLevels()) + 1, 0);
    for (int l = 0; l < refiner->GetNumLevels(); ++l)
        levelBase[size_t(l) + 1] =
            levelBase[size_t(l)] + uint32_t(refiner->GetLevel(l).GetNumVertices());
    out.cornerVertices.resize(out.params.size());
    const Far::PatchParamTable& pt = table->GetPatchParamTable();
    std::vector<uint8_t> found(out.params.size(), 0);
    detail::Parallel par;
    par.on = threads != 1 && out.params.size() >= kAdaptiveSerialBelowPatches;
    auto corners = [&] {
        par.each(out.params.size(), [&](size_t p) {
            found[p] =
                patchCorners(*refiner, ptexToFace, ptex, levelBase, pt[p], out.cornerVertices[p]);
        });
    };
    if (par.on)
        runWithThreads(threads, corners);
    else
        corners();
    for (size_t p = 0; p < out.params.size(); ++p) {
        if (!found[p])
            throw InputError(file, "patch " + std::to_string(p),
                             "the refined face of an adaptive patch was not found");
    }
    const std::vector<uint32_t> root = rootVertices(*refiner, levelBase);
    const OwnerMaps owners = assignOwners(out, root);
    assignTransitions(out, owners, *refiner, levelBase, root);
    for (size_t s = 0; s < cage.uvSets.size(); ++s)
        out.uvSets.push_back(adaptiveUvSet(*refiner, *table, cage.uvSets[s].values, int(s)));
    return out;
}

void updateAdaptivePoints(AdaptivePatches& patches, std::span<const glm::vec3> cagePositions,
                          int threads) {
    SG_EXPECTS(cagePositions.size() == patches.cagePointCount &&
                   patches.points.size() >= patches.cagePointCount,
               "updateAdaptivePoints: one position per cage vertex");
    SG_EXPECTS(threads >= 0 && threads <= kMaxThreads, "threads is 0 (all cores) or 1..1024");
    std::copy(cagePositions.begin(), cagePositions.end(), patches.points.begin());
    // The passes in order; within a pass the rows are independent (each
    // reads only points of earlier passes), so point order is pass order.
    glm::vec3* points = patches.points.data();
    const uint32_t* off = patches.stencilOffsets.data();
    const uint32_t* idx = patches.stencilIndices.data();
    const float* w = patches.stencilWeights.data();
    const uint32_t cage = patches.cagePointCount;
    const size_t rows = patches.points.size() - cage;
    detail::Parallel par;
    par.on = threads != 1 && rows >= kAdaptiveSerialBelowPatches;
    auto run = [&] {
        const std::vector<uint32_t>& passes = patches.stencilPasses;
        for (size_t p = 0; p + 1 < passes.size(); ++p) {
            const uint32_t first = passes[p] - cage;
            par.each(passes[p + 1] - passes[p], [&](size_t i) {
                const size_t r = first + i;
                glm::vec3 q(0.0f);
                for (uint32_t k = off[r]; k < off[r + 1]; ++k) q += w[k] * points[idx[k]];
                points[cage + r] = q;
            });
        }
    };
    if (par.on)
        runWithThreads(threads, run);
    else
        run();
}

} // namespace sg::mesh
