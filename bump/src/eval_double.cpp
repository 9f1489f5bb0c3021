// Double-precision evaluation of the SAME shared shader formulas
// (shaders/sg/*.glsl, copied with float literals made double by
// bump/cmake/DoubleSource.cmake). It is not an independent oracle: the
// parity suite uses it to measure how well-conditioned each input record
// is (how much the exact result moves when the inputs move by a few ulps)
// and how far the binary32 CPU and GPU builds are from the exact value of
// their own formula. Independent known answers live in tests/bump.
#include "surfgrad/eval_kernels.h"

#include <glm/glm.hpp>

// Same common-subset macros as glsl_cpp.h, with GLM's double types standing
// in for the GLSL float types.
#define SG_CPP 1
#define SG_OUT(T) T&
#define SG_INOUT(T) T&
#define SG_FN inline

namespace sg::glsl_double {
using namespace glm;
using vec2 = glm::dvec2;
using vec3 = glm::dvec3;
using vec4 = glm::dvec4;
using mat2 = glm::dmat2;
using mat3 = glm::dmat3;
using mat4 = glm::dmat4;
// Every `float` in the shared source (scalars, struct fields, casts) becomes
// a double in this translation unit only (clang warns on redefining a
// keyword; that is the point here).
#ifdef __clang__
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Wkeyword-macro"
#endif
#define float double
#include "sgd/eval/kernels.glsl"
#undef float
#ifdef __clang__
#pragma clang diagnostic pop
#endif
} // namespace sg::glsl_double

namespace sg::eval {

void evalDouble(const Entry& e, const double* in, double* out) {
    glsl_double::SgEvalIn x;
    for (int i = 0; i < SG_EVAL_IN; ++i) x.v[i] = in[i];
    glsl_double::SgEvalOut y = glsl_double::sgEvalKernel(e.kernel, x);
    for (int i = 0; i < SG_EVAL_OUT; ++i) out[i] = y.v[i];
}

} // namespace sg::eval
