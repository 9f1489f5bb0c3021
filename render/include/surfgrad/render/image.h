// Images: what the renderers produce (one AOV per image, RGBA float,
// bottom row first as OpenGL reads them back), their files, and the
// comparison of two images of unit vectors.
//
// Contract: an AOV image is an sg::image::Image (surfgrad/image/image.h) with 4
// channels, width * height * 4 samples. Writers go through the image
// module's writer (surfgrad/image/image_write.h): rows flipped to the usual
// top-first file order, written atomically (sg::io::writeAtomically); a
// failed write or an unsupported extension is an sg::io::InputError, and no
// partial file is left.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/image/image.h"

namespace sg::render {

// Patch: adaptive meshes' tessellation, (1 + patch index, tessellation
// level (the largest outer level), Far patch type (6 regular B-spline, 9
// Gregory basis), patch depth); other meshes show their shaded colour.
enum class Aov { Color = 0, Normal, SurfGrad, Tangent, Bitangent, BaseNormal, Uv, PrimId, Patch };
const char* aovName(Aov a);
// Parses an AOV name ("color", "normal", "surfgrad", "tangent", "bitangent",
// "basenormal", "uv", "primid", "patch"); nullopt for anything else.
std::optional<Aov> parseAov(const std::string& name);

// The renderers' images are the image module's (surfgrad/image/image.h): 4
// channels (RGBA float, rgba()/setRgba() per texel), bottom row first.
using Image = sg::image::Image;

// Writes an image atomically (sg::io::writeAtomically). ".exr": linear RGBA
// float (the AOV's raw values). ".png" (8-bit sRGB): colour is tone-mapped
// (sgToneMap with `exposure`); vector AOVs are mapped v -> 0.5 v + 0.5; uv
// is written as fract(uv); primid as a hashed colour; display values are
// clamped to [0, 1], NaN and infinities written as 0 (the EXR keeps them).
// Both carry the AOV's name as "surfgrad:aov" ("display" for
// writeDisplayImage). Throws InputError for an unsupported extension or a
// failed write.
void writeImage(const std::filesystem::path& path, const Image& image, Aov aov, float exposure);
Image readImage(const std::filesystem::path& path); // 4 channels (RGBA), bottom row first
// Writes display-referred values in [0, 1] as they are (8-bit PNG, RGB), e.g.
// a window capture.
void writeDisplayImage(const std::filesystem::path& path, const Image& image);

// Per-pixel comparison of two images of unit vectors (normal, tangent, ...
// AOVs), e.g. the GPU and CPU renderers' outputs. Only pixels covered by the
// same primitive in both images are compared (primA/primB: primid AOVs of
// the same views); coverage differences (silhouettes, rasterisation ties)
// are counted, not compared. Angles in degrees.
struct VectorImageDiff {
    size_t compared = 0;         // pixels covered by the same primitive in both
    size_t coverageMismatch = 0; // pixels covered in one image only, or by different primitives
    size_t nonFinite = 0;        // compared pixels with a NaN/Inf component in either image
    double meanDeg = 0, p50Deg = 0, p90Deg = 0, p99Deg = 0, p999Deg = 0, maxDeg = 0;
    int maxX = -1, maxY = -1; // where the largest angle is
};
VectorImageDiff compareVectorImages(const Image& a, const Image& b, const Image& primA,
                                    const Image& primB);

} // namespace sg::render
