// Feature-map bake, steps 5-6: the distance to the curves and its gradient at
// the grid corners, and the constrained Laplacian smoothing of the gradient.
// Parilov, Zorin, "Real-Time Rendering of Textures with Feature Curves"
// (TOG 2008) section 4, "Rasterization of distance field and its gradient";
// Parilov, Rosenberg, Zorin (TR2005-872) section 4.2.
//
//  5. Distances at every corner within `band` texels of a piece, by local
//     brute force in double (the exact point-curve distance) with
//     min-merging over pieces; the gradient is the unit vector from the
//     closest point. Straight pieces visit only the corners inside their
//     capsule.
//  6. Each corner's gradient moves halfway to the mean of its grid
//     neighbours, excluding those across a texel edge that carries a
//     discontinuity point and those with no curve within the band (no
//     gradient). The distance is never smoothed.
//
// Threads (bake_parallel.h): step 5 splits the grid into bands of corner
// rows; each band takes the pieces that reach it in input order, so every
// corner sees the same sequence of candidates (the first strictly closest
// piece wins) as in one pass. Step 6 is a Jacobi iteration (reads one
// buffer, writes the other): rows in parallel.
#include <bit>
#include <chrono>

#include "surfgrad/base/scratch_buffer.h"
#include "bake_internal.h"

namespace sg::features::detail {

namespace {

// The best squared distance found so far per corner, and how to store a
// closer one.
struct DistanceField {
    FeatureMaps& maps;
    std::vector<double> best;

    // r: corner minus closest point; tu: unit curve tangent there.
    void store(size_t ci, double dd, dvec2 r, dvec2 tu) {
        best[ci] = dd;
        double d = std::sqrt(dd);
        dvec2 grad;
        if (d > 1e-9) {
            grad = r * (1.0 / d);
        } else {
            // On the curve: the side the symbolic shift (e^2, e) leaves the
            // corner on (below, or left of a vertical curve).
            grad = dvec2(-tu.y, tu.x);
            if (grad.y > 0 || (grad.y == 0 && grad.x > 0)) grad = -grad;
        }
        maps.dist[ci] = float(d);
        maps.gradX[ci] = float(grad.x);
        maps.gradY[ci] = float(grad.y);
        maps.left[ci] = cross2(tu, grad) > 0 ? 1 : 0;
    }
};

// Corner index range [i0, i1] x [j0, j1] of the piece's control-point
// bounds grown by the band, clipped to the grid.
struct CornerBox {
    int i0, i1, j0, j1;
};
CornerBox cornerBox(const Quad& q, double band, int n) {
    dvec2 lo = glm::min(glm::min(q.p0, q.p1), q.p2) - band;
    dvec2 hi = glm::max(glm::max(q.p0, q.p1), q.p2) + band;
    return {std::max(0, int(std::ceil(lo.x))), std::min(n, int(std::floor(hi.x))),
            std::max(0, int(std::ceil(lo.y))), std::min(n, int(std::floor(hi.y)))};
}

// Corner rows [j0, j1] of one band of the distance pass.
struct RowBand {
    int j0, j1;
};

// A straight piece: the closest point in closed form; only corners inside
// the capsule of radius `band` are visited, in the rows of `rows`.
void lineDistances(const Quad& q, double band, DistanceField& f, RowBand rows) {
    const CornerBox box = cornerBox(q, band, f.maps.size);
    dvec2 p0 = q.p0, e = q.p2 - q.p0;
    double len = glm::length(e);
    dvec2 eu = e / len, fe = e / (len * len);
    for (int j = std::max(box.j0, rows.j0); j <= std::min(box.j1, rows.j1); ++j) {
        // Row interval of the capsule: the union of the two end discs and
        // the strip along the segment.
        double dy = j - p0.y, xa = 1e300, xb = -1e300;
        for (const dvec2& c : {q.p0, q.p2}) {
            double h = band * band - (j - c.y) * (j - c.y);
            if (h >= 0) {
                xa = std::min(xa, c.x - std::sqrt(h));
                xb = std::max(xb, c.x + std::sqrt(h));
            }
        }
        if (std::fabs(eu.y) > 1e-12) {
            // |cross(eu, p - p0)| <= band and 0 <= dot(eu, p - p0) <= len,
            // each linear in x on this row.
            double lo2 = -1e300, hi2 = 1e300;
            auto clip = [&](double a, double b, double vmin, double vmax) {
                // vmin <= a x + b <= vmax
                if (a == 0) {
                    if (b < vmin || b > vmax) {
                        lo2 = 1e300;
                        hi2 = -1e300;
                    }
                    return;
                }
                double x1 = (vmin - b) / a, x2 = (vmax - b) / a;
                lo2 = std::max(lo2, std::min(x1, x2));
                hi2 = std::min(hi2, std::max(x1, x2));
            };
            clip(-eu.y, eu.x * dy + eu.y * p0.x, -band, band);
            clip(eu.x, eu.y * dy - eu.x * p0.x, 0.0, len);
            if (lo2 <= hi2) {
                xa = std::min(xa, lo2);
                xb = std::max(xb, hi2);
            }
        } else if (std::fabs(dy) <= band) {
            xa = std::min(xa, std::min(q.p0.x, q.p2.x));
            xb = std::max(xb, std::max(q.p0.x, q.p2.x));
        }
        int ia = std::max(box.i0, int(std::ceil(xa))), ib = std::min(box.i1, int(std::floor(xb)));
        size_t ci = f.maps.index(ia, j);
        for (int i = ia; i <= ib; ++i, ++ci) {
            double dx = i - p0.x;
            double u = std::clamp(dx * fe.x + dy * fe.y, 0.0, 1.0);
            double rx = dx - u * e.x, ry = dy - u * e.y;
            double dd = rx * rx + ry * ry;
            if (dd < f.best[ci]) f.store(ci, dd, {rx, ry}, eu);
        }
    }
}

// A curved piece: the exact closest point (cubic roots) at every corner of
// its bounding box grown by the band, in the rows of `rows`.
void curveDistances(const Quad& q, double band, DistanceField& f, RowBand rows) {
    const CornerBox box = cornerBox(q, band, f.maps.size);
    for (int j = std::max(box.j0, rows.j0); j <= std::min(box.j1, rows.j1); ++j) {
        for (int i = box.i0; i <= box.i1; ++i) {
            dvec2 p(i, j);
            double u;
            double dd = closestParam(q, false, p, u);
            size_t ci = f.maps.index(i, j);
            if (dd < f.best[ci]) {
                dvec2 tan = q.tangent(u);
                double tl = glm::length(tan);
                f.store(ci, dd, p - q.at(u), tl > 0 ? tan / tl : dvec2(1, 0));
            }
        }
    }
}

// Corner rows per band of the distance pass: a piece costs its set-up in
// every band it reaches, a band is one task.
constexpr int kDistanceBandRows = 16;
// Rows of corners per block of the smoothing passes.
constexpr size_t kSmoothBlockRows = 16;

} // namespace

void computeDistances(const std::vector<TexelPiece>& pieces, double band, FeatureMaps& maps,
                      const std::function<void(const char*, double)>& progress, const Exec& ex) {
    const int m = maps.size + 1;
    const size_t nc = size_t(m) * size_t(m);
    sg::detail::assignWithHugePages(maps.dist, nc, float(band));
    sg::detail::assignWithHugePages(maps.gradX, nc, 0.0f);
    sg::detail::assignWithHugePages(maps.gradY, nc, 0.0f);
    sg::detail::assignWithHugePages(maps.left, nc, uint8_t(0));
    DistanceField f{maps, std::vector<double>(nc, band * band)};
    // The pieces of each band, in input order.
    const size_t bands = blockCount(size_t(m), kDistanceBandRows);
    std::vector<std::vector<uint32_t>> inBand(bands);
    for (size_t k = 0; k < pieces.size(); ++k) {
        const CornerBox box = cornerBox(pieces[k].q, band, maps.size);
        if (box.j0 > box.j1 || box.i0 > box.i1) continue; // off the map
        for (int b = box.j0 / kDistanceBandRows; b <= box.j1 / kDistanceBandRows; ++b)
            inBand[size_t(b)].push_back(uint32_t(k));
    }
    PhaseProgress report(progress, "distance", bands);
    forBlocks(ex, bands, 1, [&](size_t b, size_t, size_t) {
        const RowBand rows{int(b) * kDistanceBandRows,
                           std::min(m - 1, int(b + 1) * kDistanceBandRows - 1)};
        for (uint32_t k : inBand[b]) {
            if (pieces[k].line)
                lineDistances(pieces[k].q, band, f, rows);
            else
                curveDistances(pieces[k].q, band, f, rows);
        }
        report.add(1);
    });
    report.finish();
}

void smoothGradients(double band, int iterations, FeatureMaps& maps, const Exec& ex) {
    // Neighbour links per corner (bits: +x, -x, +y, -y): not across an edge
    // with a discontinuity point, and only between corners that have a
    // curve within the band (others carry no gradient).
    const int m = maps.size + 1;
    const size_t nc = size_t(m) * size_t(m);
    std::vector<uint8_t> links(nc, 0);
    const float inBand = float(band) * 0.9999f;
    forBlocks(ex, size_t(m), kSmoothBlockRows, [&](size_t, size_t rows0, size_t rows1) {
        for (int j = int(rows0); j < int(rows1); ++j) {
            for (int i = 0; i < m; ++i) {
                size_t k = maps.index(i, j);
                if (!(maps.dist[k] < inBand)) continue;
                uint8_t l = 0;
                if (i + 1 < m && !(maps.hPos[k] >= 0.0f) && maps.dist[k + 1] < inBand) l |= 1;
                if (i > 0 && !(maps.hPos[k - 1] >= 0.0f) && maps.dist[k - 1] < inBand) l |= 2;
                if (j + 1 < m && !(maps.vPos[k] >= 0.0f) && maps.dist[k + size_t(m)] < inBand)
                    l |= 4;
                if (j > 0 && !(maps.vPos[k - size_t(m)] >= 0.0f) &&
                    maps.dist[k - size_t(m)] < inBand)
                    l |= 8;
                links[k] = l;
            }
        }
    });
    std::vector<float> gx2(maps.gradX), gy2(maps.gradY);
    float weight[16];
    for (int l = 0; l < 16; ++l) weight[l] = l ? 0.5f / float(std::popcount(unsigned(l))) : 0.0f;
    for (int it = 0; it < iterations; ++it) {
        const float* gx = maps.gradX.data();
        const float* gy = maps.gradY.data();
        forBlocks(ex, nc, kSmoothBlockRows * size_t(m), [&](size_t, size_t k0, size_t k1) {
            for (size_t k = k0; k < k1; ++k) {
                uint8_t l = links[k];
                if (!l) continue;
                float sx = 0, sy = 0;
                if (l & 1) {
                    sx += gx[k + 1];
                    sy += gy[k + 1];
                }
                if (l & 2) {
                    sx += gx[k - 1];
                    sy += gy[k - 1];
                }
                if (l & 4) {
                    sx += gx[k + size_t(m)];
                    sy += gy[k + size_t(m)];
                }
                if (l & 8) {
                    sx += gx[k - size_t(m)];
                    sy += gy[k - size_t(m)];
                }
                float w = weight[l];
                gx2[k] = 0.5f * gx[k] + w * sx;
                gy2[k] = 0.5f * gy[k] + w * sy;
            }
        });
        maps.gradX.swap(gx2);
        maps.gradY.swap(gy2);
        // Corners without links keep their value in both buffers.
    }
}

} // namespace sg::features::detail
