// Validation, repair and topology description of PolygonMesh
// (surfgrad/mesh/mesh_io.h: validate, describe). Validation runs before anything
// else touches a loaded mesh; every failure is an InputError naming the
// file, the element (face, vertex, edge, tag) and the reason.
//
// Manifold test: an edge is manifold when at most two faces use it and two
// faces traverse it in opposite directions; a vertex is manifold when the
// corners around it are connected through manifold edges into one fan
// (union-find over face corners).
#include <algorithm>
#include <cstring>
#include <unordered_map>

#include "mesh_internal.h"
#include "surfgrad/mesh/mesh_io.h"

namespace sg::mesh {

using io::InputError;

namespace detail {

std::vector<uint32_t> cornerFaces(const std::vector<uint32_t>& offsets) {
    std::vector<uint32_t> faces(offsets.empty() ? 0 : offsets.back());
    for (size_t f = 0; f + 1 < offsets.size(); ++f) {
        std::fill(faces.begin() + offsets[f], faces.begin() + offsets[f + 1], uint32_t(f));
    }
    return faces;
}

std::vector<FaceEdge> sortedFaceEdges(const PolygonMesh& mesh,
                                      const std::vector<uint32_t>& offsets) {
    std::vector<FaceEdge> edges;
    edges.reserve(mesh.faceVertices.size());
    for (size_t f = 0; f + 1 < offsets.size(); ++f) {
        uint32_t b = offsets[f], e = offsets[f + 1];
        for (uint32_t c = b; c < e; ++c) {
            uint32_t n = c + 1 == e ? b : c + 1;
            uint32_t va = mesh.faceVertices[c], vb = mesh.faceVertices[n];
            edges.push_back({edgeKey(va, vb), c, n, va < vb});
        }
    }
    std::sort(edges.begin(), edges.end(), [](const FaceEdge& a, const FaceEdge& b) {
        return a.key != b.key ? a.key < b.key : a.corner < b.corner;
    });
    return edges;
}

Topology analyzeTopology(const PolygonMesh& mesh, const std::vector<uint32_t>& offsets,
                         uint32_t indexBase) {
    auto face = [&](uint32_t f) { return std::to_string(uint64_t(f) + indexBase); };
    Topology topo;
    const size_t nCorners = mesh.faceVertices.size();
    std::vector<FaceEdge> edges = sortedFaceEdges(mesh, offsets);
    std::vector<uint32_t> faceOf = cornerFaces(offsets);
    UnionFind corners(nCorners);
    UnionFind boundary(mesh.positions.size());
    std::vector<uint8_t> onBoundary(mesh.positions.size(), 0);
    for (size_t i = 0; i < edges.size();) {
        size_t j = i + 1;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        size_t n = j - i;
        ++topo.edges;
        const FaceEdge& a = edges[i];
        auto badEdge = [&](const std::string& reason) {
            ++topo.nonManifoldEdges;
            if (topo.firstBadEdgeV0 == UINT32_MAX) {
                topo.firstBadEdgeV0 = uint32_t(a.key >> 32);
                topo.firstBadEdgeV1 = uint32_t(a.key & 0xffffffffu);
                topo.firstBadEdgeFace = faceOf[edges[i + 1].corner];
                topo.firstBadEdgeReason = reason;
            }
        };
        if (n == 1) {
            ++topo.boundaryEdges;
            uint32_t va = mesh.faceVertices[a.corner], vb = mesh.faceVertices[a.next];
            boundary.unite(va, vb);
            onBoundary[va] = onBoundary[vb] = 1;
        } else if (n == 2) {
            const FaceEdge& b = edges[i + 1];
            if (a.forward == b.forward) {
                badEdge("faces " + face(faceOf[a.corner]) + " and " + face(faceOf[b.corner]) +
                        " traverse it in the same direction (inconsistent orientation or a Moebius "
                        "strip)");
            } else {
                // a goes va->vb in face A, b goes vb->va in face B.
                corners.unite(a.corner, b.next);
                corners.unite(a.next, b.corner);
            }
        } else {
            std::string faces;
            for (size_t k = i; k < j && k < i + 4; ++k) {
                faces += (faces.empty() ? "" : ", ") + face(faceOf[edges[k].corner]);
            }
            if (n > 4) faces += ", ...";
            badEdge("shared by " + std::to_string(n) + " faces (" + faces + "); non-manifold edge");
        }
        i = j;
    }
    // Fans per vertex = corners that are their own union-find root.
    std::vector<uint32_t> fans(mesh.positions.size(), 0);
    for (uint32_t c = 0; c < nCorners; ++c) {
        if (corners.find(c) == c) ++fans[mesh.faceVertices[c]];
    }
    for (uint32_t v = 0; v < fans.size(); ++v) {
        if (fans[v] > 1) {
            ++topo.nonManifoldVertices;
            if (topo.firstBadVertex == UINT32_MAX) {
                topo.firstBadVertex = v;
                topo.firstBadVertexFans = fans[v];
            }
        }
    }
    for (uint32_t v = 0; v < onBoundary.size(); ++v) {
        if (onBoundary[v] && boundary.find(v) == v) ++topo.boundaryLoops;
    }
    return topo;
}

} // namespace detail

namespace {

// Vertex and face numbers in messages: 0-based, or for OBJ files (with
// faceLines) as the file numbers them, from 1 (see validateImpl).
uint32_t indexBase(const std::vector<uint32_t>* faceLines) {
    return faceLines ? 1u : 0u;
}

std::string number(uint32_t i, const std::vector<uint32_t>* faceLines) {
    return std::to_string(uint64_t(i) + indexBase(faceLines));
}

std::string faceName(uint32_t f, const std::vector<uint32_t>* faceLines) {
    std::string s = "face " + number(f, faceLines);
    if (faceLines && f < faceLines->size()) s += " (line " + std::to_string((*faceLines)[f]) + ")";
    return s;
}

// Why face f is degenerate, or empty when it is not.
std::string degenerateReason(const PolygonMesh& mesh, uint32_t begin, uint32_t count,
                             std::vector<uint32_t>& scratch,
                             const std::vector<uint32_t>* faceLines) {
    if (count < 3) return "has " + std::to_string(count) + " corners (a face needs 3)";
    scratch.assign(mesh.faceVertices.begin() + begin, mesh.faceVertices.begin() + begin + count);
    std::sort(scratch.begin(), scratch.end());
    auto dup = std::adjacent_find(scratch.begin(), scratch.end());
    if (dup != scratch.end())
        return "uses vertex " + number(*dup, faceLines) + " twice (degenerate face)";
    // Newell normal in double: the cross products of float inputs are exact,
    // so zero means the corners are exactly collinear or coincident.
    double nx = 0, ny = 0, nz = 0;
    for (uint32_t k = 0; k < count; ++k) {
        const glm::vec3& p = mesh.positions[mesh.faceVertices[begin + k]];
        const glm::vec3& q = mesh.positions[mesh.faceVertices[begin + (k + 1) % count]];
        nx += (double(p.y) - q.y) * (double(p.z) + q.z);
        ny += (double(p.z) - q.z) * (double(p.x) + q.x);
        nz += (double(p.x) - q.x) * (double(p.y) + q.y);
    }
    if (nx == 0 && ny == 0 && nz == 0)
        return "has zero area (its corners are collinear or coincide)";
    return {};
}

// Counts within the limits, face sizes adding up to the corners, finite
// positions, vertex indices in range.
void checkFaces(const PolygonMesh& mesh, const std::string& file, const InputLimits& limits,
                const std::vector<uint32_t>* faceLines) {
    const size_t nV = mesh.positions.size(), nF = mesh.faceSizes.size(),
                 nC = mesh.faceVertices.size();
    if (nV > limits.maxVertices) {
        throw InputError(file, "vertices",
                         std::to_string(nV) + " vertices; the limit is " +
                             std::to_string(limits.maxVertices));
    }
    if (nF > limits.maxFaces) {
        throw InputError(file, "faces",
                         std::to_string(nF) + " faces; the limit is " +
                             std::to_string(limits.maxFaces));
    }
    if (nC > limits.maxCorners) {
        throw InputError(file, "faces",
                         std::to_string(nC) + " face corners; the limit is " +
                             std::to_string(limits.maxCorners));
    }
    uint64_t sum = 0;
    for (size_t f = 0; f < nF; ++f) {
        if (mesh.faceSizes[f] > limits.maxFaceDegree) {
            throw InputError(file, faceName(uint32_t(f), faceLines),
                             "has " + std::to_string(mesh.faceSizes[f]) +
                                 " corners; the limit is " + std::to_string(limits.maxFaceDegree));
        }
        sum += mesh.faceSizes[f];
    }
    if (sum != nC) {
        throw InputError(file, "faces",
                         "face sizes add up to " + std::to_string(sum) + " corners but " +
                             std::to_string(nC) + " are given");
    }
    for (size_t v = 0; v < nV; ++v) {
        if (!detail::finite(mesh.positions[v])) {
            throw InputError(file, "vertex " + number(uint32_t(v), faceLines),
                             "non-finite coordinate " + detail::vecString(mesh.positions[v]));
        }
    }
    {
        uint32_t f = 0, end = nF ? mesh.faceSizes[0] : 0;
        for (size_t c = 0; c < nC; ++c) {
            while (c >= end) end += mesh.faceSizes[++f];
            if (mesh.faceVertices[c] >= nV) {
                throw InputError(file, faceName(f, faceLines),
                                 "vertex index " + std::to_string(mesh.faceVertices[c]) +
                                     " is out of range (" + std::to_string(nV) + " vertices)");
            }
        }
    }
}

// UV sets and normals: counts, finite values, indices in range.
void checkFaceVaryingData(const PolygonMesh& mesh, const std::string& file,
                          const InputLimits& limits) {
    const size_t nC = mesh.faceVertices.size();
    if (mesh.uvSets.size() > limits.maxUvSets) {
        throw InputError(file, "uv sets",
                         std::to_string(mesh.uvSets.size()) + " UV sets; the limit is " +
                             std::to_string(limits.maxUvSets));
    }
    for (size_t s = 0; s < mesh.uvSets.size(); ++s) {
        const FaceVaryingChannel& ch = mesh.uvSets[s];
        std::string el = "uv set " + std::to_string(s);
        if (ch.indices.size() != nC) {
            throw InputError(file, el,
                             std::to_string(ch.indices.size()) + " corner indices for " +
                                 std::to_string(nC) + " corners");
        }
        for (size_t i = 0; i < ch.values.size(); ++i) {
            if (!detail::finite(ch.values[i]))
                throw InputError(file, el + " value " + std::to_string(i), "non-finite UV");
        }
        for (size_t c = 0; c < nC; ++c) {
            if (ch.indices[c] >= ch.values.size()) {
                throw InputError(file, el + " corner " + std::to_string(c),
                                 "UV index " + std::to_string(ch.indices[c]) +
                                     " is out of range (" + std::to_string(ch.values.size()) +
                                     " UVs)");
            }
        }
    }
    if (!mesh.normalIndices.empty() && mesh.normalIndices.size() != nC) {
        throw InputError(file, "normals",
                         std::to_string(mesh.normalIndices.size()) + " corner indices for " +
                             std::to_string(nC) + " corners");
    }
    for (size_t i = 0; i < mesh.normals.size(); ++i) {
        if (!detail::finite(mesh.normals[i]))
            throw InputError(file, "normal " + std::to_string(i), "non-finite normal");
    }
    for (size_t c = 0; c < mesh.normalIndices.size(); ++c) {
        if (mesh.normalIndices[c] >= mesh.normals.size()) {
            throw InputError(file, "corner " + std::to_string(c),
                             "normal index " + std::to_string(mesh.normalIndices[c]) +
                                 " is out of range (" + std::to_string(mesh.normals.size()) +
                                 " normals)");
        }
    }
}

// Crease, corner and hole tags: indices in range, sharpness finite and >= 0.
void checkTags(const PolygonMesh& mesh, const std::string& file) {
    const size_t nV = mesh.positions.size(), nF = mesh.faceSizes.size();
    for (size_t i = 0; i < mesh.creases.size(); ++i) {
        const EdgeCrease& e = mesh.creases[i];
        std::string el = "crease " + std::to_string(i) + " (" + std::to_string(e.v0) + ", " +
                         std::to_string(e.v1) + ")";
        if (e.v0 >= nV || e.v1 >= nV)
            throw InputError(file, el,
                             "vertex index out of range (" + std::to_string(nV) + " vertices)");
        if (e.v0 == e.v1) throw InputError(file, el, "both ends are the same vertex");
        if (!std::isfinite(e.sharpness) || e.sharpness < 0) {
            throw InputError(file, el,
                             "sharpness " + std::to_string(e.sharpness) +
                                 " is not a finite value >= 0");
        }
    }
    for (size_t i = 0; i < mesh.corners.size(); ++i) {
        const VertexCorner& k = mesh.corners[i];
        std::string el =
            "corner tag " + std::to_string(i) + " (vertex " + std::to_string(k.vertex) + ")";
        if (k.vertex >= nV)
            throw InputError(file, el,
                             "vertex index out of range (" + std::to_string(nV) + " vertices)");
        if (!std::isfinite(k.sharpness) || k.sharpness < 0) {
            throw InputError(file, el,
                             "sharpness " + std::to_string(k.sharpness) +
                                 " is not a finite value >= 0");
        }
    }
    for (uint32_t h : mesh.holes) {
        if (h >= nF)
            throw InputError(file, "hole tag (face " + std::to_string(h) + ")",
                             "face index out of range (" + std::to_string(nF) + " faces)");
    }
}

// Morph targets and weights: counts, one finite delta per vertex, finite
// weights.
void checkMorphTargets(const PolygonMesh& mesh, const std::string& file,
                       const InputLimits& limits) {
    const size_t nV = mesh.positions.size();
    if (mesh.morphTargets.size() > limits.maxMorphTargets) {
        throw InputError(file, "morph targets",
                         std::to_string(mesh.morphTargets.size()) + " targets; the limit is " +
                             std::to_string(limits.maxMorphTargets));
    }
    for (size_t t = 0; t < mesh.morphTargets.size(); ++t) {
        const CageMorphTarget& mt = mesh.morphTargets[t];
        std::string el = "morph target " + std::to_string(t);
        if (mt.positionDeltas.size() != nV) {
            throw InputError(file, el,
                             std::to_string(mt.positionDeltas.size()) + " deltas for " +
                                 std::to_string(nV) + " vertices");
        }
        for (size_t v = 0; v < nV; ++v) {
            if (!detail::finite(mt.positionDeltas[v]))
                throw InputError(file, el + " vertex " + std::to_string(v), "non-finite delta");
        }
    }
    if (!mesh.morphWeights.empty() && mesh.morphWeights.size() != mesh.morphTargets.size()) {
        throw InputError(file, "morph weights",
                         std::to_string(mesh.morphWeights.size()) + " weights for " +
                             std::to_string(mesh.morphTargets.size()) + " targets");
    }
    for (float w : mesh.morphWeights) {
        if (!std::isfinite(w)) throw InputError(file, "morph weights", "non-finite weight");
    }
}

void checkStructure(const PolygonMesh& mesh, const std::string& file, const InputLimits& limits,
                    const std::vector<uint32_t>* faceLines) {
    checkFaces(mesh, file, limits, faceLines);
    checkFaceVaryingData(mesh, file, limits);
    checkTags(mesh, file);
    checkMorphTargets(mesh, file, limits);
}

// Welds vertices with exactly equal positions and morph deltas; returns the
// number of vertices removed.
size_t weldDuplicates(PolygonMesh& mesh, LoadReport* report) {
    const size_t nV = mesh.positions.size();
    // Compare positions, then every target's delta; 0 when all are equal.
    auto cmpKey = [&](uint32_t a, uint32_t b) {
        auto cmp = [](const glm::vec3& p, const glm::vec3& q) {
            if (p.x != q.x) return p.x < q.x ? -1 : 1;
            if (p.y != q.y) return p.y < q.y ? -1 : 1;
            if (p.z != q.z) return p.z < q.z ? -1 : 1;
            return 0;
        };
        int c = cmp(mesh.positions[a], mesh.positions[b]);
        for (size_t t = 0; c == 0 && t < mesh.morphTargets.size(); ++t) {
            c = cmp(mesh.morphTargets[t].positionDeltas[a], mesh.morphTargets[t].positionDeltas[b]);
        }
        return c;
    };
    std::vector<uint32_t> order(nV);
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        int c = cmpKey(a, b);
        return c != 0 ? c < 0 : a < b;
    });
    // Within a group of equal keys the order is by index, so the group's
    // representative is its smallest index.
    std::vector<uint32_t> rep(nV);
    std::iota(rep.begin(), rep.end(), 0u);
    size_t welded = 0;
    for (size_t i = 1; i < nV; ++i) {
        if (cmpKey(order[i], order[i - 1]) == 0) {
            rep[order[i]] = rep[order[i - 1]];
            ++welded;
        }
    }
    if (welded == 0) return 0;
    std::vector<uint32_t> newIndex(nV, UINT32_MAX);
    uint32_t next = 0;
    for (uint32_t v = 0; v < nV; ++v) {
        if (rep[v] == v) newIndex[v] = next++;
    }
    for (uint32_t v = 0; v < nV; ++v) newIndex[v] = newIndex[rep[v]];
    auto compact = [&](std::vector<glm::vec3>& values) {
        std::vector<glm::vec3> out(next);
        for (uint32_t v = 0; v < nV; ++v) {
            if (rep[v] == v) out[newIndex[v]] = values[v];
        }
        values.swap(out);
    };
    compact(mesh.positions);
    for (CageMorphTarget& t : mesh.morphTargets) compact(t.positionDeltas);
    for (uint32_t& v : mesh.faceVertices) v = newIndex[v];
    std::vector<EdgeCrease> creases;
    for (EdgeCrease e : mesh.creases) {
        e.v0 = newIndex[e.v0];
        e.v1 = newIndex[e.v1];
        if (e.v0 != e.v1)
            creases.push_back(e);
        else if (report)
            report->notes.push_back("crease between two welded vertices dropped");
    }
    mesh.creases.swap(creases);
    for (VertexCorner& k : mesh.corners) k.vertex = newIndex[k.vertex];
    if (report) {
        report->duplicateVerticesWelded += welded;
        report->notes.push_back("welded " + std::to_string(welded) +
                                " vertices with exactly equal positions");
    }
    return welded;
}

// Drops the faces with drop[f]; keeps every per-corner array in step.
void dropFaces(PolygonMesh& mesh, const std::vector<uint8_t>& drop) {
    std::vector<uint32_t> offsets = faceOffsets(mesh);
    std::vector<uint32_t> newFace(mesh.faceSizes.size(), UINT32_MAX);
    size_t outF = 0, outC = 0;
    for (size_t f = 0; f < mesh.faceSizes.size(); ++f) {
        if (drop[f]) continue;
        newFace[f] = uint32_t(outF);
        for (uint32_t c = offsets[f]; c < offsets[f + 1]; ++c, ++outC) {
            mesh.faceVertices[outC] = mesh.faceVertices[c];
            for (FaceVaryingChannel& ch : mesh.uvSets) ch.indices[outC] = ch.indices[c];
            if (!mesh.normalIndices.empty()) mesh.normalIndices[outC] = mesh.normalIndices[c];
        }
        mesh.faceSizes[outF++] = mesh.faceSizes[f];
    }
    mesh.faceSizes.resize(outF);
    mesh.faceVertices.resize(outC);
    for (FaceVaryingChannel& ch : mesh.uvSets) ch.indices.resize(outC);
    if (!mesh.normalIndices.empty()) mesh.normalIndices.resize(outC);
    std::vector<uint32_t> holes;
    for (uint32_t h : mesh.holes) {
        if (newFace[h] != UINT32_MAX) holes.push_back(newFace[h]);
    }
    mesh.holes.swap(holes);
}

} // namespace

namespace detail {

void validateImpl(PolygonMesh& mesh, const std::string& file, bool repair, LoadReport* report,
                  const InputLimits& limits, bool allowNonManifold,
                  const std::vector<uint32_t>* faceLines) {
    checkStructure(mesh, file, limits, faceLines);
    std::sort(mesh.holes.begin(), mesh.holes.end());
    mesh.holes.erase(std::unique(mesh.holes.begin(), mesh.holes.end()), mesh.holes.end());
    if (repair) {
        weldDuplicates(mesh, report); // keeps face numbering (and faceLines) intact
    }
    // Degenerate faces.
    {
        std::vector<uint32_t> offsets = faceOffsets(mesh);
        std::vector<uint8_t> drop(mesh.faceSizes.size(), 0);
        std::vector<uint32_t> scratch;
        size_t dropped = 0;
        for (uint32_t f = 0; f < mesh.faceSizes.size(); ++f) {
            std::string why =
                degenerateReason(mesh, offsets[f], mesh.faceSizes[f], scratch, faceLines);
            if (why.empty()) continue;
            if (!repair)
                throw InputError(file, faceName(f, faceLines), why + " (--repair drops it)");
            drop[f] = 1;
            ++dropped;
        }
        if (dropped) {
            dropFaces(mesh, drop);
            if (report) {
                report->degenerateFacesDropped += dropped;
                report->notes.push_back("dropped " + std::to_string(dropped) + " degenerate faces");
            }
        }
    }
    if (mesh.positions.empty() || mesh.faceSizes.empty()) {
        throw InputError(
            file, "", mesh.positions.empty() ? "empty mesh: no vertices" : "empty mesh: no faces");
    }
    std::vector<uint32_t> offsets = faceOffsets(mesh);
    if (!allowNonManifold) {
        detail::Topology topo = detail::analyzeTopology(mesh, offsets, indexBase(faceLines));
        if (topo.nonManifoldEdges) {
            throw InputError(file,
                             "edge (" + number(topo.firstBadEdgeV0, faceLines) + ", " +
                                 number(topo.firstBadEdgeV1, faceLines) + ")",
                             topo.firstBadEdgeReason +
                                 (topo.nonManifoldEdges > 1
                                      ? "; " + std::to_string(topo.nonManifoldEdges) + " such edges"
                                      : ""));
        }
        if (topo.nonManifoldVertices) {
            throw InputError(
                file, "vertex " + number(topo.firstBadVertex, faceLines),
                "the faces around it form " + std::to_string(topo.firstBadVertexFans) +
                    " separate fans (non-manifold vertex)" +
                    (topo.nonManifoldVertices > 1
                         ? "; " + std::to_string(topo.nonManifoldVertices) + " such vertices"
                         : ""));
        }
    }
    // Crease tags must name edges.
    if (!mesh.creases.empty()) {
        std::vector<uint64_t> keys;
        keys.reserve(mesh.faceVertices.size());
        for (size_t f = 0; f < mesh.faceSizes.size(); ++f) {
            for (uint32_t c = offsets[f]; c < offsets[f + 1]; ++c) {
                uint32_t n = c + 1 == offsets[f + 1] ? offsets[f] : c + 1;
                keys.push_back(edgeKey(mesh.faceVertices[c], mesh.faceVertices[n]));
            }
        }
        std::sort(keys.begin(), keys.end());
        for (size_t i = 0; i < mesh.creases.size(); ++i) {
            const EdgeCrease& e = mesh.creases[i];
            if (!std::binary_search(keys.begin(), keys.end(), edgeKey(e.v0, e.v1))) {
                throw InputError(file,
                                 "crease " + std::to_string(i) + " (" + std::to_string(e.v0) +
                                     ", " + std::to_string(e.v1) + ")",
                                 "no face has an edge between these vertices");
            }
        }
    }
    if (report) {
        std::vector<uint8_t> used(mesh.positions.size(), 0);
        for (uint32_t v : mesh.faceVertices) used[v] = 1;
        size_t isolated = size_t(std::count(used.begin(), used.end(), uint8_t(0)));
        report->isolatedVertices = isolated;
        if (isolated)
            report->notes.push_back(std::to_string(isolated) +
                                    " isolated vertices (no face uses them; kept)");
    }
}

} // namespace detail

void validate(PolygonMesh& mesh, const std::string& file, bool repair, LoadReport* report,
              const InputLimits& limits, bool allowNonManifold) {
    detail::validateImpl(mesh, file, repair, report, limits, allowNonManifold, nullptr);
}

MeshInfo describe(const PolygonMesh& mesh) {
    MeshInfo info;
    info.vertices = mesh.positions.size();
    info.faces = mesh.faceSizes.size();
    info.corners = mesh.faceVertices.size();
    uint32_t maxDegree = 0;
    for (uint32_t k : mesh.faceSizes) maxDegree = std::max(maxDegree, k);
    info.faceDegreeHistogram.assign(size_t(maxDegree) + 1, 0);
    for (uint32_t k : mesh.faceSizes) ++info.faceDegreeHistogram[k];
    std::vector<uint8_t> used(mesh.positions.size(), 0);
    for (uint32_t v : mesh.faceVertices) used[v] = 1;
    info.isolatedVertices = size_t(std::count(used.begin(), used.end(), uint8_t(0)));
    std::vector<uint32_t> offsets = faceOffsets(mesh);
    detail::Topology topo = detail::analyzeTopology(mesh, offsets);
    info.edges = topo.edges;
    info.boundaryEdges = topo.boundaryEdges;
    info.boundaryLoops = topo.boundaryLoops;
    info.nonManifoldEdges = topo.nonManifoldEdges;
    info.nonManifoldVertices = topo.nonManifoldVertices;
    info.manifold = topo.nonManifoldEdges == 0 && topo.nonManifoldVertices == 0;
    info.creases = mesh.creases.size();
    for (const EdgeCrease& e : mesh.creases)
        info.infiniteCreases += e.sharpness >= kInfiniteSharpness;
    info.cornerTags = mesh.corners.size();
    info.holes = mesh.holes.size();
    info.eulerCharacteristic =
        int(info.vertices - info.isolatedVertices) - int(info.edges) + int(info.faces);
    return info;
}

} // namespace sg::mesh
