// Adaptive patches for the tessellation stages (surfgrad/mesh/adaptive_patches.h):
// OpenSubdiv's feature-adaptive PatchTable (Nießner, Loop, Meyer & DeRose
// 2012; Gregory-basis end caps) with face-varying UV patches, the stencils
// from the cage to every patch point, and each patch's corner vertices in
// the uniformly refined hierarchy.
#include "surfgrad/mesh/adaptive_patches.h"

#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/ptexIndices.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include <algorithm>
#include <array>
#include <unordered_map>

#include <glm/common.hpp>

#include "osd_plumbing.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/base/io.h"
#include "surfgrad/base/threads.h"
#include "subdivision_parallel.h"

namespace sg::mesh {

using detail::createRefiner;
using detail::Descriptor;
using detail::fvarPatchPoints;
using detail::tFarError;
using io::InputError;
namespace Far = OpenSubdiv::Far;

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