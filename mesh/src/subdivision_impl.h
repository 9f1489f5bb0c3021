// Subdivider::Impl, internal to mesh/: the state of one subdivision job
// and its steps (subdivision.cpp: refinement, render mesh, rebuilds,
// update(); limit_samples.cpp: limit evaluation), with the limit sample
// table and the patch bookkeeping those steps share.
#pragma once

#include "surfgrad/mesh/subdivision.h"

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
#include "factored_stencils.h"
#include "osd_plumbing.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/osd_primvar.h"
#include "surfgrad/base/threads.h"
#include "subdivision_parallel.h"
#include "uniform_refiner.h"

namespace sg::mesh {

namespace Far = OpenSubdiv::Far;

namespace detail {

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
inline glm::vec3 boxCentre(const glm::vec3* p, size_t n) {
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
inline void toPtexUnits(const Far::PatchParam& param, int n, float* du, float* dv) {
    if (!param.NonQuadRoot()) return;
    for (int k = 0; k < n; ++k) {
        du[k] *= 0.5f;
        dv[k] *= 0.5f;
    }
}

inline glm::vec3 safeNormal(const glm::vec3& du, const glm::vec3& dv, const glm::vec3& fallback) {
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

} // namespace detail

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
    detail::Descriptor descriptor;
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
    std::vector<detail::FactoredStencils> fvarStencils;
    std::vector<glm::vec2> uvPoints;

    // Animation / limit.
    detail::FactoredStencils
        uniformStencils;                    // cage -> every uniform level (positions, morph deltas)
    detail::FactoredStencils limitStencils; // limit: cage -> adaptive points + local points
    detail::SampleTable samples;            // limit: per render vertex
    mutable std::vector<glm::vec3> points;  // build scratch (all stencil points)
    // update() scratch: xyz in 4 floats (4th lane 0), so
    // each weighted add of detail::FactoredStencils::apply is one 4-lane multiply
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
    detail::LimitPatches buildPatches(const PolygonMesh& cage) const;
    void recordLimitStencils(const PolygonMesh& cage, const detail::LimitPatches& lp);
    void locateHomes(const Far::TopologyRefiner& uniform, const detail::LimitPatches& lp,
                     detail::LimitHomes& homes, std::vector<uint8_t>& dropFace);
    void buildSamples(const detail::LimitPatches& lp, detail::LimitHomes& homes);
    void addSample(const detail::LimitPatches& lp, detail::LimitHomes& homes,
                   const std::vector<uint32_t>& faceOf, size_t r, detail::SampleTable& table);
    void evaluatePositions(const PolygonMesh& cage);
    void evaluateUvSets(const PolygonMesh& cage, const detail::LimitPatches& lp,
                        const detail::LimitHomes& homes);
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

} // namespace sg::mesh
