// CPU/GPU parity of the shared shader functions: random and adversarial
// input records for every evaluation entry (sg::eval), evaluated by the C++
// build and by the GLSL build (compute shader on the headless context), and
// compared. Used by `surfgrad selftest` and tests/bump/parity_test.cpp.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "surfgrad/eval_kernels.h"
#include "surfgrad/gl.h"

namespace sg::parity {

// Input records for entry e: `count` records of eval::inStride() floats.
// About 40% are adversarial: zero vectors, normals at the horizon
// (component along n -> 0), parallel screen derivatives, zero-determinant
// UV Jacobians, back faces and every double-sided mode, magnitudes from
// 1e-18 to 1e18, normal-map values on and outside the unit circle. The rest
// are random with magnitudes spread over 1e-3..1e3. Deterministic in seed.
std::vector<float> generateInputs(const eval::Entry& e, size_t count, uint64_t seed);

struct Row {
    std::string entry;
    size_t records = 0;
    double maxAbsErr = 0;   // max |gpu - cpu| over all output components
    double maxRelErr = 0;   // max |gpu - cpu| / |cpu| over components with |cpu| >= 1e-6
    double maxMixedErr = 0; // max over records of |gpu - cpu|_inf / max(1, |cpu|_inf) per field
    size_t nonFiniteCpu = 0;
    size_t nonFiniteGpu = 0;
    size_t worstRecord = 0; // index of the record with maxMixedErr
};

// GPU evaluation of many records: one compute program per entry, compiled
// on first use and owned by this object (destroy it before the context).
class GpuEvaluator {
public:
    explicit GpuEvaluator(gl::HeadlessContext& ctx) : ctx_(ctx) {}
    std::vector<float> evalAll(const eval::Entry& e, const std::vector<float>& inputs);
    gl::HeadlessContext& context() { return ctx_; }

private:
    gl::HeadlessContext& ctx_;
    std::map<int, gl::Program> programs_;
};

// Evaluates all records on the CPU and on the GPU and compares.
Row compare(GpuEvaluator& gpu, const eval::Entry& e, const std::vector<float>& inputs);

// CPU evaluation of many records (eval::evalCpu in a loop).
std::vector<float> evalCpuAll(const eval::Entry& e, const std::vector<float>& inputs);

} // namespace sg::parity
