// The one writer of image files, shared by the renderer's images
// (sg::render::writeImage), the normal-map toolkit (sg::normalmap::
// writeImage, writeMipChain), the feature maps (sg::features::save) and the
// CLI's `features render`: float samples in memory to PNG, OpenEXR, TIFF
// or TGA through OpenImageIO, written atomically (sg::io::writeAtomically:
// the file appears whole or not at all, and no temporary file is left).
//
// Samples in memory: width * height * channels floats, row-major, channels
// interleaved, the BOTTOM row first (OpenGL's order, as the decoder
// (surfgrad/image/image_decode.h) and the renderer's and normal map's images hold
// them); files store the top row first, and the writer flips. Values are
// written as given, never colour-converted or divided by alpha (alpha is
// unassociated): converting to the file's sample type is all that happens:
//  - Unorm8/Unorm16: NaN and +-infinity become 0, then values are clamped
//    to [0, 1] and stored as round(v * (2^n - 1)) (OpenImageIO's
//    conversion);
//  - Half: rounded to nearest; |v| >= 65520 becomes +-infinity;
//  - Half and Float keep NaN and infinities unless
//    WriteOptions::nonFiniteToZero.
// OpenEXR files are ZIP-compressed (16 scanlines a block) and scanline
// files, except MIP chains (writeMipChainFile: 64x64 tiles). Every failure
// is an sg::io::InputError naming the destination file and the reason:
// "cannot create image writer: <OpenImageIO's reason>", "cannot write
// image: <OpenImageIO's reason>" (element "level k" for a MIP level), or
// checkWritable's refusal.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "surfgrad/image/image.h"
#include "surfgrad/image/image_format.h"

namespace sg::image {

// Throws InputError(path, "", reason) unless samples of `type` can be
// written under path's extension (lowerExtension): .png: Unorm8, Unorm16;
// .tga: Unorm8; .tif/.tiff: every type; .exr: Half, Float. The reason
// names the type and the extension and lists the pairs, e.g.
//   cannot write 8-bit samples as ".exr" (png: 8/16-bit, tga: 8-bit, tif:
//   any, exr: half/float)
// and says so when the extension is not a format this writer knows
// (".jpg") or is missing. Commands call it before long work starts.
void checkWritable(const std::filesystem::path& path, SampleType type);

// Float samples in memory, in the order of the header comment (bottom row
// first). `samples` holds width * height * channels floats and outlives
// the write. An image without pixels or channels is an InputError
// ("cannot write image: 0x0 pixels, ...").
struct FloatPixels {
    const float* samples = nullptr;
    int width = 0, height = 0; // pixels
    int channels = 0;
};

// The writer's view of `image` (surfgrad/image/image.h), which outlives the
// write. Expects image.samples to hold width * height * channels floats.
FloatPixels floatPixels(const Image& image);

// What the file holds besides the samples.
struct WriteOptions {
    SampleType type = SampleType::Float; // the file's samples (checkWritable)
    // Channel names (as many as the image's channels); empty: OpenImageIO's
    // "R", "G", "B", "A", "channel4", ... ("Y" for one channel).
    std::vector<std::string> channelNames;
    int alphaChannel = -1;        // the channel that is alpha (unassociated); -1: none
    std::string colorSpace;       // "oiio:ColorSpace", e.g. "Linear" (data) or "sRGB"; "": none
    bool nonFiniteToZero = false; // Half/Float: write NaN and +-infinity as 0
    std::vector<Attribute> attributes; // metadata, e.g. {"surfgrad:layout", "lean1"}
};

// Writes `pixels` to `path` atomically in the format of its extension
// (checkWritable(path, options.type) first).
void writeImageFile(const std::filesystem::path& path, const FloatPixels& pixels,
                    const WriteOptions& options);
// The same for an Image: writeImageFile(path, floatPixels(image), options).
void writeImageFile(const std::filesystem::path& path, const Image& image,
                    const WriteOptions& options);

// Writes a MIP chain as one tiled OpenEXR file (64x64 tiles, OpenEXR
// MIPMAP_LEVELS with ROUND_DOWN, "textureformat" "Plain Texture"):
// levels[0] is the full image, each next level max(1, floor(size / 2)) on
// both axes down to 1x1 (a caller bug otherwise), every level with the
// same channels. `path` must end in .exr and options.type be Half or
// Float (InputError otherwise); the attributes go into every level.
void writeMipChainFile(const std::filesystem::path& path, const std::vector<FloatPixels>& levels,
                       const WriteOptions& options);

} // namespace sg::image
