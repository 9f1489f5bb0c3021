// Texture files (loadTexture, decodeTextureImage): untrusted images decoded
// by the guarded decoder of surfgrad/image/image_decode.h (header scan, limits,
// band-by-band decoding into the file's own precision) under the scene's
// texture budget, which counts the mip chain in its stored format plus the
// decoder's own buffers. Channels past the highest one the layers read are
// not decoded; half sources of sRGB colour maps become float (the sRGB
// curve has no half table), float ones are linearised here.
#include <algorithm>
#include <cstring>
#include <limits>
#include <new>

#include "render_internal.h"
#include "surfgrad/image/image_decode.h"
#include "surfgrad/base/io.h"
#include "surfgrad/render.h"

namespace sg::render {

namespace fs = std::filesystem;

uint64_t defaultTextureBudget() {
    return image::defaultMemoryBudget();
}

namespace {

using io::formatBytes;
using io::InputError;

TexelType texelType(image::SampleType t) {
    switch (t) {
    case image::SampleType::Unorm8:
        return TexelType::Unorm8;
    case image::SampleType::Unorm16:
        return TexelType::Unorm16;
    case image::SampleType::Half:
        return TexelType::Half;
    case image::SampleType::Float:
        break;
    }
    return TexelType::Float;
}

} // namespace

void detail::checkTextureBudget(const std::string& name, const TextureLoadOptions& opt,
                                const std::string& what, uint64_t resident, uint64_t transient) {
    const uint64_t budget = opt.budgetBytes ? opt.budgetBytes : defaultTextureBudget();
    const uint64_t need = resident + std::min(transient, ~uint64_t(0) - resident);
    if (opt.usedBytes <= budget && need <= budget - opt.usedBytes) return;
    std::string reason = what + ": needs " + formatBytes(resident) + " with its mip chain";
    if (transient > 0) reason += " and " + formatBytes(transient) + " more while decoding";
    reason += "; the texture budget is " + formatBytes(budget);
    if (opt.otherTextures > 0) {
        reason += ", of which the scene's " + std::to_string(opt.otherTextures) + " other texture" +
                  (opt.otherTextures == 1 ? " takes " : "s take ") + formatBytes(opt.usedBytes);
    }
    throw InputError(name, "", reason + " (--texture-budget)");
}

namespace {

using detail::checkTextureBudget;

// What the decoder may produce for a texture read by layers that read the
// RGBA components `opt.channels`.
image::DecodeOptions decodeOptions(const std::string& name, bool srgb,
                                   const TextureLoadOptions& opt) {
    image::DecodeOptions d;
    d.maxSide = kMaxTextureSize;
    int highest = 0;
    for (int c = 0; c < 4; ++c)
        if (opt.channels >> c & 1u) highest = c;
    d.maxChannels = highest + 1;
    d.keepHalf = !srgb;
    // Mip levels sum up to four texels in float: larger magnitudes would
    // overflow to infinity there.
    d.maxMagnitude = std::numeric_limits<float>::max() / 4.0f;
    d.checkMemory = [name, opt](const image::DecodePlan& p) {
        checkTextureBudget(name, opt, p.describe(),
                           textureBytes(int(p.width), int(p.height), p.channels, texelType(p.type)),
                           p.transientBytes);
    };
    return d;
}

// Level 0 and the mip chain of a decoded file.
TextureImage toTexture(image::DecodedImage&& d, const std::string& name, bool srgb, Wrap wrap) {
    TextureLevel L;
    L.width = d.width;
    L.height = d.height;
    L.channels = d.channels;
    L.type = texelType(d.type);
    L.srgb = srgb && (L.type == TexelType::Unorm8 || L.type == TexelType::Unorm16);
    L.data = std::move(d.data);
    if (srgb && L.type == TexelType::Float) { // colour maps are filtered on linear values
        const size_t n = L.data.size() / 4;
        for (size_t i = 0; i < n; ++i) {
            if (int(i % size_t(L.channels)) >= 3) continue;
            float f;
            std::memcpy(&f, &L.data[4 * i], 4);
            f = srgbToLinear(f);
            std::memcpy(&L.data[4 * i], &f, 4);
        }
    }
    const uint64_t bytes = textureBytes(L.width, L.height, L.channels, L.type);
    try {
        TextureImage img = makeTexture(std::move(L), wrap);
        img.channelMask = d.fileChannels == 1 ? 0x7u : (1u << d.channels) - 1u;
        img.sourceChannels = d.fileChannels;
        return img;
    } catch (const std::bad_alloc&) {
        throw InputError(name, "",
                         "out of memory building the mip chain of " + std::to_string(d.width) +
                             "x" + std::to_string(d.height) + " pixels (" + formatBytes(bytes) +
                             ")");
    }
}

} // namespace

TextureImage decodeTextureImage(std::string_view bytes, const std::string& name, bool srgb,
                                Wrap wrap, const TextureLoadOptions& options) {
    return toTexture(image::decodeImageBytes(bytes, name, decodeOptions(name, srgb, options)), name,
                     srgb, wrap);
}

std::shared_ptr<const TextureImage> loadTexture(const TextureSource& src,
                                                const std::string& sceneName,
                                                const TextureLoadOptions& options) {
    if (src.moments != TexMoments::None) {
        // The normal map itself, then its moments (float RGBA, own mips).
        TextureSource base = src;
        base.moments = TexMoments::None;
        std::shared_ptr<const TextureImage> map = loadTexture(base, sceneName, options);
        try {
            checkTextureBudget("moments of " + base.key(), options,
                               std::to_string(map->width()) + "x" + std::to_string(map->height()) +
                                   " pixels, 4 channels as float",
                               textureBytes(map->width(), map->height(), 4, TexelType::Float),
                               map->bytes());
        } catch (const InputError& e) {
            throw InputError(sceneName, src.fieldPath, e.what());
        }
        return std::make_shared<TextureImage>(
            detail::normalMomentTexture(*map, src.moments, src.momentsEncoding));
    }
    if (!src.procedural.empty()) {
        try {
            checkTextureBudget("procedural texture " + src.procedural, options,
                               std::to_string(src.size) + "x" + std::to_string(src.size) +
                                   " pixels, 4 channels as float",
                               textureBytes(src.size, src.size, 4, TexelType::Float), 0);
        } catch (const InputError& e) {
            throw InputError(sceneName, src.fieldPath, e.what());
        }
        return std::make_shared<TextureImage>(detail::makeProceduralTexture(src));
    }
    const std::string name = src.file.lexically_normal().string();
    // "<scene>: <field>: <image>: <element>: <reason>" (detail::fromReferencedFile).
    return detail::fromReferencedFile(sceneName, src.fieldPath, [&] {
        std::error_code ec;
        if (!fs::is_regular_file(src.file, ec)) {
            throw InputError(name, "",
                             fs::exists(src.file, ec) ? "not a regular file" : "does not exist");
        }
        return std::make_shared<TextureImage>(
            toTexture(image::decodeImageFile(src.file, decodeOptions(name, src.srgb, options)),
                      name, src.srgb, src.wrap));
    });
}

} // namespace sg::render
