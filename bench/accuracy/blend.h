// The blend methods of blend.glsl compiled as C++ (sg::glsl::studyBlend*),
// next to the shared bump math (surfgrad/bump.h).
#pragma once

#include "surfgrad/bump.h"

namespace sg::glsl {
#include "blend.glsl"
} // namespace sg::glsl
