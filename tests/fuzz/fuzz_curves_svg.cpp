// Fuzz entry point: SVG drawings (sg::features::parseSvg): the XML (pugixml
// and the checks on its tree), path data, shapes, transforms and the
// cubic/arc approximation.
// Documented errors (InputError) are expected; accepted networks must
// satisfy the loader guarantees of surfgrad/features/curves.h.
#include "surfgrad/features/curves.h"
#include "surfgrad/base/io.h"

#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const auto net = sg::features::parseSvg(
            std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.svg");
        sg::features::checkNetwork(net);
        if (sg::features::findJunctions(net).empty()) std::abort();
    } catch (const sg::io::InputError&) {
    }
    return 0;
}
