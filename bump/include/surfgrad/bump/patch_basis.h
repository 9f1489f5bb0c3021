// The patch math of GPU tessellation compiled for the CPU from the shader
// source (shared GLSL/C++ subset, surfgrad/shaders/glsl_cpp.h):
//   shaders/sg/patch/basis.glsl       OpenSubdiv patch bases (regular
//                                     B-spline with PatchParam boundary
//                                     folds, Gregory basis, bilinear) and
//                                     PatchParam decoding;
//   shaders/sg/patch/tess_level.glsl  integer screen-space tessellation
//                                     level of a patch edge;
//   shaders/sg/patch/watertight.glsl  where a tessellated point is
//                                     evaluated (shared edges and corners
//                                     by their owner patch);
//   shaders/sg/patch/displace.glsl    displacement along the normal and
//                                     the height map's level;
//   shaders/sg/patch/limit_tangent.glsl  the "limit" tangent of a UV set
//                                     from the patch derivatives.
// Read the contracts there. Callable as sg::glsl::sgPatchBasis(...), etc.
// The patch tables themselves come from surfgrad/mesh/adaptive_patches.h (mesh).
#pragma once

#include "surfgrad/shaders/glsl_cpp.h"

namespace sg::glsl {
#include "sg/compat.glsl"
#include "sg/patch/basis.glsl"
#include "sg/patch/tess_level.glsl"
#include "sg/patch/watertight.glsl"
#include "sg/patch/displace.glsl"
#include "sg/patch/limit_tangent.glsl"
} // namespace sg::glsl
