// libFuzzer entry for the `surfgrad eval` line parser (surfgrad/bump/eval_line.h).
// Input: first byte selects the entry (modulo the table size), the rest is
// the JSON line. Property checked beyond "no crash / no sanitizer report /
// only LineError": every line the parser accepts is inside the documented
// input domain, so the shared functions must return finite outputs for it
// (the contract of shaders/sg/compat.glsl, SG_BIG), and formatting the
// result must give one line of valid JSON.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "surfgrad/bump/eval_kernels.h"
#include "surfgrad/bump/eval_line.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const auto& entries = sg::eval::entries();
    const sg::eval::Entry& e = entries[data[0] % entries.size()];
    const std::string_view line(reinterpret_cast<const char*>(data + 1), size - 1);
    std::vector<float> rec;
    try {
        rec = sg::eval::parseLine(e, line);
    } catch (const sg::eval::LineError&) {
        return 0; // a documented rejection
    }
    std::vector<float> out(static_cast<size_t>(sg::eval::outStride()));
    sg::eval::evalCpu(e, rec.data(), out.data());
    for (const auto& f : e.outputs) {
        for (int i = f.slot; i < f.slot + f.width; ++i) {
            if (!std::isfinite(out[size_t(i)])) {
                std::fprintf(stderr, "fuzz_eval_line: %s output '%s' is not finite\n",
                             e.name.c_str(), f.key.c_str());
                std::abort();
            }
        }
    }
    const std::string text = sg::eval::formatResult(e, out.data());
    if (text.find('\n') != std::string::npos || !nlohmann::json::accept(text)) {
        std::fprintf(stderr, "fuzz_eval_line: bad output line %s\n", text.c_str());
        std::abort();
    }
    return 0;
}
