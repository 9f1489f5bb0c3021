// Helpers shared by the normal-map toolkit's sources: row-parallel loops,
// border handling and bilinear sampling on the grids of surfgrad/normalmap/operations.h.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <string>

#include "surfgrad/bump/core.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/base/io.h"
#include "surfgrad/normalmap/operations.h"

namespace sg::normalmap::detail {

// f(j) for every row j in [0, height), rows spread over TBB's threads.
template <class F>
void forRows(int height, F&& f) {
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
        for (int j = r.begin(); j != r.end(); ++j) f(j);
    });
}

// Index i of a grid of size n under the wrap mode (i may be any integer).
inline int wrapIndex(int i, int n, Wrap wrap) {
    if (wrap == Wrap::Repeat) {
        int m = i % n;
        return m < 0 ? m + n : m;
    }
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

// Slopes of a scalar field at texel (i, j): central differences
// (sgHeightDerivCentral) inside; at the border of a Clamp grid the one-sided
// difference (h(1) - h(0), h(N-1) - h(N-2)), i.e. twice the central
// difference of the border-repeated grid.
inline glm::vec2 centralSlope(const ScalarField& s, int i, int j, Wrap wrap) {
    if (i > 0 && j > 0 && i + 1 < s.width && j + 1 < s.height) { // interior: no border rule
        return sg::glsl::sgHeightDerivCentral(s.at(i - 1, j), s.at(i + 1, j), s.at(i, j - 1),
                                              s.at(i, j + 1));
    }
    const int l = wrapIndex(i - 1, s.width, wrap), r = wrapIndex(i + 1, s.width, wrap);
    const int d = wrapIndex(j - 1, s.height, wrap), u = wrapIndex(j + 1, s.height, wrap);
    glm::vec2 g = sg::glsl::sgHeightDerivCentral(s.at(l, j), s.at(r, j), s.at(i, d), s.at(i, u));
    if (wrap == Wrap::Clamp) {
        if (i == 0 || i == s.width - 1) g.x *= 2.0f;
        if (j == 0 || j == s.height - 1) g.y *= 2.0f;
    }
    return g;
}

// Bilinear sample of a grid at texel coordinates (x, y) (texel centres at
// integer + 0.5), borders by the wrap mode.
template <class T>
T sampleBilinear(const Grid<T>& g, float x, float y, Wrap wrap) {
    const float fx = x - 0.5f, fy = y - 0.5f;
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float ax = fx - x0f, ay = fy - y0f;
    // Clamp the integer part before converting: a warped coordinate may be
    // far outside the grid.
    const float lim = 1.0e6f;
    const int x0 = int(std::fmax(-lim, std::fmin(lim, x0f)));
    const int y0 = int(std::fmax(-lim, std::fmin(lim, y0f)));
    const int xa = wrapIndex(x0, g.width, wrap), xb = wrapIndex(x0 + 1, g.width, wrap);
    const int ya = wrapIndex(y0, g.height, wrap), yb = wrapIndex(y0 + 1, g.height, wrap);
    const T bottom = g.at(xa, ya) * (1.0f - ax) + g.at(xb, ya) * ax;
    const T top = g.at(xa, yb) * (1.0f - ax) + g.at(xb, yb) * ax;
    return bottom * (1.0f - ay) + top * ay;
}

// Precondition of the ops that combine grids (a contract: the CLI checks
// the sizes of its inputs and names the files).
#define SG_NM_EXPECT_SAME_SIZE(a, b)                                                               \
    SG_EXPECTS((a).width == (b).width && (a).height == (b).height, "grids of different sizes")

// The normalised elevation (h - min) / (max - min) of every texel, 0 for a
// flat field (ops.cpp; the x of Curve).
ScalarField normalisedElevation(const ScalarField& h);

// The warped sampling point of texel (i, j) in texel coordinates and the
// warp's Jacobian in texel units (column-major: columns d/du, d/dv)
// (ops.cpp).
glm::vec2 warpTexel(const Warp& w, int width, int height, int i, int j, glm::mat2& jac);

inline const glm::vec3 kFlat(0.0f, 0.0f, 1.0f);

} // namespace sg::normalmap::detail
