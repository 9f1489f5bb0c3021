// Encodings of tangent-space maps in images (Loviscach 2008, "Care: Two,
// three, or four channels"; Mikkelsen 2019, section 2.1 and listing 4 for
// the green convention): image <-> slopes / unit normals. The value mapping
// 0.5 n + 0.5 is storage, like a texture unit's unorm decode; every slope
// and normal conversion goes through the shared functions.
#include <algorithm>
#include <cmath>

#include "normalmap_internal.h"

namespace sg::normalmap {

namespace g = sg::glsl;
using detail::forRows;

Encoding parseEncoding(std::string_view text) {
    if (text == "rgb") return Encoding::Rgb;
    if (text == "rg") return Encoding::Rg;
    if (text == "ag") return Encoding::Ag;
    if (text == "signed") return Encoding::Signed;
    if (text == "deriv") return Encoding::Deriv;
    throw io::InputError("encoding", std::string(text), "expected rgb, rg, ag, signed or deriv");
}

Green parseGreen(std::string_view text) {
    if (text == "gl") return Green::Gl;
    if (text == "dx") return Green::Dx;
    throw io::InputError("green", std::string(text), "expected gl or dx");
}

std::string_view encodingName(Encoding e) {
    switch (e) {
    case Encoding::Rgb:
        return "rgb";
    case Encoding::Rg:
        return "rg";
    case Encoding::Ag:
        return "ag";
    case Encoding::Signed:
        return "signed";
    default:
        return "deriv";
    }
}

namespace {

int channelsNeeded(Encoding e) {
    switch (e) {
    case Encoding::Rgb:
    case Encoding::Signed:
        return 3;
    case Encoding::Ag:
        return 4;
    default:
        return 2;
    }
}

void checkChannels(const Image& img, const MapFormat& f, const std::string& file) {
    const int need = channelsNeeded(f.encoding);
    if (img.channels < need) {
        throw io::InputError(file, "channels",
                             "the image has " + std::to_string(img.channels) + " channel(s); the " +
                                 std::string(encodingName(f.encoding)) + " encoding needs " +
                                 std::to_string(need));
    }
    if (f.encoding == Encoding::Signed && !img.isFloat) {
        throw io::InputError(file, "encoding",
                             "signed normals need a floating-point image (this one stores "
                             "integers; use rgb)");
    }
}

// The stored x, y (signed, file's green convention) of a normal encoding.
glm::vec2 storedXY(const Image& img, Encoding e, int i, int j) {
    if (e == Encoding::Signed) return glm::vec2(img.at(i, j, 0), img.at(i, j, 1));
    if (e == Encoding::Ag)
        return glm::vec2(2.0f * img.at(i, j, 3) - 1.0f, 2.0f * img.at(i, j, 1) - 1.0f);
    return glm::vec2(2.0f * img.at(i, j, 0) - 1.0f, 2.0f * img.at(i, j, 1) - 1.0f);
}

// The slopes a derivative map stores (file's green convention).
glm::vec2 storedDeriv(const Image& img, const MapFormat& f, int i, int j) {
    const glm::vec2 c(img.at(i, j, 0), img.at(i, j, 1));
    return img.isFloat ? c : (2.0f * c - 1.0f) * f.derivRange;
}

void storeDeriv(Image& img, const MapFormat& f, int i, int j, glm::vec2 d) {
    const glm::vec2 c = img.isFloat ? d : 0.5f + 0.5f * d / f.derivRange;
    img.at(i, j, 0) = c.x;
    img.at(i, j, 1) = c.y;
}

// Stores a unit normal (already in the file's green convention).
void storeNormal(Image& img, Encoding e, int i, int j, glm::vec3 n) {
    const glm::vec3 c = e == Encoding::Signed ? n : 0.5f * n + 0.5f;
    if (e == Encoding::Ag) {
        img.at(i, j, 0) = 1.0f; // unused channels of the layout: white
        img.at(i, j, 1) = c.y;
        img.at(i, j, 2) = 1.0f;
        img.at(i, j, 3) = c.x;
        return;
    }
    img.at(i, j, 0) = c.x;
    img.at(i, j, 1) = c.y;
    if (e == Encoding::Rgb || e == Encoding::Signed) img.at(i, j, 2) = c.z;
}

Image blankImage(int w, int h, Encoding e, bool isFloat) {
    SG_EXPECTS(e != Encoding::Signed || isFloat, "signed normals need a floating-point image");
    Image img(w, h, e == Encoding::Ag ? 4 : channelsNeeded(e));
    img.isFloat = isFloat;
    return img;
}

} // namespace

DerivField decodeSlopes(const Image& img, const MapFormat& f, const std::string& file) {
    checkChannels(img, f, file);
    DerivField d(img.width, img.height);
    const bool flipV = f.green == Green::Dx;
    forRows(img.height, [&](int j) {
        for (int i = 0; i < img.width; ++i) {
            if (f.encoding == Encoding::Deriv) {
                glm::vec2 s = storedDeriv(img, f, i, j);
                d.at(i, j) = glm::vec2(s.x, flipV ? -s.y : s.y);
            } else {
                d.at(i, j) = g::sgTspaceNormalToDeriv(storedXY(img, f.encoding, i, j), flipV);
            }
        }
    });
    return d;
}

NormalField decodeNormals(const Image& img, const MapFormat& f, const std::string& file) {
    checkChannels(img, f, file);
    NormalField n(img.width, img.height);
    const float ySign = f.green == Green::Dx ? -1.0f : 1.0f;
    forRows(img.height, [&](int j) {
        for (int i = 0; i < img.width; ++i) {
            glm::vec3 v;
            if (f.encoding == Encoding::Deriv) {
                glm::vec2 s = storedDeriv(img, f, i, j);
                v = g::sgDerivToTspaceNormal(glm::vec2(s.x, ySign * s.y), false);
            } else {
                glm::vec2 xy = storedXY(img, f.encoding, i, j);
                float z;
                if (f.encoding == Encoding::Rgb) {
                    z = 2.0f * img.at(i, j, 2) - 1.0f;
                } else if (f.encoding == Encoding::Signed) {
                    z = img.at(i, j, 2);
                } else {
                    z = std::sqrt(std::max(0.0f, 1.0f - xy.x * xy.x - xy.y * xy.y));
                }
                v = glm::vec3(xy.x, ySign * xy.y, z);
            }
            n.at(i, j) = g::sgSafeNormalize(v, detail::kFlat);
        }
    });
    return n;
}

Image encodeSlopes(const DerivField& d, const MapFormat& f, bool isFloat) {
    Image img = blankImage(d.width, d.height, f.encoding, isFloat);
    const bool flipV = f.green == Green::Dx;
    forRows(d.height, [&](int j) {
        for (int i = 0; i < d.width; ++i) {
            const glm::vec2 s = d.at(i, j);
            if (f.encoding == Encoding::Deriv) {
                storeDeriv(img, f, i, j, glm::vec2(s.x, flipV ? -s.y : s.y));
            } else {
                storeNormal(img, f.encoding, i, j, g::sgDerivToTspaceNormal(s, flipV));
            }
        }
    });
    return img;
}

Image encodeNormals(const NormalField& n, const MapFormat& f, bool isFloat) {
    Image img = blankImage(n.width, n.height, f.encoding, isFloat);
    const float ySign = f.green == Green::Dx ? -1.0f : 1.0f;
    forRows(n.height, [&](int j) {
        for (int i = 0; i < n.width; ++i) {
            const glm::vec3 v = n.at(i, j);
            if (f.encoding == Encoding::Deriv) {
                glm::vec2 s = g::sgTspaceNormalToDeriv(glm::vec2(v.x, v.y), false);
                storeDeriv(img, f, i, j, glm::vec2(s.x, ySign * s.y));
            } else {
                storeNormal(img, f.encoding, i, j, glm::vec3(v.x, ySign * v.y, v.z));
            }
        }
    });
    return img;
}

NormalField normalsFromSlopes(const DerivField& d) {
    NormalField n(d.width, d.height);
    forRows(d.height, [&](int j) {
        for (int i = 0; i < d.width; ++i) n.at(i, j) = g::sgDerivToTspaceNormal(d.at(i, j), false);
    });
    return n;
}

DerivField slopesFromNormals(const NormalField& n) {
    DerivField d(n.width, n.height);
    forRows(n.height, [&](int j) {
        for (int i = 0; i < n.width; ++i) {
            const glm::vec3 v = n.at(i, j);
            d.at(i, j) = g::sgTspaceNormalToDeriv(glm::vec2(v.x, v.y), false);
        }
    });
    return d;
}

ScalarField scalarFromImage(const Image& img, int channel, float scale, const std::string& file) {
    if (channel >= img.channels) {
        throw io::InputError(file, "channels",
                             "channel " + std::to_string(channel) + " requested; the image has " +
                                 std::to_string(img.channels));
    }
    ScalarField s(img.width, img.height);
    const bool luminance = channel < 0 && img.channels >= 3;
    const int c = channel < 0 ? 0 : channel;
    forRows(img.height, [&](int j) {
        for (int i = 0; i < img.width; ++i) {
            float v = luminance ? 0.2126f * img.at(i, j, 0) + 0.7152f * img.at(i, j, 1) +
                                      0.0722f * img.at(i, j, 2)
                                : img.at(i, j, c);
            s.at(i, j) = scale * v;
        }
    });
    return s;
}

Image imageFromScalar(const ScalarField& s, float offset, float scale, bool isFloat) {
    Image img(s.width, s.height, 1);
    img.isFloat = isFloat;
    for (size_t k = 0; k < s.size(); ++k) img.samples[k] = (s.v[k] - offset) * scale;
    return img;
}

Image shade(const NormalField& n, glm::vec3 lightDir) {
    const glm::vec3 L = g::sgSafeNormalize(lightDir, detail::kFlat);
    Image img(n.width, n.height, 3);
    forRows(n.height, [&](int j) {
        for (int i = 0; i < n.width; ++i) {
            // Grey albedo 0.85 with a little ambient so shadowed slopes keep
            // their shape.
            const float c = 0.08f + 0.85f * std::max(0.0f, glm::dot(n.at(i, j), L));
            for (int k = 0; k < 3; ++k) img.at(i, j, k) = std::min(c, 1.0f);
        }
    });
    return img;
}

} // namespace sg::normalmap
