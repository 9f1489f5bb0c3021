// Image files of the normal-map toolkit through OpenImageIO: raw channel
// values in, atomic writes out, and the MIP-chain files of
// surfgrad/normalmap.h ("MIP chains for antialiasing").
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "surfgrad/io.h"
#include "surfgrad/normalmap.h"

namespace sg::normalmap {

namespace fs = std::filesystem;

namespace {

std::string lowerExt(const fs::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

OIIO::TypeDesc oiioType(SampleType t) {
    switch (t) {
    case SampleType::U8:
        return OIIO::TypeDesc::UINT8;
    case SampleType::U16:
        return OIIO::TypeDesc::UINT16;
    case SampleType::Half:
        return OIIO::TypeDesc::HALF;
    default:
        return OIIO::TypeDesc::FLOAT;
    }
}

const char* typeName(SampleType t) {
    switch (t) {
    case SampleType::U8:
        return "8-bit";
    case SampleType::U16:
        return "16-bit";
    case SampleType::Half:
        return "half";
    default:
        return "float";
    }
}

// Opens `path` for reading with alpha kept as stored (OpenImageIO would
// multiply the colour channels of PNG/TGA/TIFF files with unassociated
// alpha by it: a height in alpha would scale the normal).
std::unique_ptr<OIIO::ImageInput> openInput(const fs::path& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        throw io::InputError(path.string(), "", "no such file");
    }
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path.string(), &config);
    if (!in) {
        throw io::InputError(path.string(), "", "cannot read image (" + OIIO::geterror() + ")");
    }
    return in;
}

void checkSize(const fs::path& path, const OIIO::ImageSpec& spec) {
    const bool sizeOk = spec.width >= 1 && spec.height >= 1 && spec.width <= kMaxImageSide &&
                        spec.height <= kMaxImageSide &&
                        size_t(spec.width) * size_t(spec.height) <= kMaxImageTexels;
    if (!sizeOk || spec.depth > 1) {
        throw io::InputError(path.string(), "size",
                             std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                                 " is not a supported image size (1 to " +
                                 std::to_string(kMaxImageSide) + " per side)");
    }
    if (spec.nchannels < 1 || spec.nchannels > 64) {
        throw io::InputError(path.string(), "channels",
                             std::to_string(spec.nchannels) +
                                 " channels (a map has 1 to 64 channels)");
    }
}

// Decodes the current subimage/level into an Image (bottom row first) and
// refuses non-finite texels.
Image decode(const fs::path& path, OIIO::ImageInput& in, int subimage, int level) {
    const OIIO::ImageSpec& spec = in.spec();
    checkSize(path, spec);
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.nchannels;
    img.isFloat = spec.format.is_floating_point();
    const size_t rowFloats = size_t(img.width) * size_t(img.channels);
    std::vector<float> raw(rowFloats * size_t(img.height));
    if (!in.read_image(subimage, level, 0, img.channels, OIIO::TypeDesc::FLOAT, raw.data())) {
        throw io::InputError(path.string(), "", "cannot decode image: " + in.geterror());
    }
    img.texels.resize(raw.size());
    for (int y = 0; y < img.height; ++y) {
        const float* src = &raw[size_t(y) * rowFloats];
        for (size_t k = 0; k < rowFloats; ++k) {
            if (!std::isfinite(src[k])) {
                throw io::InputError(path.string(),
                                     "pixel (" + std::to_string(k / size_t(img.channels)) + ", " +
                                         std::to_string(y) + ") channel " +
                                         std::to_string(k % size_t(img.channels)),
                                     "non-finite value");
            }
        }
        std::copy(src, src + rowFloats, &img.texels[size_t(img.height - 1 - y) * rowFloats]);
    }
    return img;
}

// The texels of `img` top row first, clamped to [0, 1] for integer types.
std::vector<float> fileOrder(const Image& img, SampleType type) {
    const size_t rowFloats = size_t(img.width) * size_t(img.channels);
    std::vector<float> buf(rowFloats * size_t(img.height));
    const bool clampUnit = type == SampleType::U8 || type == SampleType::U16;
    for (int y = 0; y < img.height; ++y) {
        const float* src = &img.texels[size_t(img.height - 1 - y) * rowFloats];
        float* dst = &buf[size_t(y) * rowFloats];
        for (size_t k = 0; k < rowFloats; ++k) {
            float v = std::isfinite(src[k]) ? src[k] : 0.0f;
            dst[k] = clampUnit ? std::clamp(v, 0.0f, 1.0f) : v;
        }
    }
    return buf;
}

} // namespace

Image readImage(const fs::path& path, SampleType* sampleType) {
    auto in = openInput(path);
    const OIIO::TypeDesc f = in->spec().format;
    Image img = decode(path, *in, 0, 0);
    in->close();
    if (sampleType) {
        *sampleType = f == OIIO::TypeDesc::UINT8    ? SampleType::U8
                      : f == OIIO::TypeDesc::UINT16 ? SampleType::U16
                      : f == OIIO::TypeDesc::HALF   ? SampleType::Half
                                                    : SampleType::Float;
    }
    return img;
}

SampleType defaultSampleType(const fs::path& path, bool needFloat) {
    const std::string e = lowerExt(path);
    if (e == ".exr") return SampleType::Float;
    if (needFloat) return SampleType::Float;
    if (e == ".tif" || e == ".tiff") return SampleType::U16;
    return SampleType::U8;
}

SampleType parseSampleType(std::string_view text) {
    if (text == "8") return SampleType::U8;
    if (text == "16") return SampleType::U16;
    if (text == "half") return SampleType::Half;
    if (text == "float" || text == "32") return SampleType::Float;
    throw io::InputError("--bits", std::string(text), "expected 8, 16, half or float");
}

void writeImage(const fs::path& path, const Image& image, SampleType type,
                const std::vector<std::pair<std::string, std::string>>& attributes) {
    const std::string e = lowerExt(path);
    const bool isInt = type == SampleType::U8 || type == SampleType::U16;
    bool ok = false;
    if (e == ".png") ok = isInt;
    if (e == ".tga") ok = type == SampleType::U8;
    if (e == ".tif" || e == ".tiff") ok = true;
    if (e == ".exr") ok = !isInt;
    if (!ok) {
        throw io::InputError(path.string(), "",
                             std::string("cannot write ") + typeName(type) + " samples as \"" + e +
                                 "\" (png: 8/16-bit, tga: 8-bit, tif: any, exr: half/float)");
    }
    const std::vector<float> buf = fileOrder(image, type);
    io::writeAtomically(path, [&](const fs::path& tmp) {
        auto out = OIIO::ImageOutput::create(tmp.string());
        if (!out) {
            throw io::InputError(path.string(), "",
                                 "cannot create image writer: " + OIIO::geterror());
        }
        OIIO::ImageSpec spec(image.width, image.height, image.channels, oiioType(type));
        if (image.channels == 4) spec.alpha_channel = 3;
        if (e == ".exr") spec.attribute("compression", "zip");
        for (const auto& [k, v] : attributes) spec.attribute(k, v);
        // Data, not colour: no gamma/colour-space tag beyond "linear".
        spec.attribute("oiio:ColorSpace", "Linear");
        spec.attribute("oiio:UnassociatedAlpha", 1);
        if (!out->open(tmp.string(), spec) ||
            !out->write_image(OIIO::TypeDesc::FLOAT, buf.data()) || !out->close()) {
            throw io::InputError(path.string(), "", "cannot write image: " + out->geterror());
        }
    });
}

void writeMipChain(const fs::path& path, const std::vector<Image>& levels,
                   const std::vector<std::string>& channelNames, const std::string& layout,
                   Wrap wrap) {
    if (lowerExt(path) != ".exr") {
        throw io::InputError(path.string(), "", "a MIP chain is written as OpenEXR (.exr)");
    }
    if (levels.empty() || int(channelNames.size()) != levels[0].channels) {
        throw io::InputError(path.string(), "", "empty MIP chain or channel names do not match");
    }
    io::writeAtomically(path, [&](const fs::path& tmp) {
        auto out = OIIO::ImageOutput::create(tmp.string());
        if (!out || !out->supports("mipmap")) {
            throw io::InputError(path.string(), "", "cannot create a MIP-mapped OpenEXR writer");
        }
        for (size_t k = 0; k < levels.size(); ++k) {
            const Image& L = levels[k];
            OIIO::ImageSpec spec(L.width, L.height, L.channels, OIIO::TypeDesc::FLOAT);
            spec.tile_width = 64;
            spec.tile_height = 64;
            spec.channelnames = channelNames;
            spec.attribute("compression", "zip");
            // A MIP-mapped tiled file (OpenEXR MIPMAP_LEVELS, ROUND_DOWN).
            spec.attribute("textureformat", "Plain Texture");
            spec.attribute("openexr:levelmode", 1);
            spec.attribute("openexr:roundingmode", 0);
            spec.attribute("surfgrad:layout", layout);
            spec.attribute("surfgrad:wrap", wrap == Wrap::Repeat ? "repeat" : "clamp");
            spec.attribute("oiio:ColorSpace", "Linear");
            const auto mode =
                k == 0 ? OIIO::ImageOutput::Create : OIIO::ImageOutput::AppendMIPLevel;
            const std::vector<float> buf = fileOrder(L, SampleType::Float);
            if (!out->open(tmp.string(), spec, mode) ||
                !out->write_image(OIIO::TypeDesc::FLOAT, buf.data())) {
                throw io::InputError(path.string(), "level " + std::to_string(k),
                                     "cannot write: " + out->geterror());
            }
        }
        if (!out->close()) {
            throw io::InputError(path.string(), "", "cannot write: " + out->geterror());
        }
    });
}

std::vector<std::string> mipChannelNames(std::string_view layout) {
    if (layout == kLeanLayout) return {"dx", "dy", "dxx", "dyy", "dxy"};
    if (layout == kToksvigLayout) return {"nx", "ny", "nz", "s2"};
    if (layout == kNaiveMipLayout) return {"nx", "ny", "nz"};
    return {};
}

std::vector<Image> readMipChain(const fs::path& path, std::vector<std::string>* channelNames,
                                std::string* layout) {
    auto in = openInput(path);
    const std::vector<std::string> fileNames = in->spec().channelnames;
    const std::string lay = in->spec().get_string_attribute("surfgrad:layout");
    // OpenEXR stores channels sorted by name: put a known layout's back in
    // its documented order.
    std::vector<std::string> names = mipChannelNames(lay);
    std::vector<int> from;
    for (const std::string& n : names) {
        auto it = std::find(fileNames.begin(), fileNames.end(), n);
        if (it == fileNames.end()) {
            throw io::InputError(path.string(), "channels",
                                 "layout " + lay + " needs a channel \"" + n + "\"");
        }
        from.push_back(int(it - fileNames.begin()));
    }
    if (names.empty()) {
        names = fileNames;
        for (size_t c = 0; c < names.size(); ++c) from.push_back(int(c));
    }
    std::vector<Image> levels;
    for (int level = 0; level < 64 && in->seek_subimage(0, level); ++level) {
        Image raw = decode(path, *in, 0, level);
        Image L = raw;
        L.channels = int(from.size());
        L.texels.resize(size_t(L.width) * size_t(L.height) * from.size());
        for (int j = 0; j < L.height; ++j)
            for (int i = 0; i < L.width; ++i)
                for (int c = 0; c < L.channels; ++c) L.at(i, j, c) = raw.at(i, j, from[size_t(c)]);
        levels.push_back(std::move(L));
    }
    in->close();
    if (channelNames) *channelNames = names;
    if (layout) *layout = lay;
    return levels;
}

} // namespace sg::normalmap
