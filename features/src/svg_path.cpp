// SVG path data (svg_internal.h): the grammar of the d attribute (SVG 1.1
// section 8.3.9, SVG 2 section 9.3.9) with its commands M L H V C S Q T A Z,
// absolute and relative, implicit repetition and the reflected control
// points of S and T (SVG 1.1 sections 8.3.2-8.3.8), and the elliptical arc's
// endpoint-to-center conversion and out-of-range radii correction (SVG 1.1
// appendix F.6.5-F.6.6). Cubics and arcs go to the builder as they are;
// it approximates them by quadratics (curve_approx.cpp).
#include "svg_internal.h"

#include <algorithm>

namespace sg::features::detail {

namespace {

// A path's d attribute while it is read (SVG 1.1 8.3): the scanner, the
// current point and subpath start (user space; startF in the output space),
// the last control point for S/T, the current command and its name for
// messages.
class PathReader {
public:
    explicit PathReader(const SvgDraw& d, std::string_view data)
        : d_(d), ci_(svgCurveInfo(d)), sc_(data) {}

    void run() {
        while (readCommand()) {
            drawCommand();
            prevCmd_ = cmd_;
            sc_.skipCommaSpace();
        }
        d_.builder.endSubpath();
    }

private:
    [[noreturn]] void fail(const std::string& element, const std::string& reason) const {
        svgFail(d_.source, element, reason);
    }
    glm::dvec2 out(glm::dvec2 p) const { return d_.ctm.apply(p); }

    double number(const char* what);
    bool flag(const char* what);
    // A coordinate pair, relative to the current point for lower-case commands.
    glm::dvec2 point(bool rel) {
        const double x = number("x");
        const double y = number("y");
        return rel ? cur_ + glm::dvec2(x, y) : glm::dvec2(x, y);
    }
    bool readCommand();
    // A drawing command right after Z starts a new subpath at the closed
    // subpath's start (SVG 1.1 8.3.3).
    void ensureSubpath() {
        if (!d_.builder.hasSubpath()) d_.builder.moveTo(startF_, ci_, d_.el);
    }
    void drawCommand();
    void curve(bool rel);
    void arcTo(glm::dvec2 from, double rx, double ry, double phiDeg, bool large, bool sweep,
               glm::dvec2 to);

    const SvgDraw& d_;
    const CurveInfo ci_;
    Scanner sc_;
    glm::dvec2 cur_{0.0}, start_{0.0}, startF_{0.0}, lastCtrl_{0.0};
    char cmd_ = 0, prevCmd_ = 0;
    int cmdIndex_ = 0;
    std::string cel_; // e.g. "path #3 command 2 'L'"
};

double PathReader::number(const char* what) {
    sc_.skipCommaSpace();
    double v = 0.0;
    const auto r = sc_.number(v);
    if (r == Scanner::Num::Range)
        fail(cel_, std::string(what) + " is out of range (d[" + std::to_string(sc_.pos()) + "])");
    if (r != Scanner::Num::Ok) {
        fail(cel_, std::string("expected a number (") + what + ") at d[" +
                       std::to_string(sc_.pos()) + "]");
    }
    if (std::abs(v) > kMaxAbsCoord)
        fail(cel_, std::string(what) + " exceeds the coordinate limit 1e12");
    return v;
}

bool PathReader::flag(const char* what) {
    sc_.skipCommaSpace();
    const char c = sc_.peek();
    if (c != '0' && c != '1')
        fail(cel_, std::string("expected a flag 0 or 1 (") + what + ") at d[" +
                       std::to_string(sc_.pos()) + "]");
    sc_.advance();
    return c == '1';
}

// The command of the next segment: a letter, or the previous command
// repeated by further numbers. False at the end of the data.
bool PathReader::readCommand() {
    sc_.skipSpace();
    if (sc_.atEnd()) return false;
    const char c = sc_.peek();
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z')) {
        cmd_ = c;
        sc_.advance();
        ++cmdIndex_;
        cel_ = d_.el + " command " + std::to_string(cmdIndex_) + " '" + std::string(1, c) + "'";
        if (cmdIndex_ == 1 && c != 'M' && c != 'm') fail(cel_, "path data must start with M or m");
        if (std::string_view("MmLlHhVvCcSsQqTtAaZz").find(c) == std::string_view::npos) {
            fail(cel_, "unknown path command");
        }
    } else if (sc_.atNumberStart() && cmd_ != 0 && cmd_ != 'Z' && cmd_ != 'z') {
        // Implicit repetition: after a moveto, further pairs are linetos of
        // the same relativity.
        if (cmd_ == 'M')
            cmd_ = 'L';
        else if (cmd_ == 'm')
            cmd_ = 'l';
    } else if (cmd_ == 0) {
        fail(d_.el + " command 1", "path data must start with M or m");
    } else {
        fail(cel_, "unexpected character '" + std::string(1, c) + "' at d[" +
                       std::to_string(sc_.pos()) + "]");
    }
    return true;
}

// C/c/S/s and Q/q/T/t: the smooth forms reflect the previous control point
// when the previous command was of the same family.
void PathReader::curve(bool rel) {
    const bool cubic = std::string_view("CcSs").find(cmd_) != std::string_view::npos;
    const bool smooth = cmd_ == 'S' || cmd_ == 's' || cmd_ == 'T' || cmd_ == 't';
    const std::string_view family = cubic ? "CcSs" : "QqTt";
    glm::dvec2 c1 = cur_;
    if (!smooth)
        c1 = point(rel);
    else if (family.find(prevCmd_) != std::string_view::npos)
        c1 = 2.0 * cur_ - lastCtrl_;
    if (cubic) {
        const glm::dvec2 c2 = point(rel);
        const glm::dvec2 end = point(rel);
        ensureSubpath();
        d_.builder.cubicTo(out(c1), out(c2), out(end));
        lastCtrl_ = c2;
        cur_ = end;
    } else {
        const glm::dvec2 end = point(rel);
        ensureSubpath();
        d_.builder.quadTo(out(c1), out(end));
        lastCtrl_ = c1;
        cur_ = end;
    }
}

// One segment of the current command.
void PathReader::drawCommand() {
    const bool rel = cmd_ >= 'a';
    switch (cmd_) {
    case 'M':
    case 'm':
        cur_ = point(rel);
        start_ = cur_;
        startF_ = out(cur_);
        d_.builder.moveTo(startF_, ci_, d_.el);
        break;
    case 'Z':
    case 'z':
        d_.builder.close();
        cur_ = start_;
        break;
    case 'L':
    case 'l':
    case 'H':
    case 'h':
    case 'V':
    case 'v': {
        glm::dvec2 end;
        if (cmd_ == 'L' || cmd_ == 'l') {
            end = point(rel);
        } else if (cmd_ == 'H' || cmd_ == 'h') {
            const double x = number("x");
            end = {rel ? cur_.x + x : x, cur_.y};
        } else {
            const double y = number("y");
            end = {cur_.x, rel ? cur_.y + y : y};
        }
        ensureSubpath();
        d_.builder.lineTo(out(end));
        cur_ = end;
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
        curve(rel);
        break;
    case 'A':
    case 'a': {
        const double rx = number("rx"), ry = number("ry"), phi = number("x-axis-rotation");
        const bool large = flag("large-arc-flag"), sweep = flag("sweep-flag");
        const glm::dvec2 end = point(rel);
        ensureSubpath();
        arcTo(cur_, rx, ry, phi, large, sweep, end);
        cur_ = end;
        break;
    }
    default:
        break;
    }
}

// Elliptical arc from the current point (user space `from`) to `to`.
void PathReader::arcTo(glm::dvec2 from, double rx, double ry, double phiDeg, bool large, bool sweep,
                       glm::dvec2 to) {
    // F.6.2: identical endpoints omit the arc; F.6.6 step 1: zero radius
    // makes it a line.
    if (from == to) return;
    rx = std::abs(rx);
    ry = std::abs(ry);
    const glm::dvec2 toF = out(to);
    if (rx == 0.0 || ry == 0.0) {
        d_.builder.lineTo(toF);
        return;
    }
    // F.6.5 step 1: the endpoints in the ellipse's axis frame.
    const double phi = std::fmod(phiDeg, 360.0) * kSvgPi / 180.0;
    const double cs = std::cos(phi), sn = std::sin(phi);
    const glm::dvec2 h = 0.5 * (from - to);
    const double x1 = cs * h.x + sn * h.y, y1 = -sn * h.x + cs * h.y;
    // F.6.6 step 3: radii too small to span the endpoints are scaled up
    // until the ellipse passes through both (the center is then the
    // midpoint).
    const double lambda = (x1 / rx) * (x1 / rx) + (y1 / ry) * (y1 / ry);
    if (!std::isfinite(lambda))
        fail(cel_, "arc radii are too small for its endpoints to be represented");
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
    if (sweep && dtheta < 0.0) dtheta += 2.0 * kSvgPi;
    if (!sweep && dtheta > 0.0) dtheta -= 2.0 * kSvgPi;
    ArcParams arc;
    arc.center = out(center);
    arc.axisX = d_.ctm.linear({rx * cs, rx * sn});
    arc.axisY = d_.ctm.linear({-ry * sn, ry * cs});
    arc.startAngle = theta1;
    arc.sweepAngle = dtheta;
    arc.end = toF;
    if (!std::isfinite(arc.center.x) || !std::isfinite(arc.center.y) || !std::isfinite(dtheta) ||
        !std::isfinite(theta1)) {
        fail(cel_, "arc parameters are not finite");
    }
    d_.builder.arcTo(arc);
}

} // namespace

void svgDrawPath(const SvgDraw& d) {
    const std::string* data = d.element.attr("d");
    if (!data) return; // no d: renders nothing
    PathReader(d, *data).run();
}

} // namespace sg::features::detail
