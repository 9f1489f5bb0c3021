// Evaluation entry points of the shared shader functions: a table of named
// kernels with their argument and result layouts, the CPU evaluation of one
// record, and the random and adversarial records the parity suite feeds
// them. The kernels themselves, and the one declaration per function this
// table is expanded from (layouts, docs, JSON defaults, tolerance and its
// reason, input generator), are shaders/sg/eval/kernels.glsl; the GPU side
// runs the same file in a compute shader (see sg::gl::runCompute and
// evalGpuBody below). Used by `surfgrad eval`, `surfgrad selftest` and the
// parity tests.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace sg::eval {

// Floats per input and output record (SG_EVAL_IN / SG_EVAL_OUT).
int inStride();
int outStride();

enum class FieldKind {
    Float, // JSON number; width > 1: array of numbers
    Bool,  // JSON true/false, stored as 1/0
    Int    // JSON integer, stored as a float
};

// How the parity records fill an input field (eval_inputs.cpp; the sgGen*
// options of kernels.glsl). Any: a random vector, magnitudes 1e-3..1e3
// (adversarially 0, denormal, tiny or huge).
enum class Generate {
    Any,
    Normal,       // a unit vector (adversarially scaled or axis-aligned); the n the
                  // adversarial relations refer to
    Direction,    // the same distribution, no relations
    NormalMapXY,  // xy of a normal-map texel: inside, on or outside the unit disk
    Exponent,     // 1..8 (adversarially 0.01..316)
    TexSize,      // powers of two 1..4096 per component
    Tangent,      // xyz random, w = +-1
    Symmetric,    // uniform in [-1, 1] (adversarially scaled)
    Positive,     // 1..1000 (adversarially any magnitude)
    Sign,         // +-1
    ScreenDerivX, // dpdx of the relations (parallel to dpdy, along n)
    ScreenDerivY, // dpdy of the relations
    UvDerivX,     // dstdx of the relations (parallel to dstdy)
    UvDerivY      // dstdy of the relations
};

struct Field {
    std::string key; // JSON key
    int width;       // number of floats (1, 2, 3, 4 or 16 for a mat4)
    int slot;        // first float in the record
    FieldKind kind;
    bool optional; // may be omitted on input (then defaultValue)
    float defaultValue;
    std::string doc; // one line: meaning, space, units
    // Int inputs: the values they take (checked on JSON input, drawn by the
    // parity records).
    int minValue = 0, maxValue = 0;
    Generate generate = Generate::Any; // inputs: how parity records fill it
};

// Error measure of the parity suite per output field (parity,
// surfgrad/parity/check.h): Mixed = |gpu - cpu|_inf / max(1, |cpu|_inf), Relative
// = |gpu - cpu|_inf / |cpu|_inf (outputs with no natural unit scale).
enum class ErrorMeasure { Mixed, Relative };

struct Entry;
class RecordRandom; // the generators' random source (eval_inputs.cpp)
// Fills one input record of entry e (fields already at their defaults).
using InputGenerator = void (*)(const Entry& e, RecordRandom& random, float* record,
                                bool adversarial);

struct Entry {
    std::string name;    // e.g. "resolve"
    int kernel;          // kernel id (position in the list)
    std::string summary; // what it computes and which listing
    std::vector<Field> inputs;
    std::vector<Field> outputs;
    // CPU/GPU parity (surfgrad/parity/check.h): the measure, the largest error on
    // well-conditioned records, the largest share of records excluded as
    // ill-conditioned or explained, and why these numbers.
    ErrorMeasure measure;
    double tolerance;
    double maxIllFraction;
    std::string toleranceReason;
    InputGenerator generator;
};

const std::vector<Entry>& entries();
const Entry* findEntry(std::string_view name); // nullptr if unknown

// Evaluates one record on the CPU (C++ build of the shared source).
// in: inStride() floats; out: outStride() floats.
void evalCpu(const Entry& e, const float* in, float* out);

// Evaluates one record with the same formulas in binary64 (a generated
// double-precision copy of the shader source). For measuring conditioning
// and rounding error, not an independent oracle.
// in: inStride() doubles; out: outStride() doubles.
void evalDouble(const Entry& e, const double* in, double* out);

// Body of the compute program for entry e (assemble with
// sg::shaders::assemble(body, name, defines) using evalGpuDefines(e)).
std::string evalGpuBody();
std::vector<std::string> evalGpuDefines(const Entry& e);
// The same kernels as a vertex program for dialects without compute shaders
// (GLSL 3.30, ES 3.00; sg::gl::runTransformFeedback), and the names of its
// captured outputs in record order.
std::string evalGpuVertexBody();
std::vector<std::string> evalGpuFeedback();
// The same kernels as an HLSL compute program (sg/eval/eval.hlsl; assemble
// with Target::Hlsl and evalGpuDefines(e)): one thread per record, records
// in buffer 0 and results in buffer 1, their count the result buffer's.
std::string evalHlslBody();

// Input records for entry e: `count` records of inStride() floats, made by
// its generator. About 40% are adversarial: zero vectors, normals at the
// horizon (component along n -> 0), parallel screen derivatives,
// zero-determinant UV Jacobians, back faces and every double-sided mode,
// magnitudes from denormals (1e-44) to 1e18 (the documented input domain,
// SG_BIG in shaders/sg/compat.glsl; a relation that scales one field into
// another, dpdy = c dpdx with |c| up to 2, may double that), normal-map
// values on and outside the unit circle, edge-on and far-away cameras for
// listing 17 (whose matrix is always a real inverse of viewport *
// projection * view). The rest are random with magnitudes spread over
// 1e-3..1e3. Deterministic in seed.
std::vector<float> generateInputs(const Entry& e, size_t count, uint64_t seed);

} // namespace sg::eval
