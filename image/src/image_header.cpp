// Image header scan before decoding (surfgrad/image/image_header.h). Each format
// is read from its own specification:
//  - PNG: ISO/IEC 15948 (PNG 2nd ed.) sec. 5 (chunks), 11.2.2 (IHDR);
//    zlib/deflate RFC 1950/1951: a 258-byte match costs at least two bits,
//    so deflate data expands at most 1032:1.
//  - JPEG: ITU-T T.81 annex B (markers, frame and scan headers), A.2.4
//    (blocks per component); a Huffman code is at least one bit long and
//    every block of a component in a scan codes at least its DC difference.
//  - OpenEXR: "OpenEXR file layout" (header attributes, offset tables,
//    chunk headers, lines per chunk of each compression).
//  - TIFF 6.0 sec. 2 (IFD), 3-8 (baseline tags), 9 (PackBits), 13 (LZW).
//  - Radiance HDR: G. Ward, "Real Pixels" (Graphics Gems II) and
//    Radiance's color.c (new-style run-length scanlines of 8..32767).
//  - TGA: Truevision TGA 2.0 specification (header, colour map, RLE packets).
// The bounds refuse files that cannot hold what they declare; they are
// deliberately loose for compressed data (the largest expansion a codec
// allows), so no valid file is refused.
#include "surfgrad/image/image_header.h"

#include <algorithm>
#include <cctype>
#include <cinttypes>
#include <cstring>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include "surfgrad/image/image_format.h"
#include "surfgrad/base/io.h"

namespace sg::io {

size_t MemoryBytes::read(uint64_t offset, void* dst, size_t n) const {
    if (offset >= bytes_.size()) return 0;
    size_t k = std::min<uint64_t>(n, bytes_.size() - offset);
    std::memcpy(dst, bytes_.data() + offset, k);
    return k;
}

FileBytes::FileBytes(const std::string& path) {
    file_ = std::fopen(path.c_str(), "rb");
    if (!file_) throw InputError(path, "", "cannot open for reading");
    if (std::fseek(file_, 0, SEEK_END) != 0) {
        std::fclose(file_);
        throw InputError(path, "", "cannot seek (not a regular file?)");
    }
    long end = std::ftell(file_);
    if (end < 0) {
        std::fclose(file_);
        throw InputError(path, "", "cannot tell its size");
    }
    size_ = uint64_t(end);
}

FileBytes::~FileBytes() {
    if (file_) std::fclose(file_);
}

size_t FileBytes::read(uint64_t offset, void* dst, size_t n) const {
    if (offset >= size_) return 0;
    n = size_t(std::min<uint64_t>(n, size_ - offset));
    if (offset < windowAt_ || offset + n > windowAt_ + window_.size()) {
        constexpr size_t kWindow = size_t(1) << 16;
        const size_t want = std::max(n, size_t(std::min<uint64_t>(kWindow, size_ - offset)));
        window_.resize(want);
        windowAt_ = offset;
        if (std::fseek(file_, long(offset), SEEK_SET) != 0) {
            window_.clear();
            return 0;
        }
        window_.resize(std::fread(window_.data(), 1, want, file_));
        n = std::min(n, window_.size());
    }
    std::memcpy(dst, window_.data() + (offset - windowAt_), n);
    return n;
}

const char* imageFormatName(ImageFormat f) {
    switch (f) {
    case ImageFormat::Png:
        return "PNG";
    case ImageFormat::Jpeg:
        return "JPEG";
    case ImageFormat::OpenExr:
        return "OpenEXR";
    case ImageFormat::Tiff:
        return "TIFF";
    case ImageFormat::Radiance:
        return "Radiance HDR";
    case ImageFormat::Targa:
        return "TGA";
    }
    return "?";
}

std::string formatBytes(uint64_t bytes) {
    if (bytes == std::numeric_limits<uint64_t>::max()) return "more than 16 EiB";
    if (bytes < 1024) return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes");
    static const char* kUnits[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = double(bytes) / 1024.0;
    int u = 0;
    while (v >= 1024.0 && u < 5) {
        v /= 1024.0;
        ++u;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, v < 10.0 ? "%.2f %s" : "%.1f %s", v, kUnits[u]);
    return buf;
}

namespace {

constexpr uint64_t kMax64 = std::numeric_limits<uint64_t>::max();

uint64_t mulSat(uint64_t a, uint64_t b) {
    return a != 0 && b > kMax64 / a ? kMax64 : a * b;
}
uint64_t addSat(uint64_t a, uint64_t b) {
    return a > kMax64 - b ? kMax64 : a + b;
}
uint64_t ceilDiv(uint64_t a, uint64_t b) {
    return a / b + (a % b != 0 ? 1 : 0);
}

// Bounds-checked integer reads; everything outside the file is a truncated
// header named by the current element.
class Reader {
public:
    Reader(const ByteSource& src, std::string name) : src_(src), name_(std::move(name)) {}
    uint64_t size() const { return src_.size(); }
    void element(std::string e) { element_ = std::move(e); }
    [[noreturn]] void fail(const std::string& reason) const {
        throw InputError(name_, element_, reason);
    }
    void need(uint64_t at, uint64_t n) const {
        if (at > size() || n > size() - at) {
            fail("truncated: needs bytes " + std::to_string(at) + ".." +
                 std::to_string(addSat(at, n)) + ", the file has " + std::to_string(size()));
        }
    }
    std::string bytes(uint64_t at, size_t n) const {
        need(at, n);
        std::string s(n, '\0');
        src_.read(at, s.data(), n);
        return s;
    }
    uint32_t u8(uint64_t at) const { return int_(at, 1, false); }
    uint32_t le16(uint64_t at) const { return int_(at, 2, false); }
    uint32_t le32(uint64_t at) const { return int_(at, 4, false); }
    uint32_t be16(uint64_t at) const { return int_(at, 2, true); }
    uint32_t be32(uint64_t at) const { return int_(at, 4, true); }
    uint32_t u16(uint64_t at, bool big) const { return int_(at, 2, big); }
    uint32_t u32(uint64_t at, bool big) const { return int_(at, 4, big); }

private:
    uint32_t int_(uint64_t at, size_t n, bool big) const {
        need(at, n);
        unsigned char b[4] = {0, 0, 0, 0};
        src_.read(at, b, n);
        uint32_t v = 0;
        for (size_t i = 0; i < n; ++i) v = v << 8 | b[big ? i : n - 1 - i];
        return v;
    }
    const ByteSource& src_;
    std::string name_, element_;
};

// "16384x16384 pixels, 4 channels of 8 bits (1.00 GiB)".
std::string describe(const ImageHeader& h) {
    return std::to_string(h.width) + "x" + std::to_string(h.height) + " pixels, " +
           std::to_string(h.channels) + (h.channels == 1 ? " channel" : " channels") + " of " +
           std::to_string(h.bitsPerSample) + " bits (" + formatBytes(h.pixelBytes) + ")";
}

void setPixels(ImageHeader& h, int64_t w, int64_t ht, int channels, int bits, bool isFloat) {
    h.width = w;
    h.height = ht;
    h.channels = channels;
    h.bitsPerSample = bits;
    h.floatSamples = isFloat;
    h.pixelBytes =
        mulSat(mulSat(mulSat(uint64_t(w), uint64_t(ht)), uint64_t(channels)), uint64_t(bits / 8));
}

// Refuses a file whose `have` bytes of (compressed) data cannot expand to
// the `raw` bytes the header declares at `ratio`:1.
void checkExpansion(const Reader& r, const ImageHeader& h, uint64_t raw, uint64_t have,
                    uint64_t ratio, const std::string& what,
                    const std::string& holder = "the file holds") {
    if (mulSat(have, ratio) >= raw) return;
    r.fail(describe(h) + ": " + formatBytes(raw) + " of " + what + ", but " + holder + " " +
           formatBytes(have) +
           (ratio > 1 ? ", which expand to at most " + formatBytes(mulSat(have, ratio)) + " (" +
                            std::to_string(ratio) + ":1)"
                      : ""));
}

// ---------------------------------------------------------------------------
// PNG

ImageHeader scanPng(Reader& r) {
    ImageHeader h;
    h.format = ImageFormat::Png;
    uint64_t at = 8, idat = 0;
    uint32_t w = 0, ht = 0, depth = 0, ct = 0, interlace = 0;
    bool trns = false, sawIdat = false;
    // Element names are built only on failure (a file may hold millions
    // of chunks).
    r.element("PNG chunks");
    for (;;) {
        if (r.size() - at < 12) {
            r.element("PNG chunk at byte " + std::to_string(at));
            r.fail(at == r.size() ? "the file ends without an IEND chunk"
                                  : "truncated chunk header (" + std::to_string(r.size() - at) +
                                        " bytes left)");
        }
        const uint32_t len = r.be32(at);
        char typeBytes[4];
        for (int i = 0; i < 4; ++i) typeBytes[i] = char(r.u8(at + 4 + uint64_t(i)));
        const std::string type(typeBytes, 4);
        auto failChunk = [&](const std::string& reason) {
            r.element("PNG " + type + " chunk at byte " + std::to_string(at));
            r.fail(reason);
        };
        for (char c : type) {
            if (!std::isalpha(static_cast<unsigned char>(c))) {
                r.element("PNG chunk at byte " + std::to_string(at));
                r.fail("not a chunk type");
            }
        }
        if (len > 0x7FFFFFFFu) failChunk("length " + std::to_string(len) + " over 2^31 - 1");
        if (uint64_t(len) + 12 > r.size() - at) {
            failChunk("declares " + std::to_string(len) + " bytes of data; the file has " +
                      std::to_string(r.size() - at - 12) + " after its header");
        }
        if (at == 8) {
            r.element("PNG IHDR chunk");
            if (type != "IHDR" || len != 13) r.fail("the first chunk must be a 13-byte IHDR");
            w = r.be32(at + 8);
            ht = r.be32(at + 12);
            depth = r.u8(at + 16);
            ct = r.u8(at + 17);
            interlace = r.u8(at + 20);
            const bool okDepth =
                (ct == 0 &&
                 (depth == 1 || depth == 2 || depth == 4 || depth == 8 || depth == 16)) ||
                (ct == 3 && (depth == 1 || depth == 2 || depth == 4 || depth == 8)) ||
                ((ct == 2 || ct == 4 || ct == 6) && (depth == 8 || depth == 16));
            if (w < 1 || ht < 1 || w > 0x7FFFFFFFu || ht > 0x7FFFFFFFu)
                r.fail("size " + std::to_string(w) + "x" + std::to_string(ht));
            if (!okDepth)
                r.fail("colour type " + std::to_string(ct) + " with bit depth " +
                       std::to_string(depth));
            if (r.u8(at + 18) != 0 || r.u8(at + 19) != 0 || interlace > 1)
                r.fail("unknown compression, filter or interlace method");
        } else if (type == "IDAT") {
            idat += len;
            sawIdat = true;
        } else if (type == "tRNS" && !sawIdat) {
            trns = true;
        } else if (type == "IEND") {
            break;
        }
        r.element("PNG chunks");
        at += 12 + uint64_t(len);
    }
    r.element("PNG IDAT");
    if (!sawIdat) r.fail("no image data (IDAT chunk)");
    const uint32_t samples = ct == 2 ? 3 : ct == 4 ? 2 : ct == 6 ? 4 : 1;
    const int channels = int(ct == 4 || ct == 6 ? samples : (ct == 0 ? 1 : 3) + (trns ? 1 : 0));
    setPixels(h, w, ht, channels, depth == 16 ? 16 : 8, false);
    h.compression = interlace ? "deflate, interlaced" : "deflate";
    // Inflated stream: a filter byte and the packed samples of every row
    // (interlaced: at least the packed samples).
    const uint64_t bitsPerRow = mulSat(w, samples * depth);
    const uint64_t raw =
        interlace ? ceilDiv(mulSat(bitsPerRow, ht), 8) : mulSat(ht, 1 + ceilDiv(bitsPerRow, 8));
    checkExpansion(r, h, raw, idat, 1032, "filtered rows to inflate");
    h.minFileBytes = 8 + 25 + 12 + 12 + ceilDiv(raw, 1032);
    // OpenImageIO reads an interlaced PNG whole, other PNGs row by row.
    h.decoderBytes = interlace ? h.pixelBytes : mulSat(2, ceilDiv(h.pixelBytes, ht));
    return h;
}

// ---------------------------------------------------------------------------
// JPEG

// libjpeg decodes a file cut inside its scan data with a warning only and
// fills the rest grey: the end-of-image marker (T.81 B.2.1) must follow.
// Entropy-coded data cannot hold the bytes FF D9 (a data byte FF is
// followed by 00, T.81 F.1.2.3), so the first FF D9 after the first scan
// header is the marker; bytes after it (appended data) are allowed.
void checkJpegEnd(const Reader& r, uint64_t scanStart) {
    constexpr uint64_t kChunk = 1 << 16;
    std::string chunk;
    bool lastWasFF = false;
    for (uint64_t at = scanStart; at < r.size(); at += kChunk) {
        chunk = r.bytes(at, size_t(std::min(kChunk, r.size() - at)));
        for (char c : chunk) {
            const auto b = static_cast<unsigned char>(c);
            if (lastWasFF && b == 0xD9) return;
            lastWasFF = b == 0xFF;
        }
    }
    r.fail("truncated: no end-of-image marker (0xFFD9) after the scan data, the file ends at "
           "byte " +
           std::to_string(r.size()));
}

ImageHeader scanJpeg(Reader& r) {
    ImageHeader h;
    h.format = ImageFormat::Jpeg;
    uint64_t at = 2;
    int nf = 0, ns = 0;
    uint32_t width = 0, height = 0, hMax = 1, vMax = 1;
    uint32_t hs[4] = {1, 1, 1, 1}, vs[4] = {1, 1, 1, 1};
    bool progressive = false, sawFrame = false;
    r.element("JPEG markers");
    for (;;) {
        if (r.u8(at) != 0xFF) {
            r.element("JPEG marker at byte " + std::to_string(at));
            r.fail("expected a marker (0xFF)");
        }
        while (r.u8(at) == 0xFF) ++at; // fill bytes
        const uint32_t m = r.u8(at);
        ++at;
        if (m == 0xD8 || m == 0x01 || (m >= 0xD0 && m <= 0xD7)) continue; // no length
        const bool sof = m >= 0xC0 && m <= 0xCF && m != 0xC4 && m != 0xC8 && m != 0xCC;
        // Segments are named only when checked or failing (a file may
        // hold millions of others).
        if (sof || m == 0xDA || m == 0xD9 || m == 0x00 || r.size() - at < 2 || r.be16(at) < 2 ||
            r.be16(at) > r.size() - at) {
            char name[8];
            std::snprintf(name, sizeof name, "0xFF%02X", m);
            r.element(std::string("JPEG marker ") + name + " at byte " + std::to_string(at - 2));
        }
        if (m == 0xD9) r.fail("end of image before any scan");
        if (m == 0x00) r.fail("not a marker");
        const uint32_t len = r.be16(at);
        if (len < 2) r.fail("segment length " + std::to_string(len));
        r.need(at, len);
        if (sof) {
            if (sawFrame) r.fail("a second frame header");
            if (m != 0xC0 && m != 0xC1 && m != 0xC2) {
                const char* what = m == 0xC3 || m == 0xC7 || m == 0xCB || m == 0xCF ? "lossless"
                                   : (m == 0xC5 || m == 0xC6 || m == 0xCD || m == 0xCE)
                                       ? "hierarchical"
                                       : "arithmetic-coded";
                r.fail(std::string(what) + " JPEG (SOF" + std::to_string(m - 0xC0) +
                       ") is not supported (baseline, extended and progressive Huffman are)");
            }
            sawFrame = true;
            progressive = m == 0xC2;
            if (r.u8(at + 2) != 8)
                r.fail(std::to_string(r.u8(at + 2)) + "-bit samples (8-bit JPEG only)");
            height = r.be16(at + 3);
            width = r.be16(at + 5);
            nf = int(r.u8(at + 7));
            if (height == 0) r.fail("height defined later by a DNL marker (not supported)");
            if (width == 0 || nf < 1 || nf > 4 || len != 8 + 3 * uint32_t(nf))
                r.fail("frame header: size " + std::to_string(width) + "x" +
                       std::to_string(height) + ", " + std::to_string(nf) + " components");
            for (int c = 0; c < nf; ++c) {
                const uint32_t s = r.u8(at + 9 + 3 * uint64_t(c));
                hs[c] = s >> 4;
                vs[c] = s & 15u;
                if (hs[c] < 1 || hs[c] > 4 || vs[c] < 1 || vs[c] > 4)
                    r.fail("component " + std::to_string(c) + " sampling factors");
                hMax = std::max(hMax, hs[c]);
                vMax = std::max(vMax, vs[c]);
            }
        } else if (m == 0xDA) {
            if (!sawFrame) r.fail("scan before the frame header");
            ns = int(r.u8(at + 2));
            at += len;
            break;
        }
        at += len;
    }
    r.element("JPEG scan data");
    setPixels(h, width, height, nf == 4 ? 3 : nf, 8, false);
    h.compression = progressive ? "huffman, progressive" : "huffman";
    // Blocks of component 0 (T.81 A.2.4): each costs at least one bit.
    const uint64_t blocks0 = mulSat(ceilDiv(uint64_t(width) * hs[0], 8ull * hMax),
                                    ceilDiv(uint64_t(height) * vs[0], 8ull * vMax));
    const uint64_t have = r.size() - at;
    if (have < ceilDiv(blocks0, 8)) {
        r.fail(describe(h) + ": its first component has " + std::to_string(blocks0) +
               " blocks of 8x8, at least one bit each (" + formatBytes(ceilDiv(blocks0, 8)) +
               "), but the file has " + formatBytes(have) + " after the scan header");
    }
    h.minFileBytes = at + ceilDiv(blocks0, 8);
    checkJpegEnd(r, at);
    // libjpeg keeps every coefficient of a multi-scan image (64 x 2 bytes a
    // block); a single interleaved scan needs a few rows of blocks.
    if (progressive || ns < nf) {
        uint64_t coeff = 0;
        for (int c = 0; c < nf; ++c) {
            coeff = addSat(coeff, mulSat(ceilDiv(uint64_t(width) * hs[c], 8ull * hMax) + hs[c],
                                         ceilDiv(uint64_t(height) * vs[c], 8ull * vMax) + vs[c]));
        }
        h.decoderBytes = mulSat(coeff, 128);
    } else {
        h.decoderBytes = mulSat(uint64_t(width) * uint64_t(nf), 32ull * vMax);
    }
    return h;
}

// ---------------------------------------------------------------------------
// OpenEXR

// Bytes OpenEXR's reader of a fixed-size attribute type consumes (0 for
// types read by their declared size: string, stringvector, floatvector,
// unknown/opaque; chlist and preview are checked separately).
int exrFixedTypeBytes(const std::string& type) {
    static const std::pair<const char*, int> kFixed[] = {
        {"int", 4},       {"float", 4},    {"double", 8},
        {"rational", 8},  {"timecode", 8}, {"v2i", 8},
        {"v2f", 8},       {"v2d", 16},     {"v3i", 12},
        {"v3f", 12},      {"v3d", 24},     {"box2i", 16},
        {"box2f", 16},    {"m33f", 36},    {"m33d", 72},
        {"m44f", 64},     {"m44d", 128},   {"chromaticities", 32},
        {"keycode", 28},  {"tiledesc", 9}, {"compression", 1},
        {"lineOrder", 1}, {"envmap", 1},   {"deepImageState", 1},
    };
    for (const auto& [t, n] : kFixed) {
        if (type == t) return n;
    }
    return 0;
}

// What the pixel layout attributes say (filled while the attributes are walked).
struct ExrLayout {
    bool haveChannels = false, haveCompression = false, haveWindow = false, haveTiles = false;
    int channels = 0;
    uint64_t bytesPerPixel = 0;
    bool anyFloat = false, anyWide = false;
    uint32_t compression = 0;
    int32_t box[4] = {0, 0, 0, 0};
    uint32_t tileW = 0, tileH = 0, levelMode = 0, roundUp = 0;
};

// Channel records {name\0, int32 type, uint8 pLinear, 3 reserved, int32
// xSampling, int32 ySampling}, ended by an empty name, exactly filling the
// attribute; bytes [at, at + size).
void readExrChannels(Reader& r, uint64_t at, uint64_t size, ExrLayout& L,
                     const std::function<void(const std::string&)>& badSize) {
    const uint64_t end = at + size;
    uint64_t p = at;
    for (;;) {
        std::string name;
        while (p < end && r.u8(p) != 0 && name.size() < 256) name += char(r.u8(p++));
        if (p >= end || r.u8(p) != 0) badSize("its channel list to end inside it");
        if (name.empty()) {
            if (p + 1 != end) badSize("its channel list to end exactly at its end");
            break;
        }
        if (p + 1 + 16 > end) badSize("room for every channel record");
        const uint32_t type = r.le32(p + 1), xs = r.le32(p + 9), ys = r.le32(p + 13);
        if (type > 2)
            r.fail("channel '" + name.substr(0, 64) + "' has pixel type " + std::to_string(type) +
                   " (0 uint, 1 half, 2 float)");
        if (xs != 1 || ys != 1) r.fail("channel '" + name.substr(0, 64) + "' is subsampled");
        ++L.channels;
        L.bytesPerPixel += type == 1 ? 2 : 4;
        L.anyFloat = L.anyFloat || type != 0;
        L.anyWide = L.anyWide || type != 1;
        p += 1 + 16;
    }
    L.haveChannels = true;
}

// The attribute list, checked before OpenEXR reads it: OpenEXR allocates
// each attribute's declared size before reading it, so a 2 KB file
// declaring a 2 GB string attribute takes 2 GB (found by fuzzing). Layout
// (OpenEXR file layout, "Header"): magic 76 2f 31 01, a version word (bits
// 0-7 version 2; 0x200 tiled, 0x800 deep, 0x1000 multi-part), then
// attributes {name\0, type\0, int32 size, size bytes} ended by an empty
// name. Returns the offset just past the header.
uint64_t readExrAttributes(Reader& r, ExrLayout& L) {
    r.element("EXR header");
    if (r.size() < 8 || r.le32(0) != 20000630u) r.fail("not an OpenEXR file (magic number)");
    const uint32_t version = r.le32(4);
    if ((version & 0xFFu) != 2u)
        r.fail("EXR version " + std::to_string(version & 0xFFu) + " (this reader knows 2)");
    if (version & 0x1800u) r.fail("deep or multi-part EXR (only single-part images are read)");
    uint64_t at = 8;
    // A null-terminated name of at most 255 characters (the long-name limit).
    auto cstring = [&](const char* what) {
        std::string out;
        for (;;) {
            if (at >= r.size() || out.size() > 255)
                r.fail(std::string("unterminated or over-long attribute ") + what + " at byte " +
                       std::to_string(at - out.size()));
            const char c = char(r.u8(at++));
            if (c == '\0') return out;
            out += c;
        }
    };
    constexpr int kMaxAttributes = 1024; // real headers have a few dozen
    for (int n = 0; n < kMaxAttributes; ++n) {
        const std::string attr = cstring("name");
        if (attr.empty()) return at; // end of the header
        const std::string type = cstring("type");
        if (r.size() - at < 4) r.fail("attribute '" + attr.substr(0, 64) + "' has no size");
        const uint32_t size = r.le32(at);
        at += 4;
        if (size > r.size() - at) {
            r.fail("attribute '" + attr.substr(0, 64) + "' declares " + std::to_string(size) +
                   " bytes but the file has " + std::to_string(r.size() - at) + " left");
        }
        // OpenEXR's readers of the known types read what the type needs, not
        // the declared size: a size that disagrees would leave its stream
        // somewhere else than this scan, reading later bytes as attributes.
        auto badSize = [&](const std::string& need) {
            r.fail("attribute '" + attr.substr(0, 64) + "' of type " + type + " declares " +
                   std::to_string(size) + " bytes; the type needs " + need);
        };
        if (const int fixed = exrFixedTypeBytes(type); fixed > 0 && size != uint32_t(fixed))
            badSize(std::to_string(fixed));
        if (type == "chlist") {
            ExrLayout scratch;
            readExrChannels(r, at, size, attr == "channels" ? L : scratch, badSize);
        }
        if (type == "preview") {
            // uint32 width, uint32 height, then 4 bytes per pixel (OpenEXR
            // allocates width * height * 4 before reading them).
            if (size < 8 ||
                uint64_t(r.le32(at)) * uint64_t(r.le32(at + 4)) * 4u != uint64_t(size) - 8u)
                badSize("8 + 4 * width * height");
        }
        if (attr == "compression" && type == "compression") {
            L.compression = r.u8(at);
            L.haveCompression = true;
        } else if (attr == "dataWindow" && type == "box2i") {
            for (int i = 0; i < 4; ++i) L.box[i] = int32_t(r.le32(at + 4 * uint64_t(i)));
            L.haveWindow = true;
        } else if (attr == "tiles" && type == "tiledesc") {
            L.tileW = r.le32(at);
            L.tileH = r.le32(at + 4);
            L.levelMode = r.u8(at + 8) & 15u;
            L.roundUp = r.u8(at + 8) >> 4;
            L.haveTiles = true;
        }
        at += size;
    }
    r.fail("more than " + std::to_string(kMaxAttributes) + " header attributes");
}

// OpenEXR level sizes (ImfTiledMisc): max(1, floor or ceil(size / 2^l)),
// levels 0..floor or ceil(log2(size)).
uint64_t exrLevelSize(uint64_t size, uint32_t l, bool roundUp) {
    return std::max<uint64_t>(1, roundUp ? ceilDiv(size, uint64_t(1) << l) : size >> l);
}

uint32_t exrLevels(uint64_t size, bool roundUp) {
    uint32_t l = 0;
    while ((uint64_t(1) << (l + 1)) <= size) ++l;
    if (roundUp && (uint64_t(1) << l) < size) ++l;
    return l + 1;
}

// Tiles of every level: one level, mip levels (same l on both axes) or
// rip levels (every pair).
uint64_t exrTileCount(const ExrLayout& L, uint64_t w, uint64_t ht) {
    const bool up = L.roundUp != 0;
    auto along = [&](uint64_t size, uint64_t tile, uint32_t l) {
        return ceilDiv(exrLevelSize(size, l, up), tile);
    };
    uint64_t n = 0;
    if (L.levelMode == 0) return mulSat(along(w, L.tileW, 0), along(ht, L.tileH, 0));
    if (L.levelMode == 1) {
        const uint32_t levels = exrLevels(std::max(w, ht), up);
        for (uint32_t l = 0; l < levels; ++l)
            n = addSat(n, mulSat(along(w, L.tileW, l), along(ht, L.tileH, l)));
        return n;
    }
    uint64_t nx = 0, ny = 0;
    for (uint32_t l = 0; l < exrLevels(w, up); ++l) nx = addSat(nx, along(w, L.tileW, l));
    for (uint32_t l = 0; l < exrLevels(ht, up); ++l) ny = addSat(ny, along(ht, L.tileH, l));
    return mulSat(nx, ny);
}

// The offset table after the header: every chunk starts after the table,
// and its header and its declared data lie inside the file. OpenEXR seeks
// to whatever the table says (a fuzzed table made OpenImageIO's in-memory
// reader copy from before its buffer).
void checkExrChunks(Reader& r, uint64_t headerEnd, uint64_t chunks, uint64_t chunkHeader) {
    const uint64_t tableEnd = headerEnd + 8 * chunks; // inside the file: minFileBytes
    for (uint64_t i = 0; i < chunks; ++i) {
        const uint64_t at = headerEnd + 8 * i;
        const uint64_t off = uint64_t(r.le32(at)) | uint64_t(r.le32(at + 4)) << 32;
        if (off < tableEnd || off > r.size() || chunkHeader > r.size() - off) {
            r.element("EXR chunk " + std::to_string(i));
            r.fail("offset " + std::to_string(off) + " is outside the pixel data (bytes " +
                   std::to_string(tableEnd) + ".." + std::to_string(r.size()) + ")");
        }
        const uint32_t size = r.le32(off + chunkHeader - 4);
        if (size > r.size() - off - chunkHeader) {
            r.element("EXR chunk " + std::to_string(i));
            r.fail("declares " + std::to_string(int32_t(size)) + " bytes at byte " +
                   std::to_string(off + chunkHeader) + ", the file has " +
                   std::to_string(r.size()));
        }
    }
}

ImageHeader scanExr(Reader& r) {
    ImageHeader h;
    h.format = ImageFormat::OpenExr;
    ExrLayout L;
    const uint64_t headerEnd = readExrAttributes(r, L);
    const bool tiled = (r.le32(4) & 0x200u) != 0;
    if (!L.haveChannels || !L.haveCompression || !L.haveWindow || (tiled && !L.haveTiles))
        r.fail("missing channels, compression, dataWindow or tiles attribute");
    if (L.channels < 1) r.fail("no channels");
    const int64_t w = int64_t(L.box[2]) - L.box[0] + 1, ht = int64_t(L.box[3]) - L.box[1] + 1;
    if (w < 1 || ht < 1) r.fail("empty data window");
    setPixels(h, w, ht, L.channels, L.anyWide ? 32 : 16, L.anyFloat);
    h.pixelBytes = mulSat(mulSat(uint64_t(w), uint64_t(ht)), L.bytesPerPixel);
    // Compression: name, scanlines per chunk, largest expansion (0: only
    // the 88-byte DWA chunk header is certain).
    struct Codec {
        const char* name;
        uint32_t lines;
        uint64_t ratio;
    };
    static const Codec kCodecs[] = {{"none", 1, 1},    {"rle", 1, 64},   {"zips", 1, 1032},
                                    {"zip", 16, 1032}, {"piz", 32, 410}, {"pxr24", 16, 1376},
                                    {"b44", 32, 11},   {"b44a", 32, 11}, {"dwaa", 32, 0},
                                    {"dwab", 256, 0}};
    if (L.compression >= std::size(kCodecs))
        r.fail("unknown compression " + std::to_string(L.compression));
    const Codec& codec = kCodecs[L.compression];
    h.compression = codec.name;
    uint64_t chunks = 0, chunkHeader = 8;
    const uint64_t rowBytes = mulSat(uint64_t(w), L.bytesPerPixel);
    if (tiled) {
        if (L.tileW < 1 || L.tileH < 1 || L.levelMode > 2 || L.roundUp > 1)
            r.fail("tile description " + std::to_string(L.tileW) + "x" + std::to_string(L.tileH) +
                   ", mode " + std::to_string(L.levelMode));
        chunks = exrTileCount(L, uint64_t(w), uint64_t(ht));
        chunkHeader = 20;
        h.decoderBytes = mulSat(mulSat(L.tileH, ceilDiv(uint64_t(w), L.tileW) * L.tileW + L.tileW),
                                mulSat(L.bytesPerPixel, 2));
    } else {
        chunks = ceilDiv(uint64_t(ht), codec.lines);
        h.decoderBytes = mulSat(mulSat(codec.lines, rowBytes), 3);
    }
    h.decoderBytes = addSat(h.decoderBytes, mulSat(chunks, 8)); // the offset table
    const uint64_t data = codec.ratio ? ceilDiv(h.pixelBytes, codec.ratio) : mulSat(chunks, 88);
    h.minFileBytes = addSat(addSat(headerEnd, mulSat(chunks, 8 + chunkHeader)), data);
    r.element("EXR pixel data");
    if (h.minFileBytes > r.size()) {
        r.fail(describe(h) + " in " + std::to_string(chunks) + " " +
               (L.compression == 0 ? "uncompressed" : codec.name) + " " +
               (tiled ? "tiles" : "chunks") + " need at least " + formatBytes(h.minFileBytes) +
               " (offset table, chunk headers" +
               (codec.ratio ? std::string(", pixels at ") + std::to_string(codec.ratio) + ":1"
                            : std::string(", 88-byte DWA headers")) +
               "), but the file has " + formatBytes(r.size()));
    }
    checkExrChunks(r, headerEnd, chunks, chunkHeader);
    return h;
}

// ---------------------------------------------------------------------------
// TIFF

// The first IFD's entries (TIFF 6.0 sec. 2): tag -> where its values are.
struct TiffIfd {
    struct Entry {
        uint32_t type = 0, count = 0;
        uint64_t at = 0;
    };
    bool big = false;
    std::vector<std::pair<uint32_t, Entry>> entries;

    const Entry* find(uint32_t tag) const {
        for (const auto& [t, e] : entries)
            if (t == tag) return &e;
        return nullptr;
    }
};

TiffIfd readTiffIfd(Reader& r) {
    TiffIfd ifd;
    r.element("TIFF header");
    ifd.big = r.u8(0) == 'M';
    const uint32_t magic = r.u16(2, ifd.big);
    if (magic == 43) r.fail("BigTIFF is not supported (classic TIFF is)");
    if (magic != 42) r.fail("not a TIFF file (magic number " + std::to_string(magic) + ")");
    const uint64_t at = r.u32(4, ifd.big);
    r.element("TIFF IFD at byte " + std::to_string(at));
    if (at < 8) r.fail("inside the file header");
    const uint32_t n = r.u16(at, ifd.big);
    if (n == 0) r.fail("no entries");
    r.need(at + 2, 12ull * n + 4);
    // Bytes per value of TIFF types 1..13 (unknown types: libtiff skips them).
    static const uint32_t kTypeBytes[14] = {0, 1, 1, 2, 4, 8, 1, 1, 2, 4, 8, 4, 8, 4};
    for (uint32_t i = 0; i < n; ++i) {
        const uint64_t e = at + 2 + 12ull * i;
        const uint32_t tag = r.u16(e, ifd.big), type = r.u16(e + 2, ifd.big);
        TiffIfd::Entry entry{type, r.u32(e + 4, ifd.big), e + 8};
        const uint64_t bytes = mulSat(entry.count, type < 14 ? kTypeBytes[type] : 0);
        if (bytes > 4) {
            entry.at = r.u32(e + 8, ifd.big);
            if (entry.at > r.size() || bytes > r.size() - entry.at) {
                r.element("TIFF tag " + std::to_string(tag));
                r.fail("declares " + std::to_string(bytes) + " bytes at byte " +
                       std::to_string(entry.at) + ", the file has " + std::to_string(r.size()));
            }
        }
        ifd.entries.emplace_back(tag, entry);
    }
    return ifd;
}

ImageHeader scanTiff(Reader& r) {
    ImageHeader h;
    h.format = ImageFormat::Tiff;
    const TiffIfd ifd = readTiffIfd(r);
    // Value `i` of a SHORT/LONG/BYTE entry (def when the tag is absent).
    auto entryValue = [&](uint32_t tag, const TiffIfd::Entry* e, uint32_t i,
                          uint64_t def) -> uint64_t {
        if (!e) return def;
        if (e->type == 3 && i < e->count) return r.u16(e->at + 2ull * i, ifd.big);
        if (e->type == 4 && i < e->count) return r.u32(e->at + 4ull * i, ifd.big);
        if (e->type == 1 && i < e->count) return r.u8(e->at + i);
        r.element("TIFF tag " + std::to_string(tag));
        if (i >= e->count)
            r.fail("has " + std::to_string(e->count) + " values, needs " + std::to_string(i + 1));
        r.fail("type " + std::to_string(e->type) + " (BYTE, SHORT or LONG expected)");
    };
    auto value = [&](uint32_t tag, uint32_t i, uint64_t def) {
        return entryValue(tag, ifd.find(tag), i, def);
    };
    const uint64_t w = value(256, 0, 0), ht = value(257, 0, 0), spp = value(277, 0, 1);
    const uint64_t bps = value(258, 0, 1), compression = value(259, 0, 1);
    const uint64_t photometric = value(262, 0, spp >= 3 ? 2 : 1);
    const uint64_t planar = value(284, 0, 1), format = value(339, 0, 1);
    r.element("TIFF IFD");
    if (w < 1 || ht < 1) r.fail("size " + std::to_string(w) + "x" + std::to_string(ht));
    if (spp < 1) r.fail("no samples per pixel");
    if (const TiffIfd::Entry* bits = ifd.find(258)) {
        for (uint32_t i = 1; i < std::min<uint64_t>(spp, bits->count); ++i) {
            if (entryValue(258, bits, i, bps) != bps) {
                r.element("TIFF IFD");
                r.fail("channels of different bit depths");
            }
        }
    }
    r.element("TIFF IFD");
    const bool isFloat = format == 3;
    if ((bps != 1 && bps != 2 && bps != 4 && bps != 8 && bps != 16 && bps != 32 && bps != 64) ||
        format < 1 || format > 3 || (isFloat && bps < 16) || (bps < 8 && spp != 1))
        r.fail(std::to_string(bps) + "-bit samples of format " + std::to_string(format) + " (" +
               std::to_string(spp) + " per pixel)");
    struct Codec {
        uint64_t id;
        const char* name;
        uint64_t ratio;
    };
    // JPEG: at least one bit per 8x8 block of 8-bit samples.
    const Codec kCodecs[] = {{1, "none", 1},          {5, "lzw", 4096},
                             {8, "deflate", 1032},    {32946, "deflate", 1032},
                             {32773, "packbits", 64}, {7, "jpeg", mulSat(512, spp)}};
    const Codec* codec = nullptr;
    for (const Codec& c : kCodecs)
        if (c.id == compression) codec = &c;
    if (!codec)
        r.fail("compression " + std::to_string(compression) +
               " is not supported (none, LZW, Deflate, PackBits and JPEG are)");
    if (photometric > 3 && !(photometric == 6 && compression == 7))
        r.fail("photometric interpretation " + std::to_string(photometric) +
               " is not supported (grey, RGB, palette; YCbCr with JPEG)");
    if (compression == 7 && bps != 8)
        r.fail("JPEG compression with " + std::to_string(bps) + "-bit samples");
    if (planar != 1 && planar != 2) r.fail("planar configuration " + std::to_string(planar));
    if (photometric == 3) {
        const TiffIfd::Entry* cmap = ifd.find(320);
        if (bps > 8 || !cmap || cmap->count != (3u << bps))
            r.fail("palette image without a colour map of 3 x 2^" + std::to_string(bps) +
                   " entries");
    }
    const int channels = photometric == 3 ? 3 : int(std::min<uint64_t>(spp, 1u << 16));
    setPixels(h, int64_t(w), int64_t(ht), channels, photometric == 3 || bps < 8 ? 8 : int(bps),
              isFloat);
    h.compression = codec->name;
    // Strips or tiles: every one inside the file, together long enough.
    const bool tiled = ifd.find(322) != nullptr;
    const uint64_t planes = planar == 2 ? spp : 1, perPixel = planar == 2 ? 1 : spp;
    uint64_t chunks = 0, chunkRaw = 0;
    if (tiled) {
        const uint64_t tw = value(322, 0, 0), th = value(323, 0, 0);
        r.element("TIFF IFD");
        if (tw < 1 || th < 1) r.fail("tile size " + std::to_string(tw) + "x" + std::to_string(th));
        chunks = mulSat(mulSat(ceilDiv(w, tw), ceilDiv(ht, th)), planes);
        chunkRaw = mulSat(th, ceilDiv(mulSat(mulSat(tw, bps), perPixel), 8));
        h.decoderBytes = mulSat(mulSat(th, ceilDiv(w, tw) * tw), ceilDiv(h.pixelBytes, w * ht));
    } else {
        const uint64_t rows = std::clamp<uint64_t>(value(278, 0, ht), 1, ht);
        chunks = mulSat(ceilDiv(ht, rows), planes);
        chunkRaw = mulSat(rows, ceilDiv(mulSat(mulSat(w, bps), perPixel), 8));
    }
    h.decoderBytes = addSat(h.decoderBytes, mulSat(chunkRaw, mulSat(2, planes)));
    if (compression == 7 && (spp != 3 || photometric == 6)) {
        // OpenImageIO reads these through libtiff's RGBA interface: whole.
        h.decoderBytes = addSat(h.decoderBytes, mulSat(mulSat(w, ht), 4));
    }
    const uint32_t offTag = tiled ? 324 : 273, countTag = tiled ? 325 : 279;
    const TiffIfd::Entry *offs = ifd.find(offTag), *counts = ifd.find(countTag);
    r.element(std::string("TIFF ") + (tiled ? "tiles" : "strips"));
    if (!offs || !counts || offs->count < chunks || counts->count < chunks)
        r.fail("expected " + std::to_string(chunks) + " offsets and byte counts");
    // What the byte counts promise first (the clearer message), then that
    // every strip or tile lies inside the file.
    uint64_t have = 0;
    for (uint64_t i = 0; i < chunks; ++i)
        have = addSat(have, entryValue(countTag, counts, uint32_t(i), 0));
    r.element(std::string("TIFF ") + (tiled ? "tiles" : "strips"));
    const uint64_t raw =
        tiled ? mulSat(chunks, chunkRaw)
              : mulSat(mulSat(ht, ceilDiv(mulSat(mulSat(w, bps), perPixel), 8)), planes);
    checkExpansion(r, h, raw, have, codec->ratio,
                   codec->ratio == 1 ? std::string("uncompressed samples")
                                     : std::string(codec->name) + " data to decode",
                   std::string("its ") + std::to_string(chunks) + (tiled ? " tile" : " strip") +
                       (chunks == 1 ? " holds" : "s hold"));
    for (uint64_t i = 0; i < chunks; ++i) {
        const uint64_t off = entryValue(offTag, offs, uint32_t(i), 0),
                       n = entryValue(countTag, counts, uint32_t(i), 0);
        if (off > r.size() || n > r.size() - off) {
            r.element(std::string("TIFF ") + (tiled ? "tile " : "strip ") + std::to_string(i));
            r.fail("declares " + std::to_string(n) + " bytes at byte " + std::to_string(off) +
                   ", the file has " + std::to_string(r.size()));
        }
    }
    h.minFileBytes = ceilDiv(raw, codec->ratio);
    return h;
}

// ---------------------------------------------------------------------------
// Radiance HDR

ImageHeader scanRadiance(Reader& r) {
    ImageHeader h;
    h.format = ImageFormat::Radiance;
    uint64_t at = 0;
    constexpr uint64_t kMaxLine = 4096, kMaxHeader = 1 << 16;
    auto line = [&]() {
        std::string s;
        for (;;) {
            if (at >= r.size()) r.fail("the header ends without a resolution line");
            const char c = char(r.u8(at++));
            if (c == '\n') return s;
            if (s.size() >= kMaxLine || at > kMaxHeader) r.fail("header line over 4096 bytes");
            s += c;
        }
    };
    r.element("HDR header");
    if (line().rfind("#?", 0) != 0) r.fail("not a Radiance file (#? first line)");
    bool format = false;
    for (std::string l = line(); !l.empty(); l = line()) {
        if (l == "FORMAT=32-bit_rle_rgbe") format = true;
        if (l.rfind("FORMAT=", 0) == 0 && !format) r.fail(l + " (only 32-bit_rle_rgbe is read)");
    }
    if (!format) r.fail("no FORMAT=32-bit_rle_rgbe line");
    r.element("HDR resolution line");
    // "[+-]Y H [+-]X W" or "[+-]X W [+-]Y H": N scanlines of M pixels.
    const std::string res = line();
    char a0 = 0, a1 = 0, b0 = 0, b1 = 0, extra = 0;
    long long n = 0, m = 0;
    if (std::sscanf(res.c_str(), "%c%c %lld %c%c %lld%c", &a0, &a1, &n, &b0, &b1, &m, &extra) !=
            6 ||
        (a0 != '-' && a0 != '+') || (b0 != '-' && b0 != '+') ||
        !((a1 == 'Y' && b1 == 'X') || (a1 == 'X' && b1 == 'Y')) || n < 1 || m < 1 ||
        n > 0x7FFFFFFF || m > 0x7FFFFFFF)
        r.fail("'" + res.substr(0, 64) + "'");
    setPixels(h, m, n, 3, 32, true);
    h.compression = "rle";
    // A scanline is flat RGBE (4 bytes a pixel) or, for 8..32767 pixels,
    // 4 header bytes and 4 components in runs of at most 127 (2 bytes each).
    const uint64_t flat = 4 * uint64_t(m);
    const uint64_t scan =
        m >= 8 && m <= 0x7FFF ? std::min(flat, 4 + 8 * ceilDiv(uint64_t(m), 127)) : flat;
    h.minFileBytes = addSat(at, mulSat(uint64_t(n), scan));
    h.decoderBytes = 2 * flat;
    r.element("HDR pixel data");
    if (h.minFileBytes > r.size())
        r.fail(describe(h) + ": " + std::to_string(n) + " scanlines of at least " +
               std::to_string(scan) + " bytes each need " + formatBytes(h.minFileBytes) +
               ", but the file has " + formatBytes(r.size()));
    return h;
}

// ---------------------------------------------------------------------------
// TGA

ImageHeader scanTarga(Reader& r) {
    ImageHeader h;
    h.format = ImageFormat::Targa;
    r.element("TGA header");
    r.need(0, 18);
    const uint32_t idLen = r.u8(0), cmapType = r.u8(1), type = r.u8(2);
    const uint32_t cmapFirst = r.le16(3), cmapLen = r.le16(5), cmapBits = r.u8(7);
    const uint32_t w = r.le16(12), ht = r.le16(14), bpp = r.u8(16);
    const bool paletted = type == 1 || type == 9, grey = type == 3 || type == 11;
    if (cmapType > 1 || !(paletted || grey || type == 2 || type == 10))
        r.fail("not a TGA file (colour map type " + std::to_string(cmapType) + ", image type " +
               std::to_string(type) + ")");
    if (bpp != 8 && bpp != 15 && bpp != 16 && bpp != 24 && bpp != 32)
        r.fail(std::to_string(bpp) + " bits per pixel");
    if (w < 1 || ht < 1) r.fail("size " + std::to_string(w) + "x" + std::to_string(ht));
    uint64_t cmapBytes = 0;
    if (cmapType == 1) {
        if (grey) r.fail("colour map on a grey image");
        if (cmapBits != 15 && cmapBits != 16 && cmapBits != 24 && cmapBits != 32)
            r.fail(std::to_string(cmapBits) + "-bit colour map entries");
        cmapBytes = uint64_t(cmapLen) * (cmapBits == 15 ? 2 : cmapBits / 8);
    }
    const uint64_t bytesPP = bpp == 15 ? 2 : bpp / 8;
    if (paletted) {
        // OpenImageIO 2.4 indexes the map with first + index unchecked:
        // every index the pixels can hold must be inside it.
        if (cmapType != 1 || bytesPP > 2 ||
            uint64_t(cmapFirst) + (uint64_t(1) << (8 * bytesPP)) > cmapLen)
            r.fail("colour map of " + std::to_string(cmapLen) + " entries from " +
                   std::to_string(cmapFirst) + " does not cover every " + std::to_string(bpp) +
                   "-bit index");
    }
    setPixels(h, w, ht, grey ? 1 + (bpp > 8 ? 1 : 0) : 3 + (bpp == 32 ? 1 : 0), 8, false);
    const bool rle = type >= 9;
    h.compression = rle ? "rle" : "none";
    const uint64_t pixels = uint64_t(w) * ht, start = 18 + idLen + cmapBytes;
    // RLE packets cover at most 128 pixels and take 1 + one pixel's bytes.
    const uint64_t data = rle ? ceilDiv(pixels, 128) * (1 + bytesPP) : pixels * bytesPP;
    h.minFileBytes = start + data;
    h.decoderBytes = pixels * 4; // OpenImageIO decodes the whole image first
    r.element("TGA pixel data");
    if (h.minFileBytes > r.size())
        r.fail(describe(h) + ": " + (rle ? "run-length packets" : "uncompressed pixels") +
               " need at least " + formatBytes(h.minFileBytes) +
               " with the header, but the file has " + formatBytes(r.size()));
    return h;
}

bool startsWith(const std::string& s, std::string_view prefix) {
    return s.size() >= prefix.size() && std::memcmp(s.data(), prefix.data(), prefix.size()) == 0;
}

} // namespace

ImageHeader scanImageHeader(const ByteSource& bytes, const std::string& name) {
    using namespace std::string_view_literals;
    Reader r(bytes, name);
    std::string head(std::min<uint64_t>(bytes.size(), 16), '\0');
    bytes.read(0, head.data(), head.size());
    if (startsWith(head, "\x89PNG\r\n\x1a\n"sv)) return scanPng(r);
    if (startsWith(head, "\xFF\xD8\xFF"sv)) return scanJpeg(r);
    if (startsWith(head, "\x76\x2F\x31\x01"sv)) return scanExr(r);
    if (startsWith(head, "II*\0"sv) || startsWith(head, "MM\0*"sv) || startsWith(head, "II+\0"sv) ||
        startsWith(head, "MM\0+"sv))
        return scanTiff(r);
    if (startsWith(head, "#?"sv)) return scanRadiance(r);
    const std::string ext = image::lowerExtension(name);
    if (ext == ".tga" || ext == ".tpic") return scanTarga(r);
    static const std::pair<std::string_view, const char*> kOthers[] = {
        {"GIF8"sv, "a GIF"},
        {"BM"sv, "a BMP"},
        {"8BPS"sv, "a Photoshop"},
        {"\xABKTX"sv, "a KTX"},
        {"DDS "sv, "a DDS"},
        {"\0\0\0\x0CjP"sv, "a JPEG 2000"},
        {"\xFF\x4F\xFF\x51"sv, "a JPEG 2000"}};
    std::string what = "not an image file this reader knows";
    for (const auto& [magic, kind] : kOthers)
        if (startsWith(head, magic)) what = std::string(kind) + " file";
    if (startsWith(head, "RIFF"sv) && head.size() >= 12 && head.compare(8, 4, "WEBP") == 0)
        what = "a WebP file";
    throw InputError(name, "",
                     what + "; a scene reads PNG, JPEG, OpenEXR, TIFF, Radiance HDR and TGA");
}

ImageHeader scanExrHeader(const ByteSource& bytes, const std::string& name) {
    Reader r(bytes, name);
    return scanExr(r);
}

} // namespace sg::io
