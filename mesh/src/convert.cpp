// Conversions between the polygon cage (PolygonMesh, face-varying UVs) and
// the split-vertex triangle mesh the renderer takes (RenderMesh), and
// area-weighted vertex normals (surfgrad/mesh/mesh_io.h: toRenderMesh,
// toPolygonMesh; surfgrad/mesh/subdivision.h: computeVertexNormals).
//
// A render vertex is one distinct tuple (vertex, UV index of every set,
// normal index, smooth sector) over the face corners; render vertices are
// numbered in order of first appearance, so the output is deterministic and
// roughly follows the input's memory order.
#include <cstring>

#include "mesh_internal.h"
#include "surfgrad/base/scratch_buffer.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/base/threads.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sg::mesh {

void computeVertexNormals(RenderMesh& mesh, std::span<const uint32_t> smoothGroup) {
    const size_t nV = mesh.positions.size();
    SG_EXPECTS(smoothGroup.empty() || smoothGroup.size() == nV,
               "smoothGroup is empty or has one entry per vertex");
    std::vector<glm::vec3> acc(nV, glm::vec3(0.0f));
    std::vector<glm::vec3> firstFace(nV, glm::vec3(0.0f));
    auto group = [&](uint32_t v) { return smoothGroup.empty() ? v : smoothGroup[v]; };
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        uint32_t i0 = mesh.indices[t], i1 = mesh.indices[t + 1], i2 = mesh.indices[t + 2];
        const glm::vec3 &a = mesh.positions[i0], &b = mesh.positions[i1], &c = mesh.positions[i2];
        // |cross| = twice the area: area weighting for free.
        glm::vec3 n = glm::cross(b - a, c - a);
        for (uint32_t i : {i0, i1, i2}) {
            uint32_t g = group(i);
            acc[g] += n;
            if (firstFace[g] == glm::vec3(0.0f)) firstFace[g] = n;
        }
    }
    mesh.normals.resize(nV);
    for (uint32_t v = 0; v < nV; ++v) {
        uint32_t g = group(v);
        glm::vec3 n = acc[g];
        float len = glm::length(n);
        if (!(len > 0.0f) || !std::isfinite(len)) {
            // Opposite faces cancelled (a fin) or all faces are degenerate.
            n = firstFace[g];
            len = glm::length(n);
        }
        mesh.normals[v] = len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
    }
}

namespace detail {

void splitRenderVertices(const PolygonMesh& mesh, const std::vector<uint32_t>& offsets,
                         const uint32_t* cornerSector, RenderSplit& out) {
    const size_t nC = mesh.faceVertices.size();
    const size_t nSets = mesh.uvSets.size();
    const bool useNormals = !mesh.normalIndices.empty();
    std::vector<uint8_t> isHole(mesh.faceSizes.size(), 0);
    for (uint32_t h : mesh.holes) isHole[h] = 1;
    out.cornerRenderVertex.assign(nC, UINT32_MAX);
    out.renderSourceVertex.clear();
    out.renderFirstCorner.clear();
    out.indices.clear();
    // Per source vertex a linked list of its render vertices.
    std::vector<uint32_t> head(mesh.positions.size(), UINT32_MAX);
    std::vector<uint32_t> next;
    auto sameKey = [&](uint32_t c, uint32_t d) {
        for (size_t s = 0; s < nSets; ++s) {
            if (mesh.uvSets[s].indices[c] != mesh.uvSets[s].indices[d]) return false;
        }
        if (useNormals && mesh.normalIndices[c] != mesh.normalIndices[d]) return false;
        if (cornerSector && cornerSector[c] != cornerSector[d]) return false;
        return true;
    };
    for (size_t f = 0; f < mesh.faceSizes.size(); ++f) {
        if (isHole[f]) continue;
        for (uint32_t c = offsets[f]; c < offsets[f + 1]; ++c) {
            uint32_t v = mesh.faceVertices[c];
            uint32_t r = head[v];
            while (r != UINT32_MAX && !sameKey(c, out.renderFirstCorner[r])) r = next[r];
            if (r == UINT32_MAX) {
                r = uint32_t(out.renderSourceVertex.size());
                out.renderSourceVertex.push_back(v);
                out.renderFirstCorner.push_back(c);
                next.push_back(head[v]);
                head[v] = r;
            }
            out.cornerRenderVertex[c] = r;
        }
        // Fan from corner 0 (for quads: the 0-2 diagonal).
        uint32_t b = offsets[f], k = mesh.faceSizes[f];
        for (uint32_t i = 1; i + 1 < k; ++i) {
            out.indices.push_back(out.cornerRenderVertex[b]);
            out.indices.push_back(out.cornerRenderVertex[b + i]);
            out.indices.push_back(out.cornerRenderVertex[b + i + 1]);
        }
    }
}

} // namespace detail

RenderMesh toRenderMesh(const PolygonMesh& mesh) {
    std::vector<uint32_t> offsets = faceOffsets(mesh);
    detail::RenderSplit split;
    detail::splitRenderVertices(mesh, offsets, nullptr, split);
    RenderMesh out;
    out.name = mesh.name;
    const size_t nR = split.renderSourceVertex.size();
    out.positions.resize(nR);
    for (size_t r = 0; r < nR; ++r) out.positions[r] = mesh.positions[split.renderSourceVertex[r]];
    out.uvSets.resize(mesh.uvSets.size());
    for (size_t s = 0; s < mesh.uvSets.size(); ++s) {
        out.uvSets[s].resize(nR);
        for (size_t r = 0; r < nR; ++r)
            out.uvSets[s][r] =
                mesh.uvSets[s].values[mesh.uvSets[s].indices[split.renderFirstCorner[r]]];
    }
    out.indices = std::move(split.indices);
    if (!mesh.normalIndices.empty()) {
        out.normals.resize(nR);
        bool bad = false;
        for (size_t r = 0; r < nR; ++r) {
            glm::vec3 n = mesh.normals[mesh.normalIndices[split.renderFirstCorner[r]]];
            float len = glm::length(n);
            if (!(len > 0.0f) || !std::isfinite(len)) {
                bad = true;
                break;
            }
            out.normals[r] = n / len;
        }
        if (bad) out.normals.clear(); // a zero normal in the file: recompute all (below)
    }
    if (out.normals.empty()) {
        // Smooth across UV seams: render vertices of one source vertex share a group.
        std::vector<uint32_t> group(nR);
        std::vector<uint32_t> firstRender(mesh.positions.size(), UINT32_MAX);
        for (uint32_t r = 0; r < nR; ++r) {
            uint32_t& g = firstRender[split.renderSourceVertex[r]];
            if (g == UINT32_MAX) g = r;
            group[r] = g;
        }
        computeVertexNormals(out, group);
    }
    for (const CageMorphTarget& t : mesh.morphTargets) {
        MorphTarget mt;
        mt.name = t.name;
        mt.positionDeltas.resize(nR);
        for (size_t r = 0; r < nR; ++r)
            mt.positionDeltas[r] = t.positionDeltas[split.renderSourceVertex[r]];
        out.morphTargets.push_back(std::move(mt));
    }
    out.morphWeights = mesh.morphWeights;
    if (!out.morphTargets.empty() && out.morphWeights.empty())
        out.morphWeights.assign(out.morphTargets.size(), 0.0f);
    return out;
}

namespace {

// The attribute arrays of a RenderMesh that have one entry per vertex, as
// (bytes, stride) pairs: what weldVerticesByValue() compares and compacts.
struct VertexArrays {
    std::vector<std::pair<unsigned char*, size_t>> arrays;
    template <class T>
    void add(std::vector<T>& v, size_t vertexCount) {
        if (!v.empty() && v.size() == vertexCount)
            arrays.emplace_back(reinterpret_cast<unsigned char*>(v.data()), sizeof(T));
    }
};

VertexArrays vertexArraysOf(RenderMesh& mesh) {
    const size_t n = mesh.positions.size();
    VertexArrays a;
    a.add(mesh.positions, n);
    a.add(mesh.normals, n);
    for (auto& set : mesh.uvSets) a.add(set, n);
    a.add(mesh.tangents, n);
    for (MorphTarget& t : mesh.morphTargets) {
        a.add(t.positionDeltas, n);
        a.add(t.normalDeltas, n);
        a.add(t.tangentDeltas, n);
    }
    return a;
}

} // namespace

size_t weldVerticesByValue(RenderMesh& mesh, int threads) {
    SG_EXPECTS(threads >= 0 && threads <= kMaxThreads,
               "0 (all cores) or 1..1024 threads (surfgrad/base/threads.h)");
    const size_t n = mesh.positions.size();
    if (n < 2) return 0;
    const VertexArrays va = vertexArraysOf(mesh);
    auto hashOf = [&](size_t v) {
        uint64_t h = 0x9E3779B97F4A7C15ull;
        for (const auto& [bytes, stride] : va.arrays) {
            const unsigned char* p = bytes + v * stride;
            for (size_t i = 0; i + 4 <= stride; i += 4) {
                uint32_t w;
                std::memcpy(&w, p + i, 4);
                h = (h ^ w) * 0x100000001B3ull;
                h ^= h >> 29;
            }
        }
        return h ^ (h >> 32);
    };
    auto same = [&](size_t a, size_t b) {
        for (const auto& [bytes, stride] : va.arrays)
            if (std::memcmp(bytes + a * stride, bytes + b * stride, stride) != 0) return false;
        return true;
    };
    // Every vertex's hash (bit patterns of all its attributes), in parallel
    // above the cut-over: each task writes its own range.
    // Scratch storage (scratch_buffer.h: huge pages, no zero fill).
    sg::detail::ScratchVector<uint64_t> hash(n);
    auto hashRange = [&](size_t b, size_t e) {
        for (size_t v = b; v < e; ++v) hash[v] = hashOf(v);
    };
    if (threads == 1 || n < kWeldParallelMinVertices) {
        hashRange(0, n);
    } else {
        runWithThreads(threads, [&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 16384),
                              [&](const auto& r) { hashRange(r.begin(), r.end()); });
        });
    }
    // Open addressing in vertex order (serial: the numbering is by first
    // occurrence): a vertex takes the id of the first equal vertex met,
    // else the next new id. A slot holds the hash's high half and the
    // vertex, so most probes compare no vertex data.
    size_t tableSize = 64;
    while (tableSize < 2 * n) tableSize *= 2;
    const size_t mask = tableSize - 1;
    sg::detail::ScratchVector<uint64_t> table(tableSize);
    std::fill(table.begin(), table.end(), UINT64_MAX);
    sg::detail::ScratchVector<uint32_t> newId(n);
    std::vector<uint32_t> firstOf; // new id -> first old vertex
    firstOf.reserve(n);
    for (size_t v = 0; v < n; ++v) {
        const uint64_t high = hash[v] & 0xFFFFFFFF00000000ull;
        for (size_t slot = size_t(hash[v]) & mask;; slot = (slot + 1) & mask) {
            const uint64_t entry = table[slot];
            if (entry == UINT64_MAX) {
                table[slot] = high | v;
                newId[v] = uint32_t(firstOf.size());
                firstOf.push_back(uint32_t(v));
                break;
            }
            const uint32_t w = uint32_t(entry);
            if ((entry & 0xFFFFFFFF00000000ull) == high && same(w, v)) {
                newId[v] = newId[w];
                break;
            }
        }
    }
    const size_t kept = firstOf.size();
    if (kept == n) return 0;
    // Compact in place: new id k < old vertex firstOf[k], increasing.
    for (const auto& [bytes, stride] : va.arrays)
        for (size_t k = 0; k < kept; ++k)
            if (firstOf[k] != k)
                std::memmove(bytes + k * stride, bytes + firstOf[k] * stride, stride);
    mesh.positions.resize(kept);
    if (mesh.normals.size() == n) mesh.normals.resize(kept);
    for (auto& set : mesh.uvSets)
        if (set.size() == n) set.resize(kept);
    if (mesh.tangents.size() == n) mesh.tangents.resize(kept);
    for (MorphTarget& t : mesh.morphTargets) {
        for (auto* d : {&t.positionDeltas, &t.normalDeltas, &t.tangentDeltas})
            if (d->size() == n) d->resize(kept);
    }
    for (uint32_t& i : mesh.indices) i = newId[i];
    return n - kept;
}

std::vector<uint32_t> detail::coincidentVertexGroups(const RenderMesh& mesh) {
    const size_t n = mesh.positions.size();
    auto cmp = [](const glm::vec3& p, const glm::vec3& q) {
        if (p.x != q.x) return p.x < q.x ? -1 : 1;
        if (p.y != q.y) return p.y < q.y ? -1 : 1;
        if (p.z != q.z) return p.z < q.z ? -1 : 1;
        return 0;
    };
    // Key: position, then every target's position delta.
    auto keyCmp = [&](uint32_t a, uint32_t b) {
        int c = cmp(mesh.positions[a], mesh.positions[b]);
        for (size_t t = 0; c == 0 && t < mesh.morphTargets.size(); ++t) {
            const auto& d = mesh.morphTargets[t].positionDeltas;
            if (!d.empty()) c = cmp(d[a], d[b]);
        }
        return c;
    };
    std::vector<uint32_t> order(n);
    std::iota(order.begin(), order.end(), 0u);
    // Ties by index: the first of each run is the group's smallest index.
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        int c = keyCmp(a, b);
        return c != 0 ? c < 0 : a < b;
    });
    std::vector<uint32_t> rep(n);
    for (size_t i = 0; i < n; ++i)
        rep[order[i]] =
            (i > 0 && keyCmp(order[i], order[i - 1]) == 0) ? rep[order[i - 1]] : order[i];
    return rep;
}

PolygonMesh toPolygonMesh(const RenderMesh& mesh) {
    const size_t nR = mesh.positions.size();
    // Weld: position and every target's position delta equal (exact).
    const std::vector<uint32_t> rep = detail::coincidentVertexGroups(mesh);
    // Cage vertices numbered by first use in the index buffer.
    std::vector<uint32_t> cageOf(nR, UINT32_MAX);
    PolygonMesh out;
    out.name = mesh.name;
    std::vector<uint32_t> cageSource;
    for (uint32_t r : mesh.indices) {
        uint32_t& c = cageOf[rep[r]];
        if (c == UINT32_MAX) {
            c = uint32_t(cageSource.size());
            cageSource.push_back(rep[r]);
        }
    }
    out.positions.resize(cageSource.size());
    for (size_t c = 0; c < cageSource.size(); ++c) out.positions[c] = mesh.positions[cageSource[c]];
    out.faceSizes.assign(mesh.indices.size() / 3, 3u);
    out.faceVertices.resize(mesh.indices.size());
    for (size_t i = 0; i < mesh.indices.size(); ++i)
        out.faceVertices[i] = cageOf[rep[mesh.indices[i]]];
    // Face-varying channels: one value per distinct (cage vertex, value),
    // so equal UVs on both sides of a normal-only split stay connected.
    auto faceVarying = [&](auto getValue, auto& values, std::vector<uint32_t>& indices) {
        using V = std::decay_t<decltype(getValue(0u))>;
        std::vector<std::vector<std::pair<V, uint32_t>>> perVertex(out.positions.size());
        indices.resize(mesh.indices.size());
        for (size_t i = 0; i < mesh.indices.size(); ++i) {
            V val = getValue(mesh.indices[i]);
            auto& list = perVertex[out.faceVertices[i]];
            uint32_t id = UINT32_MAX;
            for (auto& [v, k] : list) {
                if (std::memcmp(&v, &val, sizeof(V)) == 0) id = k;
            }
            if (id == UINT32_MAX) {
                id = uint32_t(values.size());
                values.push_back(val);
                list.emplace_back(val, id);
            }
            indices[i] = id;
        }
    };
    for (size_t s = 0; s < mesh.uvSets.size(); ++s) {
        FaceVaryingChannel ch;
        ch.name = "TEXCOORD_" + std::to_string(s);
        faceVarying([&](uint32_t r) { return mesh.uvSets[s][r]; }, ch.values, ch.indices);
        out.uvSets.push_back(std::move(ch));
    }
    if (!mesh.normals.empty())
        faceVarying([&](uint32_t r) { return mesh.normals[r]; }, out.normals, out.normalIndices);
    for (const MorphTarget& t : mesh.morphTargets) {
        CageMorphTarget ct;
        ct.name = t.name;
        ct.positionDeltas.assign(out.positions.size(), glm::vec3(0.0f));
        if (!t.positionDeltas.empty()) {
            for (size_t c = 0; c < cageSource.size(); ++c)
                ct.positionDeltas[c] = t.positionDeltas[cageSource[c]];
        }
        out.morphTargets.push_back(std::move(ct));
    }
    out.morphWeights = mesh.morphWeights;
    return out;
}

} // namespace sg::mesh
