// The parity records' random source and the input generators the kernel
// list of shaders/sg/eval/kernels.glsl names (internal to bump/).
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>
#include <random>

#include "surfgrad/bump/eval_kernels.h"

namespace sg::eval {

class RecordRandom {
public:
    explicit RecordRandom(uint64_t seed) : rng_(seed) {}
    double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
    int pick(int n) { return int(std::uniform_int_distribution<int>(0, n - 1)(rng_)); }
    bool chance(double p) { return uni(0, 1) < p; }
    // 10^U(lo, hi)
    double mag(double lo, double hi);
    glm::dvec3 unitVec();
    void unitVec(float* v);
    void vec(float* v, int n, double scale);

private:
    std::mt19937_64 rng_;
};

// Every field by its Generate option, then (adversarial records) one of the
// relations between the fields generated as Normal, ScreenDerivX/Y and
// UvDerivX/Y: parallel screen derivatives, a zero-determinant UV Jacobian,
// dpdx along n, or every other 3-vector at the horizon of n.
void fieldInputs(const Entry& e, RecordRandom& random, float* record, bool adversarial);

// A real camera for listing 17 (screen-deriv-of-pos): invViewProjScr =
// inverse(viewport * proj * view), the pixel (x, y) inside the viewport and
// `pos` on that pixel's view ray, n facing the camera (adversarial:
// edge-on, back-facing, far cameras, huge or tiny world scales).
void cameraInputs(const Entry& e, RecordRandom& random, float* record, bool adversarial);

} // namespace sg::eval
