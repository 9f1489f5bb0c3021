// The text format of `surfgrad eval`: one JSON object per line, keys and
// record slots from the evaluation table (surfgrad/bump/eval_kernels.h). Split
// from the CLI so the parser can be fuzzed (tests/fuzz/fuzz_eval_line.cpp)
// and tested without a process.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "surfgrad/bump/eval_kernels.h"

namespace sg::eval {

// A line that cannot be evaluated; what() names the key and the reason
// (e.g. "key 'n': expected an array of 3 numbers").
struct LineError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Largest magnitude accepted for a number: SG_BIG of shaders/sg/compat.glsl,
// the documented input domain of the shared functions (beyond it results
// would leave binary32 range).
inline constexpr double kMaxInputMagnitude = 1e18;

// Parses one JSON line into an input record of inStride() floats for entry
// e. Rejects (LineError): invalid JSON, a non-object, unknown or repeated keys, missing
// required keys, wrong types or array lengths, non-finite numbers or
// numbers beyond kMaxInputMagnitude, integers outside their field's range
// (Field::minValue..maxValue: bface_mode 0..2, count 0..4) and lines over
// 1 MiB. Never throws anything else for
// any byte string.
std::vector<float> parseLine(const Entry& e, std::string_view line);

// One output record of entry e as a JSON object on one line (shortest
// round-trip float formatting; a non-finite value, which the shared
// functions never produce for valid input, prints as null).
std::string formatResult(const Entry& e, const float* out);

} // namespace sg::eval
