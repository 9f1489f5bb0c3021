// Fuzz entry point: font files through FreeType and our outline walker
// (sg::features::parseFont). The first input byte selects the text (Latin,
// CJK, mixed with a newline) and the face index; the rest is the font file.
// Documented errors (InputError) are expected; accepted networks must
// satisfy the loader guarantees of surfgrad/features/curves.h.
#include "surfgrad/features/curves.h"
#include "surfgrad/base/io.h"

#include <cstdint>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* const kTexts[4] = {"AOg", "g", "A O\nAg",
                                          "\xE4\xB8\xAD\x41"}; // last: U+4E2D then A
    sg::features::FontOptions opt;
    opt.faceIndex = (data[0] >> 2) & 1;
    try {
        const auto net =
            sg::features::parseFont(data + 1, size - 1, kTexts[data[0] & 3], "fuzz.ttf", opt);
        sg::features::checkNetwork(net);
        if (sg::features::findJunctions(net).empty()) std::abort();
    } catch (const sg::io::InputError&) {
    }
    return 0;
}
