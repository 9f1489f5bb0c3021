// Texture files (loadTexture, decodeTextureImage): untrusted images decoded
// into the smallest TextureImage that keeps what the scene's layers read.
// The order of the checks is the point (docs/architecture.md, "Errors"):
//  1. the header scan (surfgrad/image_header.h): format, declared size, a
//     file long enough for the pixels it promises;
//  2. the size limit (kMaxTextureSize) and the texture budget, for the mip
//     chain in its stored format plus the decoder's own buffers;
//  3. OpenImageIO opens the file with the decoder of the scanned format
//     (never another plugin's guess); its spec must agree with the header,
//     and the budget is checked again with its exact channels and type;
//  4. rows are decoded a band at a time into level 0, so a truncated file
//     fails having touched only the rows it held; channels past the
//     highest one the layers read are not decoded.
// Values are OpenImageIO's: raw channel values (bump maps are data: colour
// channels are not premultiplied by alpha), an n-bit unorm sample stored
// as is and read as float(s) * (1 / (2^n - 1)), exactly what OpenImageIO's
// conversion to float gives.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <functional>
#include <limits>
#include <new>

#include "render_internal.h"
#include "surfgrad/image_header.h"
#include "surfgrad/io.h"
#include "surfgrad/render.h"

namespace sg::render {

namespace fs = std::filesystem;

uint64_t defaultTextureBudget() {
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

const char* typeName(TexelType t) {
    switch (t) {
    case TexelType::Unorm8:
        return "8-bit unorm";
    case TexelType::Unorm16:
        return "16-bit unorm";
    case TexelType::Half:
        return "half";
    case TexelType::Float:
        return "float";
    }
    return "?";
}

OIIO::TypeDesc oiioType(TexelType t) {
    switch (t) {
    case TexelType::Unorm8:
        return OIIO::TypeDesc::UINT8;
    case TexelType::Unorm16:
        return OIIO::TypeDesc::UINT16;
    case TexelType::Half:
        return OIIO::TypeDesc::HALF;
    case TexelType::Float:
        break;
    }
    return OIIO::TypeDesc::FLOAT;
}

// The smallest storage that holds channels [0, chend) exactly: the file's
// own unorm or half samples; float for everything else (and for half
// colour maps, whose sRGB decoding has no table).
TexelType storageType(const OIIO::ImageSpec& spec, int chend, bool srgb) {
    const OIIO::TypeDesc t = spec.format;
    for (int c = 0; c < chend && !spec.channelformats.empty(); ++c)
        if (spec.channelformat(c) != t) return TexelType::Float;
    if (t == OIIO::TypeDesc::UINT8) return TexelType::Unorm8;
    if (t == OIIO::TypeDesc::UINT16) return TexelType::Unorm16;
    if (t == OIIO::TypeDesc::HALF && !srgb) return TexelType::Half;
    return TexelType::Float;
}

// "16384x16384 pixels, 3 of 64 channels as 8-bit unorm".
std::string describe(int64_t w, int64_t h, int nc, int kept, TexelType type) {
    return std::to_string(w) + "x" + std::to_string(h) + " pixels, " +
           (kept == nc ? std::to_string(nc) : std::to_string(kept) + " of " + std::to_string(nc)) +
           (nc == 1 ? " channel" : " channels") + " as " + typeName(type);
}

void checkBudget(const std::string& name, const TextureLoadOptions& opt, const std::string& what,
                 uint64_t resident, uint64_t transient) {
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

// Checks a band of decoded float/half samples (file rows y0..) and applies
// the sRGB curve to float colour channels.
void finishBand(uint8_t* band, int rows, int w, int k, TexelType type, bool srgb, int y0,
                const std::string& name) {
    const size_t n = size_t(rows) * size_t(w) * size_t(k);
    auto bad = [&](size_t i, const std::string& reason = "non-finite texel value") {
        const size_t px = i / size_t(k);
        throw InputError(name,
                         "pixel (" + std::to_string(px % size_t(w)) + ", " +
                             std::to_string(size_t(y0) + px / size_t(w)) + ")",
                         reason);
    };
    // Mip levels sum up to four texels in float: larger magnitudes would
    // overflow to infinity there.
    constexpr float kMaxTexel = std::numeric_limits<float>::max() / 4.0f;
    if (type == TexelType::Half) {
        for (size_t i = 0; i < n; ++i) {
            uint16_t v;
            std::memcpy(&v, band + 2 * i, 2);
            if ((v & 0x7C00u) == 0x7C00u) bad(i);
        }
    } else if (type == TexelType::Float) {
        float* f = reinterpret_cast<float*>(band);
        for (size_t i = 0; i < n; ++i) {
            if (!std::isfinite(f[i])) bad(i);
            if (std::fabs(f[i]) > kMaxTexel) {
                char v[64];
                std::snprintf(v, sizeof v, "texel value %g is out of range (|v| <= %g)",
                              double(f[i]), double(kMaxTexel));
                bad(i, v);
            }
            // Colour maps are sRGB-encoded; filtering happens on linear values.
            if (srgb && int(i % size_t(k)) < 3) f[i] = srgbToLinear(f[i]);
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

// Decoder settings: channel values as stored. OpenImageIO multiplies the
// colour channels of PNG, TGA and TIFF files with unassociated alpha by
// alpha unless told not to, which would scale a normal map carrying a
// height in alpha (bump maps are data).
OIIO::ImageSpec rawValues() {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    return config;
}

using OpenFn = std::function<std::unique_ptr<OIIO::ImageInput>(const char* plugin)>;

// Steps 3 and 4 (the header is already checked).
TextureImage decodeOpened(OIIO::ImageInput& in, const io::ImageHeader& hdr, const std::string& name,
                          bool srgb, Wrap wrap, const TextureLoadOptions& opt) {
    const OIIO::ImageSpec& spec = in.spec();
    if (spec.width != hdr.width || spec.height != hdr.height || spec.depth != 1 ||
        spec.nchannels < 1) {
        throw InputError(name, "",
                         std::string("the decoder reads ") + std::to_string(spec.width) + "x" +
                             std::to_string(spec.height) + "x" + std::to_string(spec.depth) +
                             " pixels, the header declares " + std::to_string(hdr.width) + "x" +
                             std::to_string(hdr.height));
    }
    const int w = spec.width, h = spec.height, nc = spec.nchannels;
    int highest = 0;
    for (int c = 0; c < 4; ++c)
        if (opt.channels >> c & 1u) highest = c;
    const int k = nc == 1 ? 1 : std::min(nc, std::min(highest + 1, 4));
    const TexelType type = storageType(spec, k, srgb);
    const size_t rowBytes = size_t(w) * size_t(k) * texelTypeBytes(type);
    int bandRows = int(std::clamp<size_t>((size_t(1) << 20) / rowBytes, 1, size_t(h)));
    if (spec.tile_height > 0) { // whole rows of tiles
        const int64_t th = spec.tile_height;
        bandRows = int(std::min<int64_t>(h, (bandRows + th - 1) / th * th));
    }
    const uint64_t resident = textureBytes(w, h, k, type);
    const std::string what = describe(w, h, nc, k, type);
    checkBudget(name, opt, what, resident, hdr.decoderBytes + uint64_t(bandRows) * rowBytes);
    try {
        TextureLevel L;
        L.width = w;
        L.height = h;
        L.channels = k;
        L.type = type;
        L.srgb = srgb && (type == TexelType::Unorm8 || type == TexelType::Unorm16);
        // Reserved, not touched: pages are used as rows arrive.
        L.data.reserve(size_t(h) * rowBytes);
        std::vector<uint8_t> band(size_t(bandRows) * rowBytes);
        for (int y0 = 0; y0 < h; y0 += bandRows) {
            const int rows = std::min(bandRows, h - y0);
            // Tiled files a row of tiles at a time through read_tiles, as
            // read_image does (OpenImageIO 2.4's read_scanlines divides by
            // a zero rows-per-strip on tiled files when it converts).
            const bool ok =
                spec.tile_width > 0
                    ? in.read_tiles(0, 0, spec.x, spec.x + w, spec.y + y0, spec.y + y0 + rows,
                                    spec.z, spec.z + 1, 0, k, oiioType(type), band.data())
                    : in.read_scanlines(0, 0, spec.y + y0, spec.y + y0 + rows, 0, 0, k,
                                        oiioType(type), band.data());
            if (!ok) {
                throw InputError(name, "row " + std::to_string(y0),
                                 "cannot decode: " + oneLine(in.geterror()));
            }
            finishBand(band.data(), rows, w, k, type, srgb, y0, name);
            L.data.insert(L.data.end(), band.begin(), band.begin() + long(size_t(rows) * rowBytes));
        }
        in.close();
        // File rows come top first; level 0 starts at the bottom row.
        for (int y = 0; y < h / 2; ++y) {
            std::swap_ranges(L.data.begin() + long(size_t(y) * rowBytes),
                             L.data.begin() + long(size_t(y + 1) * rowBytes),
                             L.data.begin() + long(size_t(h - 1 - y) * rowBytes));
        }
        TextureImage img = makeTexture(std::move(L), wrap);
        img.channelMask = nc == 1 ? 0x7u : (1u << k) - 1u;
        img.sourceChannels = nc;
        return img;
    } catch (const std::bad_alloc&) {
        throw InputError(name, "",
                         "out of memory decoding " + what + " (" + formatBytes(resident) +
                             " with its mip chain)");
    }
}

TextureImage decode(const io::ByteSource& bytes, const std::string& name, bool srgb, Wrap wrap,
                    const TextureLoadOptions& opt, const OpenFn& open) {
    const io::ImageHeader hdr = io::scanImageHeader(bytes, name);
    if (hdr.width > kMaxTextureSize || hdr.height > kMaxTextureSize) {
        throw InputError(name, "",
                         std::to_string(hdr.width) + "x" + std::to_string(hdr.height) +
                             " pixels: textures are at most " + std::to_string(kMaxTextureSize) +
                             " pixels per side");
    }
    // The budget before the decoder allocates anything, from the header
    // (libjpeg decodes a progressive file when it is opened).
    {
        int highest = 0;
        for (int c = 0; c < 4; ++c)
            if (opt.channels >> c & 1u) highest = c;
        const int k = hdr.channels <= 1 ? 1 : std::min(hdr.channels, highest + 1);
        const TexelType type =
            hdr.floatSamples
                ? (hdr.bitsPerSample == 16 && !srgb ? TexelType::Half : TexelType::Float)
            : hdr.bitsPerSample == 8  ? TexelType::Unorm8
            : hdr.bitsPerSample == 16 ? TexelType::Unorm16
                                      : TexelType::Float;
        checkBudget(name, opt, describe(hdr.width, hdr.height, std::max(hdr.channels, 1), k, type),
                    textureBytes(int(hdr.width), int(hdr.height), k, type), hdr.decoderBytes);
    }
    std::unique_ptr<OIIO::ImageInput> in = open(pluginOf(hdr.format));
    if (!in) {
        std::string err = oneLine(OIIO::geterror());
        throw InputError(name, "",
                         std::string("cannot read ") + io::imageFormatName(hdr.format) + " image" +
                             (err.empty() ? "" : ": " + err));
    }
    return decodeOpened(*in, hdr, name, srgb, wrap, opt);
}

TextureImage decodeGuarded(const io::ByteSource& bytes, const std::string& name, bool srgb,
                           Wrap wrap, const TextureLoadOptions& opt, const OpenFn& open) {
    try {
        return decode(bytes, name, srgb, wrap, opt, open);
    } catch (const InputError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw InputError(name, "", "out of memory while reading the image");
    } catch (const std::exception& e) {
        // Exceptions escaping a decoder library (OpenImageIO catches most).
        throw InputError(name, "", std::string("decoder error: ") + e.what());
    }
}

} // namespace

TextureImage decodeTextureImage(std::string_view bytes, const std::string& name, bool srgb,
                                Wrap wrap, const TextureLoadOptions& options) {
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
    return decodeGuarded(source, name, srgb, wrap, options, open);
}

std::shared_ptr<const TextureImage> loadTexture(const TextureSource& src,
                                                const std::string& sceneName,
                                                const TextureLoadOptions& options) {
    if (!src.procedural.empty()) {
        try {
            checkBudget("procedural texture " + src.procedural, options,
                        std::to_string(src.size) + "x" + std::to_string(src.size) +
                            " pixels, 4 channels as float",
                        textureBytes(src.size, src.size, 4, TexelType::Float), 0);
        } catch (const InputError& e) {
            throw InputError(sceneName, src.fieldPath, e.what());
        }
        return std::make_shared<TextureImage>(detail::makeProceduralTexture(src));
    }
    const std::string name = src.file.string();
    std::error_code ec;
    if (!fs::is_regular_file(src.file, ec)) {
        throw InputError(sceneName, src.fieldPath, "texture file " + name + " does not exist");
    }
    try {
        io::FileBytes source(name);
        auto open = [&](const char* plugin) -> std::unique_ptr<OIIO::ImageInput> {
            auto in = OIIO::ImageInput::create(plugin);
            OIIO::ImageSpec spec;
            if (!in || !in->open(name, spec, rawValues())) return nullptr;
            return in;
        };
        return std::make_shared<TextureImage>(
            decodeGuarded(source, name, src.srgb, src.wrap, options, open));
    } catch (const InputError& e) {
        // "<scene>: <field>: <image>: <element>: <reason>".
        throw InputError(sceneName, src.fieldPath, e.what());
    }
}

} // namespace sg::render
