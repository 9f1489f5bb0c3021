// Image files of the normal-map toolkit: raw channel values in through the
// guarded decoder (surfgrad/image_decode.h), atomic writes out through
// OpenImageIO, and the MIP-chain files of
// surfgrad/normalmap.h ("MIP chains for antialiasing").
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "surfgrad/image_decode.h"
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

// The options of every read: at most kMaxImageSide per side and 64
// channels, and room in the memory budget for the decoded samples plus the
// float image they become.
image::DecodeOptions readOptions(const fs::path& path, int level) {
    image::DecodeOptions opt;
    opt.maxSide = kMaxImageSide;
    opt.level = level;
    opt.checkMemory = [name = path.string()](const image::DecodePlan& p) {
        if (p.fileChannels > 64) {
            throw io::InputError(name, "channels",
                                 std::to_string(p.fileChannels) +
                                     " channels (a map has 1 to 64 channels)");
        }
        const uint64_t floats = uint64_t(p.width) * uint64_t(p.height) * uint64_t(p.channels) * 4;
        const uint64_t need = floats + p.imageBytes + p.transientBytes;
        const uint64_t budget = image::defaultMemoryBudget();
        if (need > budget) {
            throw io::InputError(name, "",
                                 p.describe() + ": needs " + io::formatBytes(need) +
                                     " as float; the memory budget is " + io::formatBytes(budget));
        }
    };
    return opt;
}

// The decoder's image as floats. Refusals without an element read
// "cannot read image: <reason>".
Image decodeToFloat(const fs::path& path, int level, image::DecodedImage* info = nullptr) {
    image::DecodedImage d;
    try {
        d = image::decodeImageFile(path, readOptions(path, level));
    } catch (const io::InputError& e) {
        if (!e.element().empty() || e.reason() == "no such file" ||
            e.reason().rfind("cannot read", 0) == 0)
            throw;
        throw io::InputError(e.file(), "", "cannot read image: " + e.reason());
    }
    Image img;
    img.width = d.width;
    img.height = d.height;
    img.channels = d.channels;
    img.isFloat = d.fileType == image::SampleType::Half || d.fileType == image::SampleType::Float;
    img.texels.resize(size_t(d.width) * size_t(d.height) * size_t(d.channels));
    size_t i = 0;
    for (int y = 0; y < d.height; ++y)
        for (int x = 0; x < d.width; ++x)
            for (int c = 0; c < d.channels; ++c) img.texels[i++] = d.sample(x, y, c);
    if (info) {
        d.data = {};
        *info = std::move(d);
    }
    return img;
}

} // namespace

Image readImage(const fs::path& path, SampleType* sampleType) {
    image::DecodedImage info;
    Image img = decodeToFloat(path, 0, &info);
    if (sampleType) {
        switch (info.fileType) {
        case image::SampleType::Unorm8:
            *sampleType = SampleType::U8;
            break;
        case image::SampleType::Unorm16:
            *sampleType = SampleType::U16;
            break;
        case image::SampleType::Half:
            *sampleType = SampleType::Half;
            break;
        case image::SampleType::Float:
            *sampleType = SampleType::Float;
            break;
        }
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

void checkWritable(const fs::path& path, SampleType type) {
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
}

SampleType mapSampleType(const fs::path& path, const MapFormat& format, std::string_view bits) {
    const bool needFloat = format.encoding == Encoding::Signed;
    const SampleType type =
        bits.empty() ? defaultSampleType(path, needFloat) : parseSampleType(bits);
    const bool isFloat = type == SampleType::Half || type == SampleType::Float;
    const std::string e = lowerExt(path);
    if (needFloat && (!isFloat || e == ".png" || e == ".tga")) {
        throw io::InputError(
            path.string(), "encoding",
            "signed normals need a float output (.exr, or .tif with --bits float)");
    }
    checkWritable(path, type);
    return type;
}

void writeImage(const fs::path& path, const Image& image, SampleType type,
                const std::vector<std::pair<std::string, std::string>>& attributes) {
    checkWritable(path, type);
    const std::string e = lowerExt(path);
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
    image::DecodedImage info;
    Image first = decodeToFloat(path, 0, &info);
    const std::vector<std::string>& fileNames = info.channelNames;
    const auto attr = info.stringAttributes.find("surfgrad:layout");
    const std::string lay = attr == info.stringAttributes.end() ? "" : attr->second;
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
    for (int level = 0; level < info.levels; ++level) {
        const Image raw = level == 0 ? std::move(first) : decodeToFloat(path, level);
        Image L = raw;
        L.channels = int(from.size());
        L.texels.resize(size_t(L.width) * size_t(L.height) * from.size());
        for (int j = 0; j < L.height; ++j)
            for (int i = 0; i < L.width; ++i)
                for (int c = 0; c < L.channels; ++c) L.at(i, j, c) = raw.at(i, j, from[size_t(c)]);
        levels.push_back(std::move(L));
    }
    if (channelNames) *channelNames = names;
    if (layout) *layout = lay;
    return levels;
}

} // namespace sg::normalmap
