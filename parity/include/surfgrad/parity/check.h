// CPU/GPU parity of the shared shader functions: the random and adversarial
// input records of every evaluation entry (sg::eval::generateInputs),
// evaluated by the C++ build (binary32, GLM) and by the GLSL build (compute
// shader on the headless context), and compared with the entry's tolerance
// (eval::Entry::tolerance, maxIllFraction and the reason for both, declared
// with the function in shaders/sg/eval/kernels.glsl). Used by `surfgrad
// selftest` and tests/bump/parity_test.cpp.
//
// Error measure. Per output field (a vector or a scalar) of one record,
//   mixed = |gpu - cpu|_inf / max(1, |cpu|_inf),
// i.e. absolute below magnitude 1 and relative above it (surface gradients
// range over 36 decades on the adversarial set; unit normals are O(1)).
// Entries whose outputs have no natural unit scale (ErrorMeasure::Relative:
// screen-deriv-of-pos, listing 17, position units per pixel) use
// |gpu - cpu|_inf / |cpu|_inf.
//
// Conditioning. Two correct binary32 builds of one formula may disagree by
// far more than an ulp where the formula itself is ill-conditioned: a sign
// branch decided by a determinant that is zero up to rounding (GenBasisTB,
// listing 6), catastrophic cancellation (n . v at the horizon, listing 7),
// pow() with a large exponent (listing 14), cos() of a huge phase. Such
// records are found WITHOUT looking at the binary32 results: the same
// formulas are evaluated in binary64 (sg::eval::evalDouble) at the input and
// at kPerturbations copies of it with every float input moved by a relative
// kPerturbation (a few ulps, random sign). If the exact result moves by more
// than a quarter of the function's tolerance, the record is ill-conditioned:
// it is counted (and the count is bounded per function), its outputs must
// still be finite and satisfy the function's invariants, but its CPU/GPU
// difference is not held to the tolerance.
//
// The random probe can miss a singularity that only some directions reach
// (e.g. breaking the parallelism of two vectors that a uniform scale keeps
// parallel). So a record that passed the probe but whose CPU and GPU results
// differ by more than the tolerance is probed again with kPerturbationsLong
// directions, and then gets a backward-error check: kBackwardSearch
// binary64 evaluations at inputs moved by up to kBackwardRadius (32 to 64
// ulps); if the CPU result AND the GPU result each match (within the
// tolerance) the exact result at some such input, both builds are backward
// stable there and the disagreement is the formula's, not a bug. These
// records are counted separately ("explained"); any other disagreement
// fails.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "surfgrad/bump/eval_kernels.h"
#include "surfgrad/gl/context.h"

namespace sg::parity {

// Relative input perturbation of the conditioning probe: 2^-21, i.e. 4 ulps
// of a binary32 value at the top of its binade, 8 at the bottom.
inline constexpr double kPerturbation = 1.0 / (1 << 21);
inline constexpr int kPerturbations = 4;
// Records whose CPU and GPU results disagree beyond the tolerance are
// probed again with this many directions before anything else.
inline constexpr int kPerturbationsLong = 64;
inline constexpr double kBackwardRadius = 1.0 / (1 << 18);
inline constexpr int kBackwardSearch = 64;

struct Row {
    std::string entry;
    size_t records = 0;
    size_t illConditioned = 0;    // records the conditioning probe excludes (see above)
    size_t backwardExplained = 0; // disagreements explained by the backward-error check
    // Over well-conditioned records:
    double maxAbsErr = 0;    // max |gpu - cpu| over output components
    double maxRelErr = 0;    // max |gpu - cpu|_inf / |cpu|_inf per field (|cpu|_inf >= 1e-30)
    double maxMixedErr = 0;  // max mixed error (the toleranced measure)
    double maxCpuRefErr = 0; // max mixed error of the CPU build vs binary64
    double maxGpuRefErr = 0; // max mixed error of the GPU build vs binary64
    // Over all records:
    double maxMixedErrAll = 0;      // including ill-conditioned records
    size_t nonFiniteCpu = 0;        // records with a NaN/Inf output on the CPU
    size_t nonFiniteGpu = 0;        // ... on the GPU
    size_t invariantViolations = 0; // records breaking the function's invariants
    std::string firstViolation;     // description of the first one
    size_t worstRecord = 0;         // index of the well-conditioned record with maxMixedErr
};

// GPU evaluation of many records: one program per entry, compiled on first
// use and owned by this object (destroy it before the context). The shader
// dialect follows the context's API: a compute program on OpenGL 4.5 (GLSL
// 4.50), a transform-feedback vertex program on OpenGL 3.3 (GLSL 3.30) and
// OpenGL ES 3.0 (GLSL ES 3.00).
// `vertexStage` runs the vertex program on a 4.5 context too, which tells a
// difference of the stage (how a driver compiles vertex shaders) from one
// of the dialect.
//
// A program factory replaces the library's own programs: it makes, for an
// entry, a compute program with its records in shader-storage binding 0
// and its results in binding 1 (gl::runCompute) on a 4.5 context, e.g. one
// translated from another source language; `source` names that language
// in reports (tests/bump/parity_hlsl_test.cpp: Target::Hlsl).
class GpuEvaluator {
public:
    using ProgramFactory = std::function<gl::Program(const eval::Entry&)>;

    explicit GpuEvaluator(gl::HeadlessContext& ctx, bool vertexStage = false)
        : ctx_(ctx), vertexStage_(vertexStage || ctx.api() != gl::Api::Gl45Core) {}
    GpuEvaluator(gl::HeadlessContext& ctx, ProgramFactory factory, shaders::Target source);
    std::vector<float> evalAll(const eval::Entry& e, const std::vector<float>& inputs);
    gl::HeadlessContext& context() { return ctx_; }
    shaders::Target target() const;
    bool vertexStage() const { return vertexStage_; }

private:
    gl::HeadlessContext& ctx_;
    bool vertexStage_;
    ProgramFactory factory_;
    shaders::Target source_ = shaders::Target::Glsl450;
    std::map<int, gl::Program> programs_;
};

// Evaluates all records on the CPU, on the GPU and in binary64, classifies
// conditioning with the tolerance `mixedTol` (the entry's tolerance),
// checks invariants and compares.
Row compare(GpuEvaluator& gpu, const eval::Entry& e, const std::vector<float>& inputs,
            double mixedTol);

// CPU evaluation of many records (eval::evalCpu in a loop).
std::vector<float> evalCpuAll(const eval::Entry& e, const std::vector<float>& inputs);

// Largest mixed error between two output records of entry e (any precision).
double mixedError(const eval::Entry& e, const double* a, const double* ref);

// How far the binary64 result of record `in` moves under the conditioning
// probe (largest mixed error over `perturbations` perturbed copies).
// Deterministic in the record's contents.
double conditionProbe(const eval::Entry& e, const float* in, int perturbations = kPerturbations);

// The contract every output of entry e must satisfy on ANY input record of
// the domain (including ill-conditioned ones): all components finite, and
// per function: resolve and other normalizing functions unit length,
// triplanar weights non-negative summing to 1, signs exactly +-1,
// |tspace-to-deriv| <= 128, dividing functions bounded by 4 * SG_BIG.
// Returns an empty string when satisfied, else what is violated.
std::string checkInvariants(const eval::Entry& e, const float* in, const float* out);

// The backward-error check above: true when cpu and gpu (output records of
// entry e for input `in`) are each within mixedTol of the binary64 result at
// some input within kBackwardRadius of `in`.
bool backwardExplained(const eval::Entry& e, const float* in, const double* cpu, const double* gpu,
                       double mixedTol);

// One record as text: the entry's input fields and, when given, output fields
// of the CPU, GPU and binary64 evaluations (for --verbose reports).
std::string describeRecord(const eval::Entry& e, const float* in, const float* cpu,
                           const float* gpu, const double* ref);

} // namespace sg::parity
