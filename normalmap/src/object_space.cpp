// Tangent-space <-> object-space normal maps for a mesh's UV layout
// (Mikkelsen 2019, section 2.2: the mikktspace basis of the interpolated,
// unnormalised vertex normal and tangent; listing 5: TBN surface gradient;
// listing 1: resolve; listing 7: surface gradient of a known perturbed
// normal). The mesh's UV triangles are rasterised at texel centres and the
// vertex frame interpolated per texel, as a rasteriser would per pixel.
#include <algorithm>
#include <cmath>

#include "normalmap_internal.h"
#include "surfgrad/mesh/render_mesh.h"
#include "surfgrad/mesh/tangents.h"

namespace sg::normalmap {

namespace g = sg::glsl;
using detail::forRows;

namespace {

// Barycentric rasterisation of one UV triangle into the frames.
void rasterizeTriangle(const sg::mesh::RenderMesh& m, const std::vector<glm::vec2>& uv,
                       const uint32_t idx[3], TexelFrames& f) {
    const int W = f.covered.width, H = f.covered.height;
    glm::vec2 p[3];
    for (int k = 0; k < 3; ++k) p[k] = uv[idx[k]] * glm::vec2(float(W), float(H));
    const float area =
        (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
    if (!(std::abs(area) > 1e-12f)) return; // zero-area in UV: covers no texel centre
    const float lo[2] = {std::min({p[0].x, p[1].x, p[2].x}), std::min({p[0].y, p[1].y, p[2].y})};
    const float hi[2] = {std::max({p[0].x, p[1].x, p[2].x}), std::max({p[0].y, p[1].y, p[2].y})};
    const int i0 = std::max(0, int(std::floor(lo[0] - 0.5f))),
              i1 = std::min(W - 1, int(std::ceil(hi[0])));
    const int j0 = std::max(0, int(std::floor(lo[1] - 0.5f))),
              j1 = std::min(H - 1, int(std::ceil(hi[1])));
    for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
            const glm::vec2 c(float(i) + 0.5f, float(j) + 0.5f);
            float b[3];
            for (int k = 0; k < 3; ++k) {
                const glm::vec2 a = p[(k + 1) % 3], e = p[(k + 2) % 3];
                b[k] = ((e.x - a.x) * (c.y - a.y) - (c.x - a.x) * (e.y - a.y)) / area;
            }
            if (b[0] < 0.0f || b[1] < 0.0f || b[2] < 0.0f) continue;
            glm::vec3 n(0.0f);
            glm::vec4 t(0.0f);
            for (int k = 0; k < 3; ++k) {
                n += b[k] * m.normals[idx[k]];
                t += b[k] * m.tangents[idx[k]];
            }
            f.normal.at(i, j) = n;
            f.tangent.at(i, j) = glm::vec4(glm::vec3(t), t.w < 0.0f ? -1.0f : 1.0f);
            f.covered.at(i, j) = 1;
        }
    }
}

// Fills uncovered texels next to covered ones, one ring per pass.
void dilate(TexelFrames& f, int rings) {
    const int W = f.covered.width, H = f.covered.height;
    for (int r = 0; r < rings; ++r) {
        const Grid<uint8_t> before = f.covered;
        forRows(H, [&](int j) {
            for (int i = 0; i < W; ++i) {
                if (before.at(i, j)) continue;
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const int x = i + di, y = j + dj;
                        if (x < 0 || y < 0 || x >= W || y >= H || !before.at(x, y)) continue;
                        if (f.covered.at(i, j)) continue;
                        f.normal.at(i, j) = f.normal.at(x, y);
                        f.tangent.at(i, j) = f.tangent.at(x, y);
                        f.covered.at(i, j) = 2;
                    }
            }
        });
    }
}

g::SgFrame baseFrame(glm::vec3 vtxNormal) {
    return g::sgPrologue(vtxNormal, glm::vec3(0.0f), glm::vec3(0.0f), true, SG_BFACE_NONE);
}

} // namespace

TexelFrames rasterizeFrames(const sg::mesh::RenderMesh& mesh, int uvSet, int width, int height,
                            int dilateTexels) {
    SG_EXPECTS(uvSet >= 0 && size_t(uvSet) < mesh.uvSets.size(), "uvSet indexes mesh.uvSets");
    SG_EXPECTS(mesh.normals.size() == mesh.positions.size(), "the mesh has vertex normals");
    SG_EXPECTS(width > 0 && height > 0, "a non-empty grid");
    TexelFrames f;
    f.normal = Grid<glm::vec3>(width, height);
    f.tangent = Grid<glm::vec4>(width, height);
    f.covered = Grid<uint8_t>(width, height, 0);
    const sg::mesh::RenderMesh* m = &mesh;
    sg::mesh::RenderMesh withTangents;
    if (mesh.tangents.size() != mesh.positions.size() || mesh.tangentUvSet != uvSet) {
        withTangents = mesh;
        sg::mesh::generateMikkTSpaceTangents(withTangents, uvSet);
        m = &withTangents;
    }
    const auto& uv = m->uvSets[size_t(uvSet)];
    for (size_t t = 0; t + 2 < m->indices.size(); t += 3) {
        rasterizeTriangle(*m, uv, &m->indices[t], f);
    }
    dilate(f, dilateTexels);
    return f;
}

NormalField objectFromTangent(const DerivField& d, const TexelFrames& frames) {
    SG_NM_EXPECT_SAME_SIZE(d, frames.covered);
    NormalField n(d.width, d.height);
    forRows(d.height, [&](int j) {
        for (int i = 0; i < d.width; ++i) {
            if (!frames.covered.at(i, j)) {
                n.at(i, j) = glm::vec3(0.0f);
                continue;
            }
            const glm::vec3 vn = frames.normal.at(i, j);
            glm::vec3 tang, bino;
            g::sgMikktsBasis(vn, frames.tangent.at(i, j), tang, bino);
            n.at(i, j) = g::sgResolve(baseFrame(vn), g::sgSurfgradFromTBN(d.at(i, j), tang, bino));
        }
    });
    return n;
}

DerivField tangentFromObject(const NormalField& objectNormals, const TexelFrames& frames) {
    SG_NM_EXPECT_SAME_SIZE(objectNormals, frames.covered);
    DerivField d(objectNormals.width, objectNormals.height);
    forRows(d.height, [&](int j) {
        for (int i = 0; i < d.width; ++i) {
            d.at(i, j) = glm::vec2(0.0f);
            if (!frames.covered.at(i, j)) continue;
            const glm::vec3 vn = frames.normal.at(i, j);
            const g::SgFrame f = baseFrame(vn);
            glm::vec3 tang, bino;
            g::sgMikktsBasis(vn, frames.tangent.at(i, j), tang, bino);
            // Listing 7 recovers sg_perp / (1 - n.sg) of the gradient sg =
            // d.x tang + d.y bino that objectFromTangent resolved (the
            // interpolated basis is not exactly tangent). Solving
            //   d.x (T_perp + (n.T) g) + d.y (B_perp + (n.B) g) = g
            // for g = listing 7's gradient inverts it exactly.
            const glm::vec3 gr = g::sgSurfgradFromPerturbedNormal(f, objectNormals.at(i, j));
            const glm::vec3 nb = f.nrmBase;
            const glm::vec3 a = tang - glm::dot(nb, tang) * nb + glm::dot(nb, tang) * gr;
            const glm::vec3 b = bino - glm::dot(nb, bino) * nb + glm::dot(nb, bino) * gr;
            const float aa = glm::dot(a, a), ab = glm::dot(a, b), bb = glm::dot(b, b);
            const float det = aa * bb - ab * ab;
            if (!(det > 1e-12f * std::max(aa * bb, 1e-30f))) continue; // degenerate basis
            const float ag = glm::dot(a, gr), bg = glm::dot(b, gr);
            d.at(i, j) = glm::vec2(bb * ag - ab * bg, aa * bg - ab * ag) / det;
        }
    });
    return d;
}

namespace naive {

namespace {

// The normalised frame (t, b, n) of a texel, false when degenerate.
bool unitFrame(const TexelFrames& f, int i, int j, glm::vec3& t, glm::vec3& b, glm::vec3& n) {
    const glm::vec4 t4 = f.tangent.at(i, j);
    n = g::sgSafeNormalize(f.normal.at(i, j), glm::vec3(0.0f));
    t = g::sgSafeNormalize(glm::vec3(t4), glm::vec3(0.0f));
    b = g::sgSafeNormalize((t4.w < 0.0f ? -1.0f : 1.0f) * glm::cross(n, t), glm::vec3(0.0f));
    return glm::dot(n, n) > 0.5f && glm::dot(t, t) > 0.5f && glm::dot(b, b) > 0.5f;
}

} // namespace

NormalField objectFromTangent(const NormalField& m, const TexelFrames& frames) {
    SG_NM_EXPECT_SAME_SIZE(m, frames.covered);
    NormalField o(m.width, m.height);
    forRows(m.height, [&](int j) {
        for (int i = 0; i < m.width; ++i) {
            glm::vec3 t, b, n;
            o.at(i, j) = glm::vec3(0.0f);
            if (!frames.covered.at(i, j) || !unitFrame(frames, i, j, t, b, n)) continue;
            const glm::vec3 v = m.at(i, j);
            o.at(i, j) = g::sgSafeNormalize(v.x * t + v.y * b + v.z * n, n);
        }
    });
    return o;
}

NormalField tangentFromObject(const NormalField& objectNormals, const TexelFrames& frames) {
    SG_NM_EXPECT_SAME_SIZE(objectNormals, frames.covered);
    NormalField m(objectNormals.width, objectNormals.height);
    forRows(m.height, [&](int j) {
        for (int i = 0; i < m.width; ++i) {
            glm::vec3 t, b, n;
            m.at(i, j) = detail::kFlat;
            if (!frames.covered.at(i, j) || !unitFrame(frames, i, j, t, b, n)) continue;
            const glm::vec3 v = objectNormals.at(i, j);
            m.at(i, j) = g::sgSafeNormalize(
                glm::vec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)), detail::kFlat);
        }
    });
    return m;
}

} // namespace naive

} // namespace sg::normalmap
