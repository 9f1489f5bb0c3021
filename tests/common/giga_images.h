// Image files whose headers declare gigabytes (issue 16), kept in the
// texture fuzz corpus (tests/fuzz/corpus/texture), with the reason the
// guarded decoder (image/, surfgrad/image/image_decode.h) gives when its header
// scan refuses each one. Every program that reads images through that
// decoder (`render` textures, `normalmap` inputs) is tested against the
// whole list under a memory limit (cli.h: runSurfgradMemoryLimited).
#pragma once

#include <filesystem>
#include <vector>

namespace sg::test {

struct GigaImage {
    const char* file;   // in tests/fuzz/corpus/texture
    const char* reason; // the start of the refusal's reason, after "FILE: "
};

inline std::filesystem::path gigaImageDir() {
    return std::filesystem::path(SURFGRAD_SOURCE_DIR) / "tests/fuzz/corpus/texture";
}

// The two files of issue 16, then JPEG (baseline, progressive: libjpeg
// would decode the whole file on open), OpenEXR (uncompressed, zip),
// Radiance HDR, TGA and Deflate TIFF headers declaring gigabytes.
inline const std::vector<GigaImage>& gigaImages() {
    static const std::vector<GigaImage> images = {
        {"issue16_huge_dims.png", "PNG IDAT: 16384x16384 pixels, 4 channels of 8 bits (1.00 GiB)"},
        {"issue16_huge_64ch.tif",
         "TIFF strips: 16384x16384 pixels, 64 channels of 8 bits (16.0 GiB)"},
        {"giga_baseline.jpg", "JPEG scan data: 16384x16384 pixels, 3 channels of 8 bits"},
        {"giga_progressive.jpg", "JPEG scan data: 16384x16384 pixels, 3 channels of 8 bits"},
        {"giga_none.exr", "EXR pixel data: 16384x16384 pixels, 3 channels of 32 bits (3.00 GiB)"},
        {"giga_zip.exr", "EXR pixel data: 16384x16384 pixels"},
        {"giga.hdr", "HDR pixel data: 16384x16384 pixels, 3 channels of 32 bits (3.00 GiB)"},
        {"giga_rgba.tga", "TGA pixel data: 65535x65535 pixels, 4 channels of 8 bits (16.0 GiB)"},
        {"giga_deflate.tif", "TIFF strips: 16384x16384 pixels, 3 channels of 8 bits"},
    };
    return images;
}

} // namespace sg::test
