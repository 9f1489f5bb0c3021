// The guarded image decoder (surfgrad/image/image_decode.h): header scan, limits
// and memory check before the decoder allocates, band-by-band decoding into
// the smallest sample type the caller accepts. OpenImageIO 2.4.7 quirks it
// works around are in docs/platform.md ("OpenImageIO").
#include <Imath/half.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <optional>
#include <string_view>

#include "oiio_sample_type.h"
#include "surfgrad/image/image_decode.h"
#include "surfgrad/base/io.h"

namespace sg::image {

namespace fs = std::filesystem;

uint64_t defaultMemoryBudget() {
    constexpr uint64_t kGiB = uint64_t(1) << 30;
    const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
    const uint64_t physical =
        pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : 4 * kGiB;
    uint64_t budget = std::min(physical / 4, 8 * kGiB);
    for (int resource : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit rl{};
        if (getrlimit(resource, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
            budget = std::min<uint64_t>(budget, uint64_t(rl.rlim_cur) / 2);
    }
    return budget;
}

std::string DecodePlan::describe() const {
    const int nc = std::max(fileChannels, 1);
    return std::to_string(width) + "x" + std::to_string(height) + " pixels, " +
           (channels == nc ? std::to_string(nc)
                           : std::to_string(channels) + " of " + std::to_string(nc)) +
           (nc == 1 ? " channel" : " channels") + " as " + sampleTypeName(type);
}

float DecodedImage::sample(int x, int y, int c) const {
    const size_t i = (size_t(y) * size_t(width) + size_t(x)) * size_t(channels) + size_t(c);
    switch (type) {
    case SampleType::Unorm8:
        return float(data[i]) * (1.0f / 255.0f);
    case SampleType::Unorm16: {
        uint16_t v;
        std::memcpy(&v, &data[2 * i], 2);
        return float(v) * (1.0f / 65535.0f);
    }
    case SampleType::Half: {
        uint16_t v;
        std::memcpy(&v, &data[2 * i], 2);
        Imath::half hv;
        hv.setBits(v);
        return float(hv); // IEEE binary16 -> binary32, exact
    }
    case SampleType::Float:
        break;
    }
    float f;
    std::memcpy(&f, &data[4 * i], 4);
    return f;
}

const std::string* DecodedImage::stringAttribute(const std::string& key) const {
    const auto it = attributes.find(key);
    return it == attributes.end() ? nullptr : std::get_if<std::string>(&it->second);
}

namespace {

using io::formatBytes;
using io::InputError;

// The OpenImageIO plugin of each scanned format (by its extension).
const char* pluginOf(io::ImageFormat f) {
    switch (f) {
    case io::ImageFormat::Png:
        return "png";
    case io::ImageFormat::Jpeg:
        return "jpg";
    case io::ImageFormat::OpenExr:
        return "exr";
    case io::ImageFormat::Tiff:
        return "tif";
    case io::ImageFormat::Radiance:
        return "hdr";
    case io::ImageFormat::Targa:
        return "tga";
    }
    return "";
}

// The smallest storage that holds channels [0, k) exactly.
SampleType storageType(const OIIO::ImageSpec& spec, int k, const DecodeOptions& opt) {
    if (opt.toFloat) return SampleType::Float;
    for (int c = 0; c < k && !spec.channelformats.empty(); ++c)
        if (spec.channelformat(c) != spec.format) return SampleType::Float;
    const SampleType t = fileSampleType(spec.format);
    return t == SampleType::Half && !opt.keepHalf ? SampleType::Float : t;
}

// The same predicted from the header alone (step 2).
SampleType headerStorageType(const io::ImageHeader& hdr, const DecodeOptions& opt) {
    if (opt.toFloat) return SampleType::Float;
    if (hdr.floatSamples)
        return hdr.bitsPerSample == 16 && opt.keepHalf ? SampleType::Half : SampleType::Float;
    if (hdr.bitsPerSample == 8) return SampleType::Unorm8;
    if (hdr.bitsPerSample == 16) return SampleType::Unorm16;
    return SampleType::Float;
}

void checkMemory(const std::string& name, const DecodeOptions& opt, const DecodePlan& plan) {
    if (opt.checkMemory) {
        opt.checkMemory(plan);
        return;
    }
    const uint64_t budget = defaultMemoryBudget();
    const uint64_t need =
        plan.imageBytes + std::min(plan.transientBytes, ~uint64_t(0) - plan.imageBytes);
    if (need <= budget) return;
    std::string reason = plan.describe() + ": needs " + formatBytes(plan.imageBytes);
    if (plan.transientBytes > 0)
        reason += " and " + formatBytes(plan.transientBytes) + " more while decoding";
    throw InputError(name, "", reason + "; the memory budget is " + formatBytes(budget));
}

uint64_t imageBytes(int64_t w, int64_t h, int k, SampleType type) {
    // Sides are at most maxSide (checked first): no overflow below 2^63.
    return uint64_t(w) * uint64_t(h) * uint64_t(k) * sampleTypeBytes(type);
}

// Refuses non-finite (unless !finiteOnly) and too large half/float samples
// of a band of file rows y0.. .
void checkBand(const uint8_t* band, int rows, int w, int k, SampleType type, int y0,
               const DecodeOptions& opt, const std::string& name) {
    if (type != SampleType::Half && type != SampleType::Float) return;
    if (!opt.finiteOnly && type == SampleType::Half) return; // halves: only finiteness is checked
    const size_t n = size_t(rows) * size_t(w) * size_t(k);
    auto bad = [&](size_t i, const std::string& reason) {
        const size_t px = i / size_t(k);
        throw InputError(name,
                         "pixel (" + std::to_string(px % size_t(w)) + ", " +
                             std::to_string(size_t(y0) + px / size_t(w)) + ") channel " +
                             std::to_string(i % size_t(k)),
                         reason);
    };
    if (type == SampleType::Half) {
        for (size_t i = 0; i < n; ++i) {
            uint16_t v;
            std::memcpy(&v, band + 2 * i, 2);
            if ((v & 0x7C00u) == 0x7C00u) bad(i, "non-finite value");
        }
        return;
    }
    for (size_t i = 0; i < n; ++i) {
        float f;
        std::memcpy(&f, band + 4 * i, 4);
        if (!std::isfinite(f)) {
            if (opt.finiteOnly) bad(i, "non-finite value");
            continue;
        }
        if (std::fabs(f) > opt.maxMagnitude) {
            char v[96];
            std::snprintf(v, sizeof v, "value %g is out of range (|v| <= %g)", double(f),
                          double(opt.maxMagnitude));
            bad(i, v);
        }
    }
}

// A decoder's message on one line, at most 300 characters.
std::string oneLine(std::string msg) {
    for (char& c : msg)
        if (c == '\n' || c == '\r') c = ' ';
    while (!msg.empty() && msg.back() == ' ') msg.pop_back();
    return msg.size() > 300 ? msg.substr(0, 300) + "..." : msg;
}

// Stands for a decoder's message when OpenImageIO passed on none;
// decodeGuarded puts what the decoder printed to stderr in its place.
constexpr std::string_view kNoDecoderMessage = "the decoder gave no reason";

// OpenImageIO's error message on one line, or kNoDecoderMessage.
std::string decoderMessage(const std::string& msg) {
    const std::string line = oneLine(msg);
    return line.empty() ? std::string(kNoDecoderMessage) : line;
}

// Decoder settings: channel values as stored. OpenImageIO multiplies the
// colour channels of PNG, TGA and TIFF files with unassociated alpha by
// alpha unless told not to, which would scale a normal map carrying a
// height in alpha.
OIIO::ImageSpec rawValues() {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    return config;
}

using OpenFn = std::function<std::unique_ptr<OIIO::ImageInput>(const char* plugin)>;

// Moves `in` to the MIP level asked for; returns how many levels the file has.
int seekLevel(OIIO::ImageInput& in, const DecodeOptions& opt, const std::string& name) {
    int levels = 1;
    if (in.spec().tile_width > 0) {
        while (levels < 64 && in.seek_subimage(0, levels)) ++levels;
    }
    if (opt.level < 0 || opt.level >= levels) {
        throw InputError(name, "level " + std::to_string(opt.level),
                         "the file has " + std::to_string(levels) + " MIP level" +
                             (levels == 1 ? "" : "s"));
    }
    if (!in.seek_subimage(0, opt.level)) {
        throw InputError(name, "level " + std::to_string(opt.level),
                         "cannot read: " + decoderMessage(in.geterror()));
    }
    return levels;
}

// Step 4: bands of file rows into `out`, which ends with the bottom row first.
void readRows(OIIO::ImageInput& in, const DecodePlan& plan, int bandRows, const DecodeOptions& opt,
              const std::string& name, std::vector<uint8_t>& out) {
    const OIIO::ImageSpec& spec = in.spec();
    const int w = int(plan.width), h = int(plan.height), k = plan.channels;
    const size_t rowBytes = size_t(w) * size_t(k) * sampleTypeBytes(plan.type);
    out.reserve(size_t(h) * rowBytes); // reserved, not touched: pages are used as rows arrive
    std::vector<uint8_t> band(size_t(bandRows) * rowBytes);
    for (int y0 = 0; y0 < h; y0 += bandRows) {
        const int rows = std::min(bandRows, h - y0);
        // Tiled files a row of tiles at a time through read_tiles, as
        // read_image does (OpenImageIO 2.4's read_scanlines divides by a
        // zero rows-per-strip on tiled files when it converts).
        const bool ok =
            spec.tile_width > 0
                ? in.read_tiles(0, opt.level, spec.x, spec.x + w, spec.y + y0, spec.y + y0 + rows,
                                spec.z, spec.z + 1, 0, k, oiioType(plan.type), band.data())
                : in.read_scanlines(0, opt.level, spec.y + y0, spec.y + y0 + rows, 0, 0, k,
                                    oiioType(plan.type), band.data());
        if (!ok) {
            throw InputError(name, "row " + std::to_string(y0),
                             "cannot decode: " + decoderMessage(in.geterror()));
        }
        checkBand(band.data(), rows, w, k, plan.type, y0, opt, name);
        out.insert(out.end(), band.begin(), band.begin() + long(size_t(rows) * rowBytes));
    }
    for (int y = 0; y < h / 2; ++y) {
        std::swap_ranges(out.begin() + long(size_t(y) * rowBytes),
                         out.begin() + long(size_t(y + 1) * rowBytes),
                         out.begin() + long(size_t(h - 1 - y) * rowBytes));
    }
}

// What DecodedImage says about the file besides its samples: channel
// names and types, the data window's origin, the metadata AttributeValue
// can hold.
void describeFile(const OIIO::ImageSpec& spec, DecodedImage& img) {
    img.originX = spec.x;
    img.originY = spec.y;
    img.channelNames = spec.channelnames;
    for (int c = 0; c < spec.nchannels; ++c)
        img.channelFormats.push_back(spec.channelformat(c).c_str());
    for (const OIIO::ParamValue& p : spec.extra_attribs) {
        const OIIO::TypeDesc t = p.type();
        const std::string key = p.name().string();
        if (t == OIIO::TypeDesc::STRING) {
            img.attributes[key] = std::string(p.get_string());
        } else if (t == OIIO::TypeDesc::INT) {
            img.attributes[key] = p.get_int();
        } else if (t == OIIO::TypeDesc::DOUBLE) {
            img.attributes[key] = *static_cast<const double*>(p.data());
        } else if (t.basetype == OIIO::TypeDesc::FLOAT && t.aggregate == OIIO::TypeDesc::SCALAR &&
                   t.arraylen > 0 && p.nvalues() == 1) {
            const float* v = static_cast<const float*>(p.data());
            img.attributes[key] = std::vector<float>(v, v + t.arraylen);
        }
    }
}

// Step 3 and 4 (the header is already checked).
DecodedImage decodeOpened(OIIO::ImageInput& in, const io::ImageHeader& hdr, const std::string& name,
                          const DecodeOptions& opt) {
    DecodedImage img;
    img.levels = seekLevel(in, opt, name);
    const OIIO::ImageSpec& spec = in.spec();
    const bool sizeOk = opt.level == 0 ? spec.width == hdr.width && spec.height == hdr.height
                                       : spec.width >= 1 && spec.height >= 1 &&
                                             spec.width <= hdr.width && spec.height <= hdr.height;
    if (!sizeOk || spec.depth != 1 || spec.nchannels < 1) {
        throw InputError(name, "",
                         std::string("the decoder reads ") + std::to_string(spec.width) + "x" +
                             std::to_string(spec.height) + "x" + std::to_string(spec.depth) +
                             " pixels, the header declares " + std::to_string(hdr.width) + "x" +
                             std::to_string(hdr.height));
    }
    DecodePlan plan;
    plan.width = spec.width;
    plan.height = spec.height;
    plan.fileChannels = spec.nchannels;
    plan.channels = std::clamp(opt.maxChannels, 1, spec.nchannels);
    plan.type = storageType(spec, plan.channels, opt);
    const size_t rowBytes = size_t(spec.width) * size_t(plan.channels) * sampleTypeBytes(plan.type);
    int bandRows = int(std::clamp<size_t>((size_t(1) << 20) / rowBytes, 1, size_t(spec.height)));
    if (spec.tile_height > 0) { // whole rows of tiles
        const int64_t th = spec.tile_height;
        bandRows = int(std::min<int64_t>(spec.height, (bandRows + th - 1) / th * th));
    }
    plan.imageBytes = imageBytes(plan.width, plan.height, plan.channels, plan.type);
    plan.transientBytes = hdr.decoderBytes + uint64_t(bandRows) * rowBytes;
    checkMemory(name, opt, plan);
    img.width = spec.width;
    img.height = spec.height;
    img.channels = plan.channels;
    img.fileChannels = spec.nchannels;
    img.type = plan.type;
    img.fileType = fileSampleType(spec.format);
    describeFile(spec, img);
    try {
        readRows(in, plan, bandRows, opt, name, img.data);
    } catch (const std::bad_alloc&) {
        throw InputError(name, "",
                         "out of memory decoding " + plan.describe() + " (" +
                             formatBytes(plan.imageBytes) + ")");
    }
    in.close();
    return img;
}

DecodedImage decode(const io::ByteSource& bytes, const std::string& name, const DecodeOptions& opt,
                    const OpenFn& open) {
    const io::ImageHeader hdr = io::scanImageHeader(bytes, name);
    if (hdr.width > opt.maxSide || hdr.height > opt.maxSide) {
        throw InputError(name, "",
                         std::to_string(hdr.width) + "x" + std::to_string(hdr.height) +
                             " pixels: at most " + std::to_string(opt.maxSide) +
                             " pixels per side are read");
    }
    // The memory check before the decoder allocates anything, from the
    // header (libjpeg decodes a progressive file when it is opened).
    DecodePlan plan;
    plan.width = hdr.width;
    plan.height = hdr.height;
    plan.fileChannels = std::max(hdr.channels, 1);
    plan.channels = std::clamp(opt.maxChannels, 1, plan.fileChannels);
    plan.type = headerStorageType(hdr, opt);
    plan.imageBytes = imageBytes(hdr.width, hdr.height, plan.channels, plan.type);
    plan.transientBytes = hdr.decoderBytes;
    checkMemory(name, opt, plan);
    std::unique_ptr<OIIO::ImageInput> in = open(pluginOf(hdr.format));
    if (!in) {
        throw InputError(name, "",
                         std::string("cannot read ") + io::imageFormatName(hdr.format) +
                             " image: " + decoderMessage(OIIO::geterror()));
    }
    return decodeOpened(*in, hdr, name, opt);
}

DecodedImage decodeCatching(const io::ByteSource& bytes, const std::string& name,
                            const DecodeOptions& opt, const OpenFn& open) {
    try {
        return decode(bytes, name, opt, open);
    } catch (const InputError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw InputError(name, "", "out of memory while reading the image");
    } catch (const std::exception& e) {
        // Exceptions escaping a decoder library (OpenImageIO catches most).
        throw InputError(name, "", std::string("decoder error: ") + e.what());
    }
}

// libpng prints its own "libpng error: ..." line to stderr before
// OpenImageIO reports the error: the decoder runs with stderr captured
// (io::captureStderr), so that the user sees one error line, ours. What the
// decoder printed replaces kNoDecoderMessage when OpenImageIO passed on no
// message, and is dropped otherwise (OpenImageIO's message repeats it).
DecodedImage decodeGuarded(const io::ByteSource& bytes, const std::string& name,
                           const DecodeOptions& opt, const OpenFn& open) {
    std::optional<DecodedImage> image;
    std::exception_ptr failure;
    const std::string printed = io::captureStderr([&] {
        try {
            image.emplace(decodeCatching(bytes, name, opt, open));
        } catch (...) {
            failure = std::current_exception();
        }
    });
    if (!failure) return std::move(*image);
    try {
        std::rethrow_exception(failure);
    } catch (const InputError& e) {
        const size_t at = e.reason().find(kNoDecoderMessage);
        std::string said;
        for (char c : printed) said += c == '\n' ? std::string("; ") : std::string(1, c);
        said = oneLine(said.substr(0, said.size() > 2 ? said.size() - 2 : 0));
        if (at == std::string::npos || said.empty()) throw;
        std::string reason = e.reason();
        reason.replace(at, kNoDecoderMessage.size(), said);
        throw InputError(e.file(), e.element(), reason);
    }
}

} // namespace

DecodedImage decodeImageBytes(std::string_view bytes, const std::string& name,
                              const DecodeOptions& options) {
    io::MemoryBytes source(bytes);
    OIIO::Filesystem::IOMemReader reader(bytes.data(), bytes.size());
    auto open = [&](const char* plugin) -> std::unique_ptr<OIIO::ImageInput> {
        auto in = OIIO::ImageInput::create(plugin, false, nullptr, &reader);
        OIIO::ImageSpec config = rawValues(), spec;
        OIIO::Filesystem::IOProxy* proxy = &reader;
        config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
        if (!in || !in->set_ioproxy(&reader) || !in->open(name, spec, config)) return nullptr;
        return in;
    };
    return decodeGuarded(source, name, options, open);
}

DecodedImage decodeImageFile(const fs::path& path, const DecodeOptions& options) {
    const std::string name = path.string();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw InputError(name, "", "no such file");
    io::FileBytes source(name);
    auto open = [&](const char* plugin) -> std::unique_ptr<OIIO::ImageInput> {
        auto in = OIIO::ImageInput::create(plugin);
        OIIO::ImageSpec spec;
        if (!in || !in->open(name, spec, rawValues())) return nullptr;
        return in;
    };
    return decodeGuarded(source, name, options, open);
}

} // namespace sg::image
