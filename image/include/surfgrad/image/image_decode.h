// The one decoder of untrusted image files (the I/O policy of surfgrad/base/io.h
// applied to pixels), shared by the renderer's textures
// (sg::render::loadTexture), the normal-map toolkit
// (sg::normalmap::readImage) and the feature maps (sg::features::load).
// A file's header decides what a decoder allocates, and some decoders do
// real work when a file is opened, so a 69-byte PNG may ask for 4 GiB. The
// checks come in this order:
//  1. the image header scan (surfgrad/image/image_header.h): a format the reader
//     knows (PNG, JPEG, OpenEXR, TIFF, Radiance HDR, TGA), header records
//     inside the file, a file long enough for the pixels it promises;
//  2. the caller's side limit and memory check (DecodeOptions), from the
//     header, before the decoder opens the file;
//  3. OpenImageIO opens the file with the decoder of the scanned format
//     (never another plugin's guess); its spec must agree with the header
//     and the memory check runs again with its exact channels and type;
//  4. rows are decoded a band at a time into the result, so a truncated
//     file fails having touched only the rows it held; channels past
//     DecodeOptions::maxChannels are not decoded; half and float samples
//     must be finite (unless DecodeOptions::finiteOnly is off).
// Values are OpenImageIO's raw channel values (colour channels are never
// premultiplied by alpha: maps are data); an n-bit unorm sample is stored
// as is and reads as float(s) * (1 / (2^n - 1)), exactly OpenImageIO's
// conversion to float. Every refusal is an sg::io::InputError(name,
// element, reason); std::bad_alloc and decoder exceptions are turned into
// one too, naming what was being decoded and its size.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "surfgrad/image/image_format.h"
#include "surfgrad/image/image_header.h"

namespace sg::image {

// Decoded samples are stored as SampleType (surfgrad/image/image_format.h): the
// file's own 8/16-bit unorm or half samples, float for everything else.

// A quarter of physical memory, at most 8 GiB, and at most half of the
// process's address-space or data-segment limit (setrlimit, `ulimit -v`).
uint64_t defaultMemoryBudget();

// What a decode will hold, before anything is allocated (steps 2 and 3).
struct DecodePlan {
    int64_t width = 0, height = 0; // pixels
    int fileChannels = 0;          // channels of the file
    int channels = 0;              // channels decoded: [0, channels)
    SampleType type = SampleType::Float;
    uint64_t imageBytes = 0;     // the decoded image: width * height * channels samples
    uint64_t transientBytes = 0; // the decoder's own buffers and one band, while reading
    // "16384x16384 pixels, 3 of 64 channels as 8-bit unorm".
    std::string describe() const;
};

struct DecodeOptions {
    int maxSide = 16384;  // larger widths or heights are refused
    int maxChannels = 64; // the file's channels [0, maxChannels) are decoded, the rest skipped
    bool toFloat = false; // decode every sample to float (else the smallest SampleType)
    bool keepHalf = true; // half sources stay half (else float)
    // Finite half/float samples larger in magnitude are refused (the
    // renderer's mip filter sums four texels in float).
    float maxMagnitude = std::numeric_limits<float>::max();
    // NaN and infinite half/float samples are refused (false: kept, for a
    // caller that names the bad sample in its own terms).
    bool finiteOnly = true;
    int level = 0; // MIP level of a tiled OpenEXR/TIFF file (0: full size)
    // Called before allocating, from the header and again from the
    // decoder's spec; throws (an InputError naming `name`) to refuse. Empty:
    // imageBytes + transientBytes must fit in defaultMemoryBudget().
    std::function<void(const DecodePlan&)> checkMemory;
};

struct DecodedImage {
    int width = 0, height = 0;               // of the decoded level
    int channels = 0;                        // decoded channels
    int fileChannels = 0;                    // channels of the file
    SampleType type = SampleType::Float;     // as stored in `data`
    SampleType fileType = SampleType::Float; // the file's own sample type (the widest channel)
    int levels = 1;                          // MIP levels the file holds
    int originX = 0, originY = 0;            // the data window's origin (OpenEXR; else 0)
    std::vector<std::string> channelNames;   // of all the file's channels
    // Of all the file's channels, in OpenImageIO's names: "uint8",
    // "uint16", "half", "float", "uint" (32-bit), "double", ...
    std::vector<std::string> channelFormats;
    // The file's metadata of the types AttributeValue holds (int, double,
    // string, float arrays; scalar floats, vectors and matrices are left
    // out), by name.
    std::map<std::string, AttributeValue> attributes;
    // width * height * channels samples of `type`, row-major, the BOTTOM row
    // first (OpenGL's texel order; files store the top row first).
    std::vector<uint8_t> data;

    // Sample (x, y, c) (y from the bottom) as float.
    float sample(int x, int y, int c) const;
    // The string attribute `key`; nullptr when absent or of another type.
    const std::string* stringAttribute(const std::string& key) const;
};

// Decodes the file at `path` (its name in messages). "no such file" when
// it does not exist.
DecodedImage decodeImageFile(const std::filesystem::path& path, const DecodeOptions& options = {});
// The same for an image already in memory (fuzzing, tests); `name` stands
// for the file in messages and gives TGA's extension.
DecodedImage decodeImageBytes(std::string_view bytes, const std::string& name,
                              const DecodeOptions& options = {});

} // namespace sg::image
