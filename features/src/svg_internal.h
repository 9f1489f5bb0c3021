// Internal to surfgrad_features: the parts of the SVG loader, one concern
// per file (coverage in docs/features-input.md, "SVG coverage"):
//   svg_xml.{h,cpp}    the XML (pugixml) as elements in document order, with
//                      the XML limits;
//   svg_values.cpp     numbers, lengths and number lists of attribute values;
//   svg_transform.cpp  the transform attribute and nested viewports
//                      (SVG 1.1 sections 7.6 and 7.7-7.8);
//   svg_path.cpp       path data and elliptical arcs (SVG 1.1 section 8.3,
//                      appendix F.6);
//   svg_shapes.cpp     the basic shapes as their equivalent paths (SVG 2
//                      section 10);
//   input_svg.cpp      the document structure (svg, g, display, the root's y
//                      flip) and parseSvg / loadSvg.
// Errors are io::InputError(source, element, reason) with the element named
// as in the loader ("path #3 command 7 'A'", "rect #1 attribute 'width'").
#pragma once

#include "path_builder.h"
#include "svg_xml.h"

#include "surfgrad/features/curves.h"

#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sg::features::detail {

inline constexpr double kSvgPi = std::numbers::pi;

// Throws io::InputError(source, element, reason).
[[noreturn]] void svgFail(const std::string& source, const std::string& element,
                          const std::string& reason);

// ---------------------------------------------------------------------------
// Affine maps: x' = a x + c y + e, y' = b x + d y + f (SVG matrix(a b c d e f)).

struct Affine {
    double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;
    glm::dvec2 apply(glm::dvec2 p) const { return {a * p.x + c * p.y + e, b * p.x + d * p.y + f}; }
    glm::dvec2 linear(glm::dvec2 v) const { return {a * v.x + c * v.y, b * v.x + d * v.y}; }
    double det() const { return a * d - b * c; }
    bool finite() const {
        return std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(d) &&
               std::isfinite(e) && std::isfinite(f);
    }
};

// (l * r)(p) = l(r(p)).
inline Affine operator*(const Affine& l, const Affine& r) {
    return {l.a * r.a + l.c * r.b, l.b * r.a + l.d * r.b,       l.a * r.c + l.c * r.d,
            l.b * r.c + l.d * r.d, l.a * r.e + l.c * r.f + l.e, l.b * r.e + l.d * r.f + l.f};
}

// ---------------------------------------------------------------------------
// Number lists (path data, points, transform arguments, viewBox): a cursor
// over an attribute value (svg_values.cpp).

class Scanner {
public:
    explicit Scanner(std::string_view s) : s_(s) {}

    static bool isSpace(char c) {
        return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f';
    }
    void skipSpace() {
        while (i_ < s_.size() && isSpace(s_[i_])) ++i_;
    }
    // wsp* (',' wsp*)?
    void skipCommaSpace() {
        skipSpace();
        if (i_ < s_.size() && s_[i_] == ',') {
            ++i_;
            skipSpace();
        }
    }
    bool atEnd() const { return i_ >= s_.size(); }
    char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
    void advance() { ++i_; }
    std::size_t pos() const { return i_; }
    bool atNumberStart() const {
        const char c = peek();
        return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+';
    }

    enum class Num { Ok, None, Range };
    // SVG number: sign? (digits ('.' digits?)? | '.' digits) exponent?.
    // The longest match is taken, so ".5.5" is .5 then .5 and "-1-2" is -1
    // then -2; an 'e' not followed by digits is not part of the number.
    Num number(double& out);

private:
    std::string_view s_;
    std::size_t i_ = 0;
};

// ---------------------------------------------------------------------------
// Attribute values (svg_values.cpp). `el` names the element for errors.

// s without leading and trailing SVG whitespace.
std::string_view svgTrim(std::string_view s);

// The length attribute `name` of e in user units (px), absolute units at
// 96 dpi; nullopt when e has no such attribute.
std::optional<double> svgLength(const XmlElement& e, const char* name, const std::string& el,
                                const std::string& source);

// The numbers of s (separated by whitespace and/or one comma), each within
// kMaxAbsCoord, at most maxCount of them; `el` names the attribute.
std::vector<double> svgNumberList(std::string_view s, const std::string& el, std::size_t maxCount,
                                  const std::string& source);

// ---------------------------------------------------------------------------
// Coordinate systems (svg_transform.cpp).

// The transform attribute value s (SVG 1.1 7.6): the list's product, left
// to right; finite. `el` names the attribute.
Affine svgTransform(std::string_view s, const std::string& el, const std::string& source);

// A nested <svg>'s map from its user space to its parent's: x/y and the
// viewBox-to-viewport map with preserveAspectRatio (SVG 1.1 7.7-7.8).
Affine svgNestedViewport(const XmlElement& e, const std::string& el, const std::string& source);

// ---------------------------------------------------------------------------
// Outlines (svg_path.cpp, svg_shapes.cpp): what one element draws into the
// builder, in output coordinates through ctm.

struct SvgDraw {
    PathBuilder& builder;
    const std::string& source;
    const XmlElement& element;
    const std::string& el; // "path #3"
    const Affine& ctm;     // the element's user space -> output space
};

// The curve name of the element's outlines: its id, else `el`.
CurveInfo svgCurveInfo(const SvgDraw& d);

// <path>: the d attribute (nothing without one).
void svgDrawPath(const SvgDraw& d);

// A basic shape or <path> (`name`: its local name, e.g. "rect").
void svgDrawShape(std::string_view name, const SvgDraw& d);

} // namespace sg::features::detail
