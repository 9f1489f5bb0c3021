// CPU emulation of GLSL texture sampling (see surfgrad/render/glsl_texture.h):
// OpenGL 4.5 core section 8.14 (level of detail, eq. 8.7-8.9), 8.14.2
// (GL_LINEAR_MIPMAP_LINEAR) and 8.14.1 (bilinear filtering, wrap modes).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>

#include <glm/gtc/packing.hpp>

#include "surfgrad/base/contract.h"
#include "surfgrad/render/glsl_texture.h"

namespace sg::render {

float srgbToLinear(float encoded) {
    const float v = std::clamp(encoded, 0.0f, 1.0f);
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

namespace {

// sRGB-decoded value of every 8- and 16-bit code, as srgbToLinear gives it
// for the code's float value.
const float* srgbTable8() {
    static const std::vector<float> table = [] {
        std::vector<float> t(256);
        for (size_t i = 0; i < t.size(); ++i) t[i] = srgbToLinear(float(i) * (1.0f / 255.0f));
        return t;
    }();
    return table.data();
}

const float* srgbTable16() {
    static const std::vector<float> table = [] {
        std::vector<float> t(65536);
        for (size_t i = 0; i < t.size(); ++i) t[i] = srgbToLinear(float(i) * (1.0f / 65535.0f));
        return t;
    }();
    return table.data();
}

// Sample c (< channels) of texel index i, decoded to float.
inline float sampleAt(const TextureLevel& L, size_t i, int c) {
    const size_t k = i * size_t(L.channels) + size_t(c);
    switch (L.type) {
    case TexelType::Unorm8: {
        const uint8_t v = L.data[k];
        return L.srgb && c < 3 ? srgbTable8()[v] : float(v) * (1.0f / 255.0f);
    }
    case TexelType::Unorm16: {
        uint16_t v;
        std::memcpy(&v, &L.data[2 * k], 2);
        return L.srgb && c < 3 ? srgbTable16()[v] : float(v) * (1.0f / 65535.0f);
    }
    case TexelType::Half: {
        uint16_t v;
        std::memcpy(&v, &L.data[2 * k], 2);
        return glm::unpackHalf1x16(v);
    }
    case TexelType::Float:
        break;
    }
    float v;
    std::memcpy(&v, &L.data[4 * k], 4);
    return v;
}

inline glm::vec4 texelAt(const TextureLevel& L, size_t i) {
    switch (L.channels) {
    case 1: {
        const float v = sampleAt(L, i, 0);
        return glm::vec4(v, v, v, 1.0f);
    }
    case 2:
        return glm::vec4(sampleAt(L, i, 0), sampleAt(L, i, 1), 0.0f, 1.0f);
    case 3:
        return glm::vec4(sampleAt(L, i, 0), sampleAt(L, i, 1), sampleAt(L, i, 2), 1.0f);
    default:
        return glm::vec4(sampleAt(L, i, 0), sampleAt(L, i, 1), sampleAt(L, i, 2),
                         sampleAt(L, i, 3));
    }
}

// The next level of `src`: float, same channel count, box averages.
TextureLevel halve(const TextureLevel& src) {
    TextureLevel dst;
    dst.width = std::max(1, src.width / 2);
    dst.height = std::max(1, src.height / 2);
    dst.channels = src.channels;
    dst.type = TexelType::Float;
    const int k = src.channels;
    dst.data.resize(size_t(dst.width) * size_t(dst.height) * size_t(k) * 4);
    for (int y = 0; y < dst.height; ++y) {
        // Source rows this texel averages: 2y, 2y+1, and for an odd source
        // height the leftover last row joins the last destination row.
        int y0 = std::min(2 * y, src.height - 1);
        int y1 = (y == dst.height - 1) ? src.height - 1 : std::min(2 * y + 1, src.height - 1);
        for (int x = 0; x < dst.width; ++x) {
            int x0 = std::min(2 * x, src.width - 1);
            int x1 = (x == dst.width - 1) ? src.width - 1 : std::min(2 * x + 1, src.width - 1);
            float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            int n = 0;
            for (int yy = y0; yy <= y1; ++yy)
                for (int xx = x0; xx <= x1; ++xx) {
                    const size_t i = size_t(yy) * size_t(src.width) + size_t(xx);
                    for (int c = 0; c < k; ++c) sum[c] += sampleAt(src, i, c);
                    ++n;
                }
            float* out = reinterpret_cast<float*>(dst.data.data()) +
                         (size_t(y) * size_t(dst.width) + size_t(x)) * size_t(k);
            for (int c = 0; c < k; ++c) out[c] = sum[c] / float(n);
        }
    }
    return dst;
}

} // namespace

uint32_t texelTypeBytes(TexelType type) {
    return type == TexelType::Unorm8 ? 1 : type == TexelType::Float ? 4 : 2;
}

size_t TextureLevel::sampleBytes() const {
    return size_t(width) * size_t(height) * size_t(channels) * texelTypeBytes(type);
}

glm::vec4 TextureLevel::texel(int x, int y) const {
    return texelAt(*this, size_t(y) * size_t(width) + size_t(x));
}

void TextureLevel::expandRows(int y0, int rows, glm::vec4* out) const {
    const size_t first = size_t(y0) * size_t(width), count = size_t(rows) * size_t(width);
    for (size_t i = 0; i < count; ++i) out[i] = texelAt(*this, first + i);
}

uint64_t TextureImage::bytes() const {
    uint64_t n = 0;
    for (const auto& L : levels) n += L.data.size();
    return n;
}

uint64_t textureBytes(int width, int height, int channels, TexelType type) {
    uint64_t n = uint64_t(width) * uint64_t(height) * uint64_t(channels) * texelTypeBytes(type);
    while (width > 1 || height > 1) {
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
        n += uint64_t(width) * uint64_t(height) * uint64_t(channels) * 4;
    }
    return n;
}

TextureImage makeTexture(TextureLevel level0, Wrap wrap) {
    SG_EXPECTS(level0.width >= 1 && level0.height >= 1, "a texture has at least one texel");
    SG_EXPECTS(level0.channels >= 1 && level0.channels <= 4, "1 to 4 channels");
    SG_EXPECTS(level0.data.size() == level0.sampleBytes(), "width * height * channels samples");
    static std::atomic<uint64_t> nextUid{1};
    TextureImage img;
    img.wrap = wrap;
    img.uid = nextUid++;
    img.levels.push_back(std::move(level0));
    while (img.levels.back().width > 1 || img.levels.back().height > 1)
        img.levels.push_back(halve(img.levels.back()));
    return img;
}

TextureImage makeTexture(int width, int height, std::vector<glm::vec4> texels, Wrap wrap) {
    SG_EXPECTS(width >= 1 && height >= 1, "a texture has at least one texel");
    SG_EXPECTS(texels.size() == size_t(width) * size_t(height), "width * height texels");
    TextureLevel L;
    L.width = width;
    L.height = height;
    L.channels = 4;
    L.type = TexelType::Float;
    L.data.resize(texels.size() * sizeof(glm::vec4));
    std::memcpy(L.data.data(), texels.data(), L.data.size());
    texels = {};
    return makeTexture(std::move(L), wrap);
}

} // namespace sg::render

namespace sg::glsl {

namespace {

int wrapIndex(int i, int size, sg::render::Wrap wrap) {
    if (wrap == sg::render::Wrap::Clamp) return std::clamp(i, 0, size - 1);
    int m = i % size;
    return m < 0 ? m + size : m;
}

vec4 fetch(const sg::render::TextureLevel& L, int x, int y, sg::render::Wrap wrap) {
    return L.texel(wrapIndex(x, L.width, wrap), wrapIndex(y, L.height, wrap));
}

// Bilinear filtering on one level (eq. 8.11 - 8.13): texel centres at
// (i + 0.5) / size. Non-finite coordinates sample texel 0 (the GL leaves
// them undefined; this keeps the emulation finite).
vec4 bilinear(const sg::render::TextureLevel& L, vec2 st, sg::render::Wrap wrap) {
    float u = st.x * float(L.width) - 0.5f;
    float v = st.y * float(L.height) - 0.5f;
    if (!std::isfinite(u) || !std::isfinite(v) || std::abs(u) > 1e8f || std::abs(v) > 1e8f) {
        return L.texel(0, 0);
    }
    float fu = std::floor(u), fv = std::floor(v);
    int i0 = int(fu), j0 = int(fv);
    float a = u - fu, b = v - fv;
    vec4 t00 = fetch(L, i0, j0, wrap), t10 = fetch(L, i0 + 1, j0, wrap);
    vec4 t01 = fetch(L, i0, j0 + 1, wrap), t11 = fetch(L, i0 + 1, j0 + 1, wrap);
    return (1.0f - a) * (1.0f - b) * t00 + a * (1.0f - b) * t10 + (1.0f - a) * b * t01 +
           a * b * t11;
}

vec4 sampleLod(const sg::render::TextureImage& img, vec2 st, float lambda) {
    int q = int(img.levels.size()) - 1;
    if (!(lambda > 0.0f)) return bilinear(img.levels[0], st, img.wrap); // magnification (c = 0)
    lambda = std::min(lambda, float(q));
    int d1 = int(std::floor(lambda));
    int d2 = std::min(d1 + 1, q);
    float frac = lambda - float(d1);
    vec4 a = bilinear(img.levels[size_t(d1)], st, img.wrap);
    if (d2 == d1 || frac == 0.0f) return a;
    vec4 b = bilinear(img.levels[size_t(d2)], st, img.wrap);
    return (1.0f - frac) * a + frac * b;
}

} // namespace

vec4 textureGrad(sampler2D s, vec2 st, vec2 dSTdx, vec2 dSTdy) {
    if (!s.image || s.image->levels.empty()) return vec4(0.0f, 0.0f, 0.0f, 1.0f);
    const auto& L0 = s.image->levels[0];
    vec2 size(float(L0.width), float(L0.height));
    // Scale factor rho (eq. 8.7 with the Euclidean lengths of eq. 8.8).
    vec2 dx = dSTdx * size, dy = dSTdy * size;
    float rho2 = std::max(dot(dx, dx), dot(dy, dy));
    float lambda;
    if (!(rho2 > 0.0f) || s.lodRule == LodRule::Level0) {
        lambda = -1e9f; // zero or NaN footprint (or no filtering): magnification
    } else if (!std::isfinite(rho2)) {
        lambda = 1e9f;
    } else if (s.lodRule == LodRule::FastLog2) {
        int e = 0;
        float m = 2.0f * std::frexp(rho2, &e); // rho2 = m * 2^(e-1), m in [1, 2)
        lambda = 0.5f * (float(e - 1) + m - 1.0f);
    } else {
        lambda = 0.5f * std::log2(rho2);
    }
    return sampleLod(*s.image, st, lambda);
}

vec4 textureLod(sampler2D s, vec2 st, float lod) {
    if (!s.image || s.image->levels.empty()) return vec4(0.0f, 0.0f, 0.0f, 1.0f);
    return sampleLod(*s.image, st, std::isfinite(lod) ? lod : 0.0f);
}

vec4 texelFetch(sampler2D s, ivec2 texel, int lod) {
    if (!s.image || lod < 0 || lod >= int(s.image->levels.size())) return vec4(0.0f);
    const auto& L = s.image->levels[size_t(lod)];
    if (texel.x < 0 || texel.y < 0 || texel.x >= L.width || texel.y >= L.height) return vec4(0.0f);
    return L.texel(texel.x, texel.y);
}

ivec2 textureSize(sampler2D s, int lod) {
    if (!s.image || lod < 0 || lod >= int(s.image->levels.size())) return ivec2(1, 1);
    const auto& L = s.image->levels[size_t(lod)];
    return ivec2(L.width, L.height);
}

} // namespace sg::glsl
