// The shared GLSL subset compiled as C++ in binary64: the prelude of the
// reference evaluations that run the SAME shader formulas in double
// precision (bump/src/eval_double.cpp: the parity suite's conditioning
// measure; features/src/shared_double.cpp: the bake's validation of
// signatures). Not an independent oracle: the same source, exact to
// binary64 instead of binary32.
//
// A translation unit compiles one generated copy of the source (cmake/
// SurfgradDoubleSource.cmake, surfgrad_double_sources: float literals made
// double, includes redirected from sg/ to sgd/) by naming it, then
// including this header:
//
//   #define SG_GLSL_DOUBLE_SOURCE "sgd/eval/kernels.glsl"
//   #include "surfgrad/shaders/glsl_cpp_double.h"
//
// The source lands in namespace sg::glsl_double with the macros of
// glsl_cpp.h, GLM's double types standing in for the GLSL float types
// (vec2..vec4 -> dvec2..dvec4, mat2..mat4 -> dmat2..dmat4) and every `float`
// of the source (scalars, struct fields, casts) a `double`; ints, uints,
// ivecN, uvecN and bvecN are GLM's as in the binary32 build. The copies keep
// the shader files' include guards, so a translation unit that includes a
// binary32 build of a file (surfgrad/bump/core.h, surfgrad/features/feature_maps.h, ...)
// cannot include its binary64 copy: this header stops the build then.
// Including the header again with another SG_GLSL_DOUBLE_SOURCE adds that
// copy (files already included are skipped, as in GLSL). The copies exist
// in surfgrad's build tree only (an installation has the header, not the
// step that writes them).
#ifndef SG_GLSL_CPP_DOUBLE_H
#define SG_GLSL_CPP_DOUBLE_H

#include <glm/glm.hpp>

#include "surfgrad/shaders/glsl_cpp.h"

namespace sg::glsl_double {
using namespace glm;
using vec2 = glm::dvec2;
using vec3 = glm::dvec3;
using vec4 = glm::dvec4;
using mat2 = glm::dmat2;
using mat3 = glm::dmat3;
using mat4 = glm::dmat4;
using uint = unsigned int;
} // namespace sg::glsl_double

#endif // SG_GLSL_CPP_DOUBLE_H

#ifndef SG_GLSL_DOUBLE_SOURCE
#error "define SG_GLSL_DOUBLE_SOURCE (\"sgd/<path>\") before including this header"
#endif
#ifdef SG_COMPAT_GLSL
#ifndef SG_GLSL_DOUBLE_COMPAT
// The binary32 build is already included: the shared include guards would
// skip the binary64 copy.
#error "surfgrad/shaders/glsl_cpp_double.h after a binary32 build of the shader source"
#endif
#endif

namespace sg::glsl_double {
// Every `float` of the shared source becomes a double in this copy only
// (clang warns on redefining a keyword; that is the point here).
#ifdef __clang__
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wkeyword-macro"
#endif
#define float double
#include SG_GLSL_DOUBLE_SOURCE
#undef float
#ifdef __clang__
#pragma clang diagnostic pop
#endif
} // namespace sg::glsl_double

// compat.glsl (always included first) now belongs to the binary64 copy.
#define SG_GLSL_DOUBLE_COMPAT 1
#undef SG_GLSL_DOUBLE_SOURCE
