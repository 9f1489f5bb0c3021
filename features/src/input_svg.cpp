// SVG drawings as feature-curve networks (contract in surfgrad/features/curves.h,
// coverage in docs/features-input.md): the document structure. The root
// <svg>'s user space flipped to y up is the output space; <svg>, <g>, <a>
// and <switch> nest coordinate systems (transform attribute, nested
// viewports: svg_transform.cpp), display="none" and singular transforms
// (SVG 1.1 section 7.5) hide subtrees, and every visible basic shape or
// path draws its outline (svg_shapes.cpp, svg_path.cpp). Cubic Beziers and
// arcs become quadratic Beziers within the stated tolerance
// (curve_approx.cpp) because the feature maps of Parilov and Zorin (2008)
// are built from quadratic curves.
//
// The XML is untrusted; it is read by pugixml with the limits of
// svg_xml.cpp (no DTD processing or entity expansion, nesting depth,
// attributes per element), and the file size is checked before anything
// else.
#include "surfgrad/features/curves.h"
#include "surfgrad/base/io.h"

#include "svg_internal.h"

#include <map>

namespace sg::features {

namespace {

using detail::Affine;
using detail::XmlElement;

class SvgLoader final : public detail::XmlVisitor {
public:
    SvgLoader(const std::string& source, const SvgOptions& opt)
        : source_(source), opt_(opt), builder_(source) {}

    CurveNetwork finish() {
        if (!rootSeen_) throw io::InputError(source_, "", "no <svg> element (not an SVG file?)");
        return builder_.finish(opt_.approx,
                               "the drawing has no curves (no visible path or shape with length)");
    }

    void enter(const XmlElement& e) override;
    void leave() override { stack_.pop_back(); }

private:
    struct State {
        Affine ctm; // user space of this element -> output space
        bool skip;  // draws nothing, nor do its descendants
    };

    [[noreturn]] void fail(const std::string& element, const std::string& reason) const {
        detail::svgFail(source_, element, reason);
    }

    std::string elementName(std::string_view name) {
        return std::string(name) + " #" + std::to_string(++counters_[std::string(name)]);
    }

    Affine rootTransform(const XmlElement& e, const std::string& el) const;
    void enterChild(const XmlElement& e, std::string_view name, bool foreign,
                    const std::string& el);

    const std::string& source_;
    SvgOptions opt_;
    detail::PathBuilder builder_;
    std::vector<State> stack_;
    std::map<std::string, int> counters_;
    bool rootSeen_ = false;
};

// The local name of an element of the SVG namespace ("path", "svg:path");
// foreign for other prefixes (inkscape:, sodipodi:, ...).
std::string_view localName(std::string_view name, bool& foreign) {
    foreign = false;
    const auto colon = name.find(':');
    if (colon == std::string_view::npos) return name;
    if (name.substr(0, colon) == "svg") return name.substr(colon + 1);
    foreign = true;
    return name;
}

// display="none", as an attribute or in the style attribute.
bool hidden(const XmlElement& e) {
    using detail::svgTrim;
    if (const std::string* v = e.attr("display"); v && svgTrim(*v) == "none") return true;
    if (const std::string* st = e.attr("style")) {
        std::string_view s = *st;
        while (!s.empty()) {
            const auto semi = s.find(';');
            const std::string_view decl = s.substr(0, semi);
            const auto colon = decl.find(':');
            if (colon != std::string_view::npos && svgTrim(decl.substr(0, colon)) == "display" &&
                svgTrim(decl.substr(colon + 1)) == "none") {
                return true;
            }
            if (semi == std::string_view::npos) break;
            s = s.substr(semi + 1);
        }
    }
    return false;
}

void SvgLoader::enter(const XmlElement& e) {
    bool foreign = false;
    const std::string_view name = localName(e.name, foreign);
    const std::string el = elementName(name);
    if (stack_.empty()) {
        if (name != "svg" || foreign)
            fail(e.where(), "root element is <" + std::string(e.name) + ">, not <svg>");
        rootSeen_ = true;
        stack_.push_back({rootTransform(e, el), hidden(e)});
        return;
    }
    enterChild(e, name, foreign, el);
}

void SvgLoader::enterChild(const XmlElement& e, std::string_view name, bool foreign,
                           const std::string& el) {
    const State& parent = stack_.back();
    State st{parent.ctm, true};
    if (parent.skip || foreign || hidden(e)) {
        stack_.push_back(st);
        return;
    }
    const bool container = name == "g" || name == "a" || name == "switch";
    const bool shape = name == "path" || name == "line" || name == "polyline" ||
                       name == "polygon" || name == "rect" || name == "circle" || name == "ellipse";
    if (name == "use" || name == "text") {
        fail(el, "<" + std::string(name) + "> is not supported (convert it to paths first)");
    }
    if (container || shape || name == "svg") {
        Affine local;
        if (name == "svg") local = detail::svgNestedViewport(e, el, source_);
        if (const std::string* tr = e.attr("transform"))
            local = detail::svgTransform(*tr, el + " transform", source_) * local;
        const Affine ctm = parent.ctm * local;
        // A singular transform makes the element invisible (SVG 1.1 7.5).
        if (ctm.det() != 0.0 && std::isfinite(ctm.det())) {
            st.ctm = ctm;
            st.skip = false;
            if (shape) {
                detail::svgDrawShape(name, {builder_, source_, e, el, ctm});
                st.skip = true; // children of shapes (title, animate) draw nothing
            }
        }
    }
    // Everything else (defs, symbol, clipPath, mask, marker, pattern,
    // style, title, image, ...) draws no outline of its own: skipped.
    stack_.push_back(st);
}

// Root: its viewBox units, flipped to y up onto the same box.
Affine SvgLoader::rootTransform(const XmlElement& e, const std::string& el) const {
    Affine flip{1, 0, 0, -1, 0, 0};
    if (const std::string* vb = e.attr("viewBox")) {
        const std::string vel = el + " attribute 'viewBox'";
        const auto v = detail::svgNumberList(*vb, vel, 4, source_);
        if (v.size() != 4) fail(vel, "expected 4 numbers: min-x min-y width height");
        if (!(v[2] > 0.0 && v[3] > 0.0)) fail(vel, "width and height must be > 0");
        flip.f = 2.0 * v[1] + v[3];
    } else if (auto h = detail::svgLength(e, "height", el, source_)) {
        flip.f = *h;
    }
    Affine local;
    if (const std::string* tr = e.attr("transform"))
        local = detail::svgTransform(*tr, el + " transform", source_);
    return flip * local;
}

} // namespace

CurveNetwork parseSvg(std::string_view text, const std::string& source, const SvgOptions& opt) {
    if (text.size() > kMaxSvgBytes) {
        throw io::InputError(source, "",
                             "SVG is " + std::to_string(text.size()) + " bytes; limit is " +
                                 std::to_string(kMaxSvgBytes));
    }
    SvgLoader loader(source, opt);
    detail::visitXml(text, source, loader);
    return loader.finish();
}

CurveNetwork loadSvg(const std::filesystem::path& file, const SvgOptions& opt) {
    const std::string text = io::readFile(file, kMaxSvgBytes);
    return parseSvg(text, file.string(), opt);
}

} // namespace sg::features
