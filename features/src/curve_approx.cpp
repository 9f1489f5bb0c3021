// Quadratic approximation of cubic Beziers and elliptical arcs with a proven
// Hausdorff bound (see surfgrad/curves.h for the contracts).
//
// Parilov and Zorin (2008) build feature maps from quadratic Bezier curves
// only (seed 004, section 3), so every cubic (SVG C/S, CFF glyphs) and arc
// (SVG A, rounded rect corners, circles, ellipses) is turned into quadratics
// here, within a tolerance the caller states in input units.
//
// Cubic: on a parameter interval with Bezier points b0..b3, the quadratic
// with control point q = (3 (b1 + b2) - b0 - b3) / 4 elevated to degree 3 has
// points b0, (b0 + 2q)/3, (2q + b3)/3, b3; the difference to the cubic is
// D(t) = d/6 * 3t(1-t)(1-2t) with d = b3 - 3 b2 + 3 b1 - b0, whose maximum
// over [0,1] is |d| sqrt(3)/36. d is 1/6 of the (constant) third derivative
// times the interval length cubed, so n equal pieces divide it by n^3.
//
// Arc: the unit-circle piece of half-angle h and the quadratic through its
// endpoints with control point at the tangent intersection (radius 1/cos h).
// |B(t)|^2 is convex in u = 2t(1-t) with zero slope at u = 0, so |B| grows
// from 1 at the ends to (cos h + 1/cos h)/2 at t = 1/2; B sweeps the piece's
// angular range monotonically, so the Hausdorff distance is exactly
// (cos h + 1/cos h)/2 - 1 = 2 sin^4(h/2) / cos h (the second form avoids
// cancellation for small h). An affine map with linear part M scales
// distances by at most ||M||_2.
#include "surfgrad/curves.h"
#include "surfgrad/io.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace sg::features {

namespace {

constexpr double kPi = std::numbers::pi;

// Largest piece count we are prepared to emit for one curve before the
// global segment limit is checked by the caller.
constexpr double kMaxPieces = double(kMaxSegments);

void pushPiece(std::vector<Segment>& out, glm::dvec2 p0, glm::dvec2 p1, glm::dvec2 p2, int curve) {
    if (p0 == p1 && p1 == p2) return; // zero-length piece of a degenerate curve
    Segment s;
    s.kind = Segment::Kind::Quadratic;
    s.p0 = p0;
    s.p1 = p1;
    s.p2 = p2;
    s.curve = curve;
    out.push_back(s);
}

void checkPieceCount(double n, std::size_t have, const std::string& source, const std::string& element) {
    if (!(n <= kMaxPieces) || have + std::size_t(n) > kMaxSegments) {
        throw io::InputError(source, element,
                             "approximating this curve within the tolerance needs more than " +
                                 std::to_string(kMaxSegments) +
                                 " segments in total; raise the tolerance");
    }
}

double spectralNorm(glm::dvec2 colX, glm::dvec2 colY) {
    // sqrt of the largest eigenvalue of M^T M for M = [colX colY].
    const double a = glm::dot(colX, colX), b = glm::dot(colX, colY), c = glm::dot(colY, colY);
    const double half = 0.5 * (a - c);
    return std::sqrt(0.5 * (a + c) + std::sqrt(half * half + b * b));
}

// Hausdorff distance between a unit-circle arc of half-angle h and its
// tangent-intersection quadratic.
double circlePieceError(double halfAngle) {
    const double s = std::sin(0.5 * halfAngle);
    return 2.0 * s * s * s * s / std::cos(halfAngle);
}

} // namespace

double resolveTolerance(const ApproxOptions& opt, double drawingSize, const std::string& source) {
    if (!std::isfinite(opt.tolerance) || !std::isfinite(opt.relativeTolerance)) {
        throw io::InputError(source, "tolerance", "tolerance must be a finite number");
    }
    const double size = std::isfinite(drawingSize) ? std::max(drawingSize, 0.0) : 0.0;
    double tol = opt.tolerance;
    if (tol <= 0.0) {
        if (!(opt.relativeTolerance > 0.0)) {
            throw io::InputError(source, "tolerance",
                                 "relative tolerance must be > 0 (got " +
                                     std::to_string(opt.relativeTolerance) + ")");
        }
        tol = opt.relativeTolerance * size;
    }
    // A zero-size drawing has nothing to approximate; any positive value
    // keeps the arithmetic below meaningful.
    if (size == 0.0) return tol > 0.0 ? tol : 1.0;
    if (tol < 1e-9 * size) {
        throw io::InputError(source, "tolerance",
                             "tolerance " + std::to_string(tol) + " is below 1e-9 of the drawing size " +
                                 std::to_string(size));
    }
    return tol;
}

double appendCubicAsQuadratics(glm::dvec2 c0, glm::dvec2 c1, glm::dvec2 c2, glm::dvec2 c3,
                               double tolerance, int curve, std::vector<Segment>& out,
                               const std::string& source, const std::string& element) {
    const double bound1 = std::sqrt(3.0) / 36.0 * glm::length(c3 - 3.0 * c2 + 3.0 * c1 - c0);
    double nReal = std::max(1.0, std::ceil(std::cbrt(bound1 / tolerance)));
    checkPieceCount(nReal, out.size(), source, element);
    auto n = std::size_t(nReal);
    // cbrt may round down by an ulp: step up until the bound holds.
    while (bound1 / (double(n) * double(n) * double(n)) > tolerance) ++n;
    checkPieceCount(double(n), out.size(), source, element);

    // Power basis C(t) = c0 + t a1 + t^2 a2 + t^3 a3 for evaluation inside.
    const glm::dvec2 a1 = 3.0 * (c1 - c0);
    const glm::dvec2 a2 = 3.0 * (c2 - 2.0 * c1 + c0);
    const glm::dvec2 a3 = c3 - 3.0 * c2 + 3.0 * c1 - c0;
    auto eval = [&](double t) { return c0 + t * (a1 + t * (a2 + t * a3)); };
    auto deriv = [&](double t) { return a1 + t * (2.0 * a2 + t * 3.0 * a3); };

    const double h = 1.0 / double(n);
    glm::dvec2 prev = c0; // shared endpoint: exactly c0 for the first piece
    for (std::size_t k = 0; k < n; ++k) {
        const double ta = double(k) * h, tb = (k + 1 == n) ? 1.0 : double(k + 1) * h;
        const glm::dvec2 b0 = eval(ta), b3 = eval(tb);
        const glm::dvec2 b1 = b0 + (tb - ta) / 3.0 * deriv(ta);
        const glm::dvec2 b2 = b3 - (tb - ta) / 3.0 * deriv(tb);
        const glm::dvec2 q = (3.0 * (b1 + b2) - b0 - b3) * 0.25;
        const glm::dvec2 next = (k + 1 == n) ? c3 : b3;
        pushPiece(out, prev, q, next, curve);
        prev = next;
    }
    return bound1 / (double(n) * double(n) * double(n));
}

double appendArcAsQuadratics(const ArcParams& arc, double tolerance, int curve,
                             std::vector<Segment>& out, const std::string& source,
                             const std::string& element) {
    const double sweep = std::clamp(arc.sweepAngle, -2.0 * kPi, 2.0 * kPi);
    const double absSweep = std::abs(sweep);
    const double norm = spectralNorm(arc.axisX, arc.axisY);
    // At most 90 degrees per piece so the tangents intersect well in front.
    double nReal = std::max(1.0, std::ceil(absSweep / (0.5 * kPi) - 1e-12));
    // Error ~ norm * h^4 / 8 with h = sweep / (2n): solve for n, then step.
    if (norm > 0.0) {
        const double nErr = std::ceil(0.5 * absSweep / std::pow(8.0 * tolerance / norm, 0.25));
        if (std::isfinite(nErr)) nReal = std::max(nReal, std::max(1.0, nErr - 1.0));
        else nReal = kMaxPieces + 1.0;
    }
    checkPieceCount(nReal, out.size(), source, element);
    auto n = std::size_t(nReal);
    auto boundOf = [&](std::size_t count) { return norm * circlePieceError(0.5 * absSweep / double(count)); };
    while (boundOf(n) > tolerance) ++n;
    checkPieceCount(double(n), out.size(), source, element);

    const double step = sweep / double(n);
    const double ctrlScale = 1.0 / std::cos(0.5 * absSweep / double(n));
    auto at = [&](double angle, double radius) {
        return arc.center + radius * (std::cos(angle) * arc.axisX + std::sin(angle) * arc.axisY);
    };
    glm::dvec2 prev = arc.start;
    for (std::size_t k = 0; k < n; ++k) {
        const double a0 = arc.startAngle + double(k) * step;
        const glm::dvec2 q = at(a0 + 0.5 * step, ctrlScale);
        const glm::dvec2 next = (k + 1 == n) ? arc.end : at(a0 + step, 1.0);
        pushPiece(out, prev, q, next, curve);
        prev = next;
    }
    return boundOf(n);
}

void arcHullPoints(const ArcParams& arc, std::vector<glm::dvec2>& out) {
    const double sweep = std::clamp(arc.sweepAngle, -2.0 * kPi, 2.0 * kPi);
    const int n = std::max(1, int(std::ceil(std::abs(sweep) / (0.5 * kPi) - 1e-12)));
    const double step = sweep / n;
    const double ctrlScale = 1.0 / std::cos(0.5 * std::abs(step));
    out.push_back(arc.start);
    for (int k = 0; k < n; ++k) {
        const double mid = arc.startAngle + (k + 0.5) * step, end = arc.startAngle + (k + 1) * step;
        out.push_back(arc.center + ctrlScale * (std::cos(mid) * arc.axisX + std::sin(mid) * arc.axisY));
        out.push_back(arc.center + std::cos(end) * arc.axisX + std::sin(end) * arc.axisY);
    }
    out.push_back(arc.end);
}

} // namespace sg::features
