// What the image decoder (surfgrad/image/image_decode.h) and the image writer
// (surfgrad/image/image_write.h) share: the sample types of a file, the metadata
// values surfgrad reads and writes, and the file-name extension that picks
// a format.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

namespace sg::image {

// A file's samples (and how decoded samples are stored): 8/16-bit unorm
// (an n-bit sample s stands for s / (2^n - 1) in [0, 1]), IEEE half or
// float.
enum class SampleType : uint8_t { Unorm8, Unorm16, Half, Float };
uint32_t sampleTypeBytes(SampleType type);   // 1, 2, 2, 4
const char* sampleTypeName(SampleType type); // "8-bit unorm", "16-bit unorm", "half", "float"

// One metadata value of an image file (OpenImageIO's attribute types):
// a 32-bit int, a double, a string, or an array of at least one float.
// OpenEXR keeps arrays of 2, 3, 9 and 16 floats as its vector and matrix
// types (OpenImageIO reads them back as float2, vector, matrix33, matrix);
// other lengths come back as float arrays.
using AttributeValue = std::variant<int, double, std::string, std::vector<float>>;
struct Attribute {
    std::string name; // e.g. "surfgrad:layout"
    AttributeValue value;
};

// The extension of `path`, lower-cased (ASCII), with its dot: ".png" for
// "a/b.PNG", "" when the file name has none (std::filesystem::path::
// extension: "dir.d/file" and ".hidden" have none). Formats are chosen and
// checked by it: the writer's (image_write.h), TGA's in the header scan,
// the commands' output checks.
std::string lowerExtension(const std::filesystem::path& path);

} // namespace sg::image
