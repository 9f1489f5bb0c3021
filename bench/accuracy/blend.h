// The normal-map blends of sg/normal_blends.glsl compiled as C++
// (sg::glsl::sgNormalBlend*), next to the shared bump math
// (surfgrad/bump/core.h).
#pragma once

#include "surfgrad/bump/core.h"

namespace sg::glsl {
#include "sg/normal_blends.glsl"
} // namespace sg::glsl
