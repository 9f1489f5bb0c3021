// Internal to surfgrad_features: the XML of an SVG file (untrusted), read
// with pugixml and handed to the SVG loader as elements in document order,
// their attributes decoded. Every limit of the SVG input that is about XML
// is enforced here (docs/features-input.md, "SVG coverage"): nesting depth,
// attributes per element, no DTD processing or entity expansion, well-formed
// tags; errors name the line ("line 12").
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace sg::features::detail {

inline constexpr std::size_t kMaxXmlDepth = 256;      // nested elements, the root included
inline constexpr std::size_t kMaxXmlAttributes = 256; // per element

struct XmlAttr {
    std::string_view name;
    std::string value; // the five predefined entities and character references decoded
};

struct XmlElement {
    std::string_view name;      // qualified, as written: "path", "svg:path", "inkscape:x"
    std::size_t line = 0;       // of its start tag, 1-based
    std::vector<XmlAttr> attrs; // in document order, names distinct

    const XmlAttr* find(std::string_view attrName) const {
        for (const auto& a : attrs) {
            if (a.name == attrName) return &a;
        }
        return nullptr;
    }
    const std::string* attr(std::string_view attrName) const {
        const XmlAttr* a = find(attrName);
        return a ? &a->value : nullptr;
    }
    // "line 12", the element of an error about this element as a whole.
    std::string where() const { return "line " + std::to_string(line); }
};

class XmlVisitor {
public:
    // An element's start; the element (and its strings) lives until the
    // call returns.
    virtual void enter(const XmlElement& element) = 0;
    // The end of the element entered last and not yet left.
    virtual void leave() = 0;

protected:
    ~XmlVisitor() = default;
};

// Reads `text` as XML and calls visitor.enter / leave for every element, in
// document order (text, comments, CDATA, processing instructions and the
// DOCTYPE are skipped). Throws io::InputError(source, "line N", reason), or
// with element "" when there is no element at all. A text that is not
// well-formed XML (or has a NUL byte) is rejected before the visitor is
// called; nesting deeper than kMaxXmlDepth found before the syntax error is
// reported instead of it. The other checks run as the elements are visited,
// so their errors come in document order with the visitor's own: nesting
// deeper than kMaxXmlDepth, more than kMaxXmlAttributes attributes on an
// element, an attribute given twice, an entity reference other than the
// five predefined entities and numeric character references (DTD entities
// are never expanded), '<' in an attribute value, a second root element.
// Linear in the text's size; no recursion.
void visitXml(std::string_view text, const std::string& source, XmlVisitor& visitor);

} // namespace sg::features::detail
