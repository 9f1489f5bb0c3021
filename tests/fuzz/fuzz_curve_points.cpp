// libFuzzer entry for the text parsers of `surfgrad normalmap`: curve
// points (curves --points / --points-file, parseCurvePoints) and warps
// (deform --warp, parseWarp), surfgrad/normalmap/operations.h. Input: the first byte
// selects the parser (even: curve, odd: warp), the rest is the text.
// Properties beyond "no crash / no sanitizer report / only InputError":
// an accepted curve has 2 to 64 points with x strictly increasing in
// [0, 1] and its slope is finite everywhere in [0, 1] (and beyond); an
// accepted warp has finite parameters.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "surfgrad/base/io.h"
#include "surfgrad/normalmap/operations.h"

namespace {

void fail(const char* what) {
    std::fprintf(stderr, "fuzz_curve_points: %s\n", what);
    std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    namespace nm = sg::normalmap;
    if (data[0] % 2 == 0) {
        nm::Curve c;
        try {
            c = nm::parseCurvePoints(text, "fuzz");
        } catch (const sg::io::InputError&) {
            return 0;
        }
        if (c.points.size() < 2 || c.points.size() > 64 || c.slopes.size() != c.points.size()) {
            fail("accepted curve with a bad point count");
        }
        for (size_t k = 0; k < c.points.size(); ++k) {
            if (!(c.points[k].x >= 0.0f && c.points[k].x <= 1.0f)) fail("x outside [0, 1]");
            if (k && !(c.points[k].x > c.points[k - 1].x)) fail("x not increasing");
        }
        for (int k = -10; k <= 1010; ++k) {
            if (!std::isfinite(c.slopeAt(float(k) / 1000.0f))) fail("non-finite slope");
        }
    } else {
        nm::Warp w;
        try {
            w = nm::parseWarp(text);
        } catch (const sg::io::InputError&) {
            return 0;
        }
        if (!std::isfinite(w.a) || !std::isfinite(w.b)) fail("non-finite warp parameter");
    }
    return 0;
}
