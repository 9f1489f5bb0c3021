// Umbrella header of the translate module (surfgrad_translate, translate/).
// One program of the shared GLSL source carried to every shader target (GLSL
// 3.30, ES 3.00, SPIR-V, HLSL, MSL) and validated; glslang, SPIRV-Tools,
// SPIRV-Cross. Links shaders and base.
//
// Includes every public header of the module:
//   surfgrad/translate/shader_target.h  shader targets, translateShader and the validators
#pragma once

#include "surfgrad/translate/shader_target.h"
