// What a Subdivider::build will cost before it allocates anything
// (surfgrad/mesh/subdivision.h: estimateSubdivisionCost, defaultSubdivisionBudget).
//
// Counts: every scheme's refinement grows each level by fixed rules
// (Catmull & Clark 1978; Loop 1987; OpenSubdiv's Vtr refines faces, edges
// and vertices exactly so; the uniform refiner of uniform_refiner.h
// follows the same numbering):
//   Catmull-Clark, bilinear: an n-gon becomes n quads; every edge 2 edges
//     plus one edge per face corner; every vertex, edge and face one vertex:
//       F' = C, E' = 2E + C, V' = V + E + F, C' = 4F' (C: face corners)
//   Loop: a triangle becomes 4, E' = 2E + 3F, V' = V + E, C' = 3F'.
// Face-varying values (per UV set): a vertex keeps one value per UV
// region around it, an edge point gets 2 values on a seam edge and 1
// elsewhere, a face point 1 (not in Loop), and seam edges split in two:
//   FV' = FV + E + S + F (Loop: no F), S' = 2S.
// Level 0's FV is the number of distinct (vertex, value) pairs.
//
// Bytes: the arrays each stage keeps per refined element (topology of
// every level, the level-N primvars, the render mesh, the limit patches
// and stencils, the animation stencils), as coefficients per element
// measured with a counting allocator on spot, blub and the OpenSubdiv
// shapes (tests/mesh/subdivision_budget_test.cpp checks the estimate
// against the measured peak at levels 1-4 for every scheme and stage).
// The limit stage also refines adaptively around every irregular feature
// down to the isolation level (5..10), at a cost per feature and level.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "mesh_internal.h"
#include "surfgrad/mesh/subdivision.h"

namespace sg::mesh {

namespace {

// Element counts of one level.
struct LevelCounts {
    double vertices = 0, edges = 0, faces = 0, corners = 0;
    double seams = 0;      // edges with a UV seam, summed over UV sets
    double fvarValues = 0; // face-varying values, summed over UV sets
};

// The cage's counts, seams and irregular features (for the limit stage:
// extraordinary vertices, non-quad faces under Catmull-Clark, tagged
// vertices).
struct CageCounts {
    LevelCounts level0;
    double irregular = 0;
    double maxFiniteSharpness = 0;
};

CageCounts countCage(const PolygonMesh& cage, Scheme scheme) {
    CageCounts out;
    LevelCounts& l = out.level0;
    const std::vector<uint32_t> offsets = faceOffsets(cage);
    l.vertices = double(cage.positions.size());
    l.faces = double(cage.faceSizes.size());
    l.corners = double(cage.faceVertices.size());
    const std::vector<detail::FaceEdge> edges = detail::sortedFaceEdges(cage, offsets);
    std::vector<uint32_t> faceCount(cage.positions.size(), 0);
    std::vector<uint8_t> boundary(cage.positions.size(), 0);
    for (uint32_t v : cage.faceVertices) ++faceCount[v];
    for (size_t i = 0; i < edges.size();) {
        size_t j = i + 1;
        while (j < edges.size() && edges[j].key == edges[i].key) ++j;
        l.edges += 1;
        const detail::FaceEdge& a = edges[i];
        if (j - i == 1) {
            boundary[cage.faceVertices[a.corner]] = boundary[cage.faceVertices[a.next]] = 1;
        } else {
            const detail::FaceEdge& b = edges[i + 1];
            for (const FaceVaryingChannel& ch : cage.uvSets) {
                // a goes va -> vb, b (consistently oriented) vb -> va.
                const bool opposite = a.forward != b.forward;
                const uint32_t bAtVa = opposite ? b.next : b.corner;
                const uint32_t bAtVb = opposite ? b.corner : b.next;
                l.seams += ch.indices[a.corner] != ch.indices[bAtVa] ||
                           ch.indices[a.next] != ch.indices[bAtVb];
            }
        }
        i = j;
    }
    // Distinct (vertex, value) pairs per set: the values level 1's vertex
    // points inherit.
    for (const FaceVaryingChannel& ch : cage.uvSets) {
        std::vector<uint64_t> pairs(cage.faceVertices.size());
        for (size_t c = 0; c < pairs.size(); ++c)
            pairs[c] = uint64_t(cage.faceVertices[c]) << 32 | ch.indices[c];
        std::sort(pairs.begin(), pairs.end());
        l.fvarValues += double(std::unique(pairs.begin(), pairs.end()) - pairs.begin());
    }
    // Irregular features the limit stage isolates.
    const uint32_t regularInterior = scheme == Scheme::Loop ? 6 : 4;
    const uint32_t regularBoundary = scheme == Scheme::Loop ? 3 : 2;
    if (scheme != Scheme::Bilinear) {
        std::vector<uint8_t> tagged(cage.positions.size(), 0);
        for (const EdgeCrease& e : cage.creases) tagged[e.v0] = tagged[e.v1] = 1;
        for (const VertexCorner& k : cage.corners) tagged[k.vertex] = 1;
        for (size_t v = 0; v < cage.positions.size(); ++v) {
            if (faceCount[v] == 0) continue;
            out.irregular +=
                tagged[v] || faceCount[v] != (boundary[v] ? regularBoundary : regularInterior);
        }
        if (scheme == Scheme::Catmark) {
            for (uint32_t k : cage.faceSizes) out.irregular += k != 4;
        }
    }
    for (const EdgeCrease& e : cage.creases) {
        if (e.sharpness < kInfiniteSharpness)
            out.maxFiniteSharpness = std::max(out.maxFiniteSharpness, double(e.sharpness));
    }
    for (const VertexCorner& k : cage.corners) {
        if (k.sharpness < kInfiniteSharpness)
            out.maxFiniteSharpness = std::max(out.maxFiniteSharpness, double(k.sharpness));
    }
    return out;
}

LevelCounts refineCounts(const LevelCounts& l, Scheme scheme, double sets) {
    LevelCounts n;
    if (scheme == Scheme::Loop) {
        n.faces = 4 * l.faces;
        n.edges = 2 * l.edges + 3 * l.faces;
        n.vertices = l.vertices + l.edges;
        n.corners = 3 * n.faces;
        n.fvarValues = l.fvarValues + sets * l.edges + l.seams;
    } else {
        n.faces = l.corners;
        n.edges = 2 * l.edges + l.corners;
        n.vertices = l.vertices + l.edges + l.faces;
        n.corners = 4 * n.faces;
        n.fvarValues = l.fvarValues + sets * (l.edges + l.faces) + l.seams;
    }
    n.seams = 2 * l.seams;
    return n;
}

// Peak live heap bytes of build(): bytes per element of each stage,
// fitted (non-negative least squares on the relative error) to the peaks
// the counting allocator of tests/mesh/subdivision_budget_test.cpp measured
// on 9 cages x 4 stages x levels 1-4, then raised 5 % and rounded up so
// that no measured peak is above its estimate. Measured then: estimate /
// peak between 1.05 and 1.95.
double estimateBytes(const SubdivisionCost& c, const SubdivisionSettings& s, bool holes) {
    // Which refiner keeps the levels: the specialised one (lean arrays per
    // level) or OpenSubdiv's Vtr (every relation of every level). A cage the
    // specialised refiner declines for a reason not known here
    // (non-manifold) takes Far at about twice the topology bytes, which
    // the factor 2.5 of the test's bound covers.
    const bool fast = s.specializedRefiner && !s.limit && !holes && c.level >= 1 &&
                      s.options.scheme == Scheme::Catmark;
    double bytes = 9000; // per build, whatever the size
    // Topology of levels 0..N (per face corner) and the UV values of every
    // level (per value).
    bytes += fast ? 30 * c.sumC + 56 * c.sumFV : 55 * c.sumC + 132 * c.sumFV;
    // The render mesh: vertices split at seams (positions, normals, UVs,
    // maps back to refined()), triangles, the split's per-corner tables.
    if (s.buildRenderMesh || s.limit)
        bytes += 146 * double(c.renderVertices) + 33 * double(c.corners);
    if (s.limit) {
        // Patch lookup per level-N corner, per-sample patch weights and the
        // limit frame; the adaptive refinement around every irregular
        // feature, one ring per isolation level.
        bytes += 162 * double(c.corners) + 27700 * double(c.irregular) * c.isolation + 20300;
    }
    if (s.animate && !s.limit) {
        // Factored stencils of every level, and update()'s buffers.
        bytes += 81 * c.sumV + 71 * double(c.renderVertices);
    }
    return bytes;
}

} // namespace

SubdivisionCost estimateSubdivisionCost(const PolygonMesh& cage,
                                        const SubdivisionSettings& settings) {
    const Scheme scheme = settings.options.scheme;
    const int N = std::clamp(settings.level, 0, kMaxSubdivisionLevel);
    const CageCounts cc = countCage(cage, scheme);
    const double sets = double(cage.uvSets.size());
    // Sums over the levels every refiner keeps, and level N.
    LevelCounts l = cc.level0, sum = l;
    for (int k = 1; k <= N; ++k) {
        l = refineCounts(l, scheme, sets);
        sum.vertices += l.vertices;
        sum.edges += l.edges;
        sum.faces += l.faces;
        sum.corners += l.corners;
        sum.fvarValues += l.fvarValues;
    }
    SubdivisionCost cost;
    cost.level = N;
    cost.faces = uint64_t(l.faces);
    cost.vertices = uint64_t(l.vertices);
    cost.edges = uint64_t(l.edges);
    cost.corners = uint64_t(l.corners);
    // Level 0 keeps the cage's own values (the growth starts from the
    // distinct (vertex, value) pairs).
    double cageValues = 0;
    for (const FaceVaryingChannel& ch : cage.uvSets) cageValues += double(ch.values.size());
    cost.fvarValues = uint64_t(N == 0 ? cageValues : l.fvarValues);
    cost.irregular = uint64_t(cc.irregular);
    cost.sumV = sum.vertices;
    cost.sumE = sum.edges;
    cost.sumF = sum.faces;
    cost.sumC = sum.corners;
    cost.sumFV = sum.fvarValues;
    // Render vertices: one per (vertex, UV value) of the set with the most
    // values, as the split at seams makes them (at most: the values of
    // every set split together).
    const double renderVertices = std::max(l.vertices, sets > 0 ? l.fvarValues / sets : 0.0);
    cost.renderVertices = uint64_t(renderVertices);
    cost.isolation =
        settings.limit ? std::clamp(std::max({N, 5, int(std::ceil(cc.maxFiniteSharpness))}), 5, 10)
                       : 0;
    cost.bytes = uint64_t(estimateBytes(cost, settings, !cage.holes.empty()) + 0.5);
    return cost;
}

uint64_t defaultSubdivisionBudget() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGE_SIZE);
    uint64_t budget = pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) / 2
                                                : uint64_t(4) << 30; // unknown: 4 GiB
    for (int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        struct rlimit lim {};
        if (::getrlimit(resource, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY)
            budget = std::min(budget, uint64_t(lim.rlim_cur) / 4 * 3);
    }
    return budget;
}

std::string formatByteSize(uint64_t bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double v = double(bytes);
    int u = 0;
    while (v >= 1024 && u < 4) {
        v /= 1024;
        ++u;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", v, units[u]);
    return buf;
}

} // namespace sg::mesh
