// Glyph outlines of a text through FreeType as feature-curve networks
// (contract in surfgrad/features/curves.h, coverage in docs/features-input.md).
//
// Outlines are loaded with FT_LOAD_NO_SCALE, so coordinates are font units
// (integers for TrueType), y up, the first glyph's origin at (0, 0) on the
// baseline. The outline is walked here rather than with
// FT_Outline_Decompose because that routine computes the implied on-curve
// point between two consecutive TrueType conic controls in integer
// arithmetic (rounding odd sums); the TrueType rule puts it exactly at the
// midpoint, which doubles represent exactly for integer inputs, keeping the
// curve G1 there. Conic segments are quadratic Beziers already (Parilov and
// Zorin 2008 work on quadratic curves directly); CFF cubics go through the
// same approximation as SVG cubics.
#include "surfgrad/features/curves.h"
#include "surfgrad/base/io.h"

#include "path_builder.h"

#include <cstdio>
#include <memory>

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H

namespace sg::features {

namespace {

// FreeType's documented way to get its error messages (fterrors.h).
#undef FTERRORS_H_
#define FT_ERRORDEF(e, v, s) {e, s},
#define FT_ERROR_START_LIST {
#define FT_ERROR_END_LIST                                                                          \
    { 0, nullptr }                                                                                 \
    }                                                                                              \
    ;
const struct {
    int code;
    const char* message;
} kFtErrors[] =
#include FT_ERRORS_H

    std::string ftMessage(FT_Error err) {
    for (const auto& e : kFtErrors) {
        if (e.message && e.code == err)
            return std::string(e.message) + " (FreeType error " + std::to_string(err) + ")";
    }
    return "FreeType error " + std::to_string(err);
}

std::string codepointName(std::uint32_t cp) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "U+%04X", unsigned(cp));
    return buf;
}

// Strict UTF-8 (no overlongs, no surrogates, <= U+10FFFF).
std::vector<std::uint32_t> decodeUtf8(std::string_view s, const std::string& source) {
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < s.size();) {
        const auto b0 = static_cast<unsigned char>(s[i]);
        std::uint32_t cp = 0;
        int len = 0;
        if (b0 < 0x80) {
            cp = b0;
            len = 1;
        } else if ((b0 & 0xE0) == 0xC0) {
            cp = b0 & 0x1F;
            len = 2;
        } else if ((b0 & 0xF0) == 0xE0) {
            cp = b0 & 0x0F;
            len = 3;
        } else if ((b0 & 0xF8) == 0xF0) {
            cp = b0 & 0x07;
            len = 4;
        }
        const std::string el = "text byte " + std::to_string(i);
        if (len == 0 || i + std::size_t(len) > s.size())
            throw io::InputError(source, el, "invalid UTF-8");
        for (int k = 1; k < len; ++k) {
            const auto b = static_cast<unsigned char>(s[i + std::size_t(k)]);
            if ((b & 0xC0) != 0x80) throw io::InputError(source, el, "invalid UTF-8");
            cp = (cp << 6) | (b & 0x3F);
        }
        static constexpr std::uint32_t kMin[5] = {0, 0, 0x80, 0x800, 0x10000};
        if (cp < kMin[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
            throw io::InputError(source, el,
                                 "invalid UTF-8 (overlong, surrogate or beyond U+10FFFF)");
        }
        if (out.size() >= kMaxTextCodepoints) {
            throw io::InputError(source, el,
                                 "text is longer than " + std::to_string(kMaxTextCodepoints) +
                                     " characters");
        }
        out.push_back(cp);
        i += std::size_t(len);
    }
    return out;
}

struct LibraryDeleter {
    void operator()(FT_Library lib) const { FT_Done_FreeType(lib); }
};
struct FaceDeleter {
    void operator()(FT_Face face) const { FT_Done_Face(face); }
};
using LibraryPtr = std::unique_ptr<std::remove_pointer_t<FT_Library>, LibraryDeleter>;
using FacePtr = std::unique_ptr<std::remove_pointer_t<FT_Face>, FaceDeleter>;

// Walks one glyph outline (TrueType conics, CFF cubics) into the builder,
// offset by the pen position. One subpath (curve) per contour.
void walkOutline(const FT_Outline& outline, glm::dvec2 pen, const std::string& glyphName,
                 detail::PathBuilder& builder, const std::string& source) {
    const std::string el = "glyph " + glyphName;
    const int nPoints = outline.n_points;
    int first = 0;
    for (int ci = 0; ci < outline.n_contours; ++ci) {
        const int last = outline.contours[ci];
        if (last < first || last >= nPoints)
            throw io::InputError(source, el, "malformed outline (contour indices)");
        auto P = [&](int i) {
            return pen + glm::dvec2(double(outline.points[i].x), double(outline.points[i].y));
        };
        auto T = [&](int i) { return FT_CURVE_TAG(outline.tags[i]); };
        const int count = last - first + 1;
        CurveInfo info;
        info.name = glyphName + " contour " + std::to_string(ci);
        if (count < 2) {
            first = last + 1;
            continue; // a single point (an anchor) draws nothing
        }
        if (T(first) == FT_CURVE_TAG_CUBIC) {
            throw io::InputError(source, el,
                                 "malformed outline (contour " + std::to_string(ci) +
                                     " starts with a cubic control point)");
        }
        glm::dvec2 start;
        int begin = first, end = last; // points still to visit: begin..end
        if (T(first) == FT_CURVE_TAG_ON) {
            start = P(first);
            begin = first + 1;
        } else if (T(last) == FT_CURVE_TAG_ON) {
            start = P(last);
            end = last - 1;
        } else {
            // Both ends conic: the contour starts at their implied midpoint.
            start = 0.5 * (P(first) + P(last));
        }
        builder.moveTo(start, info, el);
        bool haveConic = false;
        glm::dvec2 conic{0.0};
        int nCubic = 0;
        glm::dvec2 cubic[2];
        auto onPoint = [&](glm::dvec2 p) {
            if (haveConic)
                builder.quadTo(conic, p);
            else if (nCubic == 2)
                builder.cubicTo(cubic[0], cubic[1], p);
            else if (nCubic == 1)
                throw io::InputError(source, el, "malformed outline (a lone cubic control point)");
            else
                builder.lineTo(p);
            haveConic = false;
            nCubic = 0;
        };
        for (int i = begin; i <= end; ++i) {
            const glm::dvec2 p = P(i);
            switch (T(i)) {
            case FT_CURVE_TAG_ON:
                onPoint(p);
                break;
            case FT_CURVE_TAG_CONIC:
                if (nCubic)
                    throw io::InputError(source, el,
                                         "malformed outline (conic after cubic control)");
                if (haveConic) {
                    // TrueType: an on-curve point is implied halfway
                    // between consecutive conic controls.
                    builder.quadTo(conic, 0.5 * (conic + p));
                }
                conic = p;
                haveConic = true;
                break;
            default: // FT_CURVE_TAG_CUBIC
                if (haveConic || nCubic == 2) {
                    throw io::InputError(source, el,
                                         "malformed outline (too many consecutive control points)");
                }
                cubic[nCubic++] = p;
                break;
            }
        }
        onPoint(start);
        builder.close();
        first = last + 1;
    }
}

} // namespace

CurveNetwork parseFont(const std::uint8_t* data, std::size_t size, std::string_view text,
                       const std::string& source, const FontOptions& opt) {
    if (text.empty()) throw io::InputError(source, "text", "the text is empty");
    const std::vector<std::uint32_t> cps = decodeUtf8(text, source);
    if (size > kMaxFontBytes) {
        throw io::InputError(source, "",
                             "font is " + std::to_string(size) + " bytes; limit is " +
                                 std::to_string(kMaxFontBytes));
    }
    if (opt.faceIndex < 0 || opt.faceIndex > 0xFFFF) {
        throw io::InputError(source, "face " + std::to_string(opt.faceIndex),
                             "face index must be 0..65535");
    }
    FT_Library rawLib = nullptr;
    if (FT_Error err = FT_Init_FreeType(&rawLib))
        throw io::InputError(source, "", "cannot start FreeType: " + ftMessage(err));
    LibraryPtr lib(rawLib);

    auto open = [&](FT_Long index) {
        FT_Face raw = nullptr;
        const FT_Error err = FT_New_Memory_Face(lib.get(), data, FT_Long(size), index, &raw);
        if (err) {
            throw io::InputError(source, index ? "face " + std::to_string(index) : std::string(),
                                 "not a usable font file: " + ftMessage(err));
        }
        return FacePtr(raw);
    };
    FacePtr face = open(0);
    if (opt.faceIndex >= face->num_faces) {
        throw io::InputError(source, "face " + std::to_string(opt.faceIndex),
                             "face index out of range: the file has " +
                                 std::to_string(face->num_faces) + " face(s)");
    }
    if (opt.faceIndex > 0) face = open(opt.faceIndex);
    const std::string faceName = std::string(face->family_name ? face->family_name : "?") + " " +
                                 (face->style_name ? face->style_name : "");
    if (!FT_IS_SCALABLE(face.get()))
        throw io::InputError(source, "", "font '" + faceName + "' has no outlines (bitmap only)");
    if (FT_Select_Charmap(face.get(), FT_ENCODING_UNICODE)) {
        throw io::InputError(source, "", "font '" + faceName + "' has no Unicode character map");
    }

    detail::PathBuilder builder(source);
    const bool kerning = FT_HAS_KERNING(face.get());
    // Line height in font units (ascender - descender + gap).
    const double lineHeight =
        face->height > 0 ? double(face->height) : 1.2 * double(face->units_per_EM);
    glm::dvec2 pen{0.0};
    FT_UInt prev = 0;
    for (std::uint32_t cp : cps) {
        if (cp == '\n') {
            pen = {0.0, pen.y - lineHeight};
            prev = 0;
            continue;
        }
        if (cp == '\r') continue;
        std::string glyphName = codepointName(cp);
        if (cp >= 0x20 && cp != 0x7F) {
            glyphName += " '";
            detail::appendUtf8(glyphName, cp);
            glyphName += "'";
        }
        const std::string el = "glyph " + codepointName(cp);
        const FT_UInt gi = FT_Get_Char_Index(face.get(), cp);
        if (gi == 0)
            throw io::InputError(source, el,
                                 "not in font '" + faceName + "' (face " +
                                     std::to_string(opt.faceIndex) + ")");
        if (kerning && prev) {
            FT_Vector delta{0, 0};
            if (!FT_Get_Kerning(face.get(), prev, gi, FT_KERNING_UNSCALED, &delta))
                pen.x += double(delta.x);
        }
        if (FT_Error err = FT_Load_Glyph(
                face.get(), gi, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP)) {
            throw io::InputError(source, el, "cannot load the glyph: " + ftMessage(err));
        }
        const FT_GlyphSlot slot = face->glyph;
        if (slot->format != FT_GLYPH_FORMAT_OUTLINE)
            throw io::InputError(source, el, "glyph is not an outline");
        walkOutline(slot->outline, pen, glyphName, builder, source);
        pen.x += double(slot->advance.x);
        prev = gi;
    }
    return builder.finish(opt.approx, "the text has no glyph outlines (only spaces?)");
}

CurveNetwork loadFont(const std::filesystem::path& file, std::string_view text,
                      const FontOptions& opt) {
    const std::string bytes = io::readFile(file, kMaxFontBytes);
    return parseFont(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), text,
                     file.string(), opt);
}

} // namespace sg::features
