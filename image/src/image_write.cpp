// The image writer (surfgrad/image/image_write.h): the format and sample-type
// check by extension, OpenImageIO's spec from WriteOptions, and the samples
// converted a band of rows at a time (flipped to the file's top-first
// order, cleaned for the file's sample type) inside sg::io::writeAtomically,
// as OpenImageIO's write_image would send them (rows of tiles for tiled
// files), without a second copy of the whole image.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <type_traits>

#include "oiio_sample_type.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/image/image_write.h"
#include "surfgrad/base/io.h"

namespace sg::image {

namespace fs = std::filesystem;

namespace {

using io::InputError;

// The type as checkWritable's messages name it.
const char* writtenTypeName(SampleType type) {
    switch (type) {
    case SampleType::Unorm8:
        return "8-bit";
    case SampleType::Unorm16:
        return "16-bit";
    case SampleType::Half:
        return "half";
    case SampleType::Float:
        break;
    }
    return "float";
}

bool isUnorm(SampleType type) {
    return type == SampleType::Unorm8 || type == SampleType::Unorm16;
}

constexpr int kMipTileSide = 64; // pixels

// OpenImageIO's spec of one image (a MIP level) from the options.
OIIO::ImageSpec makeSpec(const FloatPixels& pixels, const WriteOptions& options, bool exr) {
    OIIO::ImageSpec spec(pixels.width, pixels.height, pixels.channels, oiioType(options.type));
    if (!options.channelNames.empty()) spec.channelnames = options.channelNames;
    spec.alpha_channel = options.alphaChannel;
    if (exr) spec.attribute("compression", "zip");
    for (const Attribute& a : options.attributes) {
        std::visit(
            [&](const auto& v) {
                using T = std::decay_t<decltype(v)>;
                if constexpr (std::is_same_v<T, int> || std::is_same_v<T, std::string>) {
                    spec.attribute(a.name, v);
                } else if constexpr (std::is_same_v<T, double>) {
                    spec.attribute(a.name, OIIO::TypeDesc::DOUBLE, &v);
                } else {
                    SG_EXPECTS(!v.empty(), "a float-array attribute holds at least one float");
                    spec.attribute(a.name, OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, int(v.size())),
                                   v.data());
                }
            },
            a.value);
    }
    if (!options.colorSpace.empty()) spec.attribute("oiio:ColorSpace", options.colorSpace);
    // Colour channels as given: OpenImageIO would otherwise divide PNG's
    // colour by alpha and mark TIFF's alpha as associated.
    if (options.alphaChannel >= 0) spec.attribute("oiio:UnassociatedAlpha", 1);
    return spec;
}

// An empty image is refused (InputError: there is no such file to write);
// the rest is the caller's part of the contract.
void checkPixels(const fs::path& path, const FloatPixels& pixels, const WriteOptions& options) {
    if (pixels.width < 1 || pixels.height < 1 || pixels.channels < 1) {
        throw InputError(path.string(), "",
                         "cannot write image: " + std::to_string(pixels.width) + "x" +
                             std::to_string(pixels.height) + " pixels, " +
                             std::to_string(pixels.channels) +
                             " channels (an image has at least one pixel and one channel)");
    }
    SG_EXPECTS(pixels.samples != nullptr, "samples to write");
    SG_EXPECTS(options.channelNames.empty() ||
                   options.channelNames.size() == size_t(pixels.channels),
               "one channel name per channel, or none");
    SG_EXPECTS(options.alphaChannel >= -1 && options.alphaChannel < pixels.channels,
               "alphaChannel is -1 or one of the channels");
}

// Writes the rows of `pixels` (bottom row first in memory) to the open
// file, top row first, a band at a time: scanlines, or whole rows of tiles
// when tileRows > 0. `element` names a MIP level in messages.
void writeRows(OIIO::ImageOutput& out, const FloatPixels& pixels, const WriteOptions& options,
               int tileRows, const fs::path& path, const std::string& element) {
    const int w = pixels.width, h = pixels.height;
    const size_t rowFloats = size_t(w) * size_t(pixels.channels);
    // About 1 MiB of floats per band (at least a row, or a row of tiles).
    int bandRows = int(std::clamp<size_t>((size_t(1) << 18) / rowFloats, 1, size_t(h)));
    if (tileRows > 0) bandRows = std::min(h, (bandRows + tileRows - 1) / tileRows * tileRows);
    const bool unorm = isUnorm(options.type);
    const bool zeroNonFinite = unorm || options.nonFiniteToZero;
    std::vector<float> band(size_t(bandRows) * rowFloats);
    for (int y0 = 0; y0 < h; y0 += bandRows) {
        const int rows = std::min(bandRows, h - y0);
        for (int r = 0; r < rows; ++r) {
            const float* src = pixels.samples + size_t(h - 1 - (y0 + r)) * rowFloats;
            float* dst = band.data() + size_t(r) * rowFloats;
            if (!zeroNonFinite) {
                std::copy(src, src + rowFloats, dst);
                continue;
            }
            for (size_t k = 0; k < rowFloats; ++k) {
                const float v = std::isfinite(src[k]) ? src[k] : 0.0f;
                dst[k] = unorm ? std::clamp(v, 0.0f, 1.0f) : v;
            }
        }
        const bool ok =
            tileRows > 0
                ? out.write_tiles(0, w, y0, y0 + rows, 0, 1, OIIO::TypeDesc::FLOAT, band.data())
                : out.write_scanlines(y0, y0 + rows, 0, OIIO::TypeDesc::FLOAT, band.data());
        if (!ok) throw InputError(path.string(), element, "cannot write image: " + out.geterror());
    }
}

std::unique_ptr<OIIO::ImageOutput> createWriter(const fs::path& path, const fs::path& tmp) {
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) {
        throw InputError(path.string(), "", "cannot create image writer: " + OIIO::geterror());
    }
    return out;
}

} // namespace

void checkWritable(const fs::path& path, SampleType type) {
    const std::string ext = lowerExtension(path);
    const bool exr = ext == ".exr", png = ext == ".png", tga = ext == ".tga",
               tif = ext == ".tif" || ext == ".tiff";
    const bool ok = (png && isUnorm(type)) || (tga && type == SampleType::Unorm8) || tif ||
                    (exr && !isUnorm(type));
    if (ok) return;
    const std::string what = std::string("cannot write ") + writtenTypeName(type) + " samples";
    const std::string pairs = "png: 8/16-bit, tga: 8-bit, tif: any, exr: half/float";
    if (ext.empty()) {
        throw InputError(path.string(), "",
                         what + ": the file name has no extension to choose a format by (" + pairs +
                             ")");
    }
    const bool known = exr || png || tga || tif;
    throw InputError(path.string(), "",
                     what + " as \"" + ext + "\"" +
                         (known ? " (" : ": not an image format this writer knows (") + pairs +
                         ")");
}

void writeImageFile(const fs::path& path, const FloatPixels& pixels, const WriteOptions& options) {
    checkPixels(path, pixels, options);
    checkWritable(path, options.type);
    const bool exr = lowerExtension(path) == ".exr";
    io::writeAtomically(path, [&](const fs::path& tmp) {
        auto out = createWriter(path, tmp);
        if (!out->open(tmp.string(), makeSpec(pixels, options, exr))) {
            throw InputError(path.string(), "", "cannot write image: " + out->geterror());
        }
        writeRows(*out, pixels, options, 0, path, "");
        if (!out->close()) {
            throw InputError(path.string(), "", "cannot write image: " + out->geterror());
        }
    });
}

FloatPixels floatPixels(const Image& image) {
    SG_EXPECTS(image.samples.size() == image.texelCount() * size_t(std::max(image.channels, 0)),
               "Image::samples has width * height * channels entries");
    return {image.samples.empty() ? nullptr : image.samples.data(), image.width, image.height,
            image.channels};
}

void writeImageFile(const fs::path& path, const Image& image, const WriteOptions& options) {
    writeImageFile(path, floatPixels(image), options);
}

void writeMipChainFile(const fs::path& path, const std::vector<FloatPixels>& levels,
                       const WriteOptions& options) {
    SG_EXPECTS(!levels.empty(), "a MIP chain has a level 0");
    for (size_t k = 0; k < levels.size(); ++k) {
        checkPixels(path, levels[k], options);
        if (k == 0) continue;
        SG_EXPECTS(levels[k].channels == levels[0].channels, "every level has level 0's channels");
        SG_EXPECTS(levels[k].width == std::max(1, levels[k - 1].width / 2) &&
                       levels[k].height == std::max(1, levels[k - 1].height / 2),
                   "each level halves the previous one (rounding down, at least 1)");
    }
    SG_EXPECTS(levels.back().width == 1 && levels.back().height == 1,
               "the chain ends with a 1x1 level");
    if (lowerExtension(path) != ".exr" || isUnorm(options.type)) {
        throw InputError(path.string(), "",
                         "a MIP chain is written as OpenEXR (.exr) with half or float samples");
    }
    io::writeAtomically(path, [&](const fs::path& tmp) {
        auto out = createWriter(path, tmp);
        if (!out->supports("mipmap")) {
            throw InputError(path.string(), "", "cannot create a MIP-mapped OpenEXR writer");
        }
        for (size_t k = 0; k < levels.size(); ++k) {
            OIIO::ImageSpec spec = makeSpec(levels[k], options, true);
            spec.tile_width = kMipTileSide;
            spec.tile_height = kMipTileSide;
            spec.attribute("textureformat", "Plain Texture");
            spec.attribute("openexr:levelmode", 1);    // MIPMAP_LEVELS
            spec.attribute("openexr:roundingmode", 0); // ROUND_DOWN
            const std::string level = "level " + std::to_string(k);
            const auto mode =
                k == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendMIPLevel;
            if (!out->open(tmp.string(), spec, mode)) {
                throw InputError(path.string(), level, "cannot write image: " + out->geterror());
            }
            writeRows(*out, levels[k], options, kMipTileSide, path, level);
        }
        if (!out->close()) {
            throw InputError(path.string(), "", "cannot write image: " + out->geterror());
        }
    });
}

} // namespace sg::image
