// Image files of the normal-map toolkit: raw channel values in through the
// guarded decoder (surfgrad/image/image_decode.h), out through the image writer
// (surfgrad/image/image_write.h), and the MIP-chain files of
// surfgrad/normalmap/operations.h ("MIP chains for antialiasing").
#include <algorithm>
#include <cmath>

#include "surfgrad/image/image_decode.h"
#include "surfgrad/image/image_write.h"
#include "surfgrad/base/io.h"
#include "surfgrad/normalmap/operations.h"

namespace sg::normalmap {

namespace fs = std::filesystem;

namespace {

image::SampleType writtenType(SampleType t) {
    switch (t) {
    case SampleType::U8:
        return image::SampleType::Unorm8;
    case SampleType::U16:
        return image::SampleType::Unorm16;
    case SampleType::Half:
        return image::SampleType::Half;
    default:
        return image::SampleType::Float;
    }
}

// The options every file of the toolkit shares: data, not colour (no
// gamma/colour-space tag beyond "Linear"), non-finite texels as 0, the
// fourth channel alpha (as stored, never premultiplied).
image::WriteOptions writeOptions(const Image& img, SampleType type) {
    image::WriteOptions o;
    o.type = writtenType(type);
    o.alphaChannel = img.channels >= 4 ? 3 : -1;
    o.colorSpace = "Linear";
    o.nonFiniteToZero = true;
    return o;
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
    Image img(d.width, d.height, d.channels);
    img.isFloat = d.fileType == image::SampleType::Half || d.fileType == image::SampleType::Float;
    size_t i = 0;
    for (int y = 0; y < d.height; ++y)
        for (int x = 0; x < d.width; ++x)
            for (int c = 0; c < d.channels; ++c) img.samples[i++] = d.sample(x, y, c);
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
    const std::string e = image::lowerExtension(path);
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
    image::checkWritable(path, writtenType(type));
}

SampleType mapSampleType(const fs::path& path, const MapFormat& format, std::string_view bits) {
    const bool needFloat = format.encoding == Encoding::Signed;
    const SampleType type =
        bits.empty() ? defaultSampleType(path, needFloat) : parseSampleType(bits);
    const bool isFloat = type == SampleType::Half || type == SampleType::Float;
    const std::string e = image::lowerExtension(path);
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
    image::WriteOptions options = writeOptions(image, type);
    for (const auto& [k, v] : attributes) options.attributes.push_back({k, v});
    image::writeImageFile(path, image, options);
}

void writeMipChain(const fs::path& path, const std::vector<Image>& levels,
                   const std::vector<std::string>& channelNames, const std::string& layout,
                   Wrap wrap) {
    if (image::lowerExtension(path) != ".exr") {
        throw io::InputError(path.string(), "", "a MIP chain is written as OpenEXR (.exr)");
    }
    if (levels.empty() || int(channelNames.size()) != levels[0].channels) {
        throw io::InputError(path.string(), "", "empty MIP chain or channel names do not match");
    }
    image::WriteOptions options = writeOptions(levels[0], SampleType::Float);
    options.channelNames = channelNames;
    options.alphaChannel = -1; // named channels, none of them alpha
    options.attributes = {{"surfgrad:layout", layout},
                          {"surfgrad:wrap", wrap == Wrap::Repeat ? "repeat" : "clamp"}};
    std::vector<image::FloatPixels> pixels;
    for (const Image& level : levels) pixels.push_back(image::floatPixels(level));
    image::writeMipChainFile(path, pixels, options);
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
    const std::string* attr = info.stringAttribute("surfgrad:layout");
    const std::string lay = attr ? *attr : "";
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
        Image L(raw.width, raw.height, int(from.size()));
        L.isFloat = raw.isFloat;
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
