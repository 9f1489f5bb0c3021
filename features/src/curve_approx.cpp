// Quadratic approximation of cubic Beziers and elliptical arcs with a proven
// Hausdorff bound (see surfgrad/features/curves.h for the contracts).
//
// Parilov and Zorin (2008) build feature maps from quadratic Bezier curves
// only (seed 004, section 3), so every cubic (SVG C/S, CFF glyphs) and arc
// (SVG A, rounded rect corners, circles, ellipses) is turned into quadratics
// here, within a tolerance the caller states in input units.
//
// Cubic, G1 construction (used whenever it meets the tolerance): a cubic
// piece b0..b3 without inflection becomes the quadratic b0, q, b3 with q the
// intersection of the piece's end tangents, so consecutive pieces share
// tangent directions (no kinks at the joints). Its distance to the cubic is
// bounded rigorously by reparametrizing: for any m in (0,1), phi(t) with
// Bernstein values 0, m, 1 is a monotone map of [0,1], Q(phi(t)) is a quartic
// whose Bernstein points are blossoms of Q, and the convex-hull property gives
// max_t |C(t) - Q(phi(t))| <= max_k |C4_k - (Q o phi)_k| (C4: the cubic
// elevated to degree 4). Every curve point C(t) is that close to the point
// Q(phi(t)) and vice versa, so this bounds the Hausdorff distance; m is
// chosen to make it small, and the difference is degree-elevated to 12
// before taking the hull (same polynomial, tighter control polygon). The
// cubic is first split at its inflections (where no tangent intersection
// exists); pieces over the tolerance are then split, recursively, into the
// number of equal parts the cubic error order predicts (2 to 8): adaptive
// subdivision.
//
// Cubic, midpoint construction (fallback for pieces with parallel end
// tangents or that stay too curved after deep bisection): on a parameter
// interval with Bezier points b0..b3, the quadratic with control point
// q = (3 (b1 + b2) - b0 - b3) / 4 elevated to degree 3 has points b0,
// (b0 + 2q)/3, (2q + b3)/3, b3; the difference to the cubic is
// D(t) = d/6 * 3t(1-t)(1-2t) with d = b3 - 3 b2 + 3 b1 - b0, whose maximum
// over [0,1] is |d| sqrt(3)/36. d scales with the interval length cubed, so
// n equal pieces divide it by n^3.
//
// Arc: the unit-circle piece of half-angle h and the quadratic through its
// endpoints with control point at the tangent intersection (radius 1/cos h).
// |B(t)|^2 is convex in u = 2t(1-t) with zero slope at u = 0, so |B| grows
// from 1 at the ends to (cos h + 1/cos h)/2 at t = 1/2; B sweeps the piece's
// angular range monotonically, so the Hausdorff distance is exactly
// (cos h + 1/cos h)/2 - 1 = 2 sin^4(h/2) / cos h (the second form avoids
// cancellation for small h). An affine map with linear part M scales
// distances by at most ||M||_2.
#include "surfgrad/features/curves.h"
#include "surfgrad/base/io.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/common.hpp>
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

void checkPieceCount(double n, std::size_t have, const std::string& source,
                     const std::string& element) {
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
                             "tolerance " + std::to_string(tol) +
                                 " is below 1e-9 of the drawing size " + std::to_string(size));
    }
    return tol;
}

namespace {

struct CubicPiece {
    glm::dvec2 b[4];
};

double cross2(glm::dvec2 a, glm::dvec2 b) {
    return a.x * b.y - a.y * b.x;
}

// de Casteljau split at t.
void splitCubic(const CubicPiece& c, double t, CubicPiece& left, CubicPiece& right) {
    const glm::dvec2 p01 = glm::mix(c.b[0], c.b[1], t), p12 = glm::mix(c.b[1], c.b[2], t),
                     p23 = glm::mix(c.b[2], c.b[3], t);
    const glm::dvec2 p012 = glm::mix(p01, p12, t), p123 = glm::mix(p12, p23, t);
    const glm::dvec2 mid = glm::mix(p012, p123, t);
    left = {{c.b[0], p01, p012, mid}};
    right = {{mid, p123, p23, c.b[3]}};
}

// Rigorous bound of the Hausdorff distance between cubic c and the quadratic
// c.b[0], q, c.b[3] (see the file comment), minimized over the
// reparametrization's middle value m.
constexpr int kElevatedDegree = 12;

double g1Bound(const CubicPiece& c, glm::dvec2 q) {
    const glm::dvec2 p0 = c.b[0], p2 = c.b[3];
    const glm::dvec2 c4[5] = {p0, 0.25 * p0 + 0.75 * c.b[1], 0.5 * (c.b[1] + c.b[2]),
                              0.75 * c.b[2] + 0.25 * p2, p2};
    auto bound = [&](double m, bool elevate = false) {
        const glm::dvec2 k1 = (1.0 - m) * p0 + m * q;
        const glm::dvec2 qmm = (1.0 - m) * (1.0 - m) * p0 + 2.0 * m * (1.0 - m) * q + m * m * p2;
        const glm::dvec2 k2 = (2.0 * q + 4.0 * qmm) / 6.0;
        const glm::dvec2 k3 = (1.0 - m) * q + m * p2;
        if (!elevate) {
            return std::sqrt(
                std::max({glm::dot(c4[1] - k1, c4[1] - k1), glm::dot(c4[2] - k2, c4[2] - k2),
                          glm::dot(c4[3] - k3, c4[3] - k3)}));
        }
        // Difference in degree-4 Bernstein form (zero at both ends), degree
        // elevated so the control polygon hugs the polynomial: the hull
        // bound converges to the true maximum as O(1/degree).
        glm::dvec2 dk[kElevatedDegree + 1];
        dk[0] = glm::dvec2(0.0);
        dk[1] = c4[1] - k1;
        dk[2] = c4[2] - k2;
        dk[3] = c4[3] - k3;
        dk[4] = glm::dvec2(0.0);
        for (int n = 4; n < kElevatedDegree; ++n) {
            // degree n -> n + 1: e_k = k/(n+1) d_{k-1} + (1 - k/(n+1)) d_k.
            dk[n + 1] = dk[n];
            for (int k = n; k >= 1; --k) {
                const double w = double(k) / double(n + 1);
                dk[k] = w * dk[k - 1] + (1.0 - w) * dk[k];
            }
        }
        double worst = 0.0;
        for (int k = 1; k < kElevatedDegree; ++k) worst = std::max(worst, glm::dot(dk[k], dk[k]));
        return std::sqrt(worst);
    };
    // Choose m with the cheap degree-4 hull (coarse scan, then golden-section
    // search around the best sample; any m gives a valid bound, the search
    // only makes it tighter), then take the elevated bound at that m.
    constexpr int kScan = 16;
    double bestM = 0.5, best = bound(0.5);
    for (int i = 1; i < kScan; ++i) {
        const double m = double(i) / kScan;
        const double b = bound(m);
        if (b < best) {
            best = b;
            bestM = m;
        }
    }
    double lo = std::max(1e-3, bestM - 1.0 / kScan), hi = std::min(1.0 - 1e-3, bestM + 1.0 / kScan);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 30; ++it) {
        const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
        if (bound(m1) < bound(m2))
            hi = m2;
        else
            lo = m1;
    }
    const double mid = 0.5 * (lo + hi);
    return bound(bound(mid) < best ? mid : bestM, true);
}

// End tangent directions of a cubic piece (falling back to the next control
// point when one coincides, as at a cusp).
glm::dvec2 startTangent(const CubicPiece& c) {
    if (c.b[1] != c.b[0]) return c.b[1] - c.b[0];
    if (c.b[2] != c.b[0]) return c.b[2] - c.b[0];
    return c.b[3] - c.b[0];
}
glm::dvec2 endTangent(const CubicPiece& c) {
    if (c.b[3] != c.b[2]) return c.b[3] - c.b[2];
    if (c.b[3] != c.b[1]) return c.b[3] - c.b[1];
    return c.b[3] - c.b[0];
}

class CubicApproximator {
public:
    CubicApproximator(double tolerance, int curve, std::vector<Segment>& out,
                      const std::string& source, const std::string& element)
        : tol_(tolerance), curve_(curve), out_(out), source_(source), element_(element) {}

    // Pieces of c (from `start` exactly to `end` exactly).
    void run(const CubicPiece& c, glm::dvec2 start, glm::dvec2 end) {
        // Split at inflections: there the tangent-intersection quadratic
        // does not exist. With C'(t) = A + 2Bt + Ct^2 (A = 3(b1-b0), ...),
        // cross(C', C'') = 0 is a quadratic in t.
        const glm::dvec2 a = c.b[1] - c.b[0], b = c.b[2] - 2.0 * c.b[1] + c.b[0],
                         cc = c.b[3] - 3.0 * c.b[2] + 3.0 * c.b[1] - c.b[0];
        // cross(a + 2bt + cc t^2, 2b + 2cc t)/2 = cross(a,b) + cross(a,cc) t + cross(b,cc) t^2.
        const double q0 = cross2(a, b), q1 = cross2(a, cc), q2 = cross2(b, cc);
        std::vector<double> ts;
        const double scale = std::max({std::abs(q0), std::abs(q1), std::abs(q2)});
        if (scale > 0.0) {
            if (std::abs(q2) > 1e-12 * scale) {
                const double disc = q1 * q1 - 4.0 * q2 * q0;
                if (disc >= 0.0) {
                    const double sq = std::sqrt(disc);
                    // Numerically stable roots.
                    const double r = -0.5 * (q1 + (q1 >= 0.0 ? sq : -sq));
                    if (r != 0.0) {
                        ts.push_back(r / q2);
                        ts.push_back(q0 / r);
                    } else {
                        ts.push_back(0.0);
                    }
                }
            } else if (std::abs(q1) > 1e-12 * scale) {
                ts.push_back(-q0 / q1);
            }
        }
        std::sort(ts.begin(), ts.end());
        CubicPiece rest = c;
        double consumed = 0.0;
        glm::dvec2 from = start;
        for (double t : ts) {
            if (!(t > consumed + 1e-6 && t < 1.0 - 1e-6)) continue;
            CubicPiece left, right;
            const double local = (t - consumed) / (1.0 - consumed);
            splitCubic(rest, local, left, right);
            piece(left, from, left.b[3], 0);
            from = left.b[3];
            rest = right;
            consumed = t;
        }
        piece(rest, from, end, 0);
    }

    double maxBound() const { return maxBound_; }

private:
    void emit(glm::dvec2 p0, glm::dvec2 q, glm::dvec2 p2, double bound) {
        if (p0 == q && q == p2) return; // zero-length piece of a degenerate cubic
        if (out_.size() >= kMaxSegments) {
            throw io::InputError(source_, element_,
                                 "approximating this curve within the tolerance needs more than " +
                                     std::to_string(kMaxSegments) +
                                     " segments in total; raise the tolerance");
        }
        pushPiece(out_, p0, q, p2, curve_);
        maxBound_ = std::max(maxBound_, bound);
    }

    // Uniform midpoint construction with the exact parametric bound.
    void midpoint(const CubicPiece& c, glm::dvec2 start, glm::dvec2 end) {
        const double bound1 =
            std::sqrt(3.0) / 36.0 * glm::length(c.b[3] - 3.0 * c.b[2] + 3.0 * c.b[1] - c.b[0]);
        const double nReal = std::max(1.0, std::ceil(std::cbrt(bound1 / tol_)));
        checkPieceCount(nReal, out_.size(), source_, element_);
        auto n = std::size_t(nReal);
        while (bound1 / (double(n) * double(n) * double(n)) > tol_) ++n; // cbrt may round down
        checkPieceCount(double(n), out_.size(), source_, element_);
        const double bound = bound1 / (double(n) * double(n) * double(n));
        const glm::dvec2 a1 = 3.0 * (c.b[1] - c.b[0]);
        const glm::dvec2 a2 = 3.0 * (c.b[2] - 2.0 * c.b[1] + c.b[0]);
        const glm::dvec2 a3 = c.b[3] - 3.0 * c.b[2] + 3.0 * c.b[1] - c.b[0];
        auto eval = [&](double t) { return c.b[0] + t * (a1 + t * (a2 + t * a3)); };
        auto deriv = [&](double t) { return a1 + t * (2.0 * a2 + t * 3.0 * a3); };
        const double h = 1.0 / double(n);
        glm::dvec2 prev = start;
        for (std::size_t k = 0; k < n; ++k) {
            const double ta = double(k) * h, tb = (k + 1 == n) ? 1.0 : double(k + 1) * h;
            const glm::dvec2 b0 = eval(ta), b3 = eval(tb);
            const glm::dvec2 b1 = b0 + (tb - ta) / 3.0 * deriv(ta);
            const glm::dvec2 b2 = b3 - (tb - ta) / 3.0 * deriv(tb);
            const glm::dvec2 next = (k + 1 == n) ? end : b3;
            emit(prev, (3.0 * (b1 + b2) - b0 - b3) * 0.25, next, bound);
            prev = next;
        }
    }

    void piece(const CubicPiece& c, glm::dvec2 start, glm::dvec2 end, int depth) {
        const glm::dvec2 t0 = startTangent(c), t1 = endTangent(c);
        const double den = cross2(t0, t1);
        const double len0 = glm::length(t0), len1 = glm::length(t1);
        // Parallel end tangents (straight or S-shaped pieces): no usable
        // intersection; the midpoint construction handles them exactly.
        if (!(std::abs(den) > 1e-9 * len0 * len1)) {
            midpoint(c, start, end);
            return;
        }
        // b0 + s t0 = b3 - u t1.
        const glm::dvec2 chord = c.b[3] - c.b[0];
        const double s = cross2(chord, t1) / den, u = cross2(t0, chord) / den;
        int parts = 2;
        if (s > 0.0 && u > 0.0) {
            const glm::dvec2 q = c.b[0] + s * t0;
            const double bound = g1Bound(c, q);
            if (bound <= tol_) {
                emit(start, q, end, bound);
                return;
            }
            // The error shrinks about as (length)^3: split into as many equal
            // parts as that predicts rather than always halving, so piece
            // counts do not round up to powers of two.
            const double predicted = std::ceil(std::cbrt(bound / tol_) * 1.1);
            parts = int(std::clamp(predicted, 2.0, 8.0));
        }
        // Too far, or the tangents meet behind (a turn of more than 180
        // degrees): bisect. Deep pieces that still fail (near cusps) use the
        // midpoint construction, which always terminates.
        if (depth >= kMaxDepth) {
            midpoint(c, start, end);
            return;
        }
        CubicPiece rest = c;
        glm::dvec2 from = start;
        for (int k = 0; k + 1 < parts; ++k) {
            CubicPiece left, right;
            splitCubic(rest, 1.0 / double(parts - k), left, right);
            piece(left, from, left.b[3], depth + 1);
            from = left.b[3];
            rest = right;
        }
        piece(rest, from, end, depth + 1);
    }

    static constexpr int kMaxDepth = 20;
    double tol_;
    int curve_;
    std::vector<Segment>& out_;
    const std::string& source_;
    const std::string& element_;
    double maxBound_ = 0.0;
};

} // namespace

double appendCubicAsQuadratics(glm::dvec2 c0, glm::dvec2 c1, glm::dvec2 c2, glm::dvec2 c3,
                               double tolerance, int curve, std::vector<Segment>& out,
                               const std::string& source, const std::string& element) {
    // Hopeless requests fail before any work: the G1 construction needs at
    // least about as many pieces as the uniform midpoint one.
    const double bound1 = std::sqrt(3.0) / 36.0 * glm::length(c3 - 3.0 * c2 + 3.0 * c1 - c0);
    checkPieceCount(std::ceil(std::cbrt(bound1 / tolerance)), out.size(), source, element);
    CubicApproximator approx(tolerance, curve, out, source, element);
    approx.run({{c0, c1, c2, c3}}, c0, c3);
    return approx.maxBound();
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
        if (std::isfinite(nErr))
            nReal = std::max(nReal, std::max(1.0, nErr - 1.0));
        else
            nReal = kMaxPieces + 1.0;
    }
    checkPieceCount(nReal, out.size(), source, element);
    auto n = std::size_t(nReal);
    auto boundOf = [&](std::size_t count) {
        return norm * circlePieceError(0.5 * absSweep / double(count));
    };
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
        out.push_back(arc.center +
                      ctrlScale * (std::cos(mid) * arc.axisX + std::sin(mid) * arc.axisY));
        out.push_back(arc.center + std::cos(end) * arc.axisX + std::sin(end) * arc.axisY);
    }
    out.push_back(arc.end);
}

} // namespace sg::features
