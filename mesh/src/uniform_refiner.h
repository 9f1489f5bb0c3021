// Uniform Catmull-Clark refinement specialised for manifold cages (internal
// to mesh/; used by surfgrad/mesh/subdivision.h's Subdivider).
//
// It computes exactly what OpenSubdiv 3.5 computes for
//   Far::TopologyRefiner::RefineUniform(level N) (vertices ordered from
//   vertices first, OpenSubdiv's default) followed by
//   Far::PrimvarRefiner::Interpolate / InterpolateFaceVarying per level,
// bit for bit: the same numbering of vertices, faces, edges and
// face-varying values at every level, the same subdivision weights (the
// masks come from OpenSubdiv's own Sdc::Scheme<SCHEME_CATMARK>, fed by the
// neighbourhoods below) applied in the same order. tests/mesh/
// uniform_refiner_test.cpp compares both on every accepted shape of
// data/osd-shapes and on spot under every boundary, face-varying
// and crease option.
//
// Why it is faster than Far (3-4x on spot at level 4, bench/README.md
// "Mesh"): OpenSubdiv's Vtr is general (sparse refinement, non-manifold
// topology, any number of faces per edge), so each of its six topology
// relations is a count/offset table filled in its own pass, and the last
// level still gets its vertex-face relation for face-varying data. Here
// the cage is manifold, so edges have at most two faces and every level
// after the first is all quads: child relations are written in one pass
// per parent element with fixed strides, the last level gets only its face
// vertices and face-varying indices, smooth vertices and edges skip the
// generic mask computation (the weights are the same numbers Sdc computes),
// and every buffer is kept between builds (no page faults on a rebuild).
//
// Domain (accept() checks it on OpenSubdiv's own level 0, which the
// factory builds in ~0.1 ms; everything else goes to Far, unchanged):
// Catmull-Clark, no holes, manifold (every edge has one or two distinct
// faces, every vertex one fan, no isolated vertex), creases and corners of
// any sharpness with either creasing method, any boundary rule, the
// triangle rule, any number of UV sets with any face-varying rule except
// one: a UV seam through a vertex with semi-sharp creasing (OpenSubdiv's
// "semi-sharp"/"dependent-sharp" face-varying values) is left to Far.
//
// Vocabulary (OpenSubdiv's): level 0 is the cage; refining level L gives
// level L+1 whose vertices are, in this order, one per vertex, one per
// face and one per edge of level L; the children of face f are faces
// faceOffsets[f] + j (one per corner j); edge e splits into edges
// (corners of level L) + 2e + {0,1}.
#pragma once

#include <opensubdiv/far/topologyRefiner.h>
#include <opensubdiv/sdc/catmarkScheme.h>
#include <opensubdiv/sdc/crease.h>
#include <opensubdiv/sdc/options.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "subdivision_parallel.h"
#include "surfgrad/mesh/polygon_mesh.h"

namespace sg::mesh::detail {

// Per-edge tag bits (OpenSubdiv Vtr::Level::ETag).
enum : uint8_t { kEdgeBoundary = 1, kEdgeInfSharp = 2, kEdgeSemiSharp = 4 };
// Per-vertex tag bits (Vtr::Level::VTag); the rule is kept apart.
enum : uint8_t {
    kVertBoundary = 1,
    kVertInfSharp = 2,
    kVertSemiSharp = 4,
    kVertSemiSharpEdges = 8
};
// Face-varying value tags (Vtr::FVarLevel::ValueTag): a mismatched value
// without kValueCrease is a corner (its value is kept).
enum : uint8_t { kValueMismatch = 1, kValueCrease = 2 };
// Face-varying edge tags (Vtr::FVarLevel::ETag).
enum : uint8_t { kFvEdgeMismatch = 1, kFvEdgeLinear = 2 };

inline constexpr uint32_t kNone = UINT32_MAX;

// One face-varying channel at one level.
struct FVarLevelData {
    std::vector<uint32_t> valueOffsets; // per vertex + 1: its values are [off[v], off[v+1])
    std::vector<uint32_t> valueIndex;   // level 0 only: value slot -> cage value index
    std::vector<uint8_t> valueTags;     // per value slot
    std::vector<uint16_t> creaseStart, creaseEnd; // per value slot (creases): vertex-face span
    std::vector<uint8_t> edgeTags;                // per edge
    std::vector<uint32_t> faceValues;             // per corner: cage index (level 0) or value slot
    std::vector<uint16_t> cornerSibling;          // per corner: which of the vertex's values
};

// One level's topology. The last level holds only numbers, face vertices
// (faceVerts), face-varying values and, with sharp features, the
// sharpness/tags its vertices' rules need.
struct RefineLevel {
    uint32_t numVerts = 0, numFaces = 0, numEdges = 0, numCorners = 0;
    std::vector<uint32_t> faceOffsets; // numFaces + 1
    std::vector<uint32_t> faceVerts, faceEdges;
    std::vector<uint32_t> edgeVerts;  // 2 per edge
    std::vector<uint32_t> edgeFaces;  // 2 per edge, kNone for the missing one on a boundary
    std::vector<uint16_t> edgeInFace; // 2 per edge: the edge's index in that face
    std::vector<uint32_t> vertFaceOffsets, vertEdgeOffsets; // numVerts + 1
    std::vector<uint32_t> vertFaces, vertEdges;             // counter-clockwise around the vertex
    std::vector<uint16_t> vertInFace, vertInEdge; // the vertex's index in that face / edge
    std::vector<uint32_t> vertRing;               // per vertex edge: the edge's other vertex
    // Any sharpness > 0, boundary or non-smooth rule: tags, sharpness and
    // rules are kept (else every vertex and edge of the level is smooth).
    bool tagged = false;
    bool triangles = false; // any triangle (matters for the smooth-triangle rule)
    std::vector<float> edgeSharpness, vertSharpness;
    std::vector<uint8_t> edgeTags, vertTags, vertRules; // rules: Sdc::Crease::Rule
    std::vector<FVarLevelData> fvar;

    uint32_t faceSize(uint32_t f) const { return faceOffsets[f + 1] - faceOffsets[f]; }
    uint32_t edgeFaceCount(uint32_t e) const { return edgeFaces[2 * e + 1] == kNone ? 1u : 2u; }
};

class UniformRefiner {
public:
    // Reads level 0 from `base` (straight from TopologyRefinerFactory, not
    // refined yet) and prepares the face-varying channels of `cage` (the
    // one `base` was built from). Returns false, with `why` set, when the
    // cage is outside the domain above; then nothing else may be called.
    bool accept(const OpenSubdiv::Far::TopologyRefiner& base, const PolygonMesh& cage,
                std::string& why);

    // Refines the topology to `levels` >= 1 levels (after accept()). With
    // par.on the per-element loops of each level run on TBB (disjoint
    // outputs; offsets are prefix sums on the calling thread): the same
    // topology for every thread count.
    void refine(int levels, const Parallel& par = {});

    int maxLevel() const { return levels_; }
    const RefineLevel& level(int l) const { return level_[size_t(l)]; }
    int numFVarChannels() const { return int(level_[0].fvar.size()); }
    uint32_t numFVarValues(int l, int channel) const {
        return level_[size_t(l)].fvar[size_t(channel)].valueOffsets.back();
    }

    // Last level: face vertices (4 per face) and each channel's face
    // values. Swapped out (the caller's vectors come back as scratch, so
    // capacity moves between the refiner and its caller without copies).
    void takeLastFaceVertices(std::vector<uint32_t>& out) {
        out.swap(level_[size_t(levels_)].faceVerts);
    }
    void takeLastFaceValues(int channel, std::vector<uint32_t>& out) {
        out.swap(level_[size_t(levels_)].fvar[size_t(channel)].faceValues);
    }

    // Crease and corner tags of the last level, as Far's TopologyLevel
    // reports them (non-boundary edges with sharpness > 0, in edge order;
    // vertices with sharpness > 0, skipping boundary vertices when
    // `skipBoundaryCorners`).
    void lastLevelCreases(std::vector<EdgeCrease>& creases, std::vector<VertexCorner>& corners,
                          bool skipBoundaryCorners) const;

    // PrimvarRefiner::Interpolate(level, src, dst): vertex data of level
    // `level` - 1 to level `level`, through a writer (ArrayWriter below;
    // taken by value so its accumulator can live in registers). In three
    // phases (face, edge, vertex points); with par.on each phase runs on
    // TBB with one copy of the writer per block, so the writer must write
    // child `begin(child)`'s value only (ArrayWriter, Vec4Writer; not a
    // recorder that appends): each child's sum is formed in the same order
    // as serially, bit for bit.
    template <class Writer>
    void interpolate(int level, Writer writer, const Parallel& par = {}) const;
    // PrimvarRefiner::InterpolateFaceVarying(level, src, dst, channel).
    template <class Writer>
    void interpolateFaceVarying(int level, Writer writer, int channel,
                                const Parallel& par = {}) const;

private:
    // Sdc neighbourhoods (OpenSubdiv's EDGE / VERTEX interfaces, with the
    // same answers as Vtr's EdgeInterface / VertexInterface).
    struct EdgeHood {
        const RefineLevel* parent;
        uint32_t edge;
        int GetNumFaces() const { return int(parent->edgeFaceCount(edge)); }
        float GetSharpness() const { return parent->edgeSharpness[edge]; }
        void GetChildSharpnesses(const OpenSubdiv::Sdc::Crease&, float s[2]) const {
            s[0] = s[1] = GetSharpness() - 1.0f;
        }
        void GetNumVerticesPerFace(int counts[]) const {
            for (uint32_t i = 0; i < parent->edgeFaceCount(edge); ++i)
                counts[i] = int(parent->faceSize(parent->edgeFaces[2 * edge + i]));
        }
    };
    struct VertexHood {
        const RefineLevel* parent;
        const RefineLevel* child;
        uint32_t vert;
        int GetNumEdges() const {
            return int(parent->vertEdgeOffsets[vert + 1] - parent->vertEdgeOffsets[vert]);
        }
        int GetNumFaces() const {
            return int(parent->vertFaceOffsets[vert + 1] - parent->vertFaceOffsets[vert]);
        }
        float GetSharpness() const { return parent->vertSharpness[vert]; }
        float* GetSharpnessPerEdge(float out[]) const {
            const uint32_t* e = parent->vertEdges.data() + parent->vertEdgeOffsets[vert];
            for (int i = 0; i < GetNumEdges(); ++i) out[i] = parent->edgeSharpness[e[i]];
            return out;
        }
        float GetChildSharpness(const OpenSubdiv::Sdc::Crease&) const {
            return child->vertSharpness[vert];
        }
        float* GetChildSharpnessPerEdge(const OpenSubdiv::Sdc::Crease& crease, float out[]) const;
    };
    // PrimvarRefiner's MASK interface.
    struct Mask {
        using Weight = float;
        float *vw, *ew, *fw;
        int nv = 0, ne = 0, nf = 0;
        bool centers = false;
        int GetNumVertexWeights() const { return nv; }
        int GetNumEdgeWeights() const { return ne; }
        int GetNumFaceWeights() const { return nf; }
        void SetNumVertexWeights(int n) { nv = n; }
        void SetNumEdgeWeights(int n) { ne = n; }
        void SetNumFaceWeights(int n) { nf = n; }
        float& VertexWeight(int i) { return vw[i]; }
        float& EdgeWeight(int i) { return ew[i]; }
        float& FaceWeight(int i) { return fw[i]; }
        const float& VertexWeight(int i) const { return vw[i]; }
        const float& EdgeWeight(int i) const { return ew[i]; }
        const float& FaceWeight(int i) const { return fw[i]; }
        bool AreFaceWeightsForFaceCenters() const { return centers; }
        void SetFaceWeightsForFaceCenters(bool on) { centers = on; }
    };

    // Edge-vertex mask of parent edge e (level p -> p+1): the 2 vertex
    // weights and the face weights (one per edge face). Returns the number
    // of face weights.
    int edgeMask(const RefineLevel& P, const RefineLevel& C, uint32_t e, float vw[2],
                 float fw[2]) const;
    // Sdc's mask for the other cases (semi-sharp transitions, triangles).
    int edgeMaskGeneric(const RefineLevel& P, const RefineLevel& C, uint32_t e, float vw[2],
                        float fw[2]) const;
    bool triangleRule_(const RefineLevel& P) const {
        return P.triangles &&
               options_.GetTriangleSubdivision() == OpenSubdiv::Sdc::Options::TRI_SUB_SMOOTH;
    }
    // Vertex-vertex mask of parent vertex v (Sdc's, for any rule); the mask's
    // buffers hold 1 + 2 * valence weights.
    void vertexMask(const RefineLevel& P, const RefineLevel& C, uint32_t v, Mask& mask) const;
    bool smoothVertex(const RefineLevel& P, uint32_t v) const {
        if (!P.tagged) return true;
        const uint8_t r = P.vertRules[v];
        return r == OpenSubdiv::Sdc::Crease::RULE_SMOOTH || r == OpenSubdiv::Sdc::Crease::RULE_DART;
    }

    // Face-varying neighbourhood queries (Vtr::FVarLevel's).
    uint32_t valueAt(const FVarLevelData& F, uint32_t v, uint32_t sibling) const {
        const uint32_t slot = F.valueOffsets[v] + sibling;
        return F.valueIndex.empty() ? slot : F.valueIndex[slot];
    }
    uint32_t valueCount(const FVarLevelData& F, uint32_t v) const {
        return F.valueOffsets[v + 1] - F.valueOffsets[v];
    }
    void edgeFaceValues(const RefineLevel& P, const FVarLevelData& F, uint32_t e,
                        uint32_t faceInEdge, uint32_t out[2]) const;
    void vertexEdgeValues(const RefineLevel& P, const FVarLevelData& F, uint32_t v,
                          uint32_t* out) const;
    void creaseEndValues(const RefineLevel& P, const FVarLevelData& F, uint32_t v, uint32_t sibling,
                         uint32_t out[2]) const;

    template <class Writer>
    void fvarVertexValues(const RefineLevel& P, const RefineLevel& C, const FVarLevelData& PF,
                          uint32_t v, const uint32_t* childValue, Writer& w) const;

    bool classifyFVar(const PolygonMesh& cage, size_t channel, std::string& why);
    void refineTopology(const RefineLevel& P, RefineLevel& C, bool last, const Parallel& par);
    void refineSharpness(const RefineLevel& P, RefineLevel& C, const Parallel& par);
    void refineFVar(const RefineLevel& P, RefineLevel& C, size_t channel, bool last,
                    const Parallel& par);
    void fvarValueTags(const RefineLevel& P, RefineLevel& C, size_t channel, const Parallel& par);
    void fvarCreaseSpans(const RefineLevel& P, RefineLevel& C, size_t channel, const Parallel& par);

    OpenSubdiv::Sdc::Options options_;
    bool fvarLinear_ = false, fvarSmoothBoundaries_ = true;
    int levels_ = 0;
    std::vector<RefineLevel> level_; // kept between builds (capacity)
    // Smooth vertex weights per valence (index < kSmoothTable), computed
    // exactly as Sdc::Scheme<SCHEME_CATMARK>::assignSmoothMaskForVertex does.
    static constexpr int kSmoothTable = 64;
    float smoothVertexWeight_[kSmoothTable] = {}, smoothRingWeight_[kSmoothTable] = {};
};

// ---- Interpolation ---------------------------------------------------------------

// The writer protocol of UniformRefiner::interpolate*: for each child value
//   w.begin(child); w.add(parentValue, weight) ...; w.addChild(child2, weight) ...; w.end();
// where addChild reads a child value finished before (face points inside
// edge and vertex points), in PrimvarRefiner's order of operations. This
// writer evaluates into an array, accumulating from 0 exactly as
// PrimvarRefiner's Clear() + AddWithWeight() do (so results are bitwise
// equal); the Subdivider's stencil recorder is another writer.
template <class V>
struct ArrayWriter {
    const V* src;
    V* dst;
    V acc;
    uint32_t at = 0;
    void begin(uint32_t child) {
        at = child;
        acc = V(0.0f);
    }
    void add(uint32_t parent, float w) { acc += w * src[parent]; }
    void addChild(uint32_t child, float w) { acc += w * dst[child]; }
    void end() { dst[at] = acc; }
};

// ArrayWriter for xyz values with the arithmetic done on 4 floats (the 4th
// lane zero and ignored): In/Out are glm::vec3 or glm::vec4 arrays (the
// Subdivider keeps intermediate levels as vec4). Each weighted add is then
// one 4-lane multiply and one 4-lane add whose x, y, z lanes are exactly
// the scalar IEEE operations ArrayWriter<glm::vec3> performs (no fused
// multiply-add: the build does not enable FMA), so results are bitwise equal.
template <class In, class Out>
struct Vec4Writer {
    const In* src;
    Out* dst;
    glm::vec4 acc{0.0f};
    uint32_t at = 0;
    static glm::vec4 widen(const glm::vec3& v) { return glm::vec4(v, 0.0f); }
    static glm::vec4 widen(const glm::vec4& v) { return v; }
    static void store(glm::vec3& out, const glm::vec4& v) { out = glm::vec3(v); }
    static void store(glm::vec4& out, const glm::vec4& v) { out = v; }
    void begin(uint32_t child) {
        at = child;
        acc = glm::vec4(0.0f);
    }
    void add(uint32_t parent, float w) { acc += w * widen(src[parent]); }
    void addChild(uint32_t child, float w) { acc += w * widen(dst[child]); }
    void end() { store(dst[at], acc); }
};

inline int UniformRefiner::edgeMask(const RefineLevel& P, const RefineLevel& C, uint32_t e,
                                    float vw[2], float fw[2]) const {
    const bool creased = P.tagged && P.edgeSharpness[e] > 0.0f;
    if (!creased && !triangleRule_(P)) {
        // Sdc::Scheme<SCHEME_CATMARK>::assignSmoothMaskForEdge.
        const uint32_t n = P.edgeFaceCount(e);
        vw[0] = vw[1] = 0.25f;
        if (n == 2)
            fw[0] = fw[1] = 0.25f;
        else
            fw[0] = 0.5f / float(n);
        return int(n);
    }
    if (creased &&
        C.vertRules[P.numVerts + P.numFaces + e] == OpenSubdiv::Sdc::Crease::RULE_CREASE) {
        vw[0] = vw[1] = 0.5f; // assignCreaseMaskForEdge
        return 0;
    }
    return edgeMaskGeneric(P, C, e, vw, fw);
}

inline void UniformRefiner::edgeFaceValues(const RefineLevel& P, const FVarLevelData& F, uint32_t e,
                                           uint32_t faceInEdge, uint32_t out[2]) const {
    const uint32_t v0 = P.edgeVerts[2 * e], v1 = P.edgeVerts[2 * e + 1];
    if (valueCount(F, v0) + valueCount(F, v1) > 2) {
        const uint32_t f = P.edgeFaces[2 * e + faceInEdge], eif = P.edgeInFace[2 * e + faceInEdge];
        const uint32_t off = P.faceOffsets[f], k = P.faceOffsets[f + 1] - off;
        out[0] = F.faceValues[off + eif];
        out[1] = F.faceValues[off + (eif + 1 == k ? 0 : eif + 1)];
        if (v0 != P.faceVerts[off + eif]) std::swap(out[0], out[1]);
    } else {
        out[0] = valueAt(F, v0, 0);
        out[1] = valueAt(F, v1, 0);
    }
}

inline void UniformRefiner::vertexEdgeValues(const RefineLevel& P, const FVarLevelData& F,
                                             uint32_t v, uint32_t* out) const {
    const uint32_t* rv = P.vertRing.data() + P.vertEdgeOffsets[v];
    const uint32_t* vf = P.vertFaces.data() + P.vertFaceOffsets[v];
    const uint16_t* vif = P.vertInFace.data() + P.vertFaceOffsets[v];
    const uint32_t ne = P.vertEdgeOffsets[v + 1] - P.vertEdgeOffsets[v];
    const uint32_t nf = P.vertFaceOffsets[v + 1] - P.vertFaceOffsets[v];
    const bool boundary = ne > nf;
    for (uint32_t i = 0; i < ne; ++i) {
        const uint32_t other = rv[i];
        if (valueCount(F, other) == 1) {
            out[i] = valueAt(F, other, 0);
        } else if (boundary && i == ne - 1) {
            const uint32_t f = vf[i - 1], off = P.faceOffsets[f], k = P.faceOffsets[f + 1] - off;
            out[i] = F.faceValues[off + (vif[i - 1] ? vif[i - 1] - 1u : k - 1)];
        } else {
            const uint32_t f = vf[i], off = P.faceOffsets[f], k = P.faceOffsets[f + 1] - off;
            out[i] = F.faceValues[off + (vif[i] + 1u == k ? 0 : vif[i] + 1u)];
        }
    }
}

template <class Writer>
void UniformRefiner::interpolate(int level, Writer writer, const Parallel& par) const {
    const RefineLevel& P = level_[size_t(level) - 1];
    const RefineLevel& C = level_[size_t(level)];
    const uint32_t firstFaceChild = P.numVerts, firstEdgeChild = P.numVerts + P.numFaces;
    // Face points: the average of the face's vertices (Sdc face mask 1/n).
    par.blocks(P.numFaces, [&](size_t b, size_t end) {
        Writer w = writer;
        for (uint32_t f = uint32_t(b); f < end; ++f) {
            const uint32_t* fv = P.faceVerts.data() + P.faceOffsets[f];
            const uint32_t n = P.faceOffsets[f + 1] - P.faceOffsets[f];
            const float wf = 1.0f / float(n);
            w.begin(firstFaceChild + f);
            for (uint32_t i = 0; i < n; ++i) w.add(fv[i], wf);
            w.end();
        }
    });
    // Edge points: both ends, then the face points of the edge's faces.
    par.blocks(P.numEdges, [&](size_t b, size_t end) {
        Writer w = writer;
        float vw[2], fw[2];
        for (uint32_t e = uint32_t(b); e < end; ++e) {
            const int nf = edgeMask(P, C, e, vw, fw);
            w.begin(firstEdgeChild + e);
            w.add(P.edgeVerts[2 * e], vw[0]);
            w.add(P.edgeVerts[2 * e + 1], vw[1]);
            for (int i = 0; i < nf; ++i)
                w.addChild(firstFaceChild + P.edgeFaces[2 * e + uint32_t(i)], fw[i]);
            w.end();
        }
    });
    // Vertex points: face points, then the far ends of the edges, then the
    // vertex itself (PrimvarRefiner applies the smaller weights first).
    par.blocks(P.numVerts, [&](size_t b, size_t end) {
        Writer w = writer;
        std::vector<float> buffer;
        for (uint32_t v = uint32_t(b); v < end; ++v) {
            const uint32_t* vf = P.vertFaces.data() + P.vertFaceOffsets[v];
            const uint32_t* rv = P.vertRing.data() + P.vertEdgeOffsets[v];
            const uint32_t nf = P.vertFaceOffsets[v + 1] - P.vertFaceOffsets[v];
            const uint32_t ne = P.vertEdgeOffsets[v + 1] - P.vertEdgeOffsets[v];
            w.begin(v);
            if (nf == ne && nf < uint32_t(kSmoothTable) && smoothVertex(P, v)) {
                const float ring = smoothRingWeight_[nf];
                for (uint32_t i = 0; i < nf; ++i) w.addChild(firstFaceChild + vf[i], ring);
                for (uint32_t i = 0; i < ne; ++i) w.add(rv[i], ring);
                w.add(v, smoothVertexWeight_[nf]);
                w.end();
                continue;
            }
            buffer.resize(1 + 2 * size_t(ne));
            Mask m{buffer.data(), buffer.data() + 1, buffer.data() + 1 + ne};
            vertexMask(P, C, v, m);
            if (m.nf > 0) {
                for (uint32_t i = 0; i < nf; ++i) w.addChild(firstFaceChild + vf[i], m.fw[i]);
            }
            if (m.ne > 0) {
                for (uint32_t i = 0; i < ne; ++i) w.add(rv[i], m.ew[i]);
            }
            w.add(v, m.vw[0]);
            w.end();
        }
    });
}

template <class Writer>
void UniformRefiner::interpolateFaceVarying(int level, Writer writer, int channel,
                                            const Parallel& par) const {
    const RefineLevel& P = level_[size_t(level) - 1];
    const RefineLevel& C = level_[size_t(level)];
    const FVarLevelData& PF = P.fvar[size_t(channel)];
    const FVarLevelData& CF = C.fvar[size_t(channel)];
    const uint32_t firstFaceChild = P.numVerts, firstEdgeChild = P.numVerts + P.numFaces;
    const uint32_t* childValue = CF.valueOffsets.data(); // first value of each child vertex
    // Face values: the average of the face's values.
    par.blocks(P.numFaces, [&](size_t b, size_t end) {
        Writer w = writer;
        for (uint32_t f = uint32_t(b); f < end; ++f) {
            const uint32_t* fv = PF.faceValues.data() + P.faceOffsets[f];
            const uint32_t n = P.faceOffsets[f + 1] - P.faceOffsets[f];
            const float wf = 1.0f / float(n);
            w.begin(childValue[firstFaceChild + f]);
            for (uint32_t i = 0; i < n; ++i) w.add(fv[i], wf);
            w.end();
        }
    });
    // Edge values: continuous edges take the vertex data's mask (linear
    // channels the midpoint); each side of a seam its own midpoint.
    par.blocks(P.numEdges, [&](size_t b, size_t end) {
        Writer w = writer;
        float vw[2], fw[2];
        uint32_t ends[2];
        for (uint32_t e = uint32_t(b); e < end; ++e) {
            const uint32_t first = childValue[firstEdgeChild + e];
            if (!(PF.edgeTags[e] & (kFvEdgeMismatch | kFvEdgeLinear))) {
                int nf = 0;
                if (fvarLinear_)
                    vw[0] = vw[1] = 0.5f;
                else
                    nf = edgeMask(P, C, e, vw, fw);
                edgeFaceValues(P, PF, e, 0, ends);
                w.begin(first);
                w.add(ends[0], vw[0]);
                w.add(ends[1], vw[1]);
                for (int i = 0; i < nf; ++i)
                    w.addChild(childValue[firstFaceChild + P.edgeFaces[2 * e + uint32_t(i)]],
                               fw[i]);
                w.end();
            } else {
                const uint32_t count = childValue[firstEdgeChild + e + 1] - first;
                for (uint32_t i = 0; i < count; ++i) {
                    edgeFaceValues(P, PF, e, i, ends);
                    w.begin(first + i);
                    w.add(ends[0], 0.5f);
                    w.add(ends[1], 0.5f);
                    w.end();
                }
            }
        }
    });
    // Vertex values.
    par.blocks(P.numVerts, [&](size_t b, size_t end) {
        Writer w = writer;
        for (uint32_t v = uint32_t(b); v < end; ++v) fvarVertexValues(P, C, PF, v, childValue, w);
    });
}

// The child values of parent vertex v (interpolateFaceVarying's vertex
// phase).
template <class Writer>
void UniformRefiner::fvarVertexValues(const RefineLevel& P, const RefineLevel& C,
                                      const FVarLevelData& PF, uint32_t v,
                                      const uint32_t* childValue, Writer& w) const {
    const uint32_t firstFaceChild = P.numVerts;
    const uint32_t firstChild = childValue[v];
    const bool matches = !(PF.valueTags[PF.valueOffsets[v]] & kValueMismatch);
    if (matches) {
        w.begin(firstChild);
        if (fvarLinear_) {
            w.add(valueAt(PF, v, 0), 1.0f);
            w.end();
            return;
        }
        const uint32_t* vf = P.vertFaces.data() + P.vertFaceOffsets[v];
        const uint32_t nf = P.vertFaceOffsets[v + 1] - P.vertFaceOffsets[v];
        const uint32_t ne = P.vertEdgeOffsets[v + 1] - P.vertEdgeOffsets[v];
        uint32_t smallEdgeValues[kSmoothTable];
        std::vector<uint32_t> bigEdgeValues;
        uint32_t* edgeValues = smallEdgeValues;
        if (ne > uint32_t(kSmoothTable)) {
            bigEdgeValues.resize(ne);
            edgeValues = bigEdgeValues.data();
        }
        vertexEdgeValues(P, PF, v, edgeValues);
        if (nf == ne && nf < uint32_t(kSmoothTable) && smoothVertex(P, v)) {
            const float ring = smoothRingWeight_[nf];
            for (uint32_t i = 0; i < nf; ++i) w.addChild(childValue[firstFaceChild + vf[i]], ring);
            for (uint32_t i = 0; i < ne; ++i) w.add(edgeValues[i], ring);
            w.add(valueAt(PF, v, 0), smoothVertexWeight_[nf]);
            w.end();
            return;
        }
        float smallMask[1 + 2 * kSmoothTable];
        std::vector<float> bigMask;
        float* buffer = smallMask;
        if (ne > uint32_t(kSmoothTable)) {
            bigMask.resize(1 + 2 * size_t(ne));
            buffer = bigMask.data();
        }
        Mask m{buffer, buffer + 1, buffer + 1 + ne};
        vertexMask(P, C, v, m);
        if (m.nf > 0) {
            for (uint32_t i = 0; i < nf; ++i)
                w.addChild(childValue[firstFaceChild + vf[i]], m.fw[i]);
        }
        if (m.ne > 0) {
            for (uint32_t i = 0; i < ne; ++i) w.add(edgeValues[i], m.ew[i]);
        }
        w.add(valueAt(PF, v, 0), m.vw[0]);
        w.end();
        return;
    }
    // A seam through the vertex: each value is a corner (kept) or a
    // crease along its two seam edges (3/4, 1/8, 1/8).
    uint32_t ends[2];
    const uint32_t count = childValue[v + 1] - firstChild;
    for (uint32_t s = 0; s < count; ++s) {
        w.begin(firstChild + s);
        const uint32_t pv = valueAt(PF, v, s);
        if (fvarLinear_ || !(PF.valueTags[PF.valueOffsets[v] + s] & kValueCrease)) {
            w.add(pv, 1.0f);
        } else {
            creaseEndValues(P, PF, v, s, ends);
            w.add(ends[0], 0.125f);
            w.add(ends[1], 0.125f);
            w.add(pv, 0.75f);
        }
        w.end();
    }
}

} // namespace sg::mesh::detail
