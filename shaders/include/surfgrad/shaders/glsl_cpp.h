// The C++ side of the shared GLSL subset (the GLSL side is
// shaders/sg/compat.glsl). Including a shaders/sg/*.glsl file after this
// header, inside namespace sg::glsl, compiles the shader math as C++ through
// GLM, which mirrors GLSL's types and built-ins (vec3, dot, cross,
// inversesqrt, ...). This is how every shader function gets CPU unit tests,
// a CPU reference renderer and a CPU/GPU parity test from ONE source
// (OpenSubdiv's osd/patchBasis.h uses the same arrangement).
//
// Do not include .glsl files anywhere else; include the module headers
// (surfgrad/bump/core.h, ...) that do it.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#define SG_CPP 1
#define SG_OUT(T) T&
#define SG_INOUT(T) T&
#define SG_FN inline

namespace sg::glsl {
using namespace glm;
using uint = unsigned int;
} // namespace sg::glsl
