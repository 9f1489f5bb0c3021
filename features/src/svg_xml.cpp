// The XML of SVG files, read with pugixml (contract in svg_xml.h).
//
// pugixml 1.13 (Debian's libpugixml-dev) parses in place and without
// recursion into a tree. It runs with parse_minimal, that is:
//  - no parse_escapes: attribute values keep every '&' reference as
//    written; decodeValue() below decodes the five predefined entities and
//    numeric character references and rejects any other reference with its
//    line. pugixml never expands DTD entities (it has no DTD processing),
//    and without parse_escapes it resolves no reference at all, so nothing
//    is expanded that this file does not decode itself;
//  - no parse_doctype: the DOCTYPE, internal subset included, is skipped
//    (pugixml matches its brackets, quotes and comments in linear time) and
//    makes no node; comments, CDATA sections, processing instructions and
//    the XML declaration are skipped too (no parse_comments, parse_cdata,
//    parse_pi, parse_declaration);
//  - no parse_eol and no attribute whitespace conversion: values keep their
//    bytes, so an offset into a value is an offset into the text and the
//    line of an error inside a value is exact;
//  - encoding_utf8: the bytes are parsed as they are (no UTF-16/32
//    conversion that would move offsets); a UTF-8 byte order mark is
//    skipped.
// pugixml does not check nesting depth, attribute counts, duplicate
// attributes or a second root element: the walk over the tree below does
// (iteratively: pugixml's nodes link to their parents). A syntax error
// comes as a status and a byte offset; failSyntax() turns the offset into a
// line and the status into a reason naming the tag or construct.
#include "svg_xml.h"

#include "path_builder.h"
#include "surfgrad/base/io.h"

#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <functional>
#include <optional>
#include <unordered_set>

namespace sg::features::detail {

namespace {

constexpr unsigned kParseOptions = pugi::parse_minimal;

bool isSpace(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

bool isNameChar(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == ':' || c == '-' || c == '.' || static_cast<unsigned char>(c) >= 0x80;
}

// Lines of offsets visited in increasing order, counted once.
class LineCounter {
public:
    explicit LineCounter(std::string_view text) : text_(text) {}
    std::size_t at(std::size_t offset) {
        offset = std::min(offset, text_.size());
        if (offset < pos_) {
            pos_ = 0;
            line_ = 1;
        }
        line_ += std::size_t(std::count(text_.begin() + std::ptrdiff_t(pos_),
                                        text_.begin() + std::ptrdiff_t(offset), '\n'));
        pos_ = offset;
        return line_;
    }

private:
    std::string_view text_;
    std::size_t pos_ = 0, line_ = 1;
};

class XmlReader {
public:
    XmlReader(std::string_view text, const std::string& source)
        : text_(text), source_(source), lines_(text) {}

    void read(XmlVisitor& visitor) {
        if (const std::size_t nul = text_.find('\0'); nul != std::string_view::npos)
            fail(nul, "NUL byte (U+0000 is not allowed in XML)");
        buffer_.assign(text_);
        const pugi::xml_parse_result r = doc_.load_buffer_inplace(
            buffer_.data(), buffer_.size(), kParseOptions, pugi::encoding_utf8);
        if (!r) {
            walk(nullptr); // too deep before the error: reported as such
            failSyntax(r.status, std::size_t(std::max<std::ptrdiff_t>(r.offset, 0)));
        }
        walk(&visitor);
    }

private:
    [[noreturn]] void fail(std::size_t offset, const std::string& reason) {
        throw io::InputError(source_, "line " + std::to_string(lines_.at(offset)), reason);
    }

    // Whether pugixml's string p points into the parsed buffer (an unset
    // value points to a constant "").
    bool inBuffer(const char* p) const {
        const char* b = buffer_.data();
        return !std::less<const char*>()(p, b) && !std::less<const char*>()(b + buffer_.size(), p);
    }
    // Offset in the text of a string of the parsed buffer.
    std::size_t offsetOf(const char* p) const {
        return inBuffer(p) ? std::size_t(p - buffer_.data()) : 0;
    }

    // The name written at `offset` of the text (pugixml's copy may be cut
    // short by its terminator).
    std::string nameAt(std::size_t offset) const {
        std::size_t end = offset;
        while (end < text_.size() && end - offset < 64 && isNameChar(text_[end])) ++end;
        return std::string(text_.substr(offset, end - offset));
    }

    bool atEnd(std::size_t offset) const { return offset + 1 >= text_.size(); }

    void walk(XmlVisitor* visitor);
    void readElement(const pugi::xml_node& n);
    std::string decodeValue(std::string_view raw, std::size_t offset);
    [[noreturn]] void failSyntax(pugi::xml_parse_status status, std::size_t offset);
    [[noreturn]] void failUnbalanced(std::size_t offset);
    [[noreturn]] void failAttribute(std::size_t offset);
    [[noreturn]] void failUnterminated(std::size_t offset, std::string_view open,
                                       const std::string& what, std::string_view close);

    std::string_view text_;
    const std::string& source_;
    LineCounter lines_;
    std::string buffer_; // the text, parsed in place by doc_
    pugi::xml_document doc_;
    XmlElement element_;                        // the element being visited
    std::unordered_set<std::string_view> seen_; // its attribute names
};

// Elements depth first in document order (walk(nullptr): only the depth).
void XmlReader::walk(XmlVisitor* visitor) {
    std::size_t depth = 0; // of n; the root's is 0
    bool rootSeen = false;
    pugi::xml_node n = doc_.first_child();
    while (n) {
        if (n.type() == pugi::node_element) {
            const std::size_t at = offsetOf(n.name());
            if (depth >= kMaxXmlDepth) {
                fail(at, "elements nested deeper than " + std::to_string(kMaxXmlDepth) + " levels");
            }
            if (visitor) {
                if (depth == 0 && rootSeen)
                    fail(at, "element <" + nameAt(at) + "> after the root element");
                rootSeen = true;
                readElement(n);
                visitor->enter(element_);
            }
            if (const pugi::xml_node child = n.first_child()) {
                n = child;
                ++depth;
                continue;
            }
            if (visitor) visitor->leave();
        }
        // The next sibling, else the next sibling of the closest ancestor
        // that has one; the elements left on the way end.
        while (!n.next_sibling()) {
            n = n.parent();
            if (n.type() != pugi::node_element) return; // the document
            --depth;
            if (visitor) visitor->leave();
        }
        n = n.next_sibling();
    }
}

void XmlReader::readElement(const pugi::xml_node& n) {
    XmlElement& e = element_;
    e.name = n.name();
    e.line = lines_.at(offsetOf(n.name()));
    e.attrs.clear();
    seen_.clear();
    for (pugi::xml_attribute a = n.first_attribute(); a; a = a.next_attribute()) {
        const std::size_t at = offsetOf(a.name());
        const std::string_view name = a.name();
        std::string value = decodeValue(a.value(), offsetOf(a.value()));
        if (!seen_.insert(name).second) fail(at, "duplicate attribute " + std::string(name));
        if (e.attrs.size() >= kMaxXmlAttributes) {
            fail(at,
                 "more than " + std::to_string(kMaxXmlAttributes) + " attributes on one element");
        }
        e.attrs.push_back({name, std::move(value)});
    }
}

// An attribute value as written (pugixml left it raw: no parse_escapes)
// with its references decoded; `offset` is its first byte's in the text.
std::string XmlReader::decodeValue(std::string_view raw, std::size_t offset) {
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
        if (ref == "lt") {
            out += '<';
        } else if (ref == "gt") {
            out += '>';
        } else if (ref == "amp") {
            out += '&';
        } else if (ref == "quot") {
            out += '"';
        } else if (ref == "apos") {
            out += '\'';
        } else if (ref.size() >= 2 && ref[0] == '#') {
            const bool hex = ref[1] == 'x';
            const std::string_view digits = ref.substr(hex ? 2 : 1);
            std::uint32_t cp = 0;
            auto [p, ec] =
                std::from_chars(digits.data(), digits.data() + digits.size(), cp, hex ? 16 : 10);
            if (digits.empty() || ec != std::errc() || p != digits.data() + digits.size() ||
                cp == 0 || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
                fail(offset + k, "invalid character reference &" + std::string(ref) + ";");
            }
            appendUtf8(out, cp);
        } else {
            fail(offset + k, "entity &" + std::string(ref) +
                                 "; is not supported (only &lt; &gt; &amp; &quot; &apos; and "
                                 "numeric references; DTD entities are never expanded)");
        }
        k = semi;
    }
    return out;
}

// pugixml's status and offset as a reason and a line. The offset is where
// pugixml stopped: a construct left open at the end of the file is named
// at the line where it starts.
void XmlReader::failSyntax(pugi::xml_parse_status status, std::size_t offset) {
    switch (status) {
    case pugi::status_no_document_element:
        throw io::InputError(source_, "", "no <svg> element (not an SVG file?)");
    case pugi::status_end_element_mismatch:
        failUnbalanced(offset);
    case pugi::status_bad_attribute:
    case pugi::status_bad_start_element:
        failAttribute(offset);
    case pugi::status_bad_end_element: {
        const std::size_t lt = text_.rfind("</", offset);
        fail(offset, "expected '>' to end </" +
                         (lt == std::string_view::npos ? std::string() : nameAt(lt + 2)));
    }
    case pugi::status_unrecognized_tag: {
        const std::size_t lt = text_.rfind('<', offset);
        if (lt != std::string_view::npos && lt + 1 < text_.size() && text_[lt + 1] == '!') {
            fail(lt, "unknown declaration <!" + nameAt(lt + 2) +
                         " (comments, CDATA sections and one DOCTYPE before the root element "
                         "are allowed)");
        }
        fail(offset, "expected element name after '<'");
    }
    case pugi::status_bad_comment:
        failUnterminated(offset, "<!--", "comment", "-->");
    case pugi::status_bad_cdata:
        failUnterminated(offset, "<![CDATA[", "CDATA section", "]]>");
    case pugi::status_bad_pi:
        failUnterminated(offset, "<?", "processing instruction", "?>");
    case pugi::status_bad_doctype: {
        const std::size_t start = text_.rfind("<!DOCTYPE", offset);
        fail(start == std::string_view::npos ? offset : start,
             "malformed, unterminated or misplaced <!DOCTYPE> (one is allowed, before the root "
             "element; it is skipped, never processed)");
    }
    case pugi::status_out_of_memory:
        fail(offset, "out of memory while reading the XML");
    default: {
        pugi::xml_parse_result r;
        r.status = status;
        fail(offset, std::string("XML error: ") + r.description());
    }
    }
}

// A comment, CDATA section or processing instruction: open at the end of
// the file (named at its last opening; one in its own body would be taken
// for it), or malformed where pugixml stopped.
void XmlReader::failUnterminated(std::size_t offset, std::string_view open, const std::string& what,
                                 std::string_view close) {
    if (atEnd(offset)) {
        const std::size_t start = text_.rfind(open, offset);
        fail(start == std::string_view::npos ? offset : start, "unterminated " + what + " (no '" +
                                                                   std::string(close) +
                                                                   "' before the end of the file)");
    }
    fail(offset, "malformed " + what);
}

// status_end_element_mismatch: an end tag that does not close the open
// element (the offset is its name's), or elements left open at the end of
// the file. pugixml does not say which element is open: the text before
// the end tag (or all of it) is parsed again followed by an empty element,
// whose parent is that element.
void XmlReader::failUnbalanced(std::size_t offset) {
    const bool endTag = offset >= 2 && text_.substr(offset - 2, 2) == "</";
    doc_.reset();
    std::string().swap(buffer_);
    std::string probe(text_.substr(0, endTag ? offset - 2 : text_.size()));
    probe += "<_/>";
    pugi::xml_document doc;
    doc.load_buffer_inplace(probe.data(), probe.size(), kParseOptions, pugi::encoding_utf8);
    pugi::xml_node last = doc;
    while (last.last_child()) last = last.last_child();
    const pugi::xml_node open = last.parent();
    std::optional<std::size_t> openAt;
    if (last.type() == pugi::node_element && std::string_view(last.name()) == "_" &&
        open.type() == pugi::node_element) {
        openAt = std::size_t(open.name() - probe.data());
    }
    if (endTag) {
        fail(offset, "end tag </" + nameAt(offset) + "> does not match " +
                         (openAt ? "<" + nameAt(*openAt) + ">" : "any open element"));
    }
    if (openAt) fail(*openAt, "<" + nameAt(*openAt) + "> is not closed before the end of the file");
    fail(offset, "an element is not closed before the end of the file");
}

// status_bad_attribute / status_bad_start_element, in the start tag of the
// last element pugixml made. It stops at a value's first byte when the
// closing quote is missing, at the byte after '=' when that is not a
// quote, after the byte that is not '=' after a name, at a name right after
// a closing quote, and at the byte that cannot follow '/' or start an
// attribute.
void XmlReader::failAttribute(std::size_t offset) {
    pugi::xml_node el = doc_;
    while (el.last_child()) el = el.last_child();
    const std::string tag = "<" + nameAt(offsetOf(el.name())) + ">";
    const pugi::xml_attribute a = el.last_attribute();
    const std::string name = a ? nameAt(offsetOf(a.name())) : std::string();
    const bool valueRead = a && inBuffer(a.value());
    // pugixml's terminator replaces the text's last byte: a closing quote
    // there is not seen.
    const bool atValue = valueRead && offset > 0 && offsetOf(a.value()) == offset;
    const bool quoteLast = atValue && text_.find(text_[offset - 1], offset) + 1 == text_.size();
    if (atValue && !quoteLast) fail(offsetOf(a.name()), "unterminated value of attribute " + name);
    if (atEnd(offset) || quoteLast)
        fail(offsetOf(el.name()), "unexpected end of file inside " + tag);
    if (offset > 0 && text_[offset - 1] == '/') fail(offset, "expected '/>' in " + tag);
    if (valueRead && isNameChar(text_[offset])) {
        fail(offset, "expected whitespace before attribute " + nameAt(offset) + " in " + tag);
    }
    std::size_t before = offset;
    while (before > 0 && isSpace(text_[before - 1])) --before;
    if (a && !valueRead && before > 0 && text_[before - 1] == '=') {
        fail(offset, "attribute value of " + name + " must be quoted");
    }
    if (a && !valueRead) fail(offset, "expected '=' after attribute " + name);
    fail(offset, "malformed start tag " + tag + " (expected an attribute, '>' or '/>')");
}

} // namespace

void visitXml(std::string_view text, const std::string& source, XmlVisitor& visitor) {
    XmlReader reader(text, source);
    reader.read(visitor);
}

} // namespace sg::features::detail
