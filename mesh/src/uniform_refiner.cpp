// Uniform Catmull-Clark refinement specialised for manifold cages
// (uniform_refiner.h): level 0 from OpenSubdiv's factory, then topology,
// sharpness and face-varying topology level by level with OpenSubdiv 3.5's
// numbering and rules (Vtr::QuadRefinement, Vtr::Refinement's sharpness
// subdivision and semi-sharp reclassification, Vtr::FVarLevel's value
// classification and Vtr::FVarRefinement's propagation), written for the
// manifold all-quads case. Subdivision math: Catmull & Clark 1978; creases
// DeRose, Kass & Truong 1998 (Sdc::Crease); face-varying boundary rules as
// documented in OpenSubdiv's "Face-Varying Interpolation" options.
#include "uniform_refiner.h"

#include "surfgrad/base/contract.h"

#include <opensubdiv/far/topologyLevel.h>

#include <algorithm>

namespace sg::mesh::detail {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using Sdc::Crease;

namespace {

// Grows-or-shrinks to exactly n; a vector that had n entries last build is
// neither touched nor reallocated.
template <class T>
void sized(std::vector<T>& v, size_t n) {
    v.resize(n);
}

} // namespace

float* UniformRefiner::VertexHood::GetChildSharpnessPerEdge(const Crease& crease,
                                                            float out[]) const {
    const int n = GetNumEdges();
    float parentSharpness[64];
    std::vector<float> big;
    float* p = parentSharpness;
    if (n > 64) {
        big.resize(size_t(n));
        p = big.data();
    }
    GetSharpnessPerEdge(p);
    crease.SubdivideEdgeSharpnessesAroundVertex(n, p, out);
    return out;
}

// ---- Level 0 -------------------------------------------------------------------

bool UniformRefiner::accept(const Far::TopologyRefiner& base, const PolygonMesh& cage,
                            std::string& why) {
    levels_ = 0;
    if (base.GetSchemeType() != Sdc::SCHEME_CATMARK) {
        why = "not Catmull-Clark";
        return false;
    }
    if (!cage.holes.empty()) {
        why = "holes";
        return false;
    }
    options_ = base.GetSchemeOptions();
    for (int n = 1; n < kSmoothTable; ++n) {
        // Sdc::Scheme<SCHEME_CATMARK>::assignSmoothMaskForVertex, float.
        smoothVertexWeight_[n] = float(n - 2) / float(n);
        smoothRingWeight_[n] = 1.0f / float(n * n);
    }
    if (level_.empty()) level_.resize(1);
    RefineLevel& Z = level_[0];
    const Far::TopologyLevel& L = base.GetLevel(0);
    Z.numVerts = uint32_t(L.GetNumVertices());
    Z.numFaces = uint32_t(L.GetNumFaces());
    Z.numEdges = uint32_t(L.GetNumEdges());
    Z.numCorners = uint32_t(L.GetNumFaceVertices());

    sized(Z.faceOffsets, Z.numFaces + 1);
    sized(Z.faceVerts, Z.numCorners);
    sized(Z.faceEdges, Z.numCorners);
    Z.triangles = false;
    uint32_t at = 0;
    for (uint32_t f = 0; f < Z.numFaces; ++f) {
        Far::ConstIndexArray fv = L.GetFaceVertices(int(f)), fe = L.GetFaceEdges(int(f));
        if (fv.size() > 0xffff) {
            why = "a face with more than 65535 corners";
            return false;
        }
        Z.triangles |= fv.size() == 3;
        Z.faceOffsets[f] = at;
        for (int j = 0; j < fv.size(); ++j) {
            Z.faceVerts[at + uint32_t(j)] = uint32_t(fv[j]);
            Z.faceEdges[at + uint32_t(j)] = uint32_t(fe[j]);
        }
        at += uint32_t(fv.size());
    }
    Z.faceOffsets[Z.numFaces] = at;

    sized(Z.edgeVerts, 2 * size_t(Z.numEdges));
    sized(Z.edgeFaces, 2 * size_t(Z.numEdges));
    sized(Z.edgeInFace, 2 * size_t(Z.numEdges));
    sized(Z.edgeSharpness, Z.numEdges);
    sized(Z.edgeTags, Z.numEdges);
    bool tagged = false;
    for (uint32_t e = 0; e < Z.numEdges; ++e) {
        Far::ConstIndexArray ev = L.GetEdgeVertices(int(e)), ef = L.GetEdgeFaces(int(e));
        Far::ConstLocalIndexArray eif = L.GetEdgeFaceLocalIndices(int(e));
        if (L.IsEdgeNonManifold(int(e)) || ev[0] == ev[1] || ef.size() < 1 || ef.size() > 2 ||
            (ef.size() == 2 && ef[0] == ef[1])) {
            why = "non-manifold or degenerate edge " + std::to_string(e);
            return false;
        }
        Z.edgeVerts[2 * e] = uint32_t(ev[0]);
        Z.edgeVerts[2 * e + 1] = uint32_t(ev[1]);
        Z.edgeFaces[2 * e] = uint32_t(ef[0]);
        Z.edgeInFace[2 * e] = uint16_t(eif[0]);
        Z.edgeFaces[2 * e + 1] = ef.size() == 2 ? uint32_t(ef[1]) : kNone;
        Z.edgeInFace[2 * e + 1] = ef.size() == 2 ? uint16_t(eif[1]) : 0;
        Z.edgeSharpness[e] = L.GetEdgeSharpness(int(e));
        Z.edgeTags[e] = uint8_t((L.IsEdgeBoundary(int(e)) ? kEdgeBoundary : 0) |
                                (L.IsEdgeInfSharp(int(e)) ? kEdgeInfSharp : 0) |
                                (L.IsEdgeSemiSharp(int(e)) ? kEdgeSemiSharp : 0));
        tagged |= Z.edgeTags[e] != 0 || Z.edgeSharpness[e] > 0.0f;
    }

    sized(Z.vertFaceOffsets, Z.numVerts + 1);
    sized(Z.vertEdgeOffsets, Z.numVerts + 1);
    Z.vertFaces.clear();
    Z.vertInFace.clear();
    Z.vertEdges.clear();
    Z.vertInEdge.clear();
    Z.vertRing.clear();
    sized(Z.vertSharpness, Z.numVerts);
    sized(Z.vertTags, Z.numVerts);
    sized(Z.vertRules, Z.numVerts);
    for (uint32_t v = 0; v < Z.numVerts; ++v) {
        Far::ConstIndexArray vf = L.GetVertexFaces(int(v)), ve = L.GetVertexEdges(int(v));
        Far::ConstLocalIndexArray vif = L.GetVertexFaceLocalIndices(int(v)),
                                  vie = L.GetVertexEdgeLocalIndices(int(v));
        if (L.IsVertexNonManifold(int(v)) || vf.size() == 0 ||
            (ve.size() != vf.size() && ve.size() != vf.size() + 1)) {
            why = "non-manifold or isolated vertex " + std::to_string(v);
            return false;
        }
        Z.vertFaceOffsets[v] = uint32_t(Z.vertFaces.size());
        Z.vertEdgeOffsets[v] = uint32_t(Z.vertEdges.size());
        uint8_t tag = uint8_t((L.IsVertexBoundary(int(v)) ? kVertBoundary : 0) |
                              (L.IsVertexInfSharp(int(v)) ? kVertInfSharp : 0) |
                              (L.IsVertexSemiSharp(int(v)) ? kVertSemiSharp : 0));
        for (int i = 0; i < vf.size(); ++i) {
            Z.vertFaces.push_back(uint32_t(vf[i]));
            Z.vertInFace.push_back(uint16_t(vif[i]));
        }
        for (int i = 0; i < ve.size(); ++i) {
            Z.vertEdges.push_back(uint32_t(ve[i]));
            Z.vertInEdge.push_back(uint16_t(vie[i]));
            Z.vertRing.push_back(Z.edgeVerts[2 * size_t(ve[i]) + (vie[i] ^ 1u)]);
            if (Z.edgeTags[size_t(ve[i])] & kEdgeSemiSharp) tag |= kVertSemiSharpEdges;
        }
        Z.vertSharpness[v] = L.GetVertexSharpness(int(v));
        Z.vertTags[v] = tag;
        Z.vertRules[v] = uint8_t(L.GetVertexRule(int(v)));
        tagged |= tag != 0 || Z.vertSharpness[v] > 0.0f || Z.vertRules[v] != Crease::RULE_SMOOTH;
    }
    Z.vertFaceOffsets[Z.numVerts] = uint32_t(Z.vertFaces.size());
    Z.vertEdgeOffsets[Z.numVerts] = uint32_t(Z.vertEdges.size());
    Z.tagged = tagged;

    Z.fvar.resize(cage.uvSets.size());
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        if (!classifyFVar(cage, s, why)) return false;
    }
    return true;
}

namespace {

// The face-varying linear-interpolation option and the boundary rule as the
// questions FVarLevel asks of them.
struct FVarRules {
    explicit FVarRules(const Sdc::Options& options) {
        using Opt = Sdc::Options;
        const Opt::FVarLinearInterpolation rule = options.GetFVarLinearInterpolation();
        linearBoundaries = rule == Opt::FVAR_LINEAR_ALL || rule == Opt::FVAR_LINEAR_BOUNDARIES;
        dependentSharpness =
            rule == Opt::FVAR_LINEAR_CORNERS_PLUS1 || rule == Opt::FVAR_LINEAR_CORNERS_PLUS2;
        const bool geomCornersSmooth =
            options.GetVtxBoundaryInterpolation() != Opt::VTX_BOUNDARY_EDGE_AND_CORNER;
        fvarCornersSharp = rule != Opt::FVAR_LINEAR_NONE;
        makeSmoothCornersSharp = geomCornersSmooth && fvarCornersSharp;
        sharpenBothIfOneCorner = rule == Opt::FVAR_LINEAR_CORNERS_PLUS2;
        sharpenDarts = sharpenBothIfOneCorner || linearBoundaries;
    }
    bool linearBoundaries, dependentSharpness, fvarCornersSharp, makeSmoothCornersSharp,
        sharpenBothIfOneCorner, sharpenDarts;
};

// The faces (vf), each one's corner at the vertex (vif) and the edges (ve)
// around vertex v of a level, counter-clockwise.
struct VertexRing {
    VertexRing(const RefineLevel& Z, uint32_t v)
        : vf(Z.vertFaces.data() + Z.vertFaceOffsets[v]),
          vif(Z.vertInFace.data() + Z.vertFaceOffsets[v]),
          ve(Z.vertEdges.data() + Z.vertEdgeOffsets[v]),
          nf(Z.vertFaceOffsets[v + 1] - Z.vertFaceOffsets[v]),
          ne(Z.vertEdgeOffsets[v + 1] - Z.vertEdgeOffsets[v]) {}
    const uint32_t* vf;
    const uint16_t* vif;
    const uint32_t* ve;
    uint32_t nf, ne;
    bool boundary() const { return ne > nf; }
    // Level-0 corner index of the vertex in face i of the ring.
    uint32_t corner(const RefineLevel& Z, uint32_t i) const {
        return Z.faceOffsets[vf[i]] + vif[i];
    }
};

// Siblings (distinct values) around a vertex, in order of first appearance,
// with OpenSubdiv's shortcut for the second distinct value (which does not
// look for it among the earlier ones): sibling[i] of face i; returns the
// number of distinct values.
uint32_t siblingsAroundVertex(const std::vector<uint32_t>& values, std::vector<uint32_t>& unique,
                              std::vector<uint16_t>& sibling) {
    const size_t nf = values.size();
    unique.assign(1, values[0]);
    sibling.assign(nf, 0);
    for (size_t i = 1; i < nf; ++i) {
        if (values[i] == values[i - 1]) {
            sibling[i] = sibling[i - 1];
            continue;
        }
        sibling[i] = uint16_t(unique.size());
        if (unique.size() == 1 || (unique.size() == 2 && unique[0] != values[i])) {
            unique.push_back(values[i]);
        } else {
            auto it = std::find(unique.begin(), unique.end(), values[i]);
            if (it == unique.end())
                unique.push_back(values[i]);
            else
                sibling[i] = uint16_t(it - unique.begin());
        }
    }
    return uint32_t(unique.size());
}

// Pass 1 of classifyFVar: the seams (F.edgeTags), the vertices on one or
// made sharp by the boundary rules (mismatch), and the values around each
// vertex (count, F.cornerSibling).
void findSeamsAndSiblings(const RefineLevel& Z, FVarLevelData& F, const FVarRules& r,
                          std::vector<uint8_t>& mismatch, std::vector<uint32_t>& count) {
    std::vector<uint32_t> values, unique;
    std::vector<uint16_t> sibling;
    for (uint32_t v = 0; v < Z.numVerts; ++v) {
        const VertexRing ring(Z, v);
        const uint32_t nf = ring.nf, ne = ring.ne;
        values.resize(nf);
        for (uint32_t i = 0; i < nf; ++i) values[i] = F.faceValues[ring.corner(Z, i)];
        // Edge i lies between faces i-1 and i (OpenSubdiv's ordering).
        for (uint32_t i = ring.boundary() ? 1 : 0; i < nf; ++i) {
            const uint32_t prev = i ? i - 1 : nf - 1;
            if (values[i] != values[prev]) {
                const uint32_t e = ring.ve[i];
                mismatch[Z.edgeVerts[2 * e]] = 1;
                mismatch[Z.edgeVerts[2 * e + 1]] = 1;
                F.edgeTags[e] |=
                    uint8_t(kFvEdgeMismatch | (r.linearBoundaries ? kFvEdgeLinear : 0));
            }
        }
        if (ring.boundary() && !mismatch[v]) {
            if (r.linearBoundaries) {
                mismatch[v] = 1;
                F.edgeTags[ring.ve[0]] |= kFvEdgeLinear;
                F.edgeTags[ring.ve[ne - 1]] |= kFvEdgeLinear;
            } else if (nf == 1 && r.makeSmoothCornersSharp) {
                mismatch[v] = 1;
            }
        }
        count[v] = siblingsAroundVertex(values, unique, sibling);
        if (count[v] > 1) {
            for (uint32_t i = 0; i < nf; ++i) F.cornerSibling[ring.corner(Z, i)] = sibling[i];
        }
    }
}

// A run of faces around a vertex that share one value
// (FVarLevel::gatherValueSpans).
struct ValueSpan {
    int size = 0, start = 0, disjoint = 0, semiSharp = 0;
};

// The spans of the n values around vertex v (a vertex on a seam).
void gatherValueSpans(const RefineLevel& Z, const FVarLevelData& F, const VertexRing& ring,
                      uint32_t n, std::vector<ValueSpan>& spans) {
    const uint32_t nf = ring.nf, ne = ring.ne;
    const uint32_t* ve = ring.ve;
    auto cornerSib = [&](uint32_t i) { return F.cornerSibling[ring.corner(Z, i)]; };
    auto edgeSeam = [&](uint32_t e) { return (F.edgeTags[e] & kFvEdgeMismatch) != 0; };
    spans.assign(n, ValueSpan());
    if (n == 1) {
        for (uint32_t i = 0; i < ne; ++i) {
            if (edgeSeam(ve[i])) {
                if (spans[0].size) {
                    spans[0].disjoint = 1;
                    break;
                }
                spans[0].size = int(nf);
                spans[0].start = int(i);
            } else if (Z.edgeTags[ve[i]] & kEdgeInfSharp) {
                spans[0].disjoint = 1;
                break;
            } else if (Z.edgeTags[ve[i]] & kEdgeSemiSharp) {
                ++spans[0].semiSharp;
            }
        }
        return;
    }
    spans[0].size = 1;
    spans[0].start = 0;
    if (!ring.boundary() && cornerSib(nf - 1) == 0) {
        if (edgeSeam(ve[0]) || (Z.edgeTags[ve[0]] & kEdgeInfSharp))
            spans[0].disjoint = 1;
        else if (Z.edgeTags[ve[0]] & kEdgeSemiSharp)
            ++spans[0].semiSharp;
    }
    for (uint32_t i = 1; i < nf; ++i) {
        ValueSpan& s = spans[cornerSib(i)];
        if (cornerSib(i) == cornerSib(i - 1)) {
            if (edgeSeam(ve[i]))
                ++s.disjoint;
            else if (Z.edgeTags[ve[i]] & kEdgeInfSharp)
                s.disjoint = 1;
            else if (Z.edgeTags[ve[i]] & kEdgeSemiSharp)
                ++s.semiSharp;
        } else {
            if (s.size > 0) ++s.disjoint;
            s.start = int(i);
        }
        ++s.size;
    }
    if (cornerSib(nf - 1) == 0 && !ring.boundary()) --spans[0].disjoint;
}

// Pass 2 of classifyFVar for vertex v on a seam: each of its n values (at
// F slots off..off+n-1) becomes a corner (kept) or a crease (smoothed along
// the seam, with its span). False, with `why`, for the semi-sharp cases
// left to Far.
bool classifySeamValues(const RefineLevel& Z, FVarLevelData& F, const FVarRules& r, uint32_t v,
                        uint32_t n, std::vector<ValueSpan>& spans, std::string& why) {
    const VertexRing ring(Z, v);
    const uint32_t off = F.valueOffsets[v];
    const uint8_t vtag = Z.vertTags[v];
    bool allCorners = r.linearBoundaries || (vtag & kVertInfSharp) ||
                      (r.dependentSharpness && n > 2) ||
                      (r.sharpenDarts && n == 1 && !ring.boundary());
    if (allCorners) {
        std::fill_n(F.valueTags.begin() + off, n, kValueMismatch);
        return true;
    }
    gatherValueSpans(Z, F, ring, n, spans);
    if (r.dependentSharpness && n == 2) {
        allCorners = spans[0].disjoint || spans[1].disjoint;
        if (r.sharpenBothIfOneCorner) allCorners |= spans[0].size == 1 || spans[1].size == 1;
        if (!allCorners && (spans[0].semiSharp > 0) != (spans[1].semiSharp > 0)) {
            why = "a UV seam with semi-sharp creasing at vertex " + std::to_string(v);
            return false;
        }
    }
    if (allCorners) {
        std::fill_n(F.valueTags.begin() + off, n, kValueMismatch);
        return true;
    }
    for (uint32_t i = 0; i < n; ++i) {
        const ValueSpan& s = spans[i];
        if (s.disjoint || (s.size == 1 && r.fvarCornersSharp)) {
            F.valueTags[off + i] = kValueMismatch;
            continue;
        }
        if (s.semiSharp > 0 || (vtag & kVertSemiSharp)) {
            // OpenSubdiv's semi-sharp face-varying values (a corner
            // decaying into a crease) are left to Far.
            why = "a UV seam with semi-sharp creasing at vertex " + std::to_string(v);
            return false;
        }
        F.valueTags[off + i] = kValueMismatch | kValueCrease;
        F.creaseStart[off + i] = uint16_t(s.start);
        F.creaseEnd[off + i] = uint16_t(
            (i == 0 && s.start != 0) ? s.start + s.size - 1 - int(ring.nf) : s.start + s.size - 1);
    }
    return true;
}

} // namespace

// Vtr::FVarLevel::completeTopologyFromFaceValues for a manifold level 0:
// which values meet at each vertex (siblings), which edges are UV seams,
// and for every value on a seam whether it is a corner (kept) or a crease
// (smoothed along the seam), by the face-varying linear-interpolation
// option. The order of operations is OpenSubdiv's (a vertex's boundary
// test sees only the seams found so far), so the outcome is the same.
bool UniformRefiner::classifyFVar(const PolygonMesh& cage, size_t channel, std::string& why) {
    RefineLevel& Z = level_[0];
    FVarLevelData& F = Z.fvar[channel];
    const FVarRules rules(options_);
    fvarLinear_ = options_.GetFVarLinearInterpolation() == Sdc::Options::FVAR_LINEAR_ALL;
    fvarSmoothBoundaries_ = !rules.linearBoundaries;

    const std::vector<uint32_t>& cageIndices = cage.uvSets[channel].indices;
    F.faceValues.assign(cageIndices.begin(), cageIndices.end());
    F.edgeTags.assign(Z.numEdges, 0);
    F.cornerSibling.assign(Z.numCorners, 0);
    std::vector<uint8_t> mismatch(Z.numVerts, 0);
    std::vector<uint32_t> count(Z.numVerts, 1);
    findSeamsAndSiblings(Z, F, rules, mismatch, count);

    sized(F.valueOffsets, Z.numVerts + 1);
    uint32_t total = 0;
    for (uint32_t v = 0; v < Z.numVerts; ++v) {
        F.valueOffsets[v] = total;
        total += count[v];
    }
    F.valueOffsets[Z.numVerts] = total;
    F.valueIndex.assign(total, 0);
    F.valueTags.assign(total, 0);
    F.creaseStart.assign(total, 0);
    F.creaseEnd.assign(total, 0);

    // Pass 2: the values of each vertex and, on seams, corner or crease.
    std::vector<ValueSpan> spans;
    for (uint32_t v = 0; v < Z.numVerts; ++v) {
        const VertexRing ring(Z, v);
        const uint32_t off = F.valueOffsets[v];
        F.valueIndex[off] = F.faceValues[ring.corner(Z, 0)];
        if (!mismatch[v]) continue;
        for (uint32_t i = 1, next = 1; i < ring.nf; ++i) {
            if (F.cornerSibling[ring.corner(Z, i)] == next)
                F.valueIndex[off + next++] = F.faceValues[ring.corner(Z, i)];
        }
        if (!classifySeamValues(Z, F, rules, v, count[v], spans, why)) return false;
    }
    return true;
}

// ---- Refinement ------------------------------------------------------------------

void UniformRefiner::refine(int levels, const Parallel& par) {
    SG_EXPECTS(levels >= 1, "at least one level");
    levels_ = levels;
    if (level_.size() < size_t(levels) + 1) level_.resize(size_t(levels) + 1);
    const size_t channels = level_[0].fvar.size();
    for (int l = 1; l <= levels; ++l) {
        const RefineLevel& P = level_[size_t(l) - 1];
        RefineLevel& C = level_[size_t(l)];
        const bool last = l == levels;
        refineTopology(P, C, last, par);
        C.tagged = P.tagged;
        if (P.tagged) refineSharpness(P, C, par);
        C.fvar.resize(channels);
        for (size_t s = 0; s < channels; ++s) refineFVar(P, C, s, last, par);
    }
}

namespace {

// Child vertex numbering of a uniform split of level P: one per vertex, then
// one per face, then one per edge.
struct ChildNumbering {
    explicit ChildNumbering(const RefineLevel& P)
        : firstFace(P.numVerts), firstEdge(P.numVerts + P.numFaces) {}
    uint32_t firstFace; // child vertex of face f: firstFace + f
    uint32_t firstEdge; // child vertex of edge e: firstEdge + e
};

// Face vertices: child j of a quad keeps its parent corner at position j
// (v_j, e_j, centre, e_j-1 rotated by j); a child of another polygon starts
// at its parent corner.
void childFaceVertices(const RefineLevel& P, RefineLevel& C, const Parallel& par) {
    const ChildNumbering at(P);
    const uint32_t nF = P.numFaces;
    const uint32_t* pfo = P.faceOffsets.data();
    const uint32_t* pfv = P.faceVerts.data();
    const uint32_t* pfe = P.faceEdges.data();
    sized(C.faceVerts, C.numCorners);
    uint32_t* cfv = C.faceVerts.data();
    const bool quads = P.numCorners == 4 * nF; // every level after the first
    if (quads) {
        par.each(nF, [&](size_t fi) {
            const uint32_t f = uint32_t(fi);
            const uint32_t* v = pfv + 4 * f;
            const uint32_t* e = pfe + 4 * f;
            const uint32_t fc = at.firstFace + f;
            const uint32_t e0 = at.firstEdge + e[0], e1 = at.firstEdge + e[1],
                           e2 = at.firstEdge + e[2], e3 = at.firstEdge + e[3];
            uint32_t* out = cfv + 16 * size_t(f);
            out[0] = v[0], out[1] = e0, out[2] = fc, out[3] = e3;
            out[4] = e0, out[5] = v[1], out[6] = e1, out[7] = fc;
            out[8] = fc, out[9] = e1, out[10] = v[2], out[11] = e2;
            out[12] = e3, out[13] = fc, out[14] = e2, out[15] = v[3];
        });
        return;
    }
    par.each(nF, [&](size_t fi) {
        const uint32_t f = uint32_t(fi);
        const uint32_t off = pfo[f], k = pfo[f + 1] - off;
        for (uint32_t j = 0; j < k; ++j) {
            const uint32_t jp = j ? j - 1 : k - 1;
            uint32_t* out = cfv + 4 * (off + j);
            const uint32_t vv = pfv[off + j], en = at.firstEdge + pfe[off + j],
                           fc = at.firstFace + f, ep = at.firstEdge + pfe[off + jp];
            if (k == 4) {
                out[j] = vv;
                out[(j + 1) & 3] = en;
                out[(j + 2) & 3] = fc;
                out[(j + 3) & 3] = ep;
            } else {
                out[0] = vv;
                out[1] = en;
                out[2] = fc;
                out[3] = ep;
            }
        }
    });
}

// Face edges: the half of each parent edge at the corner, the two interior
// edges.
void childFaceEdges(const RefineLevel& P, RefineLevel& C, const Parallel& par) {
    const uint32_t nF = P.numFaces, nC = P.numCorners;
    const uint32_t* pfo = P.faceOffsets.data();
    const uint32_t* pfv = P.faceVerts.data();
    const uint32_t* pfe = P.faceEdges.data();
    const uint32_t* pev = P.edgeVerts.data();
    sized(C.faceOffsets, C.numFaces + 1);
    par.each(size_t(C.numFaces) + 1, [&](size_t c) { C.faceOffsets[c] = 4 * uint32_t(c); });
    sized(C.faceEdges, C.numCorners);
    uint32_t* cfe = C.faceEdges.data();
    par.each(nF, [&](size_t fi) {
        const uint32_t f = uint32_t(fi);
        const uint32_t off = pfo[f], k = pfo[f + 1] - off;
        for (uint32_t j = 0; j < k; ++j) {
            const uint32_t jp = j ? j - 1 : k - 1;
            const uint32_t ePrev = pfe[off + jp], eNext = pfe[off + j], corner = pfv[off + j];
            const uint32_t halfPrev = nC + 2 * ePrev + (pev[2 * ePrev] != corner ? 1u : 0u);
            const uint32_t halfNext = nC + 2 * eNext + (pev[2 * eNext] != corner ? 1u : 0u);
            uint32_t* out = cfe + 4 * (off + j);
            if (k == 4) {
                out[j] = halfNext;
                out[(j + 1) & 3] = off + j;
                out[(j + 2) & 3] = off + jp;
                out[(j + 3) & 3] = halfPrev;
            } else {
                out[0] = halfNext;
                out[1] = off + j;
                out[2] = off + jp;
                out[3] = halfPrev;
            }
        }
    });
}

// Edge vertices and edge faces: interior edges of faces first, then the
// two halves of each parent edge.
void childEdges(const RefineLevel& P, RefineLevel& C, const Parallel& par) {
    const ChildNumbering at(P);
    const uint32_t nF = P.numFaces, nE = P.numEdges, nC = P.numCorners;
    const uint32_t* pfo = P.faceOffsets.data();
    const uint32_t* pfv = P.faceVerts.data();
    const uint32_t* pfe = P.faceEdges.data();
    const uint32_t* pev = P.edgeVerts.data();
    sized(C.edgeVerts, 2 * size_t(C.numEdges));
    sized(C.edgeFaces, 2 * size_t(C.numEdges));
    sized(C.edgeInFace, 2 * size_t(C.numEdges));
    uint32_t* cev = C.edgeVerts.data();
    uint32_t* cef = C.edgeFaces.data();
    uint16_t* ceif = C.edgeInFace.data();
    par.each(nF, [&](size_t fi) {
        const uint32_t f = uint32_t(fi);
        const uint32_t off = pfo[f], k = pfo[f + 1] - off;
        for (uint32_t j = 0; j < k; ++j) {
            const uint32_t c = off + j, jn = j + 1 == k ? 0 : j + 1;
            cev[2 * c] = at.firstFace + f;
            cev[2 * c + 1] = at.firstEdge + pfe[c];
            cef[2 * c] = off + j;
            ceif[2 * c] = uint16_t(k == 4 ? jn : 1);
            cef[2 * c + 1] = off + jn;
            ceif[2 * c + 1] = uint16_t(k == 4 ? ((jn + 2) & 3) : 2);
        }
    });
    par.each(nE, [&](size_t ei) {
        const uint32_t e = uint32_t(ei);
        const uint32_t nfE = P.edgeFaceCount(e);
        for (uint32_t j = 0; j < 2; ++j) {
            const uint32_t c = nC + 2 * e + j;
            cev[2 * c] = at.firstEdge + e;
            cev[2 * c + 1] = pev[2 * e + j];
            cef[2 * c + 1] = kNone;
            ceif[2 * c + 1] = 0;
            for (uint32_t i = 0; i < nfE; ++i) {
                const uint32_t pf = P.edgeFaces[2 * e + i], eif = P.edgeInFace[2 * e + i];
                const uint32_t off = pfo[pf], k = pfo[pf + 1] - off;
                const uint32_t childOfEdge = pfv[off + eif] != pev[2 * e + j] ? 1u : 0u;
                uint32_t childInFace = eif + childOfEdge;
                if (childInFace == k) childInFace = 0;
                cef[2 * c + i] = off + childInFace;
                ceif[2 * c + i] = uint16_t(k == 4 ? eif : (childOfEdge ? 3 : 0));
            }
        }
    });
}

// Offsets of the vertex-face and vertex-edge relations (vertices of
// vertices, then of faces, then of edges), and their arrays sized.
void childVertexOffsets(const RefineLevel& P, RefineLevel& C) {
    const ChildNumbering at(P);
    const uint32_t nV = P.numVerts, nF = P.numFaces, nE = P.numEdges;
    const uint32_t* pfo = P.faceOffsets.data();
    sized(C.vertFaceOffsets, C.numVerts + 1);
    sized(C.vertEdgeOffsets, C.numVerts + 1);
    uint32_t fAt = 0, eAt = 0;
    for (uint32_t v = 0; v < nV; ++v) {
        C.vertFaceOffsets[v] = fAt;
        C.vertEdgeOffsets[v] = eAt;
        fAt += P.vertFaceOffsets[v + 1] - P.vertFaceOffsets[v];
        eAt += P.vertEdgeOffsets[v + 1] - P.vertEdgeOffsets[v];
    }
    for (uint32_t f = 0; f < nF; ++f) {
        C.vertFaceOffsets[at.firstFace + f] = fAt;
        C.vertEdgeOffsets[at.firstFace + f] = eAt;
        fAt += pfo[f + 1] - pfo[f];
        eAt += pfo[f + 1] - pfo[f];
    }
    for (uint32_t e = 0; e < nE; ++e) {
        C.vertFaceOffsets[at.firstEdge + e] = fAt;
        C.vertEdgeOffsets[at.firstEdge + e] = eAt;
        fAt += 2 * P.edgeFaceCount(e);
        eAt += 2 + P.edgeFaceCount(e);
    }
    C.vertFaceOffsets[C.numVerts] = fAt;
    C.vertEdgeOffsets[C.numVerts] = eAt;
    sized(C.vertFaces, fAt);
    sized(C.vertInFace, fAt);
    sized(C.vertEdges, eAt);
    sized(C.vertInEdge, eAt);
    sized(C.vertRing, eAt);
}

// Faces and edges around the child vertices of parent vertices and of
// parent faces, counter-clockwise.
void childVertexAndFaceVertexRelations(const RefineLevel& P, RefineLevel& C, const Parallel& par) {
    const ChildNumbering at(P);
    const uint32_t nV = P.numVerts, nF = P.numFaces, nC = P.numCorners;
    const uint32_t* pfo = P.faceOffsets.data();
    const uint32_t* pfe = P.faceEdges.data();
    uint32_t* cvf = C.vertFaces.data();
    uint16_t* cvif = C.vertInFace.data();
    uint32_t* cve = C.vertEdges.data();
    uint16_t* cvie = C.vertInEdge.data();
    uint32_t* cvr = C.vertRing.data();
    par.each(nV, [&](size_t vi) {
        const uint32_t v = uint32_t(vi);
        uint32_t fo = C.vertFaceOffsets[v];
        for (uint32_t i = P.vertFaceOffsets[v]; i < P.vertFaceOffsets[v + 1]; ++i, ++fo) {
            const uint32_t pf = P.vertFaces[i], vif = P.vertInFace[i];
            const uint32_t k = pfo[pf + 1] - pfo[pf];
            cvf[fo] = pfo[pf] + vif;
            cvif[fo] = uint16_t(k == 4 ? vif : 0);
        }
        uint32_t eo = C.vertEdgeOffsets[v];
        for (uint32_t i = P.vertEdgeOffsets[v]; i < P.vertEdgeOffsets[v + 1]; ++i, ++eo) {
            cve[eo] = nC + 2 * P.vertEdges[i] + P.vertInEdge[i];
            cvie[eo] = 1;
            cvr[eo] = at.firstEdge + P.vertEdges[i];
        }
    });
    par.each(nF, [&](size_t fi) {
        const uint32_t f = uint32_t(fi);
        const uint32_t off = pfo[f], k = pfo[f + 1] - off;
        const uint32_t fo = C.vertFaceOffsets[at.firstFace + f];
        const uint32_t eo = C.vertEdgeOffsets[at.firstFace + f];
        for (uint32_t j = 0; j < k; ++j) {
            cvf[fo + j] = off + j;
            cvif[fo + j] = uint16_t(k == 4 ? ((j + 2) & 3) : 2);
            cve[eo + j] = off + (j ? j - 1 : k - 1);
            cvie[eo + j] = 0;
            cvr[eo + j] = at.firstEdge + pfe[off + (j ? j - 1 : k - 1)];
        }
    });
}

// Faces and edges around the child vertices of parent edges,
// counter-clockwise: (half, face edge, half, ...), the first half being the
// one the first face's edge direction leaves.
void edgeVertexRelations(const RefineLevel& P, RefineLevel& C, const Parallel& par) {
    const ChildNumbering at(P);
    const uint32_t nE = P.numEdges, nC = P.numCorners;
    const uint32_t* pfo = P.faceOffsets.data();
    const uint32_t* pfv = P.faceVerts.data();
    const uint32_t* pev = P.edgeVerts.data();
    uint32_t* cvf = C.vertFaces.data();
    uint16_t* cvif = C.vertInFace.data();
    par.each(nE, [&](size_t ei) {
        const uint32_t e = uint32_t(ei);
        const uint32_t nfE = P.edgeFaceCount(e);
        uint32_t fo = C.vertFaceOffsets[at.firstEdge + e];
        const uint32_t eo = C.vertEdgeOffsets[at.firstEdge + e];
        uint32_t* edges = C.vertEdges.data() + eo;
        uint16_t* inEdge = C.vertInEdge.data() + eo;
        uint32_t* ring = C.vertRing.data() + eo;
        edges[0] = nC + 2 * e;
        edges[1] = nC + 2 * e + 1;
        inEdge[0] = inEdge[1] = 0;
        ring[0] = pev[2 * e];
        ring[1] = pev[2 * e + 1];
        for (uint32_t i = 0; i < nfE; ++i) {
            const uint32_t pf = P.edgeFaces[2 * e + i], eif = P.edgeInFace[2 * e + i];
            const uint32_t off = pfo[pf], k = pfo[pf + 1] - off;
            const uint32_t child0 = eif, child1 = eif + 1 == k ? 0 : eif + 1;
            cvf[fo] = off + child1;
            cvif[fo++] = uint16_t(k == 4 ? child0 : 3);
            cvf[fo] = off + child0;
            cvif[fo++] = uint16_t(k == 4 ? child1 : 1);
            edges[2 + i] = off + eif;
            inEdge[2 + i] = 1;
            ring[2 + i] = at.firstFace + pf;
            if (i == 0) {
                if (pfv[off + eif] == pev[2 * e]) {
                    std::swap(edges[0], edges[1]);
                    std::swap(ring[0], ring[1]);
                }
                std::swap(edges[1], edges[2]);
                std::swap(inEdge[1], inEdge[2]);
                std::swap(ring[1], ring[2]);
            }
        }
    });
}

} // namespace

// Vtr::QuadRefinement's child relations for a uniform split: child faces
// of a quad keep the parent's orientation (child j has its parent corner at
// position j), those of other polygons start at the parent corner. The
// last level gets its face vertices only.
void UniformRefiner::refineTopology(const RefineLevel& P, RefineLevel& C, bool last,
                                    const Parallel& par) {
    C.numVerts = P.numVerts + P.numFaces + P.numEdges;
    C.numFaces = P.numCorners;
    C.numCorners = 4 * P.numCorners;
    C.numEdges = 2 * P.numEdges + P.numCorners;
    C.triangles = false;
    childFaceVertices(P, C, par);
    if (last) return;
    childFaceEdges(P, C, par);
    childEdges(P, C, par);
    childVertexOffsets(P, C);
    childVertexAndFaceVertexRelations(P, C, par);
    edgeVertexRelations(P, C, par);
}

// Vtr::Refinement::subdivideSharpnessValues + reclassifySemisharpVertices.
void UniformRefiner::refineSharpness(const RefineLevel& P, RefineLevel& C, const Parallel& par) {
    const Crease crease(options_);
    const uint32_t nV = P.numVerts, nF = P.numFaces, nE = P.numEdges, nC = P.numCorners;
    const uint32_t firstEdge = nV + nF;
    C.edgeSharpness.assign(C.numEdges, 0.0f);
    C.edgeTags.assign(C.numEdges, 0);
    par.blocks(nE, [&](size_t b, size_t end) {
        std::vector<float> around;
        for (uint32_t e = uint32_t(b); e < end; ++e) {
            const uint8_t tag = P.edgeTags[e];
            for (uint32_t j = 0; j < 2; ++j) {
                const uint32_t c = nC + 2 * e + j;
                uint8_t ctag = tag;
                float s = 0.0f;
                if (tag & kEdgeInfSharp) {
                    s = Crease::SHARPNESS_INFINITE;
                } else if (tag & kEdgeSemiSharp) {
                    if (crease.IsUniform()) {
                        s = crease.SubdivideUniformSharpness(P.edgeSharpness[e]);
                    } else {
                        const uint32_t pv = P.edgeVerts[2 * e + j];
                        around.clear();
                        for (uint32_t i = P.vertEdgeOffsets[pv]; i < P.vertEdgeOffsets[pv + 1]; ++i)
                            around.push_back(P.edgeSharpness[P.vertEdges[i]]);
                        s = crease.SubdivideEdgeSharpnessAtVertex(
                            P.edgeSharpness[e], int(around.size()), around.data());
                    }
                    if (!Crease::IsSharp(s)) ctag &= uint8_t(~kEdgeSemiSharp);
                }
                C.edgeSharpness[c] = s;
                C.edgeTags[c] = ctag;
            }
        }
    });
    C.vertSharpness.assign(C.numVerts, 0.0f);
    C.vertTags.assign(C.numVerts, 0);
    C.vertRules.assign(C.numVerts, uint8_t(Crease::RULE_SMOOTH));
    par.each(nV, [&](size_t vi) {
        const uint32_t v = uint32_t(vi);
        uint8_t tag = P.vertTags[v];
        float s = 0.0f;
        if (tag & kVertInfSharp) {
            s = Crease::SHARPNESS_INFINITE;
        } else if (tag & kVertSemiSharp) {
            s = crease.SubdivideVertexSharpness(P.vertSharpness[v]);
            if (!Crease::IsSharp(s)) tag &= uint8_t(~kVertSemiSharp);
        }
        C.vertSharpness[v] = s;
        C.vertTags[v] = tag;
        C.vertRules[v] = P.vertRules[v];
    });
    par.each(nE, [&](size_t ei) {
        const uint32_t e = uint32_t(ei);
        const uint8_t etag = P.edgeTags[e];
        const uint32_t cv = firstEdge + e;
        uint8_t tag = uint8_t(((etag & kEdgeBoundary) ? kVertBoundary : 0) |
                              ((etag & kEdgeSemiSharp) ? kVertSemiSharpEdges : 0));
        uint8_t rule = uint8_t((etag & (kEdgeSemiSharp | kEdgeInfSharp)) ? Crease::RULE_CREASE
                                                                         : Crease::RULE_SMOOTH);
        if (tag & kVertSemiSharpEdges) {
            const int sharpCount = ((C.edgeTags[nC + 2 * e] & kEdgeSemiSharp) ? 1 : 0) +
                                   ((C.edgeTags[nC + 2 * e + 1] & kEdgeSemiSharp) ? 1 : 0);
            if (sharpCount == 0) tag &= uint8_t(~kVertSemiSharpEdges);
            rule = uint8_t(crease.DetermineVertexVertexRule(0.0f, sharpCount));
        }
        C.vertTags[cv] = tag;
        C.vertRules[cv] = rule;
    });
    par.each(nV, [&](size_t vi) {
        const uint32_t v = uint32_t(vi);
        const uint8_t ptag = P.vertTags[v];
        if (!(ptag & (kVertSemiSharp | kVertSemiSharpEdges))) return;
        uint8_t& ctag = C.vertTags[v];
        const bool decayed = (ptag & kVertSemiSharp) && !(ctag & kVertSemiSharp);
        if (!(ptag & kVertSemiSharpEdges) && !decayed) return;
        int infCount = 0, semiCount = 0;
        for (uint32_t i = P.vertEdgeOffsets[v]; i < P.vertEdgeOffsets[v + 1]; ++i) {
            const uint8_t t = C.edgeTags[nC + 2 * P.vertEdges[i] + P.vertInEdge[i]];
            infCount += (t & kEdgeInfSharp) ? 1 : 0;
            semiCount += (t & kEdgeSemiSharp) ? 1 : 0;
        }
        ctag =
            uint8_t(semiCount > 0 ? (ctag | kVertSemiSharpEdges) : (ctag & ~kVertSemiSharpEdges));
        if (!(ctag & kVertSemiSharp) && !(ctag & kVertInfSharp)) {
            C.vertRules[v] = uint8_t(crease.DetermineVertexVertexRule(0.0f, infCount + semiCount));
        }
    });
}

// Vtr::FVarRefinement for a uniform manifold split: values per child vertex
// (one per face child, one or two per edge child, the parent's per vertex
// child), their tags and crease spans, and each child corner's value.
void UniformRefiner::refineFVar(const RefineLevel& P, RefineLevel& C, size_t channel, bool last,
                                const Parallel& par) {
    const FVarLevelData& PF = P.fvar[channel];
    FVarLevelData& CF = C.fvar[channel];
    const uint32_t nV = P.numVerts, nF = P.numFaces, nE = P.numEdges, nC = P.numCorners;
    const uint32_t firstFace = nV, firstEdge = nV + nF;
    CF.valueIndex.clear();
    sized(CF.valueOffsets, C.numVerts + 1);
    uint32_t total = 0;
    for (uint32_t v = 0; v < nV; ++v) {
        CF.valueOffsets[v] = total;
        total += (PF.valueTags[PF.valueOffsets[v]] & kValueMismatch) ? valueCount(PF, v) : 1;
    }
    for (uint32_t f = 0; f < nF; ++f) CF.valueOffsets[firstFace + f] = total++;
    for (uint32_t e = 0; e < nE; ++e) {
        CF.valueOffsets[firstEdge + e] = total;
        total += (PF.edgeTags[e] & kFvEdgeMismatch) ? P.edgeFaceCount(e) : 1;
    }
    CF.valueOffsets[C.numVerts] = total;
    if (!last) fvarValueTags(P, C, channel, par); // (the last level's are never read)

    // Each child corner's value: the sibling of its parent corner for a
    // vertex child, the side of the seam for an edge child, the only value
    // of a face child.
    sized(CF.faceValues, C.numCorners);
    if (!last) sized(CF.cornerSibling, C.numCorners);
    const uint32_t* pfo = P.faceOffsets.data();
    const uint32_t* cvo = CF.valueOffsets.data();
    const bool quads = nC == 4 * nF;
    if (quads) {
        // As below with k = 4 (every level after the first).
        par.each(nF, [&](size_t fi) {
            const uint32_t f = uint32_t(fi);
            const uint32_t* v = P.faceVerts.data() + 4 * size_t(f);
            const uint32_t* e = P.faceEdges.data() + 4 * size_t(f);
            uint16_t se[4]; // side of each edge's seam this face is on
            for (uint32_t j = 0; j < 4; ++j)
                se[j] = ((PF.edgeTags[e[j]] & kFvEdgeMismatch) && P.edgeFaces[2 * e[j] + 1] == f)
                            ? 1
                            : 0;
            const uint16_t* sv = PF.cornerSibling.data() + 4 * size_t(f);
            const uint32_t fc = cvo[firstFace + f];
            const uint32_t ev[4] = {cvo[firstEdge + e[0]] + se[0], cvo[firstEdge + e[1]] + se[1],
                                    cvo[firstEdge + e[2]] + se[2], cvo[firstEdge + e[3]] + se[3]};
            uint32_t* out = CF.faceValues.data() + 16 * size_t(f);
            out[0] = cvo[v[0]] + sv[0], out[1] = ev[0], out[2] = fc, out[3] = ev[3];
            out[4] = ev[0], out[5] = cvo[v[1]] + sv[1], out[6] = ev[1], out[7] = fc;
            out[8] = fc, out[9] = ev[1], out[10] = cvo[v[2]] + sv[2], out[11] = ev[2];
            out[12] = ev[3], out[13] = fc, out[14] = ev[2], out[15] = cvo[v[3]] + sv[3];
            if (!last) {
                uint16_t* cs = CF.cornerSibling.data() + 16 * size_t(f);
                cs[0] = sv[0], cs[1] = se[0], cs[2] = 0, cs[3] = se[3];
                cs[4] = se[0], cs[5] = sv[1], cs[6] = se[1], cs[7] = 0;
                cs[8] = 0, cs[9] = se[1], cs[10] = sv[2], cs[11] = se[2];
                cs[12] = se[3], cs[13] = 0, cs[14] = se[2], cs[15] = sv[3];
            }
        });
    } else {
        par.each(nF, [&](size_t fi) {
            const uint32_t f = uint32_t(fi);
            const uint32_t off = pfo[f], k = pfo[f + 1] - off;
            for (uint32_t j = 0; j < k; ++j) {
                const uint32_t jp = j ? j - 1 : k - 1;
                const uint32_t eNext = P.faceEdges[off + j], ePrev = P.faceEdges[off + jp];
                const uint16_t sv = PF.cornerSibling[off + j];
                const uint16_t sn =
                    ((PF.edgeTags[eNext] & kFvEdgeMismatch) && P.edgeFaces[2 * eNext + 1] == f) ? 1
                                                                                                : 0;
                const uint16_t sp =
                    ((PF.edgeTags[ePrev] & kFvEdgeMismatch) && P.edgeFaces[2 * ePrev + 1] == f) ? 1
                                                                                                : 0;
                const uint32_t vals[4] = {CF.valueOffsets[P.faceVerts[off + j]] + sv,
                                          CF.valueOffsets[firstEdge + eNext] + sn,
                                          CF.valueOffsets[firstFace + f],
                                          CF.valueOffsets[firstEdge + ePrev] + sp};
                const uint16_t sibs[4] = {sv, sn, 0, sp};
                const uint32_t at = 4 * (off + j), rot = k == 4 ? j : 0;
                for (uint32_t m = 0; m < 4; ++m) {
                    CF.faceValues[at + ((m + rot) & 3)] = vals[m];
                    if (!last) CF.cornerSibling[at + ((m + rot) & 3)] = sibs[m];
                }
            }
        });
    }
    if (last) return;

    CF.edgeTags.assign(C.numEdges, 0);
    par.each(nE, [&](size_t e) {
        CF.edgeTags[nC + 2 * e] = CF.edgeTags[nC + 2 * e + 1] = PF.edgeTags[e];
    });
    if (fvarSmoothBoundaries_) fvarCreaseSpans(P, C, channel, par);
}

// refineFVar's value tags of a level that is refined further: a vertex
// child keeps its parent's values' tags, a face child's value matches, an
// edge child's values on a seam (or a linear edge) are mismatched (and
// creases with smooth boundaries).
void UniformRefiner::fvarValueTags(const RefineLevel& P, RefineLevel& C, size_t channel,
                                   const Parallel& par) {
    const FVarLevelData& PF = P.fvar[channel];
    FVarLevelData& CF = C.fvar[channel];
    const uint32_t nV = P.numVerts, nF = P.numFaces, nE = P.numEdges;
    const uint32_t firstFace = nV, firstEdge = nV + nF;
    sized(CF.valueTags, CF.valueOffsets.back());
    const uint8_t splitTag =
        fvarSmoothBoundaries_ ? uint8_t(kValueMismatch | kValueCrease) : uint8_t(kValueMismatch);
    par.each(nV, [&](size_t v) {
        for (uint32_t s = CF.valueOffsets[v]; s < CF.valueOffsets[v + 1]; ++s)
            CF.valueTags[s] = PF.valueTags[PF.valueOffsets[v] + (s - CF.valueOffsets[v])];
    });
    par.each(nF, [&](size_t f) { CF.valueTags[CF.valueOffsets[firstFace + f]] = 0; });
    par.each(nE, [&](size_t e) {
        const uint8_t t = (PF.edgeTags[e] & (kFvEdgeMismatch | kFvEdgeLinear)) ? splitTag : 0;
        for (uint32_t i = CF.valueOffsets[firstEdge + e]; i < CF.valueOffsets[firstEdge + e + 1];
             ++i)
            CF.valueTags[i] = t;
    });
}

// refineFVar's crease spans (smooth face-varying boundaries): an edge
// child's value on side i of a seam spans the child faces 2i, 2i+1; a
// vertex child keeps its parent's spans (same face order).
void UniformRefiner::fvarCreaseSpans(const RefineLevel& P, RefineLevel& C, size_t channel,
                                     const Parallel& par) {
    const FVarLevelData& PF = P.fvar[channel];
    FVarLevelData& CF = C.fvar[channel];
    const uint32_t nV = P.numVerts, nF = P.numFaces, nE = P.numEdges;
    const uint32_t firstEdge = nV + nF;
    const uint32_t total = CF.valueOffsets.back();
    CF.creaseStart.assign(total, 0);
    CF.creaseEnd.assign(total, 0);
    par.each(nE, [&](size_t e) {
        const uint32_t first = CF.valueOffsets[firstEdge + e],
                       n = CF.valueOffsets[firstEdge + e + 1] - first;
        if (!(CF.valueTags[first] & kValueMismatch)) return;
        for (uint32_t i = 0; i < n; ++i) {
            if (CF.valueTags[first + i] & kValueCrease) {
                CF.creaseStart[first + i] = uint16_t(2 * i);
                CF.creaseEnd[first + i] = uint16_t(2 * i + 1);
            }
        }
    });
    par.each(nV, [&](size_t v) {
        const uint32_t first = CF.valueOffsets[v], n = CF.valueOffsets[v + 1] - first;
        if (!(CF.valueTags[first] & kValueMismatch)) return;
        for (uint32_t s = 0; s < n; ++s) {
            if (CF.valueTags[first + s] & kValueCrease) {
                CF.creaseStart[first + s] = PF.creaseStart[PF.valueOffsets[v] + s];
                CF.creaseEnd[first + s] = PF.creaseEnd[PF.valueOffsets[v] + s];
            }
        }
    });
}

// ---- Masks and face-varying neighbourhoods ---------------------------------------

int UniformRefiner::edgeMaskGeneric(const RefineLevel& P, const RefineLevel& C, uint32_t e,
                                    float vw[2], float fw[2]) const {
    const bool creased = P.tagged && P.edgeSharpness[e] > 0.0f;
    const Crease::Rule childRule =
        P.tagged ? Crease::Rule(C.vertRules[P.numVerts + P.numFaces + e]) : Crease::RULE_SMOOTH;
    Mask m{vw, nullptr, fw};
    const EdgeHood hood{&P, e};
    Sdc::Scheme<Sdc::SCHEME_CATMARK>(options_).ComputeEdgeVertexMask(
        hood, m, creased ? Crease::RULE_CREASE : Crease::RULE_SMOOTH, childRule);
    return m.nf;
}

void UniformRefiner::vertexMask(const RefineLevel& P, const RefineLevel& C, uint32_t v,
                                Mask& mask) const {
    const VertexHood hood{&P, &C, v};
    const Crease::Rule parentRule = P.tagged ? Crease::Rule(P.vertRules[v]) : Crease::RULE_SMOOTH;
    const Crease::Rule childRule = P.tagged ? Crease::Rule(C.vertRules[v]) : Crease::RULE_SMOOTH;
    Sdc::Scheme<Sdc::SCHEME_CATMARK>(options_).ComputeVertexVertexMask(hood, mask, parentRule,
                                                                       childRule);
}

void UniformRefiner::creaseEndValues(const RefineLevel& P, const FVarLevelData& F, uint32_t v,
                                     uint32_t sibling, uint32_t out[2]) const {
    const uint32_t slot = F.valueOffsets[v] + sibling;
    const uint32_t base = P.vertFaceOffsets[v];
    const uint32_t f0 = P.vertFaces[base + F.creaseStart[slot]],
                   f1 = P.vertFaces[base + F.creaseEnd[slot]];
    const uint32_t i0 = P.vertInFace[base + F.creaseStart[slot]],
                   i1 = P.vertInFace[base + F.creaseEnd[slot]];
    const uint32_t o0 = P.faceOffsets[f0], k0 = P.faceOffsets[f0 + 1] - o0;
    const uint32_t o1 = P.faceOffsets[f1], k1 = P.faceOffsets[f1 + 1] - o1;
    out[0] = F.faceValues[o0 + (i0 + 1 == k0 ? 0 : i0 + 1)];
    out[1] = F.faceValues[o1 + (i1 ? i1 - 1 : k1 - 1)];
}

void UniformRefiner::lastLevelCreases(std::vector<EdgeCrease>& creases,
                                      std::vector<VertexCorner>& corners,
                                      bool skipBoundaryCorners) const {
    creases.clear();
    corners.clear();
    const RefineLevel& P = level_[size_t(levels_) - 1];
    const RefineLevel& L = level_[size_t(levels_)];
    if (!L.tagged) return;
    // Edges of the last level in index order: interior edges of faces
    // (never sharp), then the halves of each parent edge.
    for (uint32_t e = 0; e < P.numEdges; ++e) {
        for (uint32_t j = 0; j < 2; ++j) {
            const uint32_t c = P.numCorners + 2 * e + j;
            const float s = L.edgeSharpness[c];
            if (s > 0.0f && !(L.edgeTags[c] & kEdgeBoundary))
                creases.push_back({P.numVerts + P.numFaces + e, P.edgeVerts[2 * e + j], s});
        }
    }
    for (uint32_t v = 0; v < L.numVerts; ++v) {
        const float s = L.vertSharpness[v];
        if (s > 0.0f && !(skipBoundaryCorners && (L.vertTags[v] & kVertBoundary)))
            corners.push_back({v, s});
    }
}

} // namespace sg::mesh::detail
