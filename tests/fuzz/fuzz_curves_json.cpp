// Fuzz entry point: JSON curve networks (sg::features::parseCurvesJson).
// Documented errors (InputError) are expected; anything else (a crash, a
// sanitizer report, another exception) is a bug. Accepted networks must
// satisfy the loader guarantees of surfgrad/features/curves.h.
#include "surfgrad/features/curves.h"
#include "surfgrad/base/io.h"

#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const auto net = sg::features::parseCurvesJson(
            std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json");
        sg::features::checkNetwork(net);
        if (sg::features::findJunctions(net).empty()) std::abort();
    } catch (const sg::io::InputError&) {
    }
    return 0;
}
