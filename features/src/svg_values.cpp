// Attribute values of SVG drawings (svg_internal.h): the number grammar
// shared by path data, points, transforms and viewBox (SVG 1.1 section
// 8.3.9, SVG 2 section 9.3.9), lengths with absolute units (SVG 1.1 section
// 7.10, at 96 dpi), and number lists. Every number is range-checked.
#include "svg_internal.h"

#include "surfgrad/base/io.h"

#include <charconv>

namespace sg::features::detail {

void svgFail(const std::string& source, const std::string& element, const std::string& reason) {
    throw io::InputError(source, element, reason);
}

Scanner::Num Scanner::number(double& out) {
    std::size_t k = i_;
    if (k < s_.size() && (s_[k] == '+' || s_[k] == '-')) ++k;
    const std::size_t mant = k;
    bool digits = false;
    while (k < s_.size() && s_[k] >= '0' && s_[k] <= '9') {
        ++k;
        digits = true;
    }
    if (k < s_.size() && s_[k] == '.') {
        std::size_t f = k + 1;
        bool frac = false;
        while (f < s_.size() && s_[f] >= '0' && s_[f] <= '9') {
            ++f;
            frac = true;
        }
        if (digits || frac) {
            k = f;
            digits = true;
        }
    }
    if (!digits) return Num::None;
    if (k < s_.size() && (s_[k] == 'e' || s_[k] == 'E')) {
        std::size_t x = k + 1;
        if (x < s_.size() && (s_[x] == '+' || s_[x] == '-')) ++x;
        const std::size_t xd = x;
        while (x < s_.size() && s_[x] >= '0' && s_[x] <= '9') ++x;
        if (x > xd) k = x;
    }
    // from_chars takes no '+'; handle the sign ourselves.
    const bool neg = s_[i_] == '-';
    double v = 0.0;
    auto [p, ec] = std::from_chars(s_.data() + mant, s_.data() + k, v, std::chars_format::general);
    if (ec == std::errc::result_out_of_range) return Num::Range; // overflow or underflow
    if (ec != std::errc() || p != s_.data() + k) return Num::None;
    out = neg ? -v : v;
    i_ = k;
    return Num::Ok;
}

std::string_view svgTrim(std::string_view s) {
    while (!s.empty() && Scanner::isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && Scanner::isSpace(s.back())) s.remove_suffix(1);
    return s;
}

std::optional<double> svgLength(const XmlElement& e, const char* name, const std::string& el,
                                const std::string& source) {
    const std::string* v = e.attr(name);
    if (!v) return std::nullopt;
    const std::string ael = el + " attribute '" + name + "'";
    Scanner sc(*v);
    sc.skipSpace();
    double x = 0.0;
    const auto r = sc.number(x);
    if (r == Scanner::Num::Range) svgFail(source, ael, "number out of range");
    if (r != Scanner::Num::Ok)
        svgFail(source, ael, "expected a length, got \"" + v->substr(0, 40) + "\"");
    const std::string_view unit = svgTrim(std::string_view(*v).substr(sc.pos()));
    double scale = 1.0;
    if (unit.empty() || unit == "px")
        scale = 1.0;
    else if (unit == "in")
        scale = 96.0;
    else if (unit == "cm")
        scale = 96.0 / 2.54;
    else if (unit == "mm")
        scale = 96.0 / 25.4;
    else if (unit == "pt")
        scale = 96.0 / 72.0;
    else if (unit == "pc")
        scale = 16.0;
    else
        svgFail(source, ael,
                "unit '" + std::string(unit.substr(0, 10)) +
                    "' is not supported (use px, in, cm, mm, pt, pc)");
    x *= scale;
    if (std::abs(x) > kMaxAbsCoord) svgFail(source, ael, "value exceeds the coordinate limit 1e12");
    return x;
}

std::vector<double> svgNumberList(std::string_view s, const std::string& el, std::size_t maxCount,
                                  const std::string& source) {
    std::vector<double> out;
    Scanner sc(s);
    sc.skipSpace();
    while (!sc.atEnd()) {
        double v = 0.0;
        const auto r = sc.number(v);
        if (r == Scanner::Num::Range)
            svgFail(source, el, "number out of range at character " + std::to_string(sc.pos()));
        if (r != Scanner::Num::Ok)
            svgFail(source, el, "expected a number at character " + std::to_string(sc.pos()));
        if (std::abs(v) > kMaxAbsCoord)
            svgFail(source, el, "number exceeds the coordinate limit 1e12");
        if (out.size() >= maxCount)
            svgFail(source, el, "more than " + std::to_string(maxCount) + " numbers");
        out.push_back(v);
        sc.skipCommaSpace();
    }
    return out;
}

} // namespace sg::features::detail
