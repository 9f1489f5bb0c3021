// The residual normal after displacement (residual.h): Mikkelsen 2019,
// section 2.5, listings 1, 7 and 8.
#include "residual.h"

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "surfgrad/bake/baker.h"
#include "surfgrad/bump/core.h"

namespace sg::bake::detail {

namespace G = sg::glsl;

namespace {

// Central difference of (position, height) along one texel axis over the
// neighbours that are hits; one-sided when only one is; false when none is.
// A neighbour on another chart that touches this one in UV but not on the
// surface is no neighbour: of two neighbours whose steps on the surface
// differ by more than kChartJump times, the farther is dropped.
struct AxisDiff {
    glm::vec3 dPos{0.0f};
    float dHeight = 0.0f;
};

constexpr float kChartJump = 4.0f;

bool axisDiff(const normalmap::Grid<uint8_t>& state, const normalmap::NormalField& pos,
              const normalmap::ScalarField& h, int i, int j, int di, int dj, AxisDiff& out) {
    const auto hit = [&](int a, int b) {
        return a >= 0 && b >= 0 && a < state.width && b < state.height &&
               state.at(a, b) == uint8_t(TexelState::Hit);
    };
    bool fwd = hit(i + di, j + dj), back = hit(i - di, j - dj);
    if (fwd && back) {
        const float lf = glm::length(pos.at(i + di, j + dj) - pos.at(i, j));
        const float lb = glm::length(pos.at(i, j) - pos.at(i - di, j - dj));
        if (lf > kChartJump * lb) fwd = false;
        if (lb > kChartJump * lf) back = false;
    }
    if (!fwd && !back) return false;
    const int fi = fwd ? i + di : i, fj = fwd ? j + dj : j;
    const int bi = back ? i - di : i, bj = back ? j - dj : j;
    const float steps = float(int(fwd) + int(back));
    out.dPos = (pos.at(fi, fj) - pos.at(bi, bj)) / steps;
    out.dHeight = (h.at(fi, fj) - h.at(bi, bj)) / steps;
    return true;
}

} // namespace

normalmap::NormalField residualNormals(const normalmap::Grid<uint8_t>& state,
                                       const normalmap::NormalField& basePosition,
                                       const normalmap::NormalField& baseNormal,
                                       const normalmap::ScalarField& displacement,
                                       const normalmap::NormalField& objectNormal) {
    normalmap::NormalField out(state.width, state.height, glm::vec3(0.0f));
    tbb::parallel_for(
        tbb::blocked_range<int>(0, state.height), [&](const tbb::blocked_range<int>& rr) {
            for (int j = rr.begin(); j != rr.end(); ++j)
                for (int i = 0; i < state.width; ++i) {
                    if (state.at(i, j) != uint8_t(TexelState::Hit)) continue;
                    const glm::vec3 n = baseNormal.at(i, j), high = objectNormal.at(i, j);
                    AxisDiff x, y;
                    if (!axisDiff(state, basePosition, displacement, i, j, 1, 0, x) ||
                        !axisDiff(state, basePosition, displacement, i, j, 0, 1, y)) {
                        out.at(i, j) = high;
                        continue;
                    }
                    const G::SgFrame f = G::sgPrologue(n, x.dPos, y.dPos, true, SG_BFACE_NONE);
                    const glm::vec3 full = G::sgSurfgradFromPerturbedNormal(f, high);
                    const glm::vec3 bump =
                        G::sgSurfgradFromScreenDeriv(f, glm::vec2(x.dHeight, y.dHeight));
                    out.at(i, j) = G::sgResolve(f, full - bump);
                }
        });
    return out;
}

} // namespace sg::bake::detail
