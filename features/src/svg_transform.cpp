// Coordinate systems of SVG drawings (svg_internal.h): the transform
// attribute syntax (SVG 1.1 section 7.6: matrix, translate, scale, rotate
// with centre, skewX, skewY, applied right to left) and a nested <svg>'s
// viewport, its viewBox and preserveAspectRatio (SVG 1.1 sections 7.7-7.8;
// clipping to the viewport is not applied: curves are kept whole).
#include "svg_internal.h"

#include <algorithm>

namespace sg::features::detail {

namespace {

// One transform function's arguments: "(" numbers ")" after its name.
int transformArgs(Scanner& sc, std::string_view fn, double (&args)[6], const std::string& el,
                  const std::string& source) {
    sc.skipSpace();
    if (sc.peek() != '(')
        svgFail(source, el, "expected '(' after \"" + std::string(fn.substr(0, 20)) + "\"");
    sc.advance();
    int n = 0;
    sc.skipSpace();
    while (sc.peek() != ')') {
        if (n == 6) svgFail(source, el, std::string(fn) + "() takes at most 6 numbers");
        const auto r = sc.number(args[n]);
        if (r != Scanner::Num::Ok)
            svgFail(source, el, "expected a number or ')' in " + std::string(fn) + "()");
        ++n;
        sc.skipCommaSpace();
        if (sc.atEnd()) svgFail(source, el, "missing ')' in " + std::string(fn) + "()");
    }
    sc.advance();
    return n;
}

// The map of one transform function with its n arguments.
Affine transformFunction(std::string_view fn, const double (&args)[6], int n, const std::string& el,
                         const std::string& source) {
    auto want = [&](int lo, int hi) {
        if (n < lo || n > hi) {
            svgFail(source, el,
                    std::string(fn) + "() takes " + std::to_string(lo) +
                        (hi > lo ? " to " + std::to_string(hi) : std::string()) + " numbers, got " +
                        std::to_string(n));
        }
    };
    Affine t;
    const double deg = kSvgPi / 180.0;
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
            svgFail(source, el, "rotate() takes 1 or 3 numbers, got " + std::to_string(n));
        const double cs = std::cos(args[0] * deg), sn = std::sin(args[0] * deg);
        t = {cs, sn, -sn, cs, 0, 0};
        if (n == 3) {
            const Affine to{1, 0, 0, 1, args[1], args[2]}, back{1, 0, 0, 1, -args[1], -args[2]};
            t = to * t * back;
        }
    } else if (fn == "skewX") {
        want(1, 1);
        t.c = std::tan(args[0] * deg);
    } else if (fn == "skewY") {
        want(1, 1);
        t.b = std::tan(args[0] * deg);
    } else {
        svgFail(source, el, "unknown transform function \"" + std::string(fn.substr(0, 20)) + "\"");
    }
    return t;
}

} // namespace

Affine svgTransform(std::string_view s, const std::string& el, const std::string& source) {
    Affine m;
    Scanner sc(s);
    sc.skipCommaSpace();
    while (!sc.atEnd()) {
        const std::size_t b = sc.pos();
        while (!sc.atEnd() &&
               ((sc.peek() >= 'a' && sc.peek() <= 'z') || (sc.peek() >= 'A' && sc.peek() <= 'Z'))) {
            sc.advance();
        }
        const std::string_view fn = s.substr(b, sc.pos() - b);
        double args[6] = {};
        const int n = transformArgs(sc, fn, args, el, source);
        m = m * transformFunction(fn, args, n, el, source);
        sc.skipCommaSpace();
    }
    if (!m.finite()) svgFail(source, el, "transform is not finite");
    return m;
}

Affine svgNestedViewport(const XmlElement& e, const std::string& el, const std::string& source) {
    const Affine t{1,
                   0,
                   0,
                   1,
                   svgLength(e, "x", el, source).value_or(0.0),
                   svgLength(e, "y", el, source).value_or(0.0)};
    const std::string* vb = e.attr("viewBox");
    if (!vb) return t;
    const std::string vel = el + " attribute 'viewBox'";
    const auto v = svgNumberList(*vb, vel, 4, source);
    if (v.size() != 4) svgFail(source, vel, "expected 4 numbers: min-x min-y width height");
    if (!(v[2] > 0.0 && v[3] > 0.0)) svgFail(source, vel, "width and height must be > 0");
    const auto w = svgLength(e, "width", el, source), h = svgLength(e, "height", el, source);
    if (!w || !h) svgFail(source, el, "a nested <svg> with a viewBox needs width and height");
    double sx = *w / v[2], sy = *h / v[3];
    double alignX = 0.5, alignY = 0.5; // xMidYMid
    if (const std::string* par = e.attr("preserveAspectRatio")) {
        const std::string pel = el + " attribute 'preserveAspectRatio'";
        std::string_view p = svgTrim(*par);
        if (p.substr(0, 5) == "defer") p = svgTrim(p.substr(5));
        const std::string_view align = p.substr(0, p.find(' '));
        const std::string_view rest = svgTrim(p.substr(align.size()));
        if (align == "none") {
            alignX = -1.0;
        } else if (align.size() == 8 && align[0] == 'x' && align[4] == 'Y') {
            auto pos = [&](std::string_view s) {
                return s == "Min" ? 0.0 : s == "Mid" ? 0.5 : s == "Max" ? 1.0 : -1.0;
            };
            alignX = pos(align.substr(1, 3));
            alignY = pos(align.substr(5, 3));
            if (alignX < 0.0 || alignY < 0.0) svgFail(source, pel, "unknown alignment");
            if (rest == "slice")
                sx = sy = std::max(sx, sy);
            else if (rest.empty() || rest == "meet")
                sx = sy = std::min(sx, sy);
            else
                svgFail(source, pel, "expected meet or slice");
        } else {
            svgFail(source, pel, "unknown alignment");
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

} // namespace sg::features::detail
