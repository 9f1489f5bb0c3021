// The triplanar methods of triplanar.glsl compiled as C++
// (sg::glsl::studyTriplanar*), next to the shared bump math (surfgrad/bump/core.h).
#pragma once

#include "surfgrad/bump/core.h"

namespace sg::glsl {
#include "triplanar.glsl"
} // namespace sg::glsl
