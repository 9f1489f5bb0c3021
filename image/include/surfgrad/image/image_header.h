// Image headers read before any decoder sees an untrusted file (the I/O
// policy of surfgrad/base/io.h applied to images). Decoders size their buffers
// from what a header declares, and some do real work when a file is opened
// (libjpeg absorbs a whole progressive file; OpenEXR allocates every header
// attribute and the chunk offset table), so a 69-byte PNG may declare 4 GiB
// of pixels. This scan reads the header itself and refuses, with an
// sg::io::InputError, before anything is allocated:
//  - formats other than the ones a scene accepts: PNG, JPEG (8-bit,
//    Huffman-coded), OpenEXR (single-part, flat), TIFF (classic; no, LZW,
//    Deflate, PackBits or JPEG compression), Radiance HDR and TGA (the only
//    one without a signature: recognised by its extension);
//  - header records (chunks, segments, attributes, IFD entries) that do not
//    fit in the file;
//  - files too short for the pixels their header declares: exactly for
//    uncompressed data, and through the codec's largest expansion for
//    compressed data (deflate 1032:1, LZW 4096:1, PackBits 64:1, RLE
//    schemes by their longest run, Huffman-coded JPEG at least one bit per
//    8x8 block of its first component).
// What passes still needs a size limit and a memory budget from the caller
// (ImageHeader::pixelBytes, decoderBytes); the decoder then reads a file
// that is at least long enough for what it promises.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace sg::io {

// Random access to the bytes of an untrusted file.
class ByteSource {
public:
    virtual ~ByteSource() = default;
    virtual uint64_t size() const = 0;
    // Copies min(n, size() - offset) bytes starting at offset (0 when
    // offset >= size()) into dst and returns how many it copied.
    virtual size_t read(uint64_t offset, void* dst, size_t n) const = 0;
};

// Bytes already in memory (not copied: `bytes` must outlive the source).
class MemoryBytes final : public ByteSource {
public:
    explicit MemoryBytes(std::string_view bytes) : bytes_(bytes) {}
    uint64_t size() const override { return bytes_.size(); }
    size_t read(uint64_t offset, void* dst, size_t n) const override;

private:
    std::string_view bytes_;
};

// A file read through a 64 KiB window (small scattered reads stay cheap).
// Throws InputError(path, "", reason) when it cannot be opened.
class FileBytes final : public ByteSource {
public:
    explicit FileBytes(const std::string& path);
    ~FileBytes() override;
    FileBytes(const FileBytes&) = delete;
    FileBytes& operator=(const FileBytes&) = delete;
    uint64_t size() const override { return size_; }
    size_t read(uint64_t offset, void* dst, size_t n) const override;

private:
    std::FILE* file_ = nullptr;
    uint64_t size_ = 0;
    mutable std::string window_;
    mutable uint64_t windowAt_ = 0;
};

enum class ImageFormat { Png, Jpeg, OpenExr, Tiff, Radiance, Targa };
const char*
imageFormatName(ImageFormat f); // "PNG", "JPEG", "OpenEXR", "TIFF", "Radiance HDR", "TGA"

struct ImageHeader {
    ImageFormat format = ImageFormat::Png;
    int64_t width = 0, height = 0; // pixels, as the decoder delivers them (>= 1)
    int channels = 0;              // samples per pixel the decoder delivers (see below)
    int bitsPerSample = 0;         // the largest decoded sample: 8, 16, 32 or 64
    bool floatSamples = false;     // some channel is half/float/double
    std::string compression;       // e.g. "none", "deflate", "huffman, progressive"
    uint64_t pixelBytes = 0;       // the declared image as the decoder delivers it (saturating)
    uint64_t decoderBytes = 0;     // buffers the decoder allocates itself while reading
                                   // (a whole image for interlaced PNG, TGA and multi-scan
                                   // JPEG; a strip, a row of tiles or a chunk otherwise)
    uint64_t minFileBytes = 0;     // the fewest bytes a file with this header can have
};
// `channels` is what OpenImageIO 2.4 reports for the header (palette and
// transparency expanded, CMYK converted to RGB); for TGA, whose alpha may
// be announced only in its extension area, it can be one short.

// Reads and checks the header of an image file (format from the signature;
// TGA when `name` ends in .tga/.tpic and the bytes match no signature).
// Throws InputError(name, element, reason), e.g. (name, "PNG IDAT",
// "16384x16384 pixels, 4 channels of 8 bits (1.0 GiB) need ... ").
ImageHeader scanImageHeader(const ByteSource& bytes, const std::string& name);

// The same for a file that must be OpenEXR (feature maps): "not an OpenEXR
// file (magic number)" for anything else.
ImageHeader scanExrHeader(const ByteSource& bytes, const std::string& name);

// "134 bytes", "12.0 KiB", "1.00 GiB": sizes in messages.
std::string formatBytes(uint64_t bytes);

} // namespace sg::io
