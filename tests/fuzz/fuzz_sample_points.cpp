// Fuzz entry point: point files of `surfgrad features sample`
// (sg::features::parseSamplePoints), then the feature-map evaluator at every
// accepted point, as the command runs it, on a small map baked once (a star
// junction, a parabola and a line tangent to it: the evaluator's hard
// cases).
// Documented errors (InputError) are expected; accepted points must be
// finite and within 1e30, and every sample finite with d >= 0 (points far
// outside the map included). A crash, a sanitizer report or another
// exception is a bug.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "surfgrad/features/curves.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/base/io.h"

namespace {

const sg::features::GpuFeatureMaps& maps() {
    static const sg::features::GpuFeatureMaps m = [] {
        const char* json = R"({"version": 1, "curves": [
            {"points": [[8, 9], [14, 15]]}, {"points": [[8, 9], [2, 15]]},
            {"points": [[8, 9], [15, 9]]}, {"points": [[8, 9], [1, 9]]},
            {"segments": [{"quad": [[3, 5], [8, 1], [13, 5]]}]},
            {"points": [[1, 3], [15, 3]]}]})";
        const auto net = sg::features::parseCurvesJson(json, "fuzz-map.json");
        sg::features::BakeOptions o;
        o.size = 16;
        o.mode = sg::features::BakeMode::Quadratic;
        o.marginTexels = 1.0;
        return sg::features::bake(net, o).packGpu();
    }();
    return m;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    std::vector<glm::vec2> pts;
    try {
        pts = sg::features::parseSamplePoints(text, "fuzz.txt");
    } catch (const sg::io::InputError&) {
        return 0; // a documented rejection
    }
    const sg::features::GpuFeatureMaps& m = maps();
    for (const glm::vec2& p : pts) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || std::fabs(p.x) > 1e30f ||
            std::fabs(p.y) > 1e30f) {
            std::fprintf(stderr, "fuzz_sample_points: accepted point %g %g\n", p.x, p.y);
            std::abort();
        }
        const auto r = sg::features::sample(m, p);
        if (!std::isfinite(r.dist) || !std::isfinite(r.grad.x) || !std::isfinite(r.grad.y) ||
            r.dist < 0.0f) {
            std::fprintf(stderr, "fuzz_sample_points: sample at %g %g is d %g grad %g %g\n", p.x,
                         p.y, r.dist, r.grad.x, r.grad.y);
            std::abort();
        }
    }
    return 0;
}
