// SVG drawings as feature-curve networks (contract in surfgrad/curves.h,
// coverage in docs/features-input.md).
//
// Follows SVG 1.1 / SVG 2: path data grammar (SVG 1.1 section 8.3.9, SVG 2
// 9.3.9), the elliptical arc endpoint-to-center conversion and out-of-range
// radii correction (SVG 1.1 appendix F.6.5-F.6.6), the equivalent paths of
// the basic shapes (SVG 2 section 10), and the transform attribute syntax
// (SVG 1.1 section 7.6). Cubic Beziers and arcs become quadratic Beziers
// within the stated tolerance (curve_approx.cpp) because the feature maps of
// Parilov and Zorin (2008) are built from quadratic curves.
//
// The XML is untrusted and read by a small tokenizer of our own: no DTD
// processing (only the five predefined entities and numeric character
// references are expanded, so entity expansion attacks cannot happen),
// comments, CDATA, processing instructions and DOCTYPE internal subsets are
// skipped in linear time, element nesting is limited (kMaxSvgDepth) and
// tracked on an explicit stack (no recursion), attributes per element are
// limited, and every number is range-checked. Every loop advances through
// the text, so parsing is linear in the file size.
#include "surfgrad/curves.h"
#include "surfgrad/io.h"

#include "path_builder.h"

#include <charconv>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>

namespace sg::features {

namespace {

constexpr std::size_t kMaxSvgDepth = 256;
constexpr std::size_t kMaxAttributes = 256;
constexpr double kPi = std::numbers::pi;

// ---------------------------------------------------------------------------
// XML tokenizer

struct XmlAttr {
    std::string_view name;
    std::string value; // entities decoded
};

struct XmlTag {
    enum class Kind { Start, End, Eof } kind = Kind::Eof;
    std::string_view name;
    std::vector<XmlAttr> attrs;
    bool selfClosing = false;
    std::size_t offset = 0; // of '<'

    const std::string* attr(std::string_view n) const {
        for (const auto& a : attrs) {
            if (a.name == n) return &a.value;
        }
        return nullptr;
    }
};

class XmlReader {
public:
    XmlReader(std::string_view text, const std::string& source) : t_(text), source_(source) {
        // UTF-8 byte order mark.
        if (t_.size() >= 3 && t_.substr(0, 3) == "\xEF\xBB\xBF") i_ = 3;
    }

    std::string lineOf(std::size_t offset) const {
        std::size_t line = 1;
        for (std::size_t k = 0; k < offset && k < t_.size(); ++k) line += t_[k] == '\n';
        return "line " + std::to_string(line);
    }

    [[noreturn]] void fail(std::size_t offset, const std::string& reason) const {
        throw io::InputError(source_, lineOf(offset), reason);
    }

    // Next start or end tag; skips text, comments, CDATA, PIs, DOCTYPE.
    void next(XmlTag& tag) {
        tag.attrs.clear();
        tag.selfClosing = false;
        for (;;) {
            const std::size_t lt = t_.find('<', i_);
            if (lt == std::string_view::npos) {
                i_ = t_.size();
                tag.kind = XmlTag::Kind::Eof;
                tag.offset = t_.size();
                return;
            }
            i_ = lt;
            tag.offset = lt;
            if (startsWith("<!--")) {
                skipPast(lt + 4, "-->", "unterminated comment");
            } else if (startsWith("<![CDATA[")) {
                skipPast(lt + 9, "]]>", "unterminated CDATA section");
            } else if (startsWith("<?")) {
                skipPast(lt + 2, "?>", "unterminated processing instruction");
            } else if (startsWith("<!")) {
                skipDeclaration(lt);
            } else if (startsWith("</")) {
                i_ = lt + 2;
                tag.kind = XmlTag::Kind::End;
                tag.name = readName("element name after '</'");
                skipSpace();
                if (i_ >= t_.size() || t_[i_] != '>')
                    fail(lt, "expected '>' to end </" + std::string(tag.name));
                ++i_;
                return;
            } else {
                i_ = lt + 1;
                tag.kind = XmlTag::Kind::Start;
                tag.name = readName("element name after '<'");
                readAttributes(tag);
                return;
            }
        }
    }

private:
    bool startsWith(std::string_view s) const { return t_.substr(i_, s.size()) == s; }

    void skipPast(std::size_t from, std::string_view end, const char* what) {
        const std::size_t p = t_.find(end, from);
        if (p == std::string_view::npos) fail(i_, what);
        i_ = p + end.size();
    }

    // <!DOCTYPE ... [ internal subset ] >: skipped; entities declared there
    // are never expanded.
    void skipDeclaration(std::size_t lt) {
        std::size_t k = lt + 2;
        int bracket = 0;
        while (k < t_.size()) {
            const char c = t_[k];
            if (c == '"' || c == '\'') {
                const std::size_t q = t_.find(c, k + 1);
                if (q == std::string_view::npos) break;
                k = q + 1;
            } else if (t_.substr(k, 4) == "<!--") {
                const std::size_t q = t_.find("-->", k + 4);
                if (q == std::string_view::npos) break;
                k = q + 3;
            } else if (c == '[') {
                ++bracket;
                ++k;
            } else if (c == ']') {
                --bracket;
                ++k;
            } else if (c == '>' && bracket <= 0) {
                i_ = k + 1;
                return;
            } else {
                ++k;
            }
        }
        fail(lt, "unterminated <! declaration");
    }

    static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
    static bool isNameChar(char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
               c == '_' || c == ':' || c == '-' || c == '.' ||
               static_cast<unsigned char>(c) >= 0x80;
    }

    void skipSpace() {
        while (i_ < t_.size() && isSpace(t_[i_])) ++i_;
    }

    std::string_view readName(const char* what) {
        const std::size_t b = i_;
        while (i_ < t_.size() && isNameChar(t_[i_])) ++i_;
        if (i_ == b || (t_[b] >= '0' && t_[b] <= '9') || t_[b] == '-' || t_[b] == '.') {
            fail(b, std::string("expected ") + what);
        }
        return t_.substr(b, i_ - b);
    }

    void readAttributes(XmlTag& tag) {
        for (;;) {
            const std::size_t before = i_;
            skipSpace();
            if (i_ >= t_.size())
                fail(tag.offset, "unexpected end of file inside <" + std::string(tag.name) + ">");
            if (t_[i_] == '>') {
                ++i_;
                return;
            }
            if (t_[i_] == '/') {
                if (i_ + 1 < t_.size() && t_[i_ + 1] == '>') {
                    i_ += 2;
                    tag.selfClosing = true;
                    return;
                }
                fail(i_, "expected '/>'");
            }
            if (i_ == before) fail(i_, "expected whitespace before attribute");
            const std::size_t at = i_;
            XmlAttr a;
            a.name = readName("attribute name");
            skipSpace();
            if (i_ >= t_.size() || t_[i_] != '=')
                fail(i_, "expected '=' after attribute " + std::string(a.name));
            ++i_;
            skipSpace();
            if (i_ >= t_.size() || (t_[i_] != '"' && t_[i_] != '\'')) {
                fail(i_, "attribute value of " + std::string(a.name) + " must be quoted");
            }
            const char q = t_[i_];
            const std::size_t end = t_.find(q, i_ + 1);
            if (end == std::string_view::npos)
                fail(at, "unterminated value of attribute " + std::string(a.name));
            a.value = decode(t_.substr(i_ + 1, end - i_ - 1), i_ + 1);
            i_ = end + 1;
            if (tag.attr(a.name)) fail(at, "duplicate attribute " + std::string(a.name));
            if (tag.attrs.size() >= kMaxAttributes) {
                fail(at,
                     "more than " + std::to_string(kMaxAttributes) + " attributes on one element");
            }
            tag.attrs.push_back(std::move(a));
        }
    }

    std::string decode(std::string_view raw, std::size_t offset) const {
        std::string out;
        out.reserve(raw.size());
        for (std::size_t k = 0; k < raw.size(); ++k) {
            const char c = raw[k];
            if (c == '<') fail(offset + k, "'<' is not allowed in an attribute value");
            if (c != '&') {
                out += c;
                continue;
            }
            const std::size_t semi = raw.find(';', k);
            if (semi == std::string_view::npos || semi - k > 12)
                fail(offset + k, "'&' without a reference");
            const std::string_view ref = raw.substr(k + 1, semi - k - 1);
            if (ref == "lt")
                out += '<';
            else if (ref == "gt")
                out += '>';
            else if (ref == "amp")
                out += '&';
            else if (ref == "quot")
                out += '"';
            else if (ref == "apos")
                out += '\'';
            else if (ref.size() >= 2 && ref[0] == '#') {
                const bool hex = ref[1] == 'x';
                const std::string_view digits = ref.substr(hex ? 2 : 1);
                std::uint32_t cp = 0;
                auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), cp,
                                               hex ? 16 : 10);
                if (digits.empty() || ec != std::errc() || p != digits.data() + digits.size() ||
                    cp == 0 || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
                    fail(offset + k, "invalid character reference &" + std::string(ref) + ";");
                }
                detail::appendUtf8(out, cp);
            } else {
                fail(offset + k, "entity &" + std::string(ref) +
                                     "; is not supported (only &lt; &gt; &amp; &quot; &apos; and "
                                     "numeric references; DTD entities are never expanded)");
            }
            k = semi;
        }
        return out;
    }

    std::string_view t_;
    const std::string& source_;
    std::size_t i_ = 0;
};

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
Affine operator*(const Affine& l, const Affine& r) {
    return {l.a * r.a + l.c * r.b, l.b * r.a + l.d * r.b,       l.a * r.c + l.c * r.d,
            l.b * r.c + l.d * r.d, l.a * r.e + l.c * r.f + l.e, l.b * r.e + l.d * r.f + l.f};
}

// ---------------------------------------------------------------------------
// Number lists (path data, points, transform arguments, viewBox).

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
    Num number(double& out) {
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
        auto [p, ec] =
            std::from_chars(s_.data() + mant, s_.data() + k, v, std::chars_format::general);
        if (ec == std::errc::result_out_of_range) return Num::Range; // overflow or underflow
        if (ec != std::errc() || p != s_.data() + k) return Num::None;
        out = neg ? -v : v;
        i_ = k;
        return Num::Ok;
    }

private:
    std::string_view s_;
    std::size_t i_ = 0;
};

// ---------------------------------------------------------------------------
// SVG semantics

class SvgLoader {
public:
    SvgLoader(std::string_view text, const std::string& source, const SvgOptions& opt)
        : xml_(text, source), source_(source), opt_(opt), builder_(source) {}

    CurveNetwork run() {
        XmlTag tag;
        bool rootDone = false;
        for (;;) {
            xml_.next(tag);
            if (tag.kind == XmlTag::Kind::Eof) break;
            if (tag.kind == XmlTag::Kind::End) {
                if (stack_.empty() || stack_.back().name != tag.name) {
                    xml_.fail(tag.offset,
                              "end tag </" + std::string(tag.name) + "> does not match " +
                                  (stack_.empty() ? std::string("any open element")
                                                  : "<" + std::string(stack_.back().name) + ">"));
                }
                stack_.pop_back();
                if (stack_.empty()) rootDone = true;
                continue;
            }
            if (rootDone)
                xml_.fail(tag.offset,
                          "element <" + std::string(tag.name) + "> after the root element");
            if (stack_.size() >= kMaxSvgDepth) {
                xml_.fail(tag.offset, "elements nested deeper than " +
                                          std::to_string(kMaxSvgDepth) + " levels");
            }
            startElement(tag);
            if (tag.selfClosing) {
                stack_.pop_back();
                if (stack_.empty()) rootDone = true;
            }
        }
        if (!stack_.empty()) {
            xml_.fail(stack_.back().offset, "<" + std::string(stack_.back().name) +
                                                "> is not closed before the end of the file");
        }
        if (!rootDone) throw io::InputError(source_, "", "no <svg> element (not an SVG file?)");
        return builder_.finish(opt_.approx,
                               "the drawing has no curves (no visible path or shape with length)");
    }

private:
    struct State {
        std::string_view name;
        std::size_t offset;
        Affine ctm; // user space of this element -> output space
        bool skip;
    };

    [[noreturn]] void fail(const std::string& element, const std::string& reason) const {
        throw io::InputError(source_, element, reason);
    }

    static std::string_view localName(std::string_view name, bool& foreign) {
        foreign = false;
        const auto colon = name.find(':');
        if (colon == std::string_view::npos) return name;
        if (name.substr(0, colon) == "svg") return name.substr(colon + 1);
        foreign = true; // another namespace (inkscape:, sodipodi:, ...)
        return name;
    }

    static bool hidden(const XmlTag& tag) {
        if (const std::string* v = tag.attr("display"); v && trim(*v) == "none") return true;
        if (const std::string* st = tag.attr("style")) {
            std::string_view s = *st;
            while (!s.empty()) {
                const auto semi = s.find(';');
                const std::string_view decl = s.substr(0, semi);
                const auto colon = decl.find(':');
                if (colon != std::string_view::npos && trim(decl.substr(0, colon)) == "display" &&
                    trim(decl.substr(colon + 1)) == "none") {
                    return true;
                }
                if (semi == std::string_view::npos) break;
                s = s.substr(semi + 1);
            }
        }
        return false;
    }

    static std::string_view trim(std::string_view s) {
        while (!s.empty() && Scanner::isSpace(s.front())) s.remove_prefix(1);
        while (!s.empty() && Scanner::isSpace(s.back())) s.remove_suffix(1);
        return s;
    }

    // A length attribute in user units (px); absolute units at 96 dpi.
    std::optional<double> length(const XmlTag& tag, const char* name, const std::string& el) const {
        const std::string* v = tag.attr(name);
        if (!v) return std::nullopt;
        const std::string ael = el + " attribute '" + name + "'";
        Scanner sc(*v);
        sc.skipSpace();
        double x = 0.0;
        const auto r = sc.number(x);
        if (r == Scanner::Num::Range) fail(ael, "number out of range");
        if (r != Scanner::Num::Ok) fail(ael, "expected a length, got \"" + v->substr(0, 40) + "\"");
        std::string_view unit = trim(std::string_view(*v).substr(sc.pos()));
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
            fail(ael, "unit '" + std::string(unit.substr(0, 10)) +
                          "' is not supported (use px, in, cm, mm, pt, pc)");
        x *= scale;
        if (std::abs(x) > kMaxAbsCoord) fail(ael, "value exceeds the coordinate limit 1e12");
        return x;
    }

    std::vector<double> numberList(std::string_view s, const std::string& el,
                                   std::size_t maxCount) const {
        std::vector<double> out;
        Scanner sc(s);
        sc.skipSpace();
        while (!sc.atEnd()) {
            double v = 0.0;
            const auto r = sc.number(v);
            if (r == Scanner::Num::Range)
                fail(el, "number out of range at character " + std::to_string(sc.pos()));
            if (r != Scanner::Num::Ok)
                fail(el, "expected a number at character " + std::to_string(sc.pos()));
            if (std::abs(v) > kMaxAbsCoord) fail(el, "number exceeds the coordinate limit 1e12");
            if (out.size() >= maxCount)
                fail(el, "more than " + std::to_string(maxCount) + " numbers");
            out.push_back(v);
            sc.skipCommaSpace();
        }
        return out;
    }

    Affine parseTransform(std::string_view s, const std::string& el) const {
        Affine m;
        Scanner sc(s);
        sc.skipCommaSpace();
        while (!sc.atEnd()) {
            const std::size_t b = sc.pos();
            while (!sc.atEnd() && ((sc.peek() >= 'a' && sc.peek() <= 'z') ||
                                   (sc.peek() >= 'A' && sc.peek() <= 'Z'))) {
                sc.advance();
            }
            const std::string_view fn = s.substr(b, sc.pos() - b);
            sc.skipSpace();
            if (sc.peek() != '(')
                fail(el, "expected '(' after \"" + std::string(fn.substr(0, 20)) + "\"");
            sc.advance();
            double args[6];
            int n = 0;
            sc.skipSpace();
            while (sc.peek() != ')') {
                if (n == 6) fail(el, std::string(fn) + "() takes at most 6 numbers");
                const auto r = sc.number(args[n]);
                if (r != Scanner::Num::Ok)
                    fail(el, "expected a number or ')' in " + std::string(fn) + "()");
                ++n;
                sc.skipCommaSpace();
                if (sc.atEnd()) fail(el, "missing ')' in " + std::string(fn) + "()");
            }
            sc.advance();
            auto want = [&](int lo, int hi) {
                if (n < lo || n > hi) {
                    fail(el, std::string(fn) + "() takes " + std::to_string(lo) +
                                 (hi > lo ? " to " + std::to_string(hi) : std::string()) +
                                 " numbers, got " + std::to_string(n));
                }
            };
            Affine t;
            const double deg = kPi / 180.0;
            if (fn == "matrix") {
                want(6, 6);
                t = {args[0], args[1], args[2], args[3], args[4], args[5]};
            } else if (fn == "translate") {
                want(1, 2);
                t.e = args[0];
                t.f = n > 1 ? args[1] : 0.0;
            } else if (fn == "scale") {
                want(1, 2);
                t.a = args[0];
                t.d = n > 1 ? args[1] : args[0];
            } else if (fn == "rotate") {
                if (n != 1 && n != 3)
                    fail(el, "rotate() takes 1 or 3 numbers, got " + std::to_string(n));
                const double cs = std::cos(args[0] * deg), sn = std::sin(args[0] * deg);
                t = {cs, sn, -sn, cs, 0, 0};
                if (n == 3) {
                    const Affine to{1, 0, 0, 1, args[1], args[2]},
                        back{1, 0, 0, 1, -args[1], -args[2]};
                    t = to * t * back;
                }
            } else if (fn == "skewX") {
                want(1, 1);
                t.c = std::tan(args[0] * deg);
            } else if (fn == "skewY") {
                want(1, 1);
                t.b = std::tan(args[0] * deg);
            } else {
                fail(el, "unknown transform function \"" + std::string(fn.substr(0, 20)) + "\"");
            }
            m = m * t;
            sc.skipCommaSpace();
        }
        if (!m.finite()) fail(el, "transform is not finite");
        return m;
    }

    std::string elementName(std::string_view name) {
        return std::string(name) + " #" + std::to_string(++counters_[std::string(name)]);
    }

    void startElement(const XmlTag& tag) {
        bool foreign = false;
        const std::string_view name = localName(tag.name, foreign);
        const std::string el = elementName(name);
        if (stack_.empty()) {
            if (name != "svg" || foreign) {
                xml_.fail(tag.offset, "root element is <" + std::string(tag.name) + ">, not <svg>");
            }
            stack_.push_back({tag.name, tag.offset, rootTransform(tag, el), hidden(tag)});
            return;
        }
        const State& parent = stack_.back();
        State st{tag.name, tag.offset, parent.ctm, true};
        if (parent.skip || foreign || hidden(tag)) {
            stack_.push_back(st);
            return;
        }
        const bool container = name == "g" || name == "a" || name == "switch";
        const bool shape = name == "path" || name == "line" || name == "polyline" ||
                           name == "polygon" || name == "rect" || name == "circle" ||
                           name == "ellipse";
        if (name == "use" || name == "text") {
            fail(el, "<" + std::string(name) + "> is not supported (convert it to paths first)");
        }
        if (container || shape || name == "svg") {
            Affine local;
            if (name == "svg") local = nestedViewport(tag, el);
            if (const std::string* tr = tag.attr("transform"))
                local = parseTransform(*tr, el + " transform") * local;
            const Affine ctm = parent.ctm * local;
            // A singular transform makes the element invisible (SVG 1.1 7.5).
            if (ctm.det() != 0.0 && std::isfinite(ctm.det())) {
                st.ctm = ctm;
                st.skip = false;
                if (shape) {
                    emitShape(name, tag, el, ctm);
                    st.skip = true; // children of shapes (title, animate) draw nothing
                }
            }
        }
        // Everything else (defs, symbol, clipPath, mask, marker, pattern,
        // style, title, image, ...) draws no outline of its own: skipped.
        stack_.push_back(st);
    }

    // Root: its viewBox units, flipped to y up onto the same box.
    Affine rootTransform(const XmlTag& tag, const std::string& el) {
        Affine flip{1, 0, 0, -1, 0, 0};
        if (const std::string* vb = tag.attr("viewBox")) {
            const auto v = numberList(*vb, el + " attribute 'viewBox'", 4);
            if (v.size() != 4)
                fail(el + " attribute 'viewBox'", "expected 4 numbers: min-x min-y width height");
            if (!(v[2] > 0.0 && v[3] > 0.0))
                fail(el + " attribute 'viewBox'", "width and height must be > 0");
            flip.f = 2.0 * v[1] + v[3];
        } else if (auto h = length(tag, "height", el)) {
            flip.f = *h;
        }
        Affine local;
        if (const std::string* tr = tag.attr("transform"))
            local = parseTransform(*tr, el + " transform");
        return flip * local;
    }

    // Nested <svg>: x/y translation and the viewBox-to-viewport map with
    // preserveAspectRatio (SVG 1.1 7.8); clipping to the viewport is not
    // applied (curves are kept whole).
    Affine nestedViewport(const XmlTag& tag, const std::string& el) {
        Affine t{
            1, 0, 0, 1, length(tag, "x", el).value_or(0.0), length(tag, "y", el).value_or(0.0)};
        const std::string* vb = tag.attr("viewBox");
        if (!vb) return t;
        const std::string vel = el + " attribute 'viewBox'";
        const auto v = numberList(*vb, vel, 4);
        if (v.size() != 4) fail(vel, "expected 4 numbers: min-x min-y width height");
        if (!(v[2] > 0.0 && v[3] > 0.0)) fail(vel, "width and height must be > 0");
        const auto w = length(tag, "width", el), h = length(tag, "height", el);
        if (!w || !h) fail(el, "a nested <svg> with a viewBox needs width and height");
        double sx = *w / v[2], sy = *h / v[3];
        double alignX = 0.5, alignY = 0.5; // xMidYMid
        if (const std::string* par = tag.attr("preserveAspectRatio")) {
            std::string_view p = trim(*par);
            if (p.substr(0, 5) == "defer") p = trim(p.substr(5));
            const std::string_view align = p.substr(0, p.find(' '));
            const std::string_view rest = trim(p.substr(align.size()));
            if (align == "none") {
                alignX = -1.0;
            } else if (align.size() == 8 && align[0] == 'x' && align[4] == 'Y') {
                auto pos = [&](std::string_view s) {
                    return s == "Min" ? 0.0 : s == "Mid" ? 0.5 : s == "Max" ? 1.0 : -1.0;
                };
                alignX = pos(align.substr(1, 3));
                alignY = pos(align.substr(5, 3));
                if (alignX < 0.0 || alignY < 0.0)
                    fail(el + " attribute 'preserveAspectRatio'", "unknown alignment");
                if (rest == "slice")
                    sx = sy = std::max(sx, sy);
                else if (rest.empty() || rest == "meet")
                    sx = sy = std::min(sx, sy);
                else
                    fail(el + " attribute 'preserveAspectRatio'", "expected meet or slice");
            } else {
                fail(el + " attribute 'preserveAspectRatio'", "unknown alignment");
            }
        } else {
            sx = sy = std::min(sx, sy);
        }
        double tx = -v[0] * sx, ty = -v[1] * sy;
        if (alignX >= 0.0) {
            tx += alignX * (*w - v[2] * sx);
            ty += alignY * (*h - v[3] * sy);
        }
        return t * Affine{sx, 0, 0, sy, tx, ty};
    }

    CurveInfo info(const XmlTag& tag, const std::string& el) const {
        CurveInfo ci;
        const std::string* id = tag.attr("id");
        ci.name = id ? *id : el;
        if (ci.name.size() > 1024) ci.name.resize(1024);
        return ci;
    }

    // Elliptical arc from the current point (user space `from`) to `to`.
    void arcTo(glm::dvec2 from, double rx, double ry, double phiDeg, bool large, bool sweep,
               glm::dvec2 to, const Affine& ctm, const std::string& el) {
        // F.6.2: identical endpoints omit the arc; F.6.6 step 1: zero radius
        // makes it a line.
        if (from == to) return;
        rx = std::abs(rx);
        ry = std::abs(ry);
        const glm::dvec2 toF = ctm.apply(to);
        if (rx == 0.0 || ry == 0.0) {
            builder_.lineTo(toF);
            return;
        }
        // F.6.5 step 1: the endpoints in the ellipse's axis frame.
        const double phi = std::fmod(phiDeg, 360.0) * kPi / 180.0;
        const double cs = std::cos(phi), sn = std::sin(phi);
        const glm::dvec2 h = 0.5 * (from - to);
        const double x1 = cs * h.x + sn * h.y, y1 = -sn * h.x + cs * h.y;
        // F.6.6 step 3: radii too small to span the endpoints are scaled up
        // until the ellipse passes through both (the center is then the
        // midpoint).
        const double lambda = (x1 / rx) * (x1 / rx) + (y1 / ry) * (y1 / ry);
        if (!std::isfinite(lambda))
            fail(el, "arc radii are too small for its endpoints to be represented");
        if (lambda > 1.0) {
            const double s = std::sqrt(lambda);
            rx *= s;
            ry *= s;
        }
        // F.6.5 step 2: the center in the axis frame.
        const double rx2 = rx * rx, ry2 = ry * ry, x12 = x1 * x1, y12 = y1 * y1;
        const double den = rx2 * y12 + ry2 * x12;
        double coef = 0.0;
        if (den > 0.0) {
            const double num = rx2 * ry2 - den;
            coef = std::sqrt(std::max(0.0, num / den));
        }
        if (large == sweep) coef = -coef;
        const double cx1 = coef * rx * y1 / ry, cy1 = -coef * ry * x1 / rx;
        // Step 3: back to user space.
        const glm::dvec2 center{cs * cx1 - sn * cy1 + 0.5 * (from.x + to.x),
                                sn * cx1 + cs * cy1 + 0.5 * (from.y + to.y)};
        // Step 4: start angle and sweep.
        const double theta1 = std::atan2((y1 - cy1) / ry, (x1 - cx1) / rx);
        const double theta2 = std::atan2((-y1 - cy1) / ry, (-x1 - cx1) / rx);
        double dtheta = theta2 - theta1;
        if (sweep && dtheta < 0.0) dtheta += 2.0 * kPi;
        if (!sweep && dtheta > 0.0) dtheta -= 2.0 * kPi;
        ArcParams arc;
        arc.center = ctm.apply(center);
        arc.axisX = ctm.linear({rx * cs, rx * sn});
        arc.axisY = ctm.linear({-ry * sn, ry * cs});
        arc.startAngle = theta1;
        arc.sweepAngle = dtheta;
        arc.end = toF;
        if (!std::isfinite(arc.center.x) || !std::isfinite(arc.center.y) ||
            !std::isfinite(dtheta) || !std::isfinite(theta1)) {
            fail(el, "arc parameters are not finite");
        }
        builder_.arcTo(arc);
    }

    // A path's d attribute while it is read (SVG 1.1 8.3): the scanner,
    // the current point and subpath start (user space; startF in the
    // output space), the last control point for S/T, the current command
    // and its name for messages.
    struct PathCursor {
        explicit PathCursor(std::string_view d) : sc(d) {}
        Scanner sc;
        glm::dvec2 cur{0.0}, start{0.0}, startF{0.0}, lastCtrl{0.0};
        char cmd = 0, prevCmd = 0;
        int cmdIndex = 0;
        std::string cel; // e.g. "path 3 command 2 'L'"
    };

    double pathNumber(PathCursor& p, const char* what) {
        p.sc.skipCommaSpace();
        double v = 0.0;
        const auto r = p.sc.number(v);
        if (r == Scanner::Num::Range)
            fail(p.cel,
                 std::string(what) + " is out of range (d[" + std::to_string(p.sc.pos()) + "])");
        if (r != Scanner::Num::Ok) {
            fail(p.cel, std::string("expected a number (") + what + ") at d[" +
                            std::to_string(p.sc.pos()) + "]");
        }
        if (std::abs(v) > kMaxAbsCoord)
            fail(p.cel, std::string(what) + " exceeds the coordinate limit 1e12");
        return v;
    }

    bool pathFlag(PathCursor& p, const char* what) {
        p.sc.skipCommaSpace();
        const char c = p.sc.peek();
        if (c != '0' && c != '1')
            fail(p.cel, std::string("expected a flag 0 or 1 (") + what + ") at d[" +
                            std::to_string(p.sc.pos()) + "]");
        p.sc.advance();
        return c == '1';
    }

    // A coordinate pair, relative to the current point for lower-case commands.
    glm::dvec2 pathPoint(PathCursor& p, bool rel) {
        const double x = pathNumber(p, "x");
        const double y = pathNumber(p, "y");
        return rel ? p.cur + glm::dvec2(x, y) : glm::dvec2(x, y);
    }

    // The command of the next segment: a letter, or the previous command
    // repeated by further numbers. False at the end of the data.
    bool readPathCommand(PathCursor& p, const std::string& el) {
        p.sc.skipSpace();
        if (p.sc.atEnd()) return false;
        const char c = p.sc.peek();
        if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z')) {
            p.cmd = c;
            p.sc.advance();
            ++p.cmdIndex;
            p.cel = el + " command " + std::to_string(p.cmdIndex) + " '" + std::string(1, c) + "'";
            if (p.cmdIndex == 1 && c != 'M' && c != 'm')
                fail(p.cel, "path data must start with M or m");
            if (std::string_view("MmLlHhVvCcSsQqTtAaZz").find(c) == std::string_view::npos) {
                fail(p.cel, "unknown path command");
            }
        } else if (p.sc.atNumberStart() && p.cmd != 0 && p.cmd != 'Z' && p.cmd != 'z') {
            // Implicit repetition: after a moveto, further pairs are
            // linetos of the same relativity.
            if (p.cmd == 'M')
                p.cmd = 'L';
            else if (p.cmd == 'm')
                p.cmd = 'l';
        } else if (p.cmd == 0) {
            fail(el + " command 1", "path data must start with M or m");
        } else {
            fail(p.cel, "unexpected character '" + std::string(1, c) + "' at d[" +
                            std::to_string(p.sc.pos()) + "]");
        }
        return true;
    }

    // A drawing command right after Z starts a new subpath at the closed
    // subpath's start (SVG 1.1 8.3.3).
    void ensureSubpath(const PathCursor& p, const CurveInfo& ci, const std::string& el) {
        if (!builder_.hasSubpath()) builder_.moveTo(p.startF, ci, el);
    }

    // C/c/S/s and Q/q/T/t: the smooth forms reflect the previous control
    // point when the previous command was of the same family.
    void pathCurve(PathCursor& p, const CurveInfo& ci, const std::string& el, const Affine& ctm,
                   bool rel) {
        const bool cubic = std::string_view("CcSs").find(p.cmd) != std::string_view::npos;
        const bool smooth = p.cmd == 'S' || p.cmd == 's' || p.cmd == 'T' || p.cmd == 't';
        const std::string_view family = cubic ? "CcSs" : "QqTt";
        glm::dvec2 c1 = p.cur;
        if (!smooth)
            c1 = pathPoint(p, rel);
        else if (family.find(p.prevCmd) != std::string_view::npos)
            c1 = 2.0 * p.cur - p.lastCtrl;
        if (cubic) {
            const glm::dvec2 c2 = pathPoint(p, rel);
            const glm::dvec2 end = pathPoint(p, rel);
            ensureSubpath(p, ci, el);
            builder_.cubicTo(ctm.apply(c1), ctm.apply(c2), ctm.apply(end));
            p.lastCtrl = c2;
            p.cur = end;
        } else {
            const glm::dvec2 end = pathPoint(p, rel);
            ensureSubpath(p, ci, el);
            builder_.quadTo(ctm.apply(c1), ctm.apply(end));
            p.lastCtrl = c1;
            p.cur = end;
        }
    }

    // One segment of the current command.
    void drawPathCommand(PathCursor& p, const CurveInfo& ci, const std::string& el,
                         const Affine& ctm) {
        const bool rel = p.cmd >= 'a';
        switch (p.cmd) {
        case 'M':
        case 'm':
            p.cur = pathPoint(p, rel);
            p.start = p.cur;
            p.startF = ctm.apply(p.cur);
            builder_.moveTo(p.startF, ci, el);
            break;
        case 'Z':
        case 'z':
            builder_.close();
            p.cur = p.start;
            break;
        case 'L':
        case 'l':
        case 'H':
        case 'h':
        case 'V':
        case 'v': {
            glm::dvec2 end;
            if (p.cmd == 'L' || p.cmd == 'l') {
                end = pathPoint(p, rel);
            } else if (p.cmd == 'H' || p.cmd == 'h') {
                const double x = pathNumber(p, "x");
                end = {rel ? p.cur.x + x : x, p.cur.y};
            } else {
                const double y = pathNumber(p, "y");
                end = {p.cur.x, rel ? p.cur.y + y : y};
            }
            ensureSubpath(p, ci, el);
            builder_.lineTo(ctm.apply(end));
            p.cur = end;
            break;
        }
        case 'C':
        case 'c':
        case 'S':
        case 's':
        case 'Q':
        case 'q':
        case 'T':
        case 't':
            pathCurve(p, ci, el, ctm, rel);
            break;
        case 'A':
        case 'a': {
            const double rx = pathNumber(p, "rx"), ry = pathNumber(p, "ry"),
                         phi = pathNumber(p, "x-axis-rotation");
            const bool large = pathFlag(p, "large-arc-flag"), sweep = pathFlag(p, "sweep-flag");
            const glm::dvec2 end = pathPoint(p, rel);
            ensureSubpath(p, ci, el);
            arcTo(p.cur, rx, ry, phi, large, sweep, end, ctm, p.cel);
            p.cur = end;
            break;
        }
        default:
            break;
        }
    }

    void emitPath(const XmlTag& tag, const std::string& el, const Affine& ctm) {
        const std::string* d = tag.attr("d");
        if (!d) return; // no d: renders nothing
        const CurveInfo ci = info(tag, el);
        PathCursor p(*d);
        while (readPathCommand(p, el)) {
            drawPathCommand(p, ci, el, ctm);
            p.prevCmd = p.cmd;
            p.sc.skipCommaSpace();
        }
        builder_.endSubpath();
    }

    void emitShape(std::string_view name, const XmlTag& tag, const std::string& el,
                   const Affine& ctm) {
        if (name == "path") {
            emitPath(tag, el, ctm);
            return;
        }
        const CurveInfo ci = info(tag, el);
        auto len = [&](const char* a) { return length(tag, a, el).value_or(0.0); };
        auto nonNegative = [&](const char* a, double v) {
            if (v < 0.0) fail(el + " attribute '" + a + "'", "must not be negative");
            return v;
        };
        if (name == "line") {
            builder_.moveTo(ctm.apply({len("x1"), len("y1")}), ci, el);
            builder_.lineTo(ctm.apply({len("x2"), len("y2")}));
            builder_.endSubpath();
        } else if (name == "polyline" || name == "polygon") {
            const std::string* pts = tag.attr("points");
            if (!pts) return;
            const auto v = numberList(*pts, el + " attribute 'points'", 2 * kMaxSegments);
            if (v.size() % 2)
                fail(el + " attribute 'points'",
                     "odd number of coordinates (" + std::to_string(v.size()) + ")");
            if (v.size() < 4) return; // fewer than 2 points draw nothing
            builder_.moveTo(ctm.apply({v[0], v[1]}), ci, el);
            for (std::size_t k = 2; k < v.size(); k += 2)
                builder_.lineTo(ctm.apply({v[k], v[k + 1]}));
            if (name == "polygon")
                builder_.close();
            else
                builder_.endSubpath();
        } else if (name == "rect") {
            const double x = len("x"), y = len("y");
            const double w = nonNegative("width", len("width")),
                         h = nonNegative("height", len("height"));
            if (w == 0.0 || h == 0.0) return; // disables rendering
            auto rxo = length(tag, "rx", el), ryo = length(tag, "ry", el);
            if (rxo) nonNegative("rx", *rxo);
            if (ryo) nonNegative("ry", *ryo);
            // SVG 1.1 9.2: a missing radius takes the other's value; both
            // are clamped to half the side.
            double rx = rxo ? *rxo : (ryo ? *ryo : 0.0);
            double ry = ryo ? *ryo : rx;
            rx = std::min(rx, 0.5 * w);
            ry = std::min(ry, 0.5 * h);
            if (rx == 0.0 || ry == 0.0) {
                builder_.moveTo(ctm.apply({x, y}), ci, el);
                builder_.lineTo(ctm.apply({x + w, y}));
                builder_.lineTo(ctm.apply({x + w, y + h}));
                builder_.lineTo(ctm.apply({x, y + h}));
                builder_.close();
                return;
            }
            auto corner = [&](glm::dvec2 c, double a0, glm::dvec2 endUser) {
                ArcParams arc;
                arc.center = ctm.apply(c);
                arc.axisX = ctm.linear({rx, 0.0});
                arc.axisY = ctm.linear({0.0, ry});
                arc.startAngle = a0;
                arc.sweepAngle = 0.5 * kPi;
                arc.end = ctm.apply(endUser);
                builder_.arcTo(arc);
            };
            // SVG 2 10.2 equivalent path, clockwise in user space (y down).
            builder_.moveTo(ctm.apply({x + rx, y}), ci, el);
            builder_.lineTo(ctm.apply({x + w - rx, y}));
            corner({x + w - rx, y + ry}, -0.5 * kPi, {x + w, y + ry});
            builder_.lineTo(ctm.apply({x + w, y + h - ry}));
            corner({x + w - rx, y + h - ry}, 0.0, {x + w - rx, y + h});
            builder_.lineTo(ctm.apply({x + rx, y + h}));
            corner({x + rx, y + h - ry}, 0.5 * kPi, {x, y + h - ry});
            builder_.lineTo(ctm.apply({x, y + ry}));
            corner({x + rx, y + ry}, kPi, {x + rx, y});
            builder_.close();
        } else if (name == "circle" || name == "ellipse") {
            const glm::dvec2 c{len("cx"), len("cy")};
            double rx = 0.0, ry = 0.0;
            if (name == "circle") {
                rx = ry = nonNegative("r", len("r"));
            } else {
                auto rxo = length(tag, "rx", el), ryo = length(tag, "ry", el);
                rx = nonNegative("rx", rxo ? *rxo : (ryo ? *ryo : 0.0)); // SVG 2: auto = the other
                ry = nonNegative("ry", ryo ? *ryo : rx);
            }
            if (rx == 0.0 || ry == 0.0) return; // disables rendering
            const glm::dvec2 startF = ctm.apply({c.x + rx, c.y});
            ArcParams arc;
            arc.center = ctm.apply(c);
            arc.axisX = ctm.linear({rx, 0.0});
            arc.axisY = ctm.linear({0.0, ry});
            arc.startAngle = 0.0;
            arc.sweepAngle = 2.0 * kPi;
            arc.end = startF;
            builder_.moveTo(startF, ci, el);
            builder_.arcTo(arc);
            builder_.close();
        }
    }

    XmlReader xml_;
    const std::string& source_;
    SvgOptions opt_;
    detail::PathBuilder builder_;
    std::vector<State> stack_;
    std::map<std::string, int> counters_;
};

} // namespace

CurveNetwork parseSvg(std::string_view text, const std::string& source, const SvgOptions& opt) {
    if (text.size() > kMaxSvgBytes) {
        throw io::InputError(source, "",
                             "SVG is " + std::to_string(text.size()) + " bytes; limit is " +
                                 std::to_string(kMaxSvgBytes));
    }
    SvgLoader loader(text, source, opt);
    return loader.run();
}

CurveNetwork loadSvg(const std::filesystem::path& file, const SvgOptions& opt) {
    const std::string text = io::readFile(file, kMaxSvgBytes);
    return parseSvg(text, file.string(), opt);
}

} // namespace sg::features
