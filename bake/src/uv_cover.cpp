// Texel centres -> (patch, patch coordinates) by rasterising every patch's
// UV layout from a grid of limit UVs (see uv_cover.h).
#include "uv_cover.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace sg::bake::detail {

namespace {

// A patch's grid: (n + 1)^2 limit UVs in texel units, row along +v.
struct PatchGrid {
    int n = 1;
    std::vector<glm::vec2> texel;
};

int cellsPerSide(const LimitPatches& lp, uint32_t p, glm::vec2 texelsPerUv) {
    const glm::vec2 c[4] = {lp.st(p, {0, 0}) * texelsPerUv, lp.st(p, {1, 0}) * texelsPerUv,
                            lp.st(p, {1, 1}) * texelsPerUv, lp.st(p, {0, 1}) * texelsPerUv};
    const glm::vec2 mid = lp.st(p, {0.5f, 0.5f}) * texelsPerUv;
    float extent = 0.0f;
    for (int k = 0; k < 4; ++k) {
        extent = std::max(extent, glm::length(c[(k + 1) % 4] - c[k]));
        extent = std::max(extent, 2.0f * glm::length(mid - c[k]));
    }
    int n = 1;
    while (n < kMaxCellsPerSide && float(n) * kCellTexels < extent) n *= 2;
    return n;
}

PatchGrid patchGrid(const LimitPatches& lp, uint32_t p, glm::vec2 texelsPerUv) {
    PatchGrid g;
    g.n = cellsPerSide(lp, p, texelsPerUv);
    g.texel.resize(size_t(g.n + 1) * size_t(g.n + 1));
    for (int j = 0; j <= g.n; ++j)
        for (int i = 0; i <= g.n; ++i)
            g.texel[size_t(j) * size_t(g.n + 1) + size_t(i)] =
                lp.st(p, glm::vec2(float(i), float(j)) / float(g.n)) * texelsPerUv;
    return g;
}

float cross2(glm::vec2 a, glm::vec2 b) {
    return a.x * b.y - a.y * b.x;
}

class Rasteriser {
public:
    // Claims texels of rows [rowLo, rowHi) only.
    Rasteriser(UvCover& cover, int width, int height, int rowLo, int rowHi)
        : cover_(cover), w_(width), h_(height), rowLo_(rowLo), rowHi_(rowHi) {}

    // Triangle of patch p: texel-space corners x and their patch coordinates.
    void triangle(uint32_t p, const glm::vec2 (&x)[3], const glm::vec2 (&uv)[3]) {
        const float area = cross2(x[1] - x[0], x[2] - x[0]);
        if (!(std::abs(area) > 0.0f)) return; // degenerate in UV: nothing to cover
        const float orient = area > 0.0f ? 1.0f : -1.0f;
        float inv[3];
        for (int e = 0; e < 3; ++e) {
            const float len = glm::length(x[(e + 2) % 3] - x[(e + 1) % 3]);
            inv[e] = len > 0.0f ? orient / len : 0.0f;
        }
        const glm::vec2 lo = glm::min(glm::min(x[0], x[1]), x[2]) - kClaimTolTexels;
        const glm::vec2 hi = glm::max(glm::max(x[0], x[1]), x[2]) + kClaimTolTexels;
        const int i0 = std::max(0, int(std::ceil(lo.x - 0.5f))),
                  i1 = std::min(w_ - 1, int(std::floor(hi.x - 0.5f)));
        const int j0 = std::max(rowLo_, int(std::ceil(lo.y - 0.5f))),
                  j1 = std::min(rowHi_ - 1, int(std::floor(hi.y - 0.5f)));
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const glm::vec2 c(float(i) + 0.5f, float(j) + 0.5f);
                // Barycentric weight of corner e: the edge opposite e.
                float b[3], depth = INFINITY;
                for (int e = 0; e < 3; ++e) {
                    const glm::vec2 a = x[(e + 1) % 3], d = x[(e + 2) % 3];
                    const float s = cross2(d - a, c - a);
                    b[e] = s / area;
                    depth = std::min(depth, s * inv[e]);
                }
                if (depth < -kClaimTolTexels) continue;
                claim(size_t(j) * size_t(w_) + size_t(i), p, depth,
                      b[0] * uv[0] + b[1] * uv[1] + b[2] * uv[2]);
            }
    }

private:
    void claim(size_t t, uint32_t p, float depth, glm::vec2 patchUv) {
        TexelClaim& c = cover_.claims[t];
        if (c.patch == UINT32_MAX) {
            c.patch = p;
            c.depthTexels = depth;
            c.patchUv = patchUv;
        } else if (p == c.patch) {
            if (depth > c.depthTexels) {
                c.depthTexels = depth;
                c.patchUv = patchUv;
            }
        } else if (depth > c.depthTexels) { // a new owner; the old one is the runner-up
            c.otherPatch = c.patch;
            c.otherDepthTexels = c.depthTexels;
            c.otherUv = c.patchUv;
            c.patch = p;
            c.depthTexels = depth;
            c.patchUv = patchUv;
        } else if (c.otherPatch == UINT32_MAX || depth > c.otherDepthTexels) {
            c.otherPatch = p;
            c.otherDepthTexels = depth;
            c.otherUv = patchUv;
        }
    }

    UvCover& cover_;
    int w_, h_, rowLo_, rowHi_;
};

// The cells of one patch's grid whose rows reach [yLo, yHi] (texel y).
void rasterisePatch(Rasteriser& raster, uint32_t p, const PatchGrid& g, float yLo, float yHi) {
    const size_t row = size_t(g.n + 1);
    const float step = 1.0f / float(g.n);
    for (int j = 0; j < g.n; ++j)
        for (int i = 0; i < g.n; ++i) {
            const size_t k = size_t(j) * row + size_t(i);
            const glm::vec2 x00 = g.texel[k], x10 = g.texel[k + 1], x11 = g.texel[k + row + 1],
                            x01 = g.texel[k + row];
            const float lo = std::min({x00.y, x10.y, x11.y, x01.y}),
                        hi = std::max({x00.y, x10.y, x11.y, x01.y});
            if (hi < yLo || lo > yHi) continue;
            const glm::vec2 u00(float(i) * step, float(j) * step),
                u10(float(i + 1) * step, float(j) * step),
                u11(float(i + 1) * step, float(j + 1) * step),
                u01(float(i) * step, float(j + 1) * step);
            raster.triangle(p, {x00, x10, x11}, {u00, u10, u11});
            raster.triangle(p, {x00, x11, x01}, {u00, u11, u01});
        }
}

} // namespace

namespace {

// The band driver: bands of kBandRows rows on TBB, each calling
// visit(raster, yLo, yHi) which rasterises every primitive reaching texel
// rows [yLo, yHi] in primitive order, so every texel receives its claims
// in the same order for every thread count.
template <class Visit>
UvCover coverInBands(int width, int height, const Visit& visit) {
    UvCover cover;
    cover.claims.resize(size_t(width) * size_t(height));
    const int bands = (height + kBandRows - 1) / kBandRows;
    tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const tbb::blocked_range<int>& br) {
        for (int band = br.begin(); band != br.end(); ++band) {
            const int rowLo = band * kBandRows, rowHi = std::min(height, rowLo + kBandRows);
            // Texel centres of rows [rowLo, rowHi), one texel of margin.
            const float yLo = float(rowLo) + 0.5f - 1.0f, yHi = float(rowHi) - 0.5f + 1.0f;
            Rasteriser raster(cover, width, height, rowLo, rowHi);
            visit(raster, yLo, yHi);
        }
    });
    for (const TexelClaim& c : cover.claims) cover.chartTexels += c.patch != UINT32_MAX ? 1 : 0;
    return cover;
}

} // namespace

UvCover coverTexels(const LimitPatches& lp, int width, int height) {
    const glm::vec2 texelsPerUv{float(width), float(height)};
    std::vector<PatchGrid> grids(lp.patchCount());
    std::vector<glm::vec2> rowsOf(lp.patchCount()); // lowest and highest texel y of each grid
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, lp.patchCount(), 16),
                      [&](const tbb::blocked_range<uint32_t>& r) {
                          for (uint32_t p = r.begin(); p != r.end(); ++p) {
                              grids[p] = patchGrid(lp, p, texelsPerUv);
                              glm::vec2 y(INFINITY, -INFINITY);
                              for (const glm::vec2& x : grids[p].texel)
                                  y = glm::vec2(std::min(y.x, x.y), std::max(y.y, x.y));
                              rowsOf[p] = y;
                          }
                      });
    return coverInBands(width, height, [&](Rasteriser& raster, float yLo, float yHi) {
        for (uint32_t p = 0; p < lp.patchCount(); ++p) {
            if (rowsOf[p].y < yLo || rowsOf[p].x > yHi) continue;
            rasterisePatch(raster, p, grids[p], yLo, yHi);
        }
    });
}

UvCover coverTriangles(const mesh::RenderMesh& m, int uvSet, int width, int height) {
    const glm::vec2 texelsPerUv{float(width), float(height)};
    const std::vector<glm::vec2>& uv = m.uvSets[size_t(uvSet)];
    const glm::vec2 bary[3] = {{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}};
    return coverInBands(width, height, [&](Rasteriser& raster, float yLo, float yHi) {
        for (uint32_t t = 0; t < m.triangleCount(); ++t) {
            const uint32_t* v = &m.indices[size_t(t) * 3];
            const glm::vec2 x[3] = {uv[v[0]] * texelsPerUv, uv[v[1]] * texelsPerUv,
                                    uv[v[2]] * texelsPerUv};
            if (std::max({x[0].y, x[1].y, x[2].y}) < yLo ||
                std::min({x[0].y, x[1].y, x[2].y}) > yHi)
                continue;
            raster.triangle(t, x, bary);
        }
    });
}

} // namespace sg::bake::detail
