// The residual normal after displacement: what the normal map must still
// add when the renderer bumps the surface with a height layer of the baked
// displacement itself (Mikkelsen 2019, section 2.5: the bump map of a
// displaced surface is taken before displacement, and surface gradients
// add, eq. 2). Per texel:
//   g_full = sgSurfgradFromPerturbedNormal(N, n_high)       (listing 7)
//   g_h    = sgSurfgradFromScreenDeriv(frame, dH/di, dH/dj)  (listing 8,
//            with the texel grid as the "screen": dP/di, dP/dj and dH/di,
//            dH/dj by central differences of the base position and the
//            displacement over neighbouring hits, one-sided at a chart's
//            edge and where the neighbour on one side lies on another chart
//            that touches this one in UV: a step on the surface over 4x
//            the other side's)
//   n_res  = sgResolve(N, g_full - g_h)                      (listing 1)
// so that a height layer of the displacement (scale 1) plus a normal map of
// n_res resolves to n_high up to the difference between the renderer's
// screen derivatives and these texel differences (second order in the
// texel size where the height is smooth).
#pragma once

#include <cstdint>

#include "surfgrad/normalmap/operations.h"

namespace sg::bake::detail {

// Object-space unit normals n_res for the texels whose state is Hit
// (TexelState); (0, 0, 0) elsewhere. A hit with no hit neighbour along i or
// along j keeps n_high (no height derivative can be taken: g_h = 0).
// basePosition, baseNormal: the base surface per texel (bake.h).
normalmap::NormalField residualNormals(const normalmap::Grid<uint8_t>& state,
                                       const normalmap::NormalField& basePosition,
                                       const normalmap::NormalField& baseNormal,
                                       const normalmap::ScalarField& displacement,
                                       const normalmap::NormalField& objectNormal);

} // namespace sg::bake::detail
