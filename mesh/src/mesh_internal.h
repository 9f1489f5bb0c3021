// Internal helpers shared by the mesh/ sources (not installed, not public):
// edge tables over face-vertex arrays, union-find, finite checks, timing.
#pragma once

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <filesystem>
#include <string_view>

#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/mesh/render_mesh.h"

namespace sg::mesh::detail {

inline bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline bool finite(const glm::vec2& v) {
    return std::isfinite(v.x) && std::isfinite(v.y);
}

// "(x, y, z)" in the shortest form that reads back exactly ("nan", "inf").
inline std::string vecString(const glm::vec3& v) {
    std::string s = "(";
    for (int i = 0; i < 3; ++i) {
        char buf[32];
        auto r = std::to_chars(buf, buf + sizeof buf, v[i]);
        s.append(buf, r.ptr);
        s += i < 2 ? ", " : ")";
    }
    return s;
}

// Union-find with path halving; indices are uint32_t.
class UnionFind {
public:
    explicit UnionFind(size_t n = 0) { reset(n); }
    void reset(size_t n) {
        parent_.resize(n);
        std::iota(parent_.begin(), parent_.end(), 0u);
    }
    uint32_t find(uint32_t a) {
        while (parent_[a] != a) {
            parent_[a] = parent_[parent_[a]];
            a = parent_[a];
        }
        return a;
    }
    // The smaller root wins, so roots are the smallest member (deterministic).
    void unite(uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a == b) return;
        if (a < b)
            parent_[b] = a;
        else
            parent_[a] = b;
    }

private:
    std::vector<uint32_t> parent_;
};

// One directed face edge: corner `corner` of the face goes from vertex
// faceVertices[corner] to the face's next corner. Sorted by undirected key.
struct FaceEdge {
    uint64_t key;    // (min << 32) | max
    uint32_t corner; // global corner index of the edge's start
    uint32_t next;   // global corner index of the edge's end
    bool forward;    // start vertex < end vertex
};

inline uint64_t edgeKey(uint32_t a, uint32_t b) {
    return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
}

// All face edges of the faces with keep[f] (or all faces when keep is
// empty), sorted by key (ties by corner, so the order is deterministic).
std::vector<FaceEdge> sortedFaceEdges(const PolygonMesh& mesh,
                                      const std::vector<uint32_t>& offsets);

// Manifold analysis of a face-vertex mesh (no degenerate faces assumed).
struct Topology {
    size_t edges = 0, boundaryEdges = 0, boundaryLoops = 0;
    size_t nonManifoldEdges = 0, nonManifoldVertices = 0;
    // First offenders, for messages (UINT32_MAX when none).
    uint32_t firstBadEdgeV0 = UINT32_MAX, firstBadEdgeV1 = UINT32_MAX,
             firstBadEdgeFace = UINT32_MAX;
    std::string firstBadEdgeReason;
    uint32_t firstBadVertex = UINT32_MAX;
    size_t firstBadVertexFans = 0;
};
// Reasons name faces as face + indexBase (1 for OBJ files, see validateImpl).
Topology analyzeTopology(const PolygonMesh& mesh, const std::vector<uint32_t>& offsets,
                         uint32_t indexBase = 0);

// Face index of each global corner.
std::vector<uint32_t> cornerFaces(const std::vector<uint32_t>& offsets);

// Render-vertex split of a PolygonMesh (convert.cpp): one render vertex per
// distinct (vertex, UV indices, normal index, sector) over the corners of
// non-hole faces, numbered by first appearance; fan triangulation from
// corner 0.
struct RenderSplit {
    std::vector<uint32_t> cornerRenderVertex; // per corner (UINT32_MAX in holes)
    std::vector<uint32_t> renderSourceVertex; // per render vertex
    std::vector<uint32_t> renderFirstCorner;  // per render vertex: its home corner
    std::vector<uint32_t> indices;            // triangles
};
// Per render vertex: the smallest index of the vertices that coincide with
// it in the base mesh AND in every morph target (exact comparison of the
// position and of each target's position delta), i.e. copies of one cage
// vertex split at UV seams or normal creases. rep[v] == v for the first of
// each group. O(n log n).
std::vector<uint32_t> coincidentVertexGroups(const RenderMesh& mesh);

// cornerSector: optional per-corner smooth-sector id (corners with different
// ids never share a render vertex).
void splitRenderVertices(const PolygonMesh& mesh, const std::vector<uint32_t>& offsets,
                         const uint32_t* cornerSector, RenderSplit& out);

// `threads`: parseObj's (surfgrad/mesh/mesh_io.h).
PolygonMesh parseObjImpl(std::string_view text, const std::string& file, const InputLimits& limits,
                         LoadReport* report, std::vector<uint32_t>* faceLines, int threads);
// faceLines (OBJ files: the line of each face) also switches messages to
// the file's own numbering: vertices and faces from 1, faces with their
// line ("face 25 (line 161): uses vertex 52 twice"); without it, 0-based.
void validateImpl(PolygonMesh& mesh, const std::string& file, bool repair, LoadReport* report,
                  const InputLimits& limits, bool allowNonManifold,
                  const std::vector<uint32_t>* faceLines);
PolygonMesh readWithOpenMesh(const std::filesystem::path& path, const InputLimits& limits,
                             LoadReport* report);

class Stopwatch {
public:
    Stopwatch() : t0_(std::chrono::steady_clock::now()) {}
    double lap() {
        auto t = std::chrono::steady_clock::now();
        double s = std::chrono::duration<double>(t - t0_).count();
        t0_ = t;
        return s;
    }

private:
    std::chrono::steady_clock::time_point t0_;
};

} // namespace sg::mesh::detail
