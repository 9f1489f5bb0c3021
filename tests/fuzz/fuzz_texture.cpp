// Fuzz entry point: texture files as a scene reads them
// (sg::render::decodeTextureImage, render/src/texture_file.cpp, over
// the one image decoder of image/src/image_decode.cpp): the
// image header scan (surfgrad/image/image_header.h), the size limit and the
// texture budget, then OpenImageIO's decoder of the scanned format, band
// by band, and the mip chain. Every format a scene accepts is reached:
// PNG, JPEG, OpenEXR, TIFF and Radiance HDR by their signatures, anything
// else as TGA (the name ends in .tga). The input's length picks what the
// layers read (all of RGBA, a normal map's r and g, DXT5nm's g and a, one
// height channel, or an sRGB colour map), so mutations reach every
// channel count and storage type.
//
// Documented errors (InputError) are expected. A crash, a hang, a
// sanitizer report, another exception, or a texture that breaks what the
// renderers rely on (level sizes, storage size equal to the budgeted
// prediction and within the budget, finite texels) is a bug.
//
// Seed corpus (corpus/texture): small valid files of every format and
// storage (oiiotool; a palette PNG with transparency, interlaced), the two
// files of issue 16 (a 69-byte PNG declaring 16384x16384 RGBA, a 134-byte
// TIFF declaring 64 channels) and JPEG, EXR, HDR and TGA headers declaring
// gigabytes.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "surfgrad/base/io.h"
#include "surfgrad/render.h"

namespace {

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz_texture: accepted texture violates: %s\n", what);
        std::abort();
    }
}

// Small enough that no input makes the fuzzer allocate much.
constexpr uint64_t kBudget = uint64_t(64) << 20;

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace sg::render;
    static const uint32_t kChannels[] = {0xFu, 0x3u, 0xAu, 0x8u, 0x7u};
    const size_t pick = size % 5;
    TextureLoadOptions opt;
    opt.channels = kChannels[pick];
    opt.budgetBytes = kBudget;
    const bool srgb = pick == 4;
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    TextureImage img;
    try {
        img = decodeTextureImage(bytes, "fuzz.tga", srgb, Wrap::Repeat, opt);
    } catch (const sg::io::InputError&) {
        return 0; // a documented refusal
    }
    check(!img.levels.empty(), "has levels");
    const TextureLevel& L0 = img.levels[0];
    check(L0.width >= 1 && L0.height >= 1 && L0.width <= kMaxTextureSize &&
              L0.height <= kMaxTextureSize,
          "level 0 size");
    check(L0.channels >= 1 && L0.channels <= 4 && L0.data.size() == L0.sampleBytes(),
          "level 0 storage");
    check(img.bytes() == textureBytes(L0.width, L0.height, L0.channels, L0.type),
          "storage equals the budgeted prediction");
    check(img.bytes() <= kBudget, "within the budget");
    check(img.sourceChannels >= 1 && (img.channelMask & ~0xFu) == 0, "channel bookkeeping");
    for (size_t l = 1; l < img.levels.size(); ++l) {
        const TextureLevel& a = img.levels[l - 1];
        const TextureLevel& b = img.levels[l];
        check(b.width == std::max(1, a.width / 2) && b.height == std::max(1, a.height / 2),
              "GL mip level sizes");
    }
    check(img.levels.back().width == 1 && img.levels.back().height == 1, "chain down to 1x1");
    // Texels the renderers will filter: finite everywhere (at most ~64k
    // samples per level so large images stay fast).
    for (const TextureLevel& L : img.levels) {
        const int step = std::max(1, int(std::sqrt(double(L.width) * L.height / 65536.0)));
        for (int y = 0; y < L.height; y += step)
            for (int x = 0; x < L.width; x += step) {
                const glm::vec4 t = L.texel(x, y);
                check(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z) &&
                          std::isfinite(t.w),
                      "finite texels");
            }
    }
    return 0;
}
