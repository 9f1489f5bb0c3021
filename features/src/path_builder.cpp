// Outline primitives -> CurveNetwork (see path_builder.h).
#include "path_builder.h"

#include "surfgrad/base/io.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

namespace sg::features::detail {

void PathBuilder::moveTo(glm::dvec2 p, const CurveInfo& info, const std::string& element) {
    endSubpath();
    if (curves_.size() >= kMaxCurves) {
        throw io::InputError(source_, element,
                             "more than " + std::to_string(kMaxCurves) + " curves");
    }
    curves_.push_back(info);
    curveElement_.push_back(element);
    open_ = true;
    start_ = cur_ = p;
}

void PathBuilder::push(const Prim& p) {
    if (prims_.size() >= kMaxSegments) {
        throw io::InputError(source_, curveElement_.back(),
                             "more than " + std::to_string(kMaxSegments) +
                                 " segments in the drawing");
    }
    prims_.push_back(p);
}

void PathBuilder::lineTo(glm::dvec2 p) {
    if (p == cur_) return;
    push({Prim::Kind::Line, {cur_, p, p, p}, {}, int(curves_.size()) - 1});
    cur_ = p;
}

void PathBuilder::quadTo(glm::dvec2 c, glm::dvec2 p) {
    if (c == cur_ && p == cur_) return;
    push({Prim::Kind::Quad, {cur_, c, p, p}, {}, int(curves_.size()) - 1});
    cur_ = p;
}

void PathBuilder::cubicTo(glm::dvec2 c1, glm::dvec2 c2, glm::dvec2 p) {
    if (c1 == cur_ && c2 == cur_ && p == cur_) return;
    push({Prim::Kind::Cubic, {cur_, c1, c2, p}, {}, int(curves_.size()) - 1});
    cur_ = p;
}

void PathBuilder::arcTo(const ArcParams& arcIn) {
    ArcParams arc = arcIn;
    arc.start = cur_;
    if (arc.end == cur_ && arc.sweepAngle == 0.0) return;
    push({Prim::Kind::Arc, {cur_, arc.end, arc.end, arc.end}, arc, int(curves_.size()) - 1});
    cur_ = arc.end;
}

void PathBuilder::close() {
    if (!open_) return;
    lineTo(start_);
    cur_ = start_;
    endSubpath();
}

void PathBuilder::endSubpath() {
    if (!open_) return;
    open_ = false;
    // A subpath without primitives (a lone moveto) is no curve.
    if (prims_.empty() || prims_.back().curve != int(curves_.size()) - 1) {
        curves_.pop_back();
        curveElement_.pop_back();
    }
}

CurveNetwork PathBuilder::finish(const ApproxOptions& opt, const std::string& emptyReason,
                                 double* maxError) {
    endSubpath();
    if (maxError) *maxError = 0.0;
    if (prims_.empty()) throw io::InputError(source_, "", emptyReason);

    // Drawing size from the control points (arcs: their <= 90 degree hulls).
    glm::dvec2 lo = prims_.front().p[0], hi = lo;
    std::vector<glm::dvec2> hull;
    for (const Prim& p : prims_) {
        hull.clear();
        if (p.kind == Prim::Kind::Arc)
            arcHullPoints(p.arc, hull);
        else
            hull.assign(p.p, p.p + 4);
        for (glm::dvec2 q : hull) {
            if (!std::isfinite(q.x) || !std::isfinite(q.y) || std::abs(q.x) > kMaxAbsCoord ||
                std::abs(q.y) > kMaxAbsCoord) {
                throw io::InputError(source_, curveElement_[std::size_t(p.curve)],
                                     "a coordinate is not finite or exceeds 1e12 in magnitude "
                                     "(after transforms)");
            }
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
    }
    const double drawingSize = std::max(hi.x - lo.x, hi.y - lo.y);
    const double tol = resolveTolerance(opt, drawingSize, source_);

    CurveNetwork net;
    net.source = source_;
    std::vector<int> remap(curves_.size(), -1);
    for (const Prim& p : prims_) {
        int& c = remap[std::size_t(p.curve)];
        if (c < 0) {
            c = int(net.curves.size());
            net.curves.push_back(curves_[std::size_t(p.curve)]);
        }
        const std::string& el = curveElement_[std::size_t(p.curve)];
        switch (p.kind) {
        case Prim::Kind::Line: {
            if (net.segments.size() >= kMaxSegments) {
                throw io::InputError(source_, el,
                                     "more than " + std::to_string(kMaxSegments) + " segments");
            }
            Segment s;
            s.kind = Segment::Kind::Line;
            s.p0 = p.p[0];
            s.p2 = p.p[1];
            s.p1 = 0.5 * (s.p0 + s.p2);
            s.curve = c;
            net.segments.push_back(s);
            break;
        }
        case Prim::Kind::Quad: {
            if (net.segments.size() >= kMaxSegments) {
                throw io::InputError(source_, el,
                                     "more than " + std::to_string(kMaxSegments) + " segments");
            }
            Segment s;
            s.kind = Segment::Kind::Quadratic;
            s.p0 = p.p[0];
            s.p1 = p.p[1];
            s.p2 = p.p[2];
            s.curve = c;
            net.segments.push_back(s);
            break;
        }
        case Prim::Kind::Cubic: {
            const double e = appendCubicAsQuadratics(p.p[0], p.p[1], p.p[2], p.p[3], tol, c,
                                                     net.segments, source_, el);
            if (maxError) *maxError = std::max(*maxError, e);
            break;
        }
        case Prim::Kind::Arc: {
            const double e = appendArcAsQuadratics(p.arc, tol, c, net.segments, source_, el);
            if (maxError) *maxError = std::max(*maxError, e);
            break;
        }
        }
    }
    // Curves whose primitives all vanished (cannot happen for the kinds
    // above, which keep every non-degenerate primitive) would break the
    // curve/segment correspondence; drop them defensively.
    std::vector<int> count(net.curves.size(), 0);
    for (const Segment& s : net.segments) ++count[std::size_t(s.curve)];
    if (std::find(count.begin(), count.end(), 0) != count.end()) {
        std::vector<int> newIndex(net.curves.size(), -1);
        std::vector<CurveInfo> kept;
        for (std::size_t i = 0; i < net.curves.size(); ++i) {
            if (count[i] > 0) {
                newIndex[i] = int(kept.size());
                kept.push_back(net.curves[i]);
            }
        }
        net.curves = std::move(kept);
        for (Segment& s : net.segments) s.curve = newIndex[std::size_t(s.curve)];
    }
    if (net.segments.empty()) throw io::InputError(source_, "", emptyReason);
    // closed == loop, by the network's definition.
    std::size_t first = 0;
    for (std::size_t i = 0; i < net.segments.size(); ++i) {
        if (i + 1 == net.segments.size() || net.segments[i + 1].curve != net.segments[i].curve) {
            net.curves[std::size_t(net.segments[i].curve)].closed =
                net.segments[i].p2 == net.segments[first].p0;
            first = i + 1;
        }
    }
    checkNetwork(net);
    return net;
}

void appendUtf8(std::string& out, std::uint32_t cp) {
    if (cp < 0x80) {
        out += char(cp);
    } else if (cp < 0x800) {
        out += char(0xC0 | (cp >> 6));
        out += char(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
        out += char(0xE0 | (cp >> 12));
        out += char(0x80 | ((cp >> 6) & 0x3F));
        out += char(0x80 | (cp & 0x3F));
    } else {
        out += char(0xF0 | (cp >> 18));
        out += char(0x80 | ((cp >> 12) & 0x3F));
        out += char(0x80 | ((cp >> 6) & 0x3F));
        out += char(0x80 | (cp & 0x3F));
    }
}

} // namespace sg::features::detail
