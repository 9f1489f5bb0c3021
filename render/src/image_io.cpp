// The renderer's image files: an AOV's values to what a PNG or OpenEXR file
// holds (encodings documented at writeImage()), written by the image
// module's writer (surfgrad/image/image_write.h), and read back through its
// decoder for tests and comparisons.
#include <algorithm>
#include <cmath>

#include "surfgrad/base/contract.h"
#include "surfgrad/image/image_decode.h"
#include "surfgrad/image/image_write.h"
#include "surfgrad/base/io.h"
#include "surfgrad/render.h"
#include "surfgrad/render/render_shaders.h"

namespace sg::render {

namespace fs = std::filesystem;

namespace {

// A colour per positive integer id (0: black).
glm::vec3 hashColour(float id) {
    if (id <= 0.0f) return glm::vec3(0.0f);
    uint32_t h = uint32_t(id) * 0x9e3779b1u;
    h ^= h >> 15;
    h *= 0x85ebca77u;
    h ^= h >> 13;
    return glm::vec3(float(h & 255u), float((h >> 8) & 255u), float((h >> 16) & 255u)) / 255.0f;
}

// Aov(-1): already display-referred.
glm::vec3 displayValue(const glm::vec4& v, Aov aov, float exposure) {
    if (int(aov) < 0) return glm::vec3(v);
    switch (aov) {
    case Aov::Color:
        return sg::glsl::sgToneMap(glm::vec3(v), exposure);
    case Aov::Uv:
        return glm::vec3(v.x - std::floor(v.x), v.y - std::floor(v.y), 0.0f);
    case Aov::PrimId:
        return hashColour(v.x);
    case Aov::Patch: {
        // Each patch its own hue, brighter with its tessellation level
        // (level 1: a third, level 64: full); other meshes' colour as is.
        // (z is the patch type, 6 or 9, on patch pixels.)
        if (!(v.z == 6.0f || v.z == 9.0f)) return sg::glsl::sgToneMap(glm::vec3(v), exposure);
        const float lit = 1.0f / 3.0f + 2.0f / 3.0f * std::log2(std::max(v.y, 1.0f)) / 6.0f;
        return hashColour(v.x) * (0.25f + 0.75f * lit);
    }
    default:
        return 0.5f * glm::vec3(v) + glm::vec3(0.5f); // unit vectors to [0,1]
    }
}

} // namespace

void writeDisplayImage(const fs::path& path, const Image& image) {
    if (image::lowerExtension(path) != ".png") {
        throw io::InputError(path.string(), "", "expected a .png file name for a display image");
    }
    writeImage(path, image, Aov(-1), 1.0f);
}

void writeImage(const fs::path& path, const Image& image, Aov aov, float exposure) {
    const std::string ext = image::lowerExtension(path);
    if (ext != ".png" && ext != ".exr") {
        throw io::InputError(path.string(), "",
                             "unsupported image format \"" + ext + "\" (expected .png or .exr)");
    }
    SG_EXPECTS(image.channels == 4 && image.samples.size() == image.texelCount() * 4,
               "an AOV image has 4 channels, width * height * 4 samples");
    image::WriteOptions options;
    options.attributes = {{"surfgrad:aov", int(aov) < 0 ? "display" : aovName(aov)}};
    if (ext == ".exr") {
        // The raw values, RGBA float (bottom row first, as Image holds them).
        options.type = image::SampleType::Float;
        options.channelNames = {"R", "G", "B", "A"};
        options.alphaChannel = 3;
        image::writeImageFile(path, image, options);
        return;
    }
    // Display values, 8-bit RGB (the writer clamps to [0, 1], NaN to 0).
    std::vector<float> display(image.texelCount() * 3);
    for (size_t i = 0; i < image.texelCount(); ++i) {
        const glm::vec3 d = displayValue(image.rgba(i), aov, exposure);
        for (int c = 0; c < 3; ++c) display[3 * i + size_t(c)] = d[c];
    }
    options.type = image::SampleType::Unorm8;
    image::writeImageFile(path, {display.data(), image.width, image.height, 3}, options);
}

Image readImage(const fs::path& path) {
    // The guarded decoder (surfgrad/image/image_decode.h): header checked against
    // the file, memory checked, before anything is allocated.
    image::DecodeOptions options;
    options.maxChannels = 4;
    const image::DecodedImage d = image::decodeImageFile(path, options);
    Image img(d.width, d.height, 4);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            glm::vec4 v(0, 0, 0, 1);
            for (int c = 0; c < d.channels; ++c) v[c] = d.sample(x, y, c);
            if (d.channels == 1) v = glm::vec4(v.x, v.x, v.x, 1);
            img.setRgba(x, y, v);
        }
    return img;
}

} // namespace sg::render
