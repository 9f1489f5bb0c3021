// surfgrad bump core: the surface-gradient framework of Mikkelsen,
// "Surface Gradient Based Bump Mapping Framework" (2019), and the
// derivative-space editing operations of Loviscach, "Care and Feeding of
// Normal Vectors" (GDC 2008), compiled for the CPU from the shader source.
//
// The functions are declared, documented and defined ONCE, in
//   shaders/sg/frame.glsl       SgFrame, prologue (L16), double-sided modes
//                               (2.10), mikktspace basis (2.2), re-prologue
//                               (2.11, 3), analytic dPdx/dPdy (L17);
//   shaders/sg/surfgrad.glsl    resolve (L1), bump scale (L2, L3),
//                               tangent-space normal -> derivative (L4),
//                               TBN (L5), procedural basis (L6), perturbed
//                               normal (L7), scale-dependent (L8, L9),
//                               parallax (L10, L11), volume (L12),
//                               triplanar (L13, L14), decals (L15);
//   shaders/sg/deriv_edit.glsl  scale, add/blend, masked blend, modulate,
//                               curves (boost, Hermite points), deform,
//                               central-difference height derivative;
//   shaders/sg/lean.glsl        LEAN moments and covariance, Toksvig variance
//                               and factor (antialiasing).
// Read the contracts (spaces, units, degenerate cases) there. This header
// makes them callable from C++ as sg::glsl::sgResolve(...), etc., with GLM
// types (sg::glsl::vec3 == glm::vec3).
#pragma once

#include "surfgrad/shaders/glsl_cpp.h"

namespace sg::glsl {
#include "sg/frame.glsl"
#include "sg/surfgrad.glsl"
#include "sg/deriv_edit.glsl"
#include "sg/lean.glsl"
} // namespace sg::glsl

namespace sg {
// Version of the shared shader library; bumps when a function's contract
// changes.
inline constexpr int kBumpLibraryVersion = 1;
} // namespace sg
