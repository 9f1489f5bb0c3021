// The C++ side of GLSL texture sampling for the shared shader subset:
// sampler2D, textureGrad, textureLod, texelFetch and textureSize, so shared
// layer functions (shaders/sg/render/*.glsl) that sample textures compile as
// C++ and run in the CPU reference renderer (the GLSL side is the driver's).
//
// Semantics follow the OpenGL 4.5 core specification, section 8.14
// (texture minification), with GL_LINEAR_MIPMAP_LINEAR minification,
// GL_LINEAR magnification, no anisotropy, and GL_REPEAT or GL_CLAMP_TO_EDGE
// wrapping:
//   rho    = max(|d(st)/dx * size|, |d(st)/dy * size|)   (Euclidean, eq. 8.7/8.8)
//   lambda = log2(rho), clamped to [0, levels - 1]
//   lambda <= 0: bilinear on level 0; else linear blend of the bilinear
//   samples of levels floor(lambda) and floor(lambda) + 1.
// Texel centres are at (i + 0.5) / size. The GPU renderer uploads the very
// same mip levels (TextureImage, expanded to RGBA float), so both sides
// filter identical texels; what
// can still differ is the driver's LOD arithmetic (llvmpipe: see
// docs/scene.md, "CPU reference") and float rounding.
//
// There is deliberately no texture(): it takes the screen derivatives from
// the 2x2 quad implicitly, and shared functions never use implicit
// derivatives (docs/architecture.md): callers pass dFdxFine values on the
// GPU and analytic ones on the CPU, so both sides select the same LOD.
//
// A default-constructed sampler2D (no image) samples (0, 0, 0, 1), like an
// incomplete texture in GL, and has size (1, 1).
//
// LodRule::FastLog2 replaces log2 by the piecewise-linear approximation
// Mesa's llvmpipe uses (gallivm lp_build_fast_log2: for x = 2^e * m with m
// in [1, 2), log2 x ~ e + m - 1, exact at powers of two, at most 0.086 too
// low in between), lambda = 0.5 * fastlog2(rho^2). It exists so tests can
// tell the driver's LOD arithmetic apart from differences in shader code.
#pragma once

#include <cstdint>
#include <vector>

#include "surfgrad/shaders/glsl_cpp.h"

namespace sg::render {

enum class Wrap { Repeat, Clamp };

// How a level stores its samples. A decoded file keeps its own precision
// (8/16-bit unorm, half, float) in level 0; the smaller levels are box
// averages and stay float, exactly the values an all-float chain held.
enum class TexelType : uint8_t { Unorm8, Unorm16, Half, Float };

// One mip level, row 0 at the BOTTOM of the image (t = 0), i.e. OpenGL's
// texel order. `channels` samples per texel are stored and expanded to RGBA
// on fetch: 1 -> (v, v, v, 1), 2 -> (r, g, 0, 1), 3 -> (r, g, b, 1),
// 4 -> (r, g, b, a); an n-bit unorm sample s reads as float(s) * (1.0f /
// (2^n - 1)) (OpenImageIO's conversion, so a file decoded to 8 bits
// samples bit for bit as the same file decoded to float); with `srgb`,
// channels 0..2 of a unorm level are sRGB codes read through the sRGB
// curve (IEC 61966-2-1) to linear values.
struct TextureLevel {
    int width = 0;
    int height = 0;
    int channels = 4; // 1..4
    TexelType type = TexelType::Float;
    bool srgb = false;
    // width * height * channels samples of `type`, row-major from the bottom row.
    std::vector<uint8_t> data;

    glm::vec4 texel(int x, int y) const;
    // RGBA of rows [y0, y0 + rows) into out (width * rows texels).
    void expandRows(int y0, int rows, glm::vec4* out) const;
    size_t sampleBytes() const;
};

// A texture as both renderers see it: the full mip chain down to 1x1.
struct TextureImage {
    std::vector<TextureLevel> levels;
    Wrap wrap = Wrap::Repeat;
    uint64_t uid = 0; // unique per makeTexture() call: GPU caches key on it, not on addresses
    // RGBA components that hold the source's values (bit c: component c);
    // the others are the constants of the channel expansion.
    uint32_t channelMask = 0xFu;
    int sourceChannels = 0; // channels of the decoded file (0: generated)

    int width() const { return levels.empty() ? 0 : levels[0].width; }
    int height() const { return levels.empty() ? 0 : levels[0].height; }
    uint64_t bytes() const; // every level's samples
};

// Builds the mip chain of a level-0 image (width, height >= 1; texels has
// width * height entries, bottom row first). Level sizes follow GL
// (max(1, floor(size / 2)) per level); each texel of a smaller level is the
// box average of the up to 2x2 texels it covers (the last row/column of an
// odd level is folded into its neighbour's average).
TextureImage makeTexture(int width, int height, std::vector<glm::vec4> texels, Wrap wrap);
// The same from a level 0 in any stored format (data holds width * height *
// channels samples of its type); the smaller levels are float with level
// 0's channel count, averaged from its decoded values in the order the
// RGBA float chain uses, so they equal that chain's levels bit for bit.
TextureImage makeTexture(TextureLevel level0, Wrap wrap);
// Bytes makeTexture() holds for such a level 0 (all levels).
uint64_t textureBytes(int width, int height, int channels, TexelType type);
uint32_t texelTypeBytes(TexelType type);
// The sRGB transfer curve colour maps are decoded with (IEC 61966-2-1),
// of a value clamped to [0, 1]: linear value.
float srgbToLinear(float encoded);

} // namespace sg::render

namespace sg::glsl {

// Level0: no filtering across levels, always bilinear on level 0 (the
// ground truth of supersampled renders: bench/accuracy/table_antialias.cpp).
enum class LodRule { Exact, FastLog2, Level0 };

struct sampler2D {
    const sg::render::TextureImage* image = nullptr;
    LodRule lodRule = LodRule::Exact;
};

// Filtered lookup at normalized st with explicit screen derivatives of st.
vec4 textureGrad(sampler2D s, vec2 st, vec2 dSTdx, vec2 dSTdy);
// Filtered lookup at an explicit level of detail.
vec4 textureLod(sampler2D s, vec2 st, float lod);
// Unfiltered texel (out-of-range coordinates return (0, 0, 0, 0), as the GL
// leaves them undefined).
vec4 texelFetch(sampler2D s, ivec2 texel, int lod);
// Size of a level ((1, 1) without an image).
ivec2 textureSize(sampler2D s, int lod);

} // namespace sg::glsl
