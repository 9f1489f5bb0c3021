// The CPU reference of the adaptive-patch draw: every patch tessellated at
// the levels the GPU's control stage computes (the shared
// sgPatchEdgeTessLevel of sg/patch/tess_level.glsl, from the same corner
// vertices; transition edges the sum of their halves'), into the domain
// points and triangles of GL's quad tessellation with equal spacing
// (OpenGL 4.5 core, section 11.2.2.2) as Mesa's llvmpipe generates them,
// and every point evaluated as the evaluation stage does
// (sg/patch/watertight.glsl for edge points, the shared basis
// sg/patch/basis.glsl, "limit" tangents from sg/patch/limit_tangent.glsl).
//
// Tessellation. GL fixes the domain points of integer levels (i / n along
// each edge and across the inner grid) but leaves their rounding and the
// triangles to the implementation. Here both are llvmpipe's: Mesa's draw
// module runs the Direct3D 11 reference tessellator (Mesa 22.3,
// src/gallium/auxiliary/tessellator: p_tessellator.cpp maps GL's
// equal_spacing to its integer partitioning, tessellator.cpp tessellates;
// this file is a separate implementation of the behaviour learnt from
// them). For integer outer levels (edges u = 0, v = 0, u = 1, v = 1) and
// inner levels m (along u), n (along v):
//  - Every level 1: one quad, two triangles split along (1,0)-(0,1).
//    Otherwise an inner level 1 counts as 2 (GL's "1 + epsilon" rule).
//  - Points: level L puts point i (0 <= i <= L) at i / L in 16-bit fixed
//    point: i * s / 2^16 on the first half of the edge (2i < L),
//    1 - (L - i) * s / 2^16 on the second, 1/2 exactly in the middle, with
//    s = 2^16 / L rounded to nearest (domainCoord; 1/3 is 21845 / 2^16).
//    Each outer edge uses its own level; the inner lattice point (i, j) is
//    at (domainCoord(m, i), domainCoord(n, j)). The evaluation stage
//    recovers an edge point's i as round(t L) (sg/patch/watertight.glsl),
//    so edge positions do not depend on this rounding; interior points and
//    every point's UVs do, and here they are llvmpipe's bit for bit.
//  - Rings: the lattice points at distance r from the domain's border form
//    ring r; ring 0 is replaced by the four outer edges, rings
//    1 .. min(m, n) / 2 (integer halves) follow inwards. Every ring is
//    walked counter-clockwise in (u, v) as four sides, each from corner to
//    corner: u = low downward in v, v = low rightward in u, u = high
//    upward, v = high leftward. Each side of ring r is stitched to the same
//    side of ring r - 1 by a sequence of steps, one triangle each: an outer
//    step (outer a, outer a + 1, inner b), an inner step (outer a, inner b,
//    inner b + 1).
//  - Ring 1 against an outer edge of level f, the side's inner level g
//    (m or n): each half of the side is walked from its end to its middle
//    over the 32 points of a half edge at level 64, in the order in which
//    a growing level inserts them (ruler order, rulerRank: position 17
//    first, then 9 and 25, then 5, 13, 21, 29, ..., position 1 last); the
//    outer row advances at every position that level f has (rank below
//    f / 2, integer half), the inner row at every position g has, the
//    inner row first on the way in (first half), the outer first on the
//    way back out (second half, walked from the middle to the end). The
//    outer row also advances once at each end (if f > 1); in the middle,
//    an odd g adds an inner step and an odd f an outer one (inner first).
//  - Rings r >= 2 (the outer side has two points more): an outer step,
//    then one quad per inner segment, then an outer step; the quads of the
//    side's first half (the middle one, if any, included) are split from
//    the outer row's earlier corner to the inner row's later one, those of
//    the second half the mirror way.
//  - Centre: an even shorter inner level leaves the last ring degenerate
//    (a row, a column or a point: nothing left to fill). An odd one leaves
//    a strip of quads one cell wide inside the last ring: along u (m > n,
//    n odd) every quad split along (i + 1, j)-(i, j + 1); along v (n >= m,
//    m odd) along (i, j)-(i + 1, j + 1), except the middle quad, split the
//    other way, when n is odd.
// tests/render/patch_gpu_test.cpp (QuadDomainGpu) checks the triangles and
// the points against llvmpipe's own for every level the renderer uses.
// Other implementations (hardware tessellators) place the same points up
// to rounding but may choose other diagonals: the two images then differ
// inside triangles by the interpolated attributes' second difference
// across a cell (docs/platform.md).
#include <algorithm>
#include <bit>
#include <cmath>

#include "render_internal.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/bump/patch_basis.h"

namespace sg::render::detail {

namespace {

namespace G = sg::glsl;

// Domain points and triangles (indices into the points) of one patch;
// counter-clockwise in (u, v).
struct QuadDomain {
    std::vector<glm::vec2> uv;
    std::vector<uint32_t> tris;

    uint32_t add(glm::vec2 p) {
        uv.push_back(p);
        return uint32_t(uv.size() - 1);
    }
    void tri(uint32_t a, uint32_t b, uint32_t c) {
        const glm::vec2 e1 = uv[b] - uv[a], e2 = uv[c] - uv[a];
        if (e1.x * e2.y - e1.y * e2.x < 0.0f) std::swap(b, c);
        tris.insert(tris.end(), {a, b, c});
    }
};

// Point i of level `level` along an edge or the inner lattice: i / level
// in llvmpipe's 16-bit fixed point (see the top of the file).
float domainCoord(int level, int i) {
    if (2 * i == level) return 0.5f;
    const uint32_t step = (65536u + uint32_t(level) / 2u) / uint32_t(level);
    const bool secondHalf = 2 * i > level;
    const uint32_t fixed = uint32_t(secondHalf ? level - i : i) * step;
    return float(secondHalf ? 65536u - fixed : fixed) / 65536.0f;
}

// When a growing level inserts position p (0..32) of a half edge at level
// 64: a level with h points on the half (h = level / 2) has the positions
// of rank below h. Position 0 is the end (always there); then the ruler
// function of p - 1 (17 first, 9 and 25, 5, 13, 21, 29, ...); position 1
// last.
int rulerRank(int p) {
    if (p == 0) return 0;
    if (p == 1) return 32;
    const int k = p - 1, zeros = std::countr_zero(unsigned(k));
    return (16 >> zeros) + (k >> (zeros + 1));
}

// A stitch between an outer and an inner row: true steps the outer row.
using Steps = std::vector<bool>;

// Ring 1's side against the outer edge (level outerLevel; innerLevel the
// inner level along the side, at least 2).
Steps transitionSteps(int outerLevel, int innerLevel) {
    const int outerHalf = outerLevel / 2, innerHalf = innerLevel / 2;
    Steps s;
    if (outerHalf > 0) s.push_back(true);
    for (int p = 1; p <= 32; ++p) {
        if (rulerRank(p) < innerHalf) s.push_back(false);
        if (rulerRank(p) < outerHalf) s.push_back(true);
    }
    if (innerLevel % 2 == 1) s.push_back(false);
    if (outerLevel % 2 == 1) s.push_back(true);
    for (int p = 32; p >= 1; --p) {
        if (rulerRank(p) < outerHalf) s.push_back(true);
        if (rulerRank(p) < innerHalf) s.push_back(false);
    }
    if (outerHalf > 0) s.push_back(true);
    return s;
}

// A side of ring r >= 2 (innerPoints points) against ring r - 1's.
Steps ringSteps(size_t innerPoints) {
    Steps s{true};
    for (size_t q = 0; q + 1 < innerPoints; ++q) {
        const bool firstHalf = q < innerPoints / 2;
        s.push_back(!firstHalf);
        s.push_back(firstHalf);
    }
    s.push_back(true);
    return s;
}

// Triangles between two rows walked by `steps`.
void zip(QuadDomain& d, const std::vector<uint32_t>& outer, const std::vector<uint32_t>& inner,
         const Steps& steps) {
    size_t a = 0, b = 0;
    for (const bool outerStep : steps) {
        if (outerStep) {
            d.tri(outer[a], outer[a + 1], inner[b]);
            ++a;
        } else {
            d.tri(outer[a], inner[b], inner[b + 1]);
            ++b;
        }
    }
    SG_ASSERT(a + 1 == outer.size() && b + 1 == inner.size(), "a stitch walks both rows");
}

// The inner lattice of a patch: point (i, j) for 1 <= i < m, 1 <= j < n.
struct Lattice {
    int m, n;
    std::vector<uint32_t> ids;

    Lattice(QuadDomain& d, int m_, int n_) : m(m_), n(n_), ids(size_t(m_ + 1) * size_t(n_ + 1)) {
        for (int j = 1; j < n; ++j)
            for (int i = 1; i < m; ++i) at(i, j) = d.add({domainCoord(m, i), domainCoord(n, j)});
    }
    uint32_t& at(int i, int j) { return ids[size_t(j) * size_t(m + 1) + size_t(i)]; }
    // Side k of ring r, in the ring's counter-clockwise order.
    std::vector<uint32_t> side(int r, int k) {
        std::vector<uint32_t> row;
        if (k == 0)
            for (int j = n - r; j >= r; --j) row.push_back(at(r, j));
        if (k == 1)
            for (int i = r; i <= m - r; ++i) row.push_back(at(i, r));
        if (k == 2)
            for (int j = r; j <= n - r; ++j) row.push_back(at(m - r, j));
        if (k == 3)
            for (int i = m - r; i >= r; --i) row.push_back(at(i, n - r));
        return row;
    }
};

// The strip of quads inside the last ring when the shorter inner level is
// odd (nothing when it is even).
void centreStrip(QuadDomain& d, Lattice& g) {
    const int m = g.m, n = g.n;
    std::vector<uint32_t> outer, inner;
    bool flipMiddle = false;
    if (m > n && n % 2 == 1) {
        const int r = n / 2;
        for (int i = r; i <= m - r; ++i) {
            outer.push_back(g.at(i, r));
            inner.push_back(g.at(i, r + 1));
        }
    } else if (n >= m && m % 2 == 1) {
        const int r = m / 2;
        for (int j = n - r; j >= r; --j) {
            outer.push_back(g.at(r, j));
            inner.push_back(g.at(r + 1, j));
        }
        flipMiddle = n % 2 == 1;
    }
    if (outer.empty()) return;
    const size_t quads = outer.size() - 1;
    Steps s;
    for (size_t q = 0; q < quads; ++q) {
        const bool flip = flipMiddle && 2 * q + 1 == quads;
        s.push_back(!flip);
        s.push_back(flip);
    }
    zip(d, outer, inner, s);
}

QuadDomain quadDomain(const int outer[4], int innerU, int innerV) {
    SG_ASSERT(std::max({outer[0], outer[1], outer[2], outer[3], innerU, innerV}) <= 64,
              "levels up to 64 (the ruler order spans a half edge of 32 segments)");
    QuadDomain d;
    const uint32_t c00 = d.add({0.0f, 0.0f}), c10 = d.add({1.0f, 0.0f});
    const uint32_t c11 = d.add({1.0f, 1.0f}), c01 = d.add({0.0f, 1.0f});
    if (innerU <= 1 && innerV <= 1 && outer[0] <= 1 && outer[1] <= 1 && outer[2] <= 1 &&
        outer[3] <= 1) {
        d.tri(c00, c10, c01);
        d.tri(c10, c11, c01);
        return d;
    }
    Lattice g(d, std::max(innerU, 2), std::max(innerV, 2));
    // Ring 1 against the outer edges (side k runs from first[k] to last[k]).
    const uint32_t first[4] = {c01, c00, c10, c11}, last[4] = {c00, c10, c11, c01};
    for (int k = 0; k < 4; ++k) {
        const int level = std::max(outer[k], 1);
        const bool backwards = k == 0 || k == 3; // against the edge's own parameter
        std::vector<uint32_t> row{first[k]};
        for (int s = 1; s < level; ++s)
            row.push_back(
                d.add(G::sgPatchEdgeUv(k, domainCoord(level, backwards ? level - s : s))));
        row.push_back(last[k]);
        zip(d, row, g.side(1, k), transitionSteps(level, k % 2 == 0 ? g.n : g.m));
    }
    for (int r = 2; r <= std::min(g.m, g.n) / 2; ++r)
        for (int k = 0; k < 4; ++k) {
            const std::vector<uint32_t> inner = g.side(r, k);
            zip(d, g.side(r - 1, k), inner, ringSteps(inner.size()));
        }
    centreStrip(d, g);
    return d;
}

glm::vec3 evalPoint(const sg::mesh::AdaptivePatches& ap, const std::vector<uint32_t>& arrayOf,
                    uint32_t p, glm::vec2 uv, glm::vec3* du, glm::vec3* dv) {
    const auto& arr = ap.arrays[arrayOf[p]];
    const uint32_t f1 = ap.params[p].y;
    const G::SgPatchBasis b = G::sgPatchBasis(arr.type, f1, G::sgPatchUnnormalizeUv(f1, uv));
    const uint32_t* idx =
        &ap.indices[arr.firstIndex + (p - arr.firstPatch) * uint32_t(arr.pointsPerPatch)];
    glm::vec3 pos(0.0f), su(0.0f), sv(0.0f);
    for (int i = 0; i < b.count; ++i) {
        const glm::vec3 c = ap.points[idx[i]];
        pos += b.pos.v[i] * c;
        su += b.du.v[i] * c;
        sv += b.dv.v[i] * c;
    }
    *du = su;
    *dv = sv;
    return pos;
}

// UV set s of patch p at (u,v) of the ptex face (the evaluation stage's
// patchUv and patchUvDeriv, sg/patch/patch_tes.glsl), and its derivatives
// with respect to that (u,v) when du, dv are given.
glm::vec2 evalUv(const sg::mesh::AdaptiveUvSet& set, uint32_t p, glm::vec2 faceUv,
                 glm::vec2* du = nullptr, glm::vec2* dv = nullptr) {
    const uint32_t f1 = set.field1[p];
    const G::SgPatchBasis b = G::sgPatchBasis(int(set.types[p]), f1, faceUv);
    const uint32_t* idx = &set.indices[size_t(p) * sg::mesh::AdaptiveUvSet::kUvValuesPerPatch];
    glm::vec2 st(0.0f), su(0.0f), sv(0.0f);
    for (int i = 0; i < b.count; ++i) {
        const glm::vec2 x = set.values[idx[i]];
        st += b.pos.v[i] * x;
        su += b.du.v[i] * x;
        sv += b.dv.v[i] * x;
    }
    if (du) *du = su;
    if (dv) *dv = sv;
    return st;
}

// The evaluation stage's displacement of one point (SG_DISPLACEMENT):
// everything from the site (sg/patch/displace.glsl).
glm::vec3 displace(const sg::mesh::AdaptivePatches& ap, const PatchDisplacement& d,
                   const glm::mat4& modelRel, float focalPx, float pixelsPerEdge,
                   const G::SgPatchSite& site, glm::vec3 pos, glm::vec3 du, glm::vec3 dv) {
    glm::vec2 dispDu, dispDv;
    const glm::vec2 st =
        evalUv(ap.uvSets[size_t(d.uvSet)], site.patchIndex,
               G::sgPatchUnnormalizeUv(ap.params[site.patchIndex].y, site.uv), &dispDu, &dispDv);
    const glm::mat3 m3(modelRel);
    const glm::vec3 relBase = glm::vec3(modelRel * glm::vec4(pos, 1.0f));
    const glm::ivec2 size = G::textureSize(d.map, 0);
    const float lod = G::sgDisplaceLod(m3 * du, m3 * dv, dispDu, dispDv, glm::length(relBase),
                                       focalPx, pixelsPerEdge, float(std::max(size.x, size.y)));
    const float height = G::textureLod(d.map, st, lod).x;
    const glm::vec3 n = G::sgSafeNormalize(glm::cross(du, dv), glm::vec3(0.0f, 0.0f, 1.0f));
    return G::sgDisplacePoint(pos, n, height, d.scale, d.offset);
}

// The evaluation stage's "limit" tangents of one point (SG_VTX_TANGENT_k,
// sg/patch/patch_tes.glsl): this patch's own derivatives at its own domain
// point (evaluated again on the boundary, where the site is the owner's),
// each set's face-varying derivatives there, orthogonal to the normal.
void addTangents(const sg::mesh::AdaptivePatches& ap, const std::vector<uint32_t>& arrayOf,
                 uint32_t mask, uint32_t p, glm::vec2 uv, glm::vec3 du, glm::vec3 dv,
                 glm::vec3 normal, std::vector<std::vector<glm::vec4>>& tangents) {
    const bool onBoundary = uv.x == 0.0f || uv.x == 1.0f || uv.y == 0.0f || uv.y == 1.0f;
    glm::vec3 ownDu = du, ownDv = dv;
    if (onBoundary) evalPoint(ap, arrayOf, p, uv, &ownDu, &ownDv);
    const glm::vec2 faceUv = G::sgPatchUnnormalizeUv(ap.params[p].y, uv);
    for (size_t k = 0; k < tangents.size(); ++k) {
        if (!((mask >> k) & 1u)) continue;
        glm::vec2 sdu, sdv;
        evalUv(ap.uvSets[k], p, faceUv, &sdu, &sdv);
        int resolved = 0;
        tangents[k].push_back(G::sgPatchLimitTangent(ownDu, ownDv, sdu, sdv, normal, resolved));
    }
}

} // namespace

QuadTessellation tessellateQuadDomain(const std::array<int, 4>& outer, int innerU, int innerV) {
    SG_EXPECTS(innerU >= 1 && innerV >= 1 && *std::min_element(outer.begin(), outer.end()) >= 1 &&
                   std::max({outer[0], outer[1], outer[2], outer[3], innerU, innerV}) <= 64,
               "integer levels in 1..64");
    QuadDomain d = quadDomain(outer.data(), innerU, innerV);
    return {std::move(d.uv), std::move(d.tris)};
}

TessellatedPatches tessellatePatches(const sg::mesh::AdaptivePatches& ap, const glm::mat4& modelRel,
                                     float focalPx, float pixelsPerEdge,
                                     const PatchDisplacement* displacement, uint32_t tangentMask) {
    SG_EXPECTS(pixelsPerEdge > 0.0f, "a positive pixels-per-edge target");
    SG_EXPECTS(!displacement ||
                   (displacement->uvSet >= 0 && size_t(displacement->uvSet) < ap.uvSets.size()),
               "the displacement's UV set is one of the patches'");
    std::vector<uint32_t> arrayOf(ap.patchCount(), 0u);
    for (size_t a = 0; a < ap.arrays.size(); ++a)
        for (uint32_t k = 0; k < ap.arrays[a].patchCount; ++k)
            arrayOf[ap.arrays[a].firstPatch + k] = uint32_t(a);
    TessellatedPatches result;
    sg::mesh::RenderMesh& out = result.mesh;
    const size_t uvSets = std::min(ap.uvSets.size(), size_t(kMaxUvSets));
    out.uvSets.resize(uvSets);
    SG_EXPECTS((tangentMask >> uvSets) == 0u, "tangents only for UV sets the patches have");
    result.vertexTangents.resize(uvSets);
    auto rel = [&](uint32_t v) { return glm::vec3(modelRel * glm::vec4(ap.points[v], 1.0f)); };
    for (uint32_t p = 0; p < uint32_t(ap.patchCount()); ++p) {
        // The control stage's levels (patch_tcs.glsl), same inputs and order.
        const glm::uvec4 cv = ap.cornerVertices[p];
        const glm::vec3 c00 = rel(cv.x), c10 = rel(cv.y), c11 = rel(cv.z), c01 = rel(cv.w);
        const float halfMax = G::sgPatchHalfMaxLevel(SG_TESS_MAX_LEVEL);
        auto level = [&](glm::vec3 a, glm::vec3 b, float maxLevel) {
            return G::sgPatchEdgeTessLevel(a, b, focalPx, pixelsPerEdge, maxLevel);
        };
        // A transition half: its owner's own edge, from its corner vertices.
        auto halfLevel = [&](uint32_t owner) {
            static constexpr int kFrom[4] = {0, 0, 1, 3}, kTo[4] = {3, 1, 2, 2};
            const glm::uvec4 oc = ap.cornerVertices[owner >> 3];
            const int e = int((owner >> 1) & 3u);
            return level(rel(oc[kFrom[e]]), rel(oc[kTo[e]]), halfMax);
        };
        const uint32_t mask = ap.transitionMask[p];
        G::SgPatchTransitions tr = G::sgPatchNoTransitions();
        tr.lo = ap.transitionLo[p];
        tr.hi = ap.transitionHi[p];
        tr.mid = ap.transitionMid[p];
        const glm::vec3 ends[4][2] = {{c00, c01}, {c00, c10}, {c10, c11}, {c01, c11}};
        glm::vec4 outer;
        for (int k = 0; k < 4; ++k) {
            if ((mask >> k) & 1u) {
                tr.loLevel[k] = halfLevel(tr.lo[k]);
                outer[k] = tr.loLevel[k] + halfLevel(tr.hi[k]);
            } else {
                const bool isHalf = (mask >> (4 + k)) & 1u;
                outer[k] = level(ends[k][0], ends[k][1], isHalf ? halfMax : SG_TESS_MAX_LEVEL);
            }
        }
        const int ol[4] = {int(outer.x), int(outer.y), int(outer.z), int(outer.w)};
        const QuadDomain d =
            quadDomain(ol, int(std::max(outer.y, outer.w)), int(std::max(outer.x, outer.z)));
        const uint32_t base = uint32_t(out.positions.size());
        for (glm::vec2 uv : d.uv) {
            const G::SgPatchSite s =
                G::sgPatchEvalSite(p, ap.edgeOwners[p], ap.cornerOwners[p], tr, outer, uv);
            glm::vec3 du, dv;
            const glm::vec3 pos = evalPoint(ap, arrayOf, s.patchIndex, s.uv, &du, &dv);
            if (displacement) {
                result.framePositions.push_back(pos);
                out.positions.push_back(
                    displace(ap, *displacement, modelRel, focalPx, pixelsPerEdge, s, pos, du, dv));
            } else {
                out.positions.push_back(pos);
            }
            // The normal of this patch at this point (the evaluation stage
            // takes it from the owner too: the same point, the same tangent plane).
            out.normals.push_back(G::sgSafeNormalize(glm::cross(du, dv), glm::vec3(0, 0, 1)));
            // UVs of this patch at its own domain point (not the owner's:
            // a UV seam keeps its two sides).
            const glm::vec2 faceUv = G::sgPatchUnnormalizeUv(ap.params[p].y, uv);
            for (size_t k = 0; k < uvSets; ++k)
                out.uvSets[k].push_back(evalUv(ap.uvSets[k], p, faceUv));
            if (tangentMask != 0u)
                addTangents(ap, arrayOf, tangentMask, p, uv, du, dv, out.normals.back(),
                            result.vertexTangents);
        }
        for (uint32_t i : d.tris) out.indices.push_back(base + i);
        const float maxOuter = std::max(std::max(outer.x, outer.y), std::max(outer.z, outer.w));
        const uint32_t f1 = ap.params[p].y;
        result.patchAov.resize(out.positions.size(),
                               glm::vec4(float(p + 1u), maxOuter, float(ap.arrays[arrayOf[p]].type),
                                         float(G::sgPatchDepth(f1))));
    }
    return result;
}

} // namespace sg::render::detail
