// Image output through OpenImageIO, written atomically (sg::io), and input
// for tests and comparisons. Encodings are documented at writeImage().
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "surfgrad/image_decode.h"
#include "surfgrad/io.h"
#include "surfgrad/render.h"
#include "surfgrad/render_shaders.h"

namespace sg::render {

namespace fs = std::filesystem;

namespace {

std::string lowerExt(const fs::path& p) {
    std::string e = p.extension().string();
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

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
    if (lowerExt(path) != ".png") {
        throw io::InputError(path.string(), "", "expected a .png file name for a display image");
    }
    writeImage(path, image, Aov(-1), 1.0f);
}

void writeImage(const fs::path& path, const Image& image, Aov aov, float exposure) {
    const std::string ext = lowerExt(path);
    if (ext != ".png" && ext != ".exr") {
        throw io::InputError(path.string(), "",
                             "unsupported image format \"" + ext + "\" (expected .png or .exr)");
    }
    const int W = image.width, H = image.height;
    const bool exr = ext == ".exr";
    const int nc = exr ? 4 : 3;
    std::vector<float> buf(size_t(W) * size_t(H) * size_t(nc));
    for (int y = 0; y < H; ++y) {
        int row = H - 1 - y; // files store the top row first
        for (int x = 0; x < W; ++x) {
            const glm::vec4& v = image.at(x, y);
            float* o = &buf[(size_t(row) * size_t(W) + size_t(x)) * size_t(nc)];
            if (exr) {
                for (int c = 0; c < 4; ++c) o[c] = v[c];
            } else {
                glm::vec3 d = displayValue(v, aov, exposure);
                for (int c = 0; c < 3; ++c)
                    o[c] = std::isfinite(d[c]) ? std::clamp(d[c], 0.0f, 1.0f) : 0.0f;
            }
        }
    }
    io::writeAtomically(path, [&](const fs::path& tmp) {
        auto out = OIIO::ImageOutput::create(tmp.string());
        if (!out)
            throw io::InputError(path.string(), "",
                                 "cannot create image writer: " + OIIO::geterror());
        OIIO::ImageSpec spec(W, H, nc, exr ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
        if (exr) {
            spec.channelnames = {"R", "G", "B", "A"};
            spec.alpha_channel = 3;
            spec.attribute("compression", "zip");
        }
        spec.attribute("surfgrad:aov", int(aov) < 0 ? "display" : aovName(aov));
        if (!out->open(tmp.string(), spec) ||
            !out->write_image(OIIO::TypeDesc::FLOAT, buf.data()) || !out->close()) {
            throw io::InputError(path.string(), "", "cannot write image: " + out->geterror());
        }
    });
}

Image readImage(const fs::path& path) {
    // The guarded decoder (surfgrad/image_decode.h): header checked against
    // the file, memory checked, before anything is allocated.
    image::DecodeOptions options;
    options.maxChannels = 4;
    const image::DecodedImage d = image::decodeImageFile(path, options);
    Image img;
    img.width = d.width;
    img.height = d.height;
    img.pixels.resize(size_t(img.width) * size_t(img.height));
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            glm::vec4 v(0, 0, 0, 1);
            for (int c = 0; c < d.channels; ++c) v[c] = d.sample(x, y, c);
            if (d.channels == 1) v = glm::vec4(v.x, v.x, v.x, 1);
            img.at(x, y) = v;
        }
    return img;
}

} // namespace sg::render
