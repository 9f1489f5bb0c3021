// MikkTSpace, the fast implementation (Mikkelsen 2008, "Simulation of
// Wrinkled Surfaces Revisited", section 4.2; the published mikktspace.c
// algorithm with its default 180-degree threshold). Same stages as the
// oracle (mikktspace_reference.cpp, read that first) and the same float
// kernels (mikktspace_common.h); what changes is the data layout:
//
//  - welding hashes INPUT VERTICES (not corners): corners that name the same
//    vertex have the same values, so V lookups instead of 3T; welded ids are
//    numbered densely in order of first use and their values copied into
//    compact arrays, so every later stage reads 32 bytes per welded vertex
//    in roughly triangle order;
//  - adjacency uses a vertex -> incident-corner table (counting sort, lists
//    in ascending triangle order) whose entries carry the previous and next
//    welded vertex of the corner: the triangles on an edge {a, b} are found
//    by scanning a's list, in the order the reference's sorted edge list
//    has them, without sorting 3T edges;
//  - group membership is a bit per corner, the flood fill an explicit stack,
//    and a group's projected derivatives and corner angles are computed once
//    per member (the reference recomputes them per pair); when every pair of
//    members passes the threshold test (almost always: the default threshold
//    only separates exactly opposite frames) the group is one subgroup and
//    its frame is accumulated once;
//  - all buffers live in the generator and are reused between calls.
#include <algorithm>
#include <limits>
#include <vector>

#include "mikktspace_common.h"

namespace sg::mesh {

namespace mikk {

size_t validateInput(const MikkTSpaceInput& in) {
    const size_t vertexCount = in.positions.size();
    if (in.normals.size() != vertexCount || in.uvs.size() != vertexCount)
        throw std::invalid_argument("MikkTSpace: positions (" + std::to_string(vertexCount) +
                                    "), normals (" + std::to_string(in.normals.size()) +
                                    ") and uvs (" + std::to_string(in.uvs.size()) +
                                    ") must have the same length");
    for (size_t v = 0; v < vertexCount; ++v) {
        const glm::vec3 p = in.positions[v], n = in.normals[v];
        const glm::vec2 t = in.uvs[v];
        if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
              std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z) &&
              std::isfinite(t.x) && std::isfinite(t.y)))
            throw std::invalid_argument("MikkTSpace: vertex " + std::to_string(v) +
                                        " has a non-finite position, normal or uv");
    }
    const size_t cornerCount = in.cornerVertices.size();
    size_t triangles = 0;
    if (in.faceSizes.empty()) {
        if (cornerCount % 3 != 0)
            throw std::invalid_argument("MikkTSpace: " + std::to_string(cornerCount) +
                                        " corners is not a multiple of 3 (no face sizes given)");
        triangles = cornerCount / 3;
    } else {
        size_t sum = 0;
        for (const uint32_t n : in.faceSizes) {
            sum += n;
            triangles += n == 3 ? 1 : (n == 4 ? 2 : 0);
            if (sum > cornerCount) break;
        }
        if (sum != cornerCount)
            throw std::invalid_argument("MikkTSpace: face sizes do not sum to the " +
                                        std::to_string(cornerCount) + " corners");
    }
    if (triangles >= (size_t(1) << 30))
        throw std::invalid_argument("MikkTSpace: too many triangles (" +
                                    std::to_string(triangles) + ", limit 2^30)");
    for (size_t c = 0; c < cornerCount; ++c)
        if (in.cornerVertices[c] >= vertexCount)
            throw std::invalid_argument("MikkTSpace: corner " + std::to_string(c) +
                                        " names vertex " + std::to_string(in.cornerVertices[c]) +
                                        " of " + std::to_string(vertexCount));
    return triangles;
}

} // namespace mikk

namespace {

using mikk::Vec3;

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
constexpr int32_t kNoNeighbor = -1;
constexpr int32_t kUnresolved = -2;

// Triangle flags.
constexpr uint8_t kOrient = 1;        // orientation preserving
constexpr uint8_t kAny = 2;           // group-with-any (zero UV area or magnitude)
constexpr uint8_t kQuadOneDegen = 4;  // quad whose other triangle is degenerate
constexpr uint8_t kGrouped0 = 8;      // corner 0 is in a group (then 16, 32)
constexpr uint8_t kGroupedAll = 8 | 16 | 32;

// An entry of the vertex -> incident corners table.
struct Incidence {
    uint32_t tri;  // good triangle index
    uint32_t prev; // welded id of the previous corner of that triangle
    uint32_t next; // welded id of the next corner
};

struct GroupRec {
    uint32_t vertex;
    uint32_t begin, count; // into groupMembers
    bool orient;
};

struct WeldedVertex {
    Vec3 position;
    Vec3 normal;
    glm::vec2 uv;
};

inline uint64_t mix(uint64_t h, uint32_t v) {
    h ^= v;
    h *= 0x9E3779B97F4A7C15ull;
    return h ^ (h >> 29);
}

} // namespace

struct MikkTSpaceGenerator::Scratch {
    // Triangulation (only filled when faceSizes is given).
    std::vector<uint32_t> triVertex;  // input vertex per triangle corner
    std::vector<uint32_t> triCorner;  // output corner per triangle corner
    std::vector<uint32_t> triFace;    // original face per triangle
    std::vector<uint8_t> triVertInFace;
    // Welding.
    std::vector<uint32_t> vertexClass; // input vertex -> welded id
    std::vector<uint32_t> hashTable;   // welded ids, kNone = empty
    std::vector<WeldedVertex> welded;
    std::vector<uint32_t> triWelded; // welded id per triangle corner (all triangles)
    // Degenerate handling and the good-first order.
    std::vector<uint8_t> degenerate;
    std::vector<uint8_t> quadOneDegen; // only with quads and degenerates
    std::vector<uint32_t> order; // good triangles then degenerate ones (only if any degenerate)
    std::vector<uint32_t> goodWelded, goodCorner, goodFace;
    std::vector<uint8_t> goodVertInFace;
    // Per good triangle.
    std::vector<Vec3> vOs, vOt;
    std::vector<float> magS, magT;
    std::vector<uint8_t> flags;
    std::vector<int32_t> neighbor;
    // Vertex -> incident corners.
    std::vector<uint32_t> incidenceStart;
    std::vector<Incidence> incidence;
    std::vector<uint32_t> edgeGroup; // scratch for non-manifold edges
    // Groups.
    std::vector<GroupRec> groups;
    std::vector<uint32_t> groupMembers;
    std::vector<uint32_t> stack;
    // Per group member (reused).
    std::vector<Vec3> memberOs, memberOt;
    std::vector<float> memberAngle;
    std::vector<uint32_t> subgroup;
    // Output stage.
    std::vector<mikk::CornerSpace> spaces; // quads or full frames requested
    std::vector<uint32_t> firstGoodCorner;
};

MikkTSpaceGenerator::MikkTSpaceGenerator() : scratch_(new Scratch) {}
MikkTSpaceGenerator::~MikkTSpaceGenerator() { delete scratch_; }

void MikkTSpaceGenerator::generate(const MikkTSpaceInput& in, std::vector<glm::vec4>& cornerTangents,
                                   std::vector<MikkTSpaceFrame>* frames) {
    const size_t triCount = mikk::validateInput(in);
    Scratch& s = *scratch_;
    const size_t cornerCount = in.cornerVertices.size();
    const bool trianglesOnly = in.faceSizes.empty() ||
                               std::all_of(in.faceSizes.begin(), in.faceSizes.end(),
                                           [](uint32_t n) { return n == 3; });
    const bool hasQuads = !trianglesOnly;
    // Corners of faces that are neither triangles nor quads stay zero.
    cornerTangents.assign(cornerCount, glm::vec4(0.0f));
    if (frames) frames->assign(cornerCount, MikkTSpaceFrame{{0, 0, 0}, 0, {0, 0, 0}, 0, 0});
    if (triCount == 0) return;

    // --- Step 1: triangle list. Without quads a triangle's corners are the
    // input corners 3t..3t+2 and nothing is copied.
    const uint32_t* triVertex = in.cornerVertices.data();
    if (!trianglesOnly) {
        s.triVertex.resize(triCount * 3);
        s.triCorner.resize(triCount * 3);
        s.triFace.resize(triCount);
        s.triVertInFace.resize(triCount * 3);
        size_t t = 0, first = 0;
        for (size_t f = 0; f < in.faceSizes.size(); first += in.faceSizes[f], ++f) {
            const uint32_t n = in.faceSizes[f];
            if (n != 3 && n != 4) continue;
            const uint32_t* fv = in.cornerVertices.data() + first;
            auto emit = [&](int a, int b, int c) {
                const int k[3] = {a, b, c};
                for (int i = 0; i < 3; ++i) {
                    s.triVertex[t * 3 + size_t(i)] = fv[k[i]];
                    s.triCorner[t * 3 + size_t(i)] = uint32_t(first) + uint32_t(k[i]);
                    s.triVertInFace[t * 3 + size_t(i)] = uint8_t(k[i]);
                }
                s.triFace[t] = uint32_t(f);
                ++t;
            };
            if (n == 3) {
                emit(0, 1, 2);
                continue;
            }
            // Shorter UV diagonal; on a tie the shorter position diagonal.
            auto uvDist2 = [&](int a, int b) {
                const glm::vec2 ta = in.uvs[fv[a]], tb = in.uvs[fv[b]];
                const float dx = tb.x - ta.x, dy = tb.y - ta.y;
                return dx * dx + dy * dy;
            };
            const float uv02 = uvDist2(0, 2), uv13 = uvDist2(1, 3);
            bool diagonal02;
            if (uv02 < uv13) {
                diagonal02 = true;
            } else if (uv13 < uv02) {
                diagonal02 = false;
            } else {
                auto posDist2 = [&](int a, int b) {
                    return mikk::lengthSquared(
                        mikk::sub(mikk::toVec3(in.positions[fv[b]]), mikk::toVec3(in.positions[fv[a]])));
                };
                diagonal02 = !(posDist2(1, 3) < posDist2(0, 2));
            }
            if (diagonal02) {
                emit(0, 1, 2);
                emit(0, 2, 3);
            } else {
                emit(0, 1, 3);
                emit(1, 2, 3);
            }
        }
        triVertex = s.triVertex.data();
    }
    auto outCornerOf = [&](const uint32_t* corners, size_t triCorner) -> uint32_t {
        return hasQuads ? corners[triCorner] : uint32_t(triCorner);
    };

    // --- Step 2: weld by exact (position, normal, uv), through the input
    // vertices. Welded ids in order of first use; their values are those of
    // the first corner using them (as the oracle's representative).
    {
        const size_t vertexCount = in.positions.size();
        s.vertexClass.assign(vertexCount, kNone);
        size_t tableSize = 64;
        while (tableSize < 2 * std::min(vertexCount, triCount * 3)) tableSize *= 2;
        s.hashTable.assign(tableSize, kNone);
        s.welded.clear();
        s.triWelded.resize(triCount * 3);
        const size_t mask = tableSize - 1;
        for (size_t c = 0; c < triCount * 3; ++c) {
            const uint32_t v = triVertex[c];
            uint32_t id = s.vertexClass[v];
            if (id == kNone) {
                const glm::vec3 p = in.positions[v], n = in.normals[v];
                const glm::vec2 uv = in.uvs[v];
                uint64_t h = 0x243F6A8885A308D3ull;
                h = mix(h, mikk::weldBits(p.x));
                h = mix(h, mikk::weldBits(p.y));
                h = mix(h, mikk::weldBits(p.z));
                h = mix(h, mikk::weldBits(n.x));
                h = mix(h, mikk::weldBits(n.y));
                h = mix(h, mikk::weldBits(n.z));
                h = mix(h, mikk::weldBits(uv.x));
                h = mix(h, mikk::weldBits(uv.y));
                for (size_t slot = size_t(h) & mask;; slot = (slot + 1) & mask) {
                    const uint32_t cand = s.hashTable[slot];
                    if (cand == kNone) {
                        id = uint32_t(s.welded.size());
                        s.welded.push_back({mikk::toVec3(p), mikk::toVec3(n), uv});
                        s.hashTable[slot] = id;
                        break;
                    }
                    const WeldedVertex& w = s.welded[cand];
                    if (w.position.x == p.x && w.position.y == p.y && w.position.z == p.z &&
                        w.normal.x == n.x && w.normal.y == n.y && w.normal.z == n.z &&
                        w.uv.x == uv.x && w.uv.y == uv.y) {
                        id = cand;
                        break;
                    }
                }
                s.vertexClass[v] = id;
            }
            s.triWelded[c] = id;
        }
    }
    const WeldedVertex* wv = s.welded.data();

    // --- Steps 3-4: degenerate triangles (two corners at one position) go
    // last; quads with one degenerate half are marked.
    s.degenerate.assign(triCount, 0);
    size_t degenerateCount = 0;
    for (size_t t = 0; t < triCount; ++t) {
        const Vec3& p0 = wv[s.triWelded[t * 3]].position;
        const Vec3& p1 = wv[s.triWelded[t * 3 + 1]].position;
        const Vec3& p2 = wv[s.triWelded[t * 3 + 2]].position;
        const bool d = mikk::exactlyEqual(p0, p1) || mikk::exactlyEqual(p0, p2) ||
                       mikk::exactlyEqual(p1, p2);
        s.degenerate[t] = d;
        degenerateCount += d;
    }
    const size_t goodCount = triCount - degenerateCount;
    s.flags.assign(triCount, 0); // indexed in the good-first order below
    const uint32_t* gWelded = s.triWelded.data();
    const uint32_t* gCorner = hasQuads ? s.triCorner.data() : nullptr;
    const uint32_t* gFace = hasQuads ? s.triFace.data() : nullptr;
    const uint8_t* gVertInFace = hasQuads ? s.triVertInFace.data() : nullptr;
    std::vector<uint8_t>& quadOneDegen = s.quadOneDegen;
    if (degenerateCount > 0) {
        if (hasQuads) {
            quadOneDegen.assign(triCount, 0);
            for (size_t t = 0; t + 1 < triCount;) {
                if (s.triFace[t] == s.triFace[t + 1]) {
                    if (s.degenerate[t] != s.degenerate[t + 1]) quadOneDegen[t] = quadOneDegen[t + 1] = 1;
                    t += 2;
                } else {
                    ++t;
                }
            }
        }
        s.order.clear();
        for (size_t t = 0; t < triCount; ++t)
            if (!s.degenerate[t]) s.order.push_back(uint32_t(t));
        for (size_t t = 0; t < triCount; ++t)
            if (s.degenerate[t]) s.order.push_back(uint32_t(t));
        s.goodWelded.resize(triCount * 3);
        s.goodCorner.resize(triCount * 3);
        if (hasQuads) {
            s.goodFace.resize(triCount);
            s.goodVertInFace.resize(triCount * 3);
        }
        for (size_t t = 0; t < triCount; ++t) {
            const size_t src = s.order[t];
            for (size_t i = 0; i < 3; ++i) {
                s.goodWelded[t * 3 + i] = s.triWelded[src * 3 + i];
                s.goodCorner[t * 3 + i] = outCornerOf(s.triCorner.data(), src * 3 + i);
                if (hasQuads) s.goodVertInFace[t * 3 + i] = s.triVertInFace[src * 3 + i];
            }
            if (hasQuads) {
                s.goodFace[t] = s.triFace[src];
                if (quadOneDegen[src]) s.flags[t] |= kQuadOneDegen;
            }
        }
        gWelded = s.goodWelded.data();
        gCorner = s.goodCorner.data();
        gFace = hasQuads ? s.goodFace.data() : nullptr;
        gVertInFace = hasQuads ? s.goodVertInFace.data() : nullptr;
    }
    // Output corner of good-order triangle corner j, and its face.
    auto cornerOut = [&](size_t j) -> uint32_t { return gCorner ? gCorner[j] : uint32_t(j); };
    auto faceOf = [&](size_t t) -> uint32_t { return gFace ? gFace[t] : uint32_t(t); };

    // --- Step 5: per-triangle derivatives and orientation (eq. 18/19).
    s.vOs.resize(goodCount);
    s.vOt.resize(goodCount);
    s.magS.resize(goodCount);
    s.magT.resize(goodCount);
    for (size_t t = 0; t < goodCount; ++t) {
        const WeldedVertex& a = wv[gWelded[t * 3]];
        const WeldedVertex& b = wv[gWelded[t * 3 + 1]];
        const WeldedVertex& c = wv[gWelded[t * 3 + 2]];
        const mikk::FaceDerivatives d =
            mikk::faceDerivatives(a.position, b.position, c.position, a.uv, b.uv, c.uv);
        s.vOs[t] = d.vOs;
        s.vOt[t] = d.vOt;
        s.magS[t] = d.magS;
        s.magT[t] = d.magT;
        s.flags[t] |= uint8_t((d.orientPreserving ? kOrient : 0) | (d.groupWithAny ? kAny : 0));
    }
    if (hasQuads) { // one orientation per quad
        for (size_t t = 0; t + 1 < goodCount;) {
            if (faceOf(t) != faceOf(t + 1)) {
                ++t;
                continue;
            }
            uint8_t& fa = s.flags[t];
            uint8_t& fb = s.flags[t + 1];
            if ((fa & kOrient) != (fb & kOrient)) {
                const uint32_t* wa = gWelded + t * 3;
                const uint32_t* wb = gWelded + (t + 1) * 3;
                const bool keepFirst =
                    (fb & kAny) != 0 ||
                    mikk::uvAreaTimes2(wv[wa[0]].uv, wv[wa[1]].uv, wv[wa[2]].uv) >=
                        mikk::uvAreaTimes2(wv[wb[0]].uv, wv[wb[1]].uv, wv[wb[2]].uv);
                if (keepFirst) fb = uint8_t((fb & ~kOrient) | (fa & kOrient));
                else fa = uint8_t((fa & ~kOrient) | (fb & kOrient));
            }
            t += 2;
        }
    }

    // --- Step 6: adjacency through the vertex -> incident corners table.
    const size_t weldedCount = s.welded.size();
    s.incidenceStart.assign(weldedCount + 1, 0);
    for (size_t j = 0; j < goodCount * 3; ++j) ++s.incidenceStart[gWelded[j] + 1];
    for (size_t w = 0; w < weldedCount; ++w) s.incidenceStart[w + 1] += s.incidenceStart[w];
    s.incidence.resize(goodCount * 3);
    {
        // Fill in ascending triangle order (so each list is sorted), using
        // the next list's start as a moving cursor and restoring it after.
        uint32_t* cursor = s.incidenceStart.data();
        for (size_t t = 0; t < goodCount; ++t) {
            const uint32_t* w = gWelded + t * 3;
            s.incidence[cursor[w[0]]++] = {uint32_t(t), w[2], w[1]};
            s.incidence[cursor[w[1]]++] = {uint32_t(t), w[0], w[2]};
            s.incidence[cursor[w[2]]++] = {uint32_t(t), w[1], w[0]};
        }
        for (size_t w = weldedCount; w > 0; --w) s.incidenceStart[w] = s.incidenceStart[w - 1];
        s.incidenceStart[0] = 0;
    }
    s.neighbor.assign(goodCount * 3, kUnresolved);
    for (size_t t = 0; t < goodCount; ++t) {
        for (uint32_t e = 0; e < 3; ++e) {
            if (s.neighbor[t * 3 + e] != kUnresolved) continue;
            const uint32_t a = gWelded[t * 3 + e];
            const uint32_t b = gWelded[t * 3 + (e + 1) % 3];
            // Triangles on edge {a, b}, ascending: entries of a's list whose
            // previous or next corner is b. Edge number: a->b is the edge
            // starting at a's corner; b->a ends at a's corner.
            const Incidence* list = s.incidence.data() + s.incidenceStart[a];
            const size_t listSize = s.incidenceStart[a + 1] - s.incidenceStart[a];
            s.edgeGroup.clear();
            for (size_t k = 0; k < listSize; ++k)
                if (list[k].next == b || list[k].prev == b) s.edgeGroup.push_back(uint32_t(k));
            // Edge slot of entry k (triangle, edge index) and whether it runs a->b.
            auto slot = [&](uint32_t k, bool& forward) -> size_t {
                const Incidence& inc = list[k];
                const uint32_t* w = gWelded + size_t(inc.tri) * 3;
                const uint32_t ca = w[0] == a ? 0 : (w[1] == a ? 1 : 2);
                forward = inc.next == b;
                return size_t(inc.tri) * 3 + (forward ? ca : (ca + 2) % 3);
            };
            if (s.edgeGroup.size() == 2) { // manifold edge (or two same-direction faces)
                bool fx, fy;
                const size_t sx = slot(s.edgeGroup[0], fx), sy = slot(s.edgeGroup[1], fy);
                if (fx != fy) {
                    s.neighbor[sx] = int32_t(list[s.edgeGroup[1]].tri);
                    s.neighbor[sy] = int32_t(list[s.edgeGroup[0]].tri);
                } else {
                    s.neighbor[sx] = s.neighbor[sy] = kNoNeighbor;
                }
                continue;
            }
            // Boundary edge, or several triangles on one edge: the
            // reference's greedy pairing in ascending triangle order.
            for (size_t x = 0; x < s.edgeGroup.size(); ++x) {
                bool fx;
                const size_t sx = slot(s.edgeGroup[x], fx);
                if (s.neighbor[sx] != kUnresolved) continue;
                s.neighbor[sx] = kNoNeighbor;
                for (size_t y = x + 1; y < s.edgeGroup.size(); ++y) {
                    bool fy;
                    const size_t sy = slot(s.edgeGroup[y], fy);
                    if (fy != fx && s.neighbor[sy] == kUnresolved) {
                        s.neighbor[sx] = int32_t(list[s.edgeGroup[y]].tri);
                        s.neighbor[sy] = int32_t(list[s.edgeGroup[x]].tri);
                        break;
                    }
                }
            }
        }
    }

    // --- Step 7: groups, seeded in triangle order, flooded depth first.
    s.groups.clear();
    s.groupMembers.clear();
    s.groupMembers.reserve(goodCount * 3);
    for (size_t f = 0; f < goodCount; ++f) {
        for (uint32_t i = 0; i < 3; ++i) {
            if ((s.flags[f] & kAny) || (s.flags[f] & (kGrouped0 << i))) continue;
            GroupRec g{gWelded[f * 3 + i], uint32_t(s.groupMembers.size()), 1,
                       (s.flags[f] & kOrient) != 0};
            s.flags[f] |= uint8_t(kGrouped0 << i);
            s.groupMembers.push_back(uint32_t(f));
            s.stack.clear();
            auto pushNeighbors = [&](size_t t, uint32_t c) {
                const int32_t right = s.neighbor[t * 3 + (c + 2) % 3];
                const int32_t left = s.neighbor[t * 3 + c];
                if (right >= 0) s.stack.push_back(uint32_t(right));
                if (left >= 0) s.stack.push_back(uint32_t(left));
            };
            pushNeighbors(f, i);
            while (!s.stack.empty()) {
                const uint32_t t = s.stack.back();
                s.stack.pop_back();
                const uint32_t* w = gWelded + size_t(t) * 3;
                const uint32_t c = w[0] == g.vertex ? 0 : (w[1] == g.vertex ? 1 : 2);
                uint8_t& fl = s.flags[t];
                if (fl & (kGrouped0 << c)) continue;
                if ((fl & kAny) && (fl & kGroupedAll) == 0)
                    fl = uint8_t((fl & ~kOrient) | (g.orient ? kOrient : 0));
                if (((fl & kOrient) != 0) != g.orient) continue;
                fl |= uint8_t(kGrouped0 << c);
                s.groupMembers.push_back(t);
                ++g.count;
                pushNeighbors(t, c);
            }
            s.groups.push_back(g);
        }
    }

    // --- Step 8: one frame per subgroup, written to the members' corners.
    // Corners are written straight into the outputs unless quads (two
    // writes to average) or full frames need the complete corner state.
    const bool fullSpaces = hasQuads || frames != nullptr;
    if (fullSpaces) s.spaces.assign(cornerCount, mikk::CornerSpace{});
    glm::vec4* tangentsOut = cornerTangents.data();
    auto writeCorner = [&](uint32_t corner, const mikk::FrameAccumulator& fr, bool orient) {
        if (fullSpaces) mikk::writeCornerSpace(s.spaces[corner], fr, orient);
        else tangentsOut[corner] = glm::vec4(fr.vOs.x, fr.vOs.y, fr.vOs.z, orient ? 1.0f : -1.0f);
    };
    // Corners of triangles no group reached keep the reference's default.
    if (!fullSpaces)
        for (size_t j = 0; j < goodCount * 3; ++j) tangentsOut[cornerOut(j)] = glm::vec4(1, 0, 0, -1);
    const float thresholdCos = mikk::defaultThresholdCos();
    for (const GroupRec& g : s.groups) {
        uint32_t* members = s.groupMembers.data() + g.begin;
        const size_t k = g.count;
        if (k <= 16) { // insertion sort: groups are a handful of triangles
            for (size_t x = 1; x < k; ++x) {
                const uint32_t v = members[x];
                size_t y = x;
                for (; y > 0 && members[y - 1] > v; --y) members[y] = members[y - 1];
                members[y] = v;
            }
        } else {
            std::sort(members, members + k);
        }
        const Vec3 n = wv[g.vertex].normal;
        s.memberOs.resize(k);
        s.memberOt.resize(k);
        s.memberAngle.resize(k);
        for (size_t x = 0; x < k; ++x) {
            const uint32_t t = members[x];
            s.memberOs[x] = mikk::projectToPlane(s.vOs[t], n);
            s.memberOt[x] = mikk::projectToPlane(s.vOt[t], n);
            if (s.flags[t] & kAny) continue; // contributes no angle
            const uint32_t* w = gWelded + size_t(t) * 3;
            const uint32_t c = w[0] == g.vertex ? 0 : (w[1] == g.vertex ? 1 : 2);
            s.memberAngle[x] = mikk::cornerAngle(wv[w[(c + 2) % 3]].position, wv[w[c]].position,
                                                 wv[w[(c + 1) % 3]].position, n);
        }
        auto together = [&](size_t x, size_t y) {
            const uint32_t tx = members[x], ty = members[y];
            return ((s.flags[tx] | s.flags[ty]) & kAny) != 0 || faceOf(tx) == faceOf(ty) ||
                   (mikk::dot(s.memberOs[x], s.memberOs[y]) > thresholdCos &&
                    mikk::dot(s.memberOt[x], s.memberOt[y]) > thresholdCos);
        };
        bool oneSubgroup = true;
        for (size_t x = 0; x < k && oneSubgroup; ++x)
            for (size_t y = x + 1; y < k; ++y)
                if (!together(x, y)) {
                    oneSubgroup = false;
                    break;
                }
        auto cornerOfMember = [&](uint32_t t) {
            const uint32_t* w = gWelded + size_t(t) * 3;
            const uint32_t c = w[0] == g.vertex ? 0 : (w[1] == g.vertex ? 1 : 2);
            return cornerOut(size_t(t) * 3 + c);
        };
        if (oneSubgroup) {
            mikk::FrameAccumulator fr;
            for (size_t x = 0; x < k; ++x) {
                const uint32_t t = members[x];
                if (s.flags[t] & kAny) continue;
                fr.accumulate(s.memberAngle[x], s.memberOs[x], s.memberOt[x], s.magS[t], s.magT[t]);
            }
            fr.finish();
            for (size_t x = 0; x < k; ++x) writeCorner(cornerOfMember(members[x]), fr, g.orient);
            continue;
        }
        // Rare: the group splits. Member x's subgroup is every y together
        // with it, in ascending order (members are sorted).
        for (size_t x = 0; x < k; ++x) {
            mikk::FrameAccumulator fr;
            for (size_t y = 0; y < k; ++y) {
                const uint32_t t = members[y];
                if (!together(x, y) || (s.flags[t] & kAny)) continue;
                fr.accumulate(s.memberAngle[y], s.memberOs[y], s.memberOt[y], s.magS[t], s.magT[t]);
            }
            fr.finish();
            writeCorner(cornerOfMember(members[x]), fr, g.orient);
        }
    }

    // --- Step 9: degenerate triangles copy frames from good corners.
    auto copyCorner = [&](uint32_t dst, uint32_t src) {
        if (fullSpaces) s.spaces[dst] = s.spaces[src];
        else tangentsOut[dst] = tangentsOut[src];
    };
    if (degenerateCount > 0) {
        s.firstGoodCorner.assign(weldedCount, kNone);
        for (size_t j = goodCount * 3; j-- > 0;) s.firstGoodCorner[gWelded[j]] = uint32_t(j);
        for (size_t t = goodCount; t < triCount; ++t) {
            if (s.flags[t] & kQuadOneDegen) continue;
            for (size_t i = 0; i < 3; ++i) {
                const uint32_t j = s.firstGoodCorner[gWelded[t * 3 + i]];
                if (j != kNone) copyCorner(cornerOut(t * 3 + i), cornerOut(j));
                else if (!fullSpaces) tangentsOut[cornerOut(t * 3 + i)] = glm::vec4(1, 0, 0, -1);
            }
        }
        if (hasQuads) {
            for (size_t t = 0; t < goodCount; ++t) {
                if (!(s.flags[t] & kQuadOneDegen)) continue;
                const uint8_t* vf = gVertInFace + t * 3;
                const int present = (1 << vf[0]) | (1 << vf[1]) | (1 << vf[2]);
                const int missing = (present & 2) == 0 ? 1 : ((present & 4) == 0 ? 2 : ((present & 8) == 0 ? 3 : 0));
                // Face corner k of this triangle's face: output corner
                // (first corner of the face) + k.
                const uint32_t faceFirst = cornerOut(t * 3) - vf[0];
                const Vec3 missingPos =
                    mikk::toVec3(in.positions[in.cornerVertices[faceFirst + uint32_t(missing)]]);
                for (size_t i = 0; i < 3; ++i) {
                    const Vec3 p = mikk::toVec3(in.positions[in.cornerVertices[faceFirst + vf[i]]]);
                    if (mikk::exactlyEqual(p, missingPos)) {
                        copyCorner(faceFirst + uint32_t(missing), faceFirst + vf[i]);
                        break;
                    }
                }
            }
        }
    }

    // --- Step 10: outputs.
    if (fullSpaces) {
        // Only corners of triangles and quads; others stay zero.
        auto emitCorner = [&](size_t c) {
            const MikkTSpaceFrame fr = mikk::toFrame(s.spaces[c]);
            tangentsOut[c] = glm::vec4(fr.tangent, fr.sign);
            if (frames) (*frames)[c] = fr;
        };
        if (in.faceSizes.empty()) {
            for (size_t c = 0; c < cornerCount; ++c) emitCorner(c);
        } else {
            size_t first = 0;
            for (const uint32_t n : in.faceSizes) {
                if (n == 3 || n == 4)
                    for (size_t k = 0; k < n; ++k) emitCorner(first + k);
                first += n;
            }
        }
    }
}

} // namespace sg::mesh
