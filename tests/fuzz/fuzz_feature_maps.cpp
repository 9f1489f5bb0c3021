// Fuzz entry point: feature-map files (OpenEXR through the image decoder,
// image/src/image_decode.cpp, then our validation of channels, values,
// metadata and signatures;
// sg::features::loadFromMemory). Documented errors (InputError) are
// expected; maps that load must evaluate to finite values everywhere, which
// is what the validation promises the shader.
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/base/io.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string bytes(reinterpret_cast<const char*>(data), size);
    try {
        sg::features::FeatureMaps m = sg::features::loadFromMemory(bytes, "fuzz.exr");
        sg::features::GpuFeatureMaps g = m.packGpu();
        const int per = 3;
        for (int j = -1; j <= g.size * per + 1; ++j) {
            for (int i = -1; i <= g.size * per + 1; ++i) {
                auto r = sg::features::sample(g, glm::vec2(float(i) / per, float(j) / per));
                if (!std::isfinite(r.dist) || !std::isfinite(r.grad.x) ||
                    !std::isfinite(r.grad.y) || r.dist < 0.0f) {
                    std::abort();
                }
            }
        }
    } catch (const sg::io::InputError&) {
    }
    return 0;
}
