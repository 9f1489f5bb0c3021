// The one in-memory image of surfgrad: a raster of float samples, as the
// renderers produce it (sg::render::Image: one AOV, RGBA), the normal-map
// toolkit reads, edits and writes it (sg::normalmap::Image: 1 to 64
// channels) and the image writer (surfgrad/image/image_write.h) stores it.
// GPU textures with their MIP levels (sg::render::TextureImage) and the
// decoder's typed samples (sg::image::DecodedImage) are not images in this
// sense; they convert to and from this one where they meet it.
//
// Contract (every function taking an Image may rely on it, and the
// writers check it):
//  - `samples` holds width * height * channels floats: row-major, channels
//    interleaved, the BOTTOM row first (OpenGL's order: glReadPixels and
//    texture uploads take `samples` as they are; files store the top row
//    first and the reader and writer flip). Texel (x, y) is the x-th from
//    the left in the y-th row from the bottom; its samples start at
//    index(x, y) * channels.
//  - width, height and channels are >= 0. An image with no texels (width
//    or height 0) or no channels has no samples; the default Image is
//    0 x 0 with 0 channels. Writers refuse images without samples.
//  - Values are whatever the producer stored (linear data, never
//    colour-converted, alpha unassociated); NaN and infinities are allowed
//    in memory (readers and writers document what they do with them).
//  - at(x, y, c) needs 0 <= x < width, 0 <= y < height, 0 <= c < channels;
//    rgba/setRgba need channels == 4 and a texel inside the image. These
//    accessors are unchecked (they run per texel in the renderers' loops);
//    the constructors check their arguments (surfgrad/base/contract.h).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include <glm/vec4.hpp>

#include "surfgrad/base/contract.h"

namespace sg::image {

struct Image {
    int width = 0, height = 0; // texels
    int channels = 0;          // samples per texel
    // The values are not unorm data: they were decoded from half or float
    // samples, or are to be written as such (the normal-map encodings read
    // unorm channels as 0.5 v + 0.5, float channels as v). Renderers leave
    // it false; their images are always written as float or display data.
    bool isFloat = false;
    std::vector<float> samples; // width * height * channels, bottom row first

    Image() = default;
    // width x height texels of `channels` samples, each `fill`.
    Image(int w, int h, int c, float fill = 0.0f)
        : width(w), height(h), channels(c),
          samples(size_t(std::max(w, 0)) * size_t(std::max(h, 0)) * size_t(std::max(c, 0)), fill) {
        SG_EXPECTS(w >= 0 && h >= 0 && c >= 0, "an image's size and channels are >= 0");
    }
    // An RGBA image: width x height texels, each `fill`.
    Image(int w, int h, const glm::vec4& fill) : Image(w, h, 4) {
        for (size_t i = 0; i < texelCount(); ++i) setRgba(i, fill);
    }

    size_t texelCount() const { return size_t(width) * size_t(height); }
    bool empty() const { return samples.empty(); }
    // The texel index of (x, y): y * width + x.
    size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }

    float& at(int x, int y, int c) { return samples[index(x, y) * size_t(channels) + size_t(c)]; }
    float at(int x, int y, int c) const {
        return samples[index(x, y) * size_t(channels) + size_t(c)];
    }

    // 4-channel images: texel (x, y), or texel i = index(x, y), as RGBA.
    glm::vec4 rgba(size_t i) const {
        const float* s = samples.data() + 4 * i;
        return {s[0], s[1], s[2], s[3]};
    }
    glm::vec4 rgba(int x, int y) const { return rgba(index(x, y)); }
    void setRgba(size_t i, const glm::vec4& v) {
        float* s = samples.data() + 4 * i;
        s[0] = v.x;
        s[1] = v.y;
        s[2] = v.z;
        s[3] = v.w;
    }
    void setRgba(int x, int y, const glm::vec4& v) { setRgba(index(x, y), v); }
};

} // namespace sg::image
