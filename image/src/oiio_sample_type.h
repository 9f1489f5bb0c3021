// SampleType (surfgrad/image/image_format.h) to and from OpenImageIO's TypeDesc,
// for the decoder and the writer of this module (private).
#pragma once

#include <OpenImageIO/typedesc.h>

#include "surfgrad/image/image_format.h"

namespace sg::image {

inline OIIO::TypeDesc oiioType(SampleType t) {
    switch (t) {
    case SampleType::Unorm8:
        return OIIO::TypeDesc::UINT8;
    case SampleType::Unorm16:
        return OIIO::TypeDesc::UINT16;
    case SampleType::Half:
        return OIIO::TypeDesc::HALF;
    case SampleType::Float:
        break;
    }
    return OIIO::TypeDesc::FLOAT;
}

// A file's channel type as SampleType: 8/16-bit unsigned and half as
// themselves, everything else (float, double, 32-bit ints) as Float.
inline SampleType fileSampleType(OIIO::TypeDesc t) {
    if (t == OIIO::TypeDesc::UINT8) return SampleType::Unorm8;
    if (t == OIIO::TypeDesc::UINT16) return SampleType::Unorm16;
    if (t == OIIO::TypeDesc::HALF) return SampleType::Half;
    return SampleType::Float;
}

} // namespace sg::image
