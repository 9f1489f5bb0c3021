// SVG basic shapes (svg_internal.h): line, polyline, polygon, rect with
// rounded corners, circle and ellipse drawn as their equivalent paths (SVG 2
// section 10; rect's radii per SVG 1.1 section 9.2); <path> goes to
// svg_path.cpp. Zero sizes draw nothing, negative sizes are errors.
#include "svg_internal.h"

#include <algorithm>

namespace sg::features::detail {

namespace {

double nonNegative(const SvgDraw& d, const char* attr, double v) {
    if (v < 0.0) svgFail(d.source, d.el + " attribute '" + attr + "'", "must not be negative");
    return v;
}

double lengthOr0(const SvgDraw& d, const char* attr) {
    return svgLength(d.element, attr, d.el, d.source).value_or(0.0);
}

void drawPoly(const SvgDraw& d, bool closed) {
    const std::string* pts = d.element.attr("points");
    if (!pts) return;
    const std::string pel = d.el + " attribute 'points'";
    const auto v = svgNumberList(*pts, pel, 2 * kMaxSegments, d.source);
    if (v.size() % 2)
        svgFail(d.source, pel, "odd number of coordinates (" + std::to_string(v.size()) + ")");
    if (v.size() < 4) return; // fewer than 2 points draw nothing
    d.builder.moveTo(d.ctm.apply({v[0], v[1]}), svgCurveInfo(d), d.el);
    for (std::size_t k = 2; k < v.size(); k += 2) d.builder.lineTo(d.ctm.apply({v[k], v[k + 1]}));
    if (closed)
        d.builder.close();
    else
        d.builder.endSubpath();
}

void drawRect(const SvgDraw& d) {
    const CurveInfo ci = svgCurveInfo(d);
    const Affine& ctm = d.ctm;
    const double x = lengthOr0(d, "x"), y = lengthOr0(d, "y");
    const double w = nonNegative(d, "width", lengthOr0(d, "width")),
                 h = nonNegative(d, "height", lengthOr0(d, "height"));
    if (w == 0.0 || h == 0.0) return; // disables rendering
    auto rxo = svgLength(d.element, "rx", d.el, d.source),
         ryo = svgLength(d.element, "ry", d.el, d.source);
    if (rxo) nonNegative(d, "rx", *rxo);
    if (ryo) nonNegative(d, "ry", *ryo);
    // SVG 1.1 9.2: a missing radius takes the other's value; both are
    // clamped to half the side.
    double rx = rxo ? *rxo : (ryo ? *ryo : 0.0);
    double ry = ryo ? *ryo : rx;
    rx = std::min(rx, 0.5 * w);
    ry = std::min(ry, 0.5 * h);
    if (rx == 0.0 || ry == 0.0) {
        d.builder.moveTo(ctm.apply({x, y}), ci, d.el);
        d.builder.lineTo(ctm.apply({x + w, y}));
        d.builder.lineTo(ctm.apply({x + w, y + h}));
        d.builder.lineTo(ctm.apply({x, y + h}));
        d.builder.close();
        return;
    }
    auto corner = [&](glm::dvec2 c, double a0, glm::dvec2 endUser) {
        ArcParams arc;
        arc.center = ctm.apply(c);
        arc.axisX = ctm.linear({rx, 0.0});
        arc.axisY = ctm.linear({0.0, ry});
        arc.startAngle = a0;
        arc.sweepAngle = 0.5 * kSvgPi;
        arc.end = ctm.apply(endUser);
        d.builder.arcTo(arc);
    };
    // SVG 2 10.2 equivalent path, clockwise in user space (y down).
    d.builder.moveTo(ctm.apply({x + rx, y}), ci, d.el);
    d.builder.lineTo(ctm.apply({x + w - rx, y}));
    corner({x + w - rx, y + ry}, -0.5 * kSvgPi, {x + w, y + ry});
    d.builder.lineTo(ctm.apply({x + w, y + h - ry}));
    corner({x + w - rx, y + h - ry}, 0.0, {x + w - rx, y + h});
    d.builder.lineTo(ctm.apply({x + rx, y + h}));
    corner({x + rx, y + h - ry}, 0.5 * kSvgPi, {x, y + h - ry});
    d.builder.lineTo(ctm.apply({x, y + ry}));
    corner({x + rx, y + ry}, kSvgPi, {x + rx, y});
    d.builder.close();
}

void drawEllipse(const SvgDraw& d, bool circle) {
    const CurveInfo ci = svgCurveInfo(d);
    const glm::dvec2 c{lengthOr0(d, "cx"), lengthOr0(d, "cy")};
    double rx = 0.0, ry = 0.0;
    if (circle) {
        rx = ry = nonNegative(d, "r", lengthOr0(d, "r"));
    } else {
        auto rxo = svgLength(d.element, "rx", d.el, d.source),
             ryo = svgLength(d.element, "ry", d.el, d.source);
        rx = nonNegative(d, "rx", rxo ? *rxo : (ryo ? *ryo : 0.0)); // SVG 2: auto = the other
        ry = nonNegative(d, "ry", ryo ? *ryo : rx);
    }
    if (rx == 0.0 || ry == 0.0) return; // disables rendering
    const glm::dvec2 startF = d.ctm.apply({c.x + rx, c.y});
    ArcParams arc;
    arc.center = d.ctm.apply(c);
    arc.axisX = d.ctm.linear({rx, 0.0});
    arc.axisY = d.ctm.linear({0.0, ry});
    arc.startAngle = 0.0;
    arc.sweepAngle = 2.0 * kSvgPi;
    arc.end = startF;
    d.builder.moveTo(startF, ci, d.el);
    d.builder.arcTo(arc);
    d.builder.close();
}

} // namespace

CurveInfo svgCurveInfo(const SvgDraw& d) {
    CurveInfo ci;
    const std::string* id = d.element.attr("id");
    ci.name = id ? *id : d.el;
    if (ci.name.size() > 1024) ci.name.resize(1024);
    return ci;
}

void svgDrawShape(std::string_view name, const SvgDraw& d) {
    if (name == "path") {
        svgDrawPath(d);
    } else if (name == "line") {
        const CurveInfo ci = svgCurveInfo(d);
        d.builder.moveTo(d.ctm.apply({lengthOr0(d, "x1"), lengthOr0(d, "y1")}), ci, d.el);
        d.builder.lineTo(d.ctm.apply({lengthOr0(d, "x2"), lengthOr0(d, "y2")}));
        d.builder.endSubpath();
    } else if (name == "polyline" || name == "polygon") {
        drawPoly(d, name == "polygon");
    } else if (name == "rect") {
        drawRect(d);
    } else if (name == "circle" || name == "ellipse") {
        drawEllipse(d, name == "circle");
    }
}

} // namespace sg::features::detail
