// Sample types and the lower-cased file extension
// (surfgrad/image/image_format.h), shared by the image decoder and writer.
#include <cctype>

#include "surfgrad/image/image_format.h"

namespace sg::image {

uint32_t sampleTypeBytes(SampleType type) {
    switch (type) {
    case SampleType::Unorm8:
        return 1;
    case SampleType::Unorm16:
    case SampleType::Half:
        return 2;
    case SampleType::Float:
        break;
    }
    return 4;
}

const char* sampleTypeName(SampleType type) {
    switch (type) {
    case SampleType::Unorm8:
        return "8-bit unorm";
    case SampleType::Unorm16:
        return "16-bit unorm";
    case SampleType::Half:
        return "half";
    case SampleType::Float:
        break;
    }
    return "float";
}

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

} // namespace sg::image
