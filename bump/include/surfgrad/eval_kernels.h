// Evaluation entry points of the shared shader functions: a table of named
// kernels with their argument and result layouts, and the CPU evaluation of
// one record. The kernels themselves are shaders/sg/eval/kernels.glsl; the
// GPU side runs the same file in a compute shader (see sg::gl::runCompute
// and evalGpuProgramSource below). Used by `surfgrad eval`, `surfgrad
// selftest` and the parity tests.
#pragma once

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

struct Field {
    std::string key; // JSON key
    int width;       // number of floats (1, 2, 3, 4 or 16 for a mat4)
    int slot;        // first float in the record
    FieldKind kind;
    bool optional; // may be omitted on input (then defaultValue)
    float defaultValue;
    std::string doc; // one line: meaning, space, units
};

struct Entry {
    std::string name;    // e.g. "resolve"
    int kernel;          // SG_K_* id
    std::string summary; // what it computes and which listing
    std::vector<Field> inputs;
    std::vector<Field> outputs;
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

} // namespace sg::eval
