// Structural checks of curve networks and exact junction detection (see
// surfgrad/features/curves.h). The feature-map preprocessing of Parilov and Zorin
// (2008, section 4) must know where curves end and meet: a texel holding a
// junction gets a different configuration than one crossed by a smooth
// curve. Loaders make shared endpoints bit-identical, so junctions are found
// by exact comparison, without a distance threshold that would merge nearby
// but distinct curve ends.
#include "surfgrad/features/curves.h"
#include "surfgrad/base/io.h"

#include <algorithm>
#include <cmath>
#include <compare>
#include <sstream>

namespace sg::features {

namespace {

std::string fmtPoint(glm::dvec2 p) {
    std::ostringstream s;
    s.precision(17);
    s << "(" << p.x << ", " << p.y << ")";
    return s.str();
}

bool validCoord(glm::dvec2 p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::abs(p.x) <= kMaxAbsCoord &&
           std::abs(p.y) <= kMaxAbsCoord;
}

} // namespace

void checkNetwork(const CurveNetwork& net) {
    const std::string& file = net.source;
    if (net.segments.empty())
        throw io::InputError(file, "", "the curve network is empty (no segments)");
    if (net.segments.size() > kMaxSegments) {
        throw io::InputError(file, "",
                             std::to_string(net.segments.size()) + " segments; limit is " +
                                 std::to_string(kMaxSegments));
    }
    if (net.curves.size() > kMaxCurves) {
        throw io::InputError(file, "",
                             std::to_string(net.curves.size()) + " curves; limit is " +
                                 std::to_string(kMaxCurves));
    }
    std::vector<std::size_t> firstSeg(net.curves.size(), SIZE_MAX);
    std::vector<std::size_t> lastSeg(net.curves.size(), SIZE_MAX);
    int prevCurve = -1;
    for (std::size_t i = 0; i < net.segments.size(); ++i) {
        const Segment& s = net.segments[i];
        const std::string el = "segment " + std::to_string(i);
        if (s.curve < 0 || std::size_t(s.curve) >= net.curves.size()) {
            throw io::InputError(file, el,
                                 "curve index " + std::to_string(s.curve) + " out of range");
        }
        for (glm::dvec2 p : {s.p0, s.p1, s.p2}) {
            if (!validCoord(p)) {
                throw io::InputError(file, el,
                                     "coordinate " + fmtPoint(p) +
                                         " is not finite or exceeds 1e12 in magnitude");
            }
        }
        if (s.p0 == s.p1 && s.p1 == s.p2) {
            throw io::InputError(file, el,
                                 "all control points coincide at " + fmtPoint(s.p0) +
                                     " (zero-length segment)");
        }
        if (s.kind == Segment::Kind::Line && s.p1 != 0.5 * (s.p0 + s.p2)) {
            throw io::InputError(file, el, "line segment's p1 is not the midpoint of p0 and p2");
        }
        if (s.curve != prevCurve) {
            if (firstSeg[std::size_t(s.curve)] != SIZE_MAX) {
                throw io::InputError(file, el,
                                     "segments of curve " + std::to_string(s.curve) +
                                         " are not stored consecutively");
            }
            firstSeg[std::size_t(s.curve)] = i;
        } else if (net.segments[i - 1].p2 != s.p0) {
            throw io::InputError(file, el,
                                 "starts at " + fmtPoint(s.p0) +
                                     " but the previous segment of its curve ends at " +
                                     fmtPoint(net.segments[i - 1].p2));
        }
        lastSeg[std::size_t(s.curve)] = i;
        prevCurve = s.curve;
    }
    for (std::size_t c = 0; c < net.curves.size(); ++c) {
        const std::string el = "curve " + std::to_string(c);
        if (firstSeg[c] == SIZE_MAX) throw io::InputError(file, el, "has no segments");
        const bool loop = net.segments[lastSeg[c]].p2 == net.segments[firstSeg[c]].p0;
        if (loop != net.curves[c].closed) {
            throw io::InputError(file, el,
                                 loop ? "ends where it starts but is not marked closed"
                                      : "is marked closed but does not end where it starts");
        }
    }
}

std::vector<Junction> findJunctions(const CurveNetwork& net) {
    struct End {
        double x, y;
        std::uint32_t id;
    };
    std::vector<End> ends;
    ends.reserve(2 * net.segments.size());
    for (std::size_t i = 0; i < net.segments.size(); ++i) {
        const Segment& s = net.segments[i];
        // + 0.0 maps -0.0 to +0.0 so the two zeros compare as one point.
        ends.push_back({s.p0.x + 0.0, s.p0.y + 0.0, std::uint32_t(2 * i)});
        ends.push_back({s.p2.x + 0.0, s.p2.y + 0.0, std::uint32_t(2 * i + 1)});
    }
    // strong_order is a total order even for NaN (which checkNetwork rejects
    // anyway), so sorting never has undefined behaviour.
    auto key = [](const End& a, const End& b) {
        auto c = std::strong_order(a.x, b.x);
        if (c != 0) return c < 0;
        c = std::strong_order(a.y, b.y);
        if (c != 0) return c < 0;
        return a.id < b.id;
    };
    std::sort(ends.begin(), ends.end(), key);
    std::vector<Junction> out;
    for (std::size_t i = 0; i < ends.size();) {
        std::size_t j = i;
        Junction jn;
        jn.pos = {ends[i].x, ends[i].y};
        while (j < ends.size() && std::strong_order(ends[j].x, ends[i].x) == 0 &&
               std::strong_order(ends[j].y, ends[i].y) == 0) {
            jn.ends.push_back(ends[j].id);
            ++j;
        }
        out.push_back(std::move(jn));
        i = j;
    }
    return out;
}

} // namespace sg::features
