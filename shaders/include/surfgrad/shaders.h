// Umbrella header of the shaders module (surfgrad_shaders, shaders/).
// The GLSL library (shaders/sg/**.glsl) embedded at build time, the #include
// resolver and program assembler, and the C++ half of the shared GLSL/C++
// subset. Includes nothing of another module.
//
// Includes every public header of the module:
//   surfgrad/shaders/shader_files.h     the embedded library, shader targets, the program assembler
//   surfgrad/shaders/glsl_cpp.h         the C++ side of the shared GLSL subset (binary32, GLM)
//   surfgrad/shaders/glsl_cpp_double.h  the subset in binary64; NOT included here: it compiles the
//                                       one .glsl file its includer names in SG_GLSL_DOUBLE_SOURCE
#pragma once

#include "surfgrad/shaders/glsl_cpp.h"
#include "surfgrad/shaders/shader_files.h"
