// Double-precision evaluation of the SAME shared shader formulas
// (shaders/sg/*.glsl, copied with float literals made double by
// surfgrad_double_sources, compiled through surfgrad/shaders/glsl_cpp_double.h). It
// is not an independent oracle: the parity suite uses it to measure how
// well-conditioned each input record is (how much the exact result moves
// when the inputs move by a few ulps) and how far the binary32 CPU and GPU
// builds are from the exact value of their own formula. Independent known
// answers live in tests/bump.
#include "surfgrad/bump/eval_kernels.h"

// The shared source in binary64: sg::glsl_double::sgEvalKernel and the rest.
#define SG_GLSL_DOUBLE_SOURCE "sgd/eval/kernels.glsl"
#include "surfgrad/shaders/glsl_cpp_double.h"

namespace sg::eval {

void evalDouble(const Entry& e, const double* in, double* out) {
    glsl_double::SgEvalIn x;
    for (int i = 0; i < SG_EVAL_IN; ++i) x.v[i] = in[i];
    glsl_double::SgEvalOut y = glsl_double::sgEvalKernel(e.kernel, x);
    for (int i = 0; i < SG_EVAL_OUT; ++i) out[i] = y.v[i];
}

} // namespace sg::eval
