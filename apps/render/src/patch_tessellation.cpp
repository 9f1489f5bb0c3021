// The CPU reference of the adaptive-patch draw: every patch tessellated at
// the levels the GPU's control stage computes (the shared
// sgPatchEdgeTessLevel of sg/patch/tess_level.glsl, from the same corner
// vertices; transition edges the sum of their halves'), its domain points
// those of the GL specification's quad tessellation with equal spacing
// (OpenGL 4.5 core, section 11.2.2.2), and every point evaluated as the
// evaluation stage does (sg/patch/watertight.glsl for edge points, the
// shared basis sg/patch/basis.glsl, "limit" tangents from
// sg/patch/limit_tangent.glsl).
//
// Triangulation. GL fixes the domain points for integer levels but leaves
// the triangles of the ring between the outer edges and the inner grid to
// the implementation. Here: inner levels below 2 count as 2 (the
// specification's 1 + epsilon rule for equal spacing, unless every level is
// 1: one quad, two triangles); the inner grid (points i/m, j/n,
// 1 <= i < m, 1 <= j < n) is cut into quads, each split along its
// (i, j)-(i+1, j+1) diagonal; each side's strip between the n_outer + 1
// points of the outer edge and the points of the inner grid's side is
// "zipped": walking both rows in order, the next triangle advances the
// row whose next point lies further back along the side (ties: the outer
// row). Same points as the GPU, possibly different diagonals in the strip
// and in the grid: the parity test's tolerance is derived from this
// (tests/render/adaptive_test.cpp).
#include <algorithm>
#include <cmath>

#include "render_internal.h"
#include "surfgrad/adaptive_patches.h"
#include "surfgrad/contract.h"
#include "surfgrad/patch_basis.h"

namespace sg::render::detail {

namespace {

namespace G = sg::glsl;

// Domain points and triangles (indices into the points) of GL's quad
// tessellation at integer outer levels (u = 0, v = 0, u = 1, v = 1) and
// inner levels (along u, along v); counter-clockwise in (u, v).
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

// Zips an outer row and an inner row (both ordered along the same side,
// with their positions along it) into triangles.
void zip(QuadDomain& d, const std::vector<uint32_t>& outer, const std::vector<float>& outerT,
         const std::vector<uint32_t>& inner, const std::vector<float>& innerT) {
    size_t i = 0, j = 0;
    while (i + 1 < outer.size() || j + 1 < inner.size()) {
        const bool advanceOuter =
            j + 1 >= inner.size() || (i + 1 < outer.size() && outerT[i + 1] <= innerT[j + 1]);
        if (advanceOuter) {
            d.tri(outer[i], outer[i + 1], inner[j]);
            ++i;
        } else {
            d.tri(outer[i], inner[j + 1], inner[j]);
            ++j;
        }
    }
}

QuadDomain quadDomain(const int outer[4], int innerU, int innerV) {
    QuadDomain d;
    if (innerU <= 1 && innerV <= 1 && outer[0] == 1 && outer[1] == 1 && outer[2] == 1 &&
        outer[3] == 1) {
        const uint32_t a = d.add(glm::vec2(0.0f, 0.0f)), b = d.add(glm::vec2(1.0f, 0.0f));
        const uint32_t c = d.add(glm::vec2(1.0f, 1.0f)), e = d.add(glm::vec2(0.0f, 1.0f));
        d.tri(a, b, c);
        d.tri(a, c, e);
        return d;
    }
    const int m = std::max(innerU, 2), n = std::max(innerV, 2);
    // Inner grid: (m - 1) x (n - 1) points.
    std::vector<uint32_t> grid(size_t(m - 1) * size_t(n - 1));
    auto g = [&](int i, int j) -> uint32_t& {
        return grid[size_t(j - 1) * size_t(m - 1) + size_t(i - 1)];
    };
    for (int j = 1; j < n; ++j)
        for (int i = 1; i < m; ++i)
            g(i, j) = d.add(glm::vec2(float(i) / float(m), float(j) / float(n)));
    for (int j = 1; j + 1 < n; ++j)
        for (int i = 1; i + 1 < m; ++i) {
            d.tri(g(i, j), g(i + 1, j), g(i + 1, j + 1));
            d.tri(g(i, j), g(i + 1, j + 1), g(i, j + 1));
        }
    // Corners, then each side: the outer edge's points (corner to corner)
    // against the inner grid's outermost row or column on that side.
    const uint32_t c00 = d.add(glm::vec2(0.0f, 0.0f)), c10 = d.add(glm::vec2(1.0f, 0.0f));
    const uint32_t c11 = d.add(glm::vec2(1.0f, 1.0f)), c01 = d.add(glm::vec2(0.0f, 1.0f));
    for (int k = 0; k < 4; ++k) {
        const int lvl = std::max(outer[k], 1);
        const bool alongV = k == 0 || k == 2; // edges u = 0 and u = 1 run along v
        std::vector<uint32_t> orow, irow;
        std::vector<float> ot, it;
        orow.push_back(k == 0 ? c00 : k == 1 ? c00 : k == 2 ? c10 : c01);
        ot.push_back(0.0f);
        for (int s = 1; s < lvl; ++s) {
            const float t = float(s) / float(lvl);
            orow.push_back(d.add(G::sgPatchEdgeUv(k, t)));
            ot.push_back(t);
        }
        orow.push_back(k == 0 ? c01 : k == 1 ? c10 : k == 2 ? c11 : c11);
        ot.push_back(1.0f);
        const int count = alongV ? n - 1 : m - 1;
        for (int s = 1; s <= count; ++s) {
            const int i = k == 0 ? 1 : k == 2 ? m - 1 : s;
            const int j = k == 1 ? 1 : k == 3 ? n - 1 : s;
            irow.push_back(g(i, j));
            it.push_back(alongV ? float(j) / float(n) : float(i) / float(m));
        }
        zip(d, orow, ot, irow, it);
    }
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
        pos += b.point.v[i] * c;
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
        st += b.point.v[i] * x;
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
    return G::sgDisplacePoint(pos, n, height, d.scale);
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
