// JSON curve networks (schema in docs/features-input.md; contract in
// surfgrad/features/curves.h): polylines and explicit line / quadratic Bezier
// segments, the input form of the feature curves of Parilov and Zorin (2008,
// section 3: "a set of quadratic Bezier curves").
//
// The file is untrusted: every field is type-checked, every number must be
// finite and within kMaxAbsCoord, counts are checked against the limits in
// curves.h before anything proportional to them is allocated, unknown keys
// are errors (typos such as "widht" must not be silently ignored), and
// nesting depth is checked before the DOM parser sees the text.
#include "surfgrad/features/curves.h"
#include "surfgrad/base/io.h"

#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

namespace sg::features {

namespace {

using nlohmann::json;

// Deepest nesting of a valid file is 7 (root, curves, curve, segments,
// segment, points, point); 16 leaves room for nothing else and stops
// pathological inputs early.
constexpr int kMaxJsonDepth = 16;
constexpr std::size_t kMaxNameBytes = 1024;
constexpr std::size_t kMaxProfileBytes = 256; // a table of 16 heights fits

std::string typeName(const json& v) {
    if (v.is_number()) return "number";
    return v.type_name();
}

std::string fmtNum(double v) {
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

class Reader {
public:
    explicit Reader(const std::string& source) : source_(source) {}

    [[noreturn]] void fail(const std::string& element, const std::string& reason) const {
        throw io::InputError(source_, element, reason);
    }

    // Rejects keys outside `allowed` (keys starting with '_' are comments).
    void checkKeys(const json& obj, const std::string& element,
                   std::initializer_list<const char*> allowed) const {
        for (auto it = obj.begin(); it != obj.end(); ++it) {
            const std::string& k = it.key();
            if (!k.empty() && k[0] == '_') continue;
            bool ok = false;
            for (const char* a : allowed) ok = ok || k == a;
            if (!ok) {
                std::string list;
                for (const char* a : allowed)
                    list += std::string(list.empty() ? "" : ", ") + "\"" + a + "\"";
                fail(element.empty() ? k : element + "." + k,
                     "unknown key (expected " + list + "; keys starting with '_' are comments)");
            }
        }
    }

    double number(const json& v, const std::string& element) const {
        if (!v.is_number()) fail(element, "expected a number, got " + typeName(v));
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail(element, "number is not finite (overflows a double)");
        if (std::abs(d) > kMaxAbsCoord) {
            fail(element, "|" + fmtNum(d) + "| exceeds the coordinate limit 1e12");
        }
        return d;
    }

    glm::dvec2 point(const json& v, const std::string& element) const {
        if (!v.is_array()) fail(element, "expected a point [x, y], got " + typeName(v));
        if (v.size() != 2) {
            fail(element,
                 "expected a point [x, y] with 2 numbers, got " + std::to_string(v.size()));
        }
        return {number(v[0], element + "[0]"), number(v[1], element + "[1]")};
    }

    const std::string& source() const { return source_; }

private:
    const std::string& source_;
};

// Line and column (1-based) of a byte offset.
std::string lineColumn(std::string_view text, std::size_t offset) {
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            col = 1;
        } else {
            ++col;
        }
    }
    return "line " + std::to_string(line) + " column " + std::to_string(col);
}

// Checks bracket nesting outside strings before the DOM parser runs.
void checkDepth(std::string_view text, const std::string& source) {
    int depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth) {
                throw io::InputError(source, lineColumn(text, i),
                                     "nesting deeper than " + std::to_string(kMaxJsonDepth) +
                                         " levels (the schema needs at most 7)");
            }
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

// The whole text as a JSON DOM (syntax and number errors name the line).
json parseText(std::string_view text, const std::string& source) {
    checkDepth(text, source);
    try {
        return json::parse(text.begin(), text.end());
    } catch (const json::parse_error& e) {
        // nlohmann's message: "[json.exception.parse_error.101] parse error at
        // line L, column C: <reason>"; keep only the reason.
        std::string what = e.what();
        const auto colPos = what.find("column ");
        const auto sep = colPos == std::string::npos ? std::string::npos : what.find(": ", colPos);
        const std::size_t offset = e.byte > 0 ? e.byte - 1 : 0;
        throw io::InputError(source, lineColumn(text, offset),
                             "JSON syntax error: " +
                                 (sep == std::string::npos ? what : what.substr(sep + 2)));
    } catch (const json::exception& e) {
        // out_of_range.406: a number literal overflows a double (e.g. 1e400).
        // Locate the literal nlohmann quotes so the message names its line.
        std::string what = e.what();
        const auto close = what.find("] ");
        std::string element;
        const auto q0 = what.find('\''), q1 = what.rfind('\'');
        if (q0 != std::string::npos && q1 > q0 + 1) {
            const auto at = text.find(std::string_view(what).substr(q0 + 1, q1 - q0 - 1));
            if (at != std::string_view::npos) element = lineColumn(text, at);
        }
        throw io::InputError(source, element,
                             "JSON number error: " +
                                 (close == std::string::npos ? what : what.substr(close + 2)));
    }
}

// The root object: version 1 and a non-empty array of curves.
const json& curvesOf(const json& root, const Reader& rd) {
    if (!root.is_object())
        rd.fail("", "expected a JSON object at the top level, got " + typeName(root));
    rd.checkKeys(root, "", {"version", "curves"});
    if (!root.contains("version")) rd.fail("version", "missing (this build reads version 1)");
    const json& version = root["version"];
    if (!version.is_number_integer() && !version.is_number_unsigned()) {
        rd.fail("version", "expected an integer, got " + typeName(version));
    }
    if (version.get<long long>() != 1) {
        rd.fail("version",
                "unsupported version " + version.dump() + " (this build reads version 1)");
    }
    if (!root.contains("curves")) rd.fail("curves", "missing (an array of curves)");
    const json& curves = root["curves"];
    if (!curves.is_array()) rd.fail("curves", "expected an array, got " + typeName(curves));
    if (curves.empty()) rd.fail("curves", "no curves: the network is empty");
    if (curves.size() > kMaxCurves) {
        rd.fail("curves",
                std::to_string(curves.size()) + " curves; limit is " + std::to_string(kMaxCurves));
    }
    return curves;
}

// A curve's name and profile (the width is read with its vertices).
CurveInfo curveInfo(const json& c, const std::string& el, const Reader& rd) {
    CurveInfo info;
    if (c.contains("name")) {
        const json& v = c["name"];
        if (!v.is_string()) rd.fail(el + ".name", "expected a string, got " + typeName(v));
        info.name = v.get<std::string>();
        if (info.name.size() > kMaxNameBytes) {
            rd.fail(el + ".name", "longer than " + std::to_string(kMaxNameBytes) + " bytes");
        }
    }
    if (c.contains("profile")) {
        const json& v = c["profile"];
        if (!v.is_string())
            rd.fail(el + ".profile", "expected a profile name (string), got " + typeName(v));
        info.profile = v.get<std::string>();
        if (info.profile.empty() || info.profile.size() > kMaxProfileBytes) {
            rd.fail(el + ".profile", "profile name must have 1 to " +
                                         std::to_string(kMaxProfileBytes) + " characters");
        }
        for (char ch : info.profile) {
            const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                            (ch >= '0' && ch <= '9') || ch == '-' || ch == '_' || ch == '.' ||
                            ch == ':' || ch == ',';
            if (!ok)
                rd.fail(el + ".profile",
                        "profile name may use only letters, digits, '-', '_', '.', ':', ','");
        }
    }
    return info;
}

// Appends segments of one curve (the limit on their total is checked).
struct CurveBuilder {
    CurveNetwork& net;
    const Reader& rd;
    int curveIndex;

    void add(const Segment& s, const std::string& sel) {
        if (net.segments.size() >= kMaxSegments) {
            rd.fail(sel, "more than " + std::to_string(kMaxSegments) + " segments in the network");
        }
        net.segments.push_back(s);
    }
    Segment line(glm::dvec2 a, glm::dvec2 b) const {
        Segment s;
        s.kind = Segment::Kind::Line;
        s.p0 = a;
        s.p2 = b;
        s.p1 = 0.5 * (a + b);
        s.curve = curveIndex;
        return s;
    }
};

void readPolyline(const json& pts, const std::string& pel, CurveBuilder& cb) {
    const Reader& rd = cb.rd;
    if (!pts.is_array()) rd.fail(pel, "expected an array of points, got " + typeName(pts));
    if (pts.size() < 2)
        rd.fail(pel, "a polyline needs at least 2 points, got " + std::to_string(pts.size()));
    if (pts.size() - 1 > kMaxSegments) {
        rd.fail(pel,
                std::to_string(pts.size()) + " points; limit is " + std::to_string(kMaxSegments));
    }
    glm::dvec2 prev = rd.point(pts[0], pel + "[0]");
    for (std::size_t i = 1; i < pts.size(); ++i) {
        const std::string iel = pel + "[" + std::to_string(i) + "]";
        const glm::dvec2 p = rd.point(pts[i], iel);
        if (p == prev) rd.fail(iel, "coincides with the previous point (zero-length line segment)");
        cb.add(cb.line(prev, p), iel);
        prev = p;
    }
}

// One {"line": [p0, p2]} or {"quad": [p0, p1, p2]} entry.
Segment readSegment(const json& s, const std::string& sel, const CurveBuilder& cb) {
    const Reader& rd = cb.rd;
    if (!s.is_object())
        rd.fail(sel, "expected an object {\"line\": ...} or {\"quad\": ...}, got " + typeName(s));
    rd.checkKeys(s, sel, {"line", "quad"});
    const bool isLine = s.contains("line"), isQuad = s.contains("quad");
    if (isLine == isQuad)
        rd.fail(sel, isLine ? "has both \"line\" and \"quad\"" : "needs \"line\" or \"quad\"");
    const std::string key = isLine ? "line" : "quad";
    const std::string kel = sel + "." + key;
    const json& p = s[key];
    const std::size_t want = isLine ? 2 : 3;
    if (!p.is_array() || p.size() != want) {
        rd.fail(kel, "expected " + std::to_string(want) + " points, got " +
                         (p.is_array() ? std::to_string(p.size()) + " entries" : typeName(p)));
    }
    glm::dvec2 q[3];
    for (std::size_t k = 0; k < want; ++k)
        q[k] = rd.point(p[k], kel + "[" + std::to_string(k) + "]");
    if (isLine) {
        if (q[0] == q[1]) rd.fail(kel, "both endpoints coincide (zero-length line segment)");
        return cb.line(q[0], q[1]);
    }
    if (q[0] == q[1] && q[1] == q[2])
        rd.fail(kel, "all three control points coincide (zero-length segment)");
    Segment seg;
    seg.kind = Segment::Kind::Quadratic;
    seg.p0 = q[0];
    seg.p1 = q[1];
    seg.p2 = q[2];
    seg.curve = cb.curveIndex;
    return seg;
}

void readSegments(const json& segs, const std::string& sel0, CurveBuilder& cb) {
    const Reader& rd = cb.rd;
    if (!segs.is_array()) rd.fail(sel0, "expected an array of segments, got " + typeName(segs));
    if (segs.empty()) rd.fail(sel0, "a curve needs at least 1 segment");
    if (segs.size() > kMaxSegments) {
        rd.fail(sel0, std::to_string(segs.size()) + " segments; limit is " +
                          std::to_string(kMaxSegments));
    }
    for (std::size_t i = 0; i < segs.size(); ++i) {
        const std::string sel = sel0 + "[" + std::to_string(i) + "]";
        const Segment seg = readSegment(segs[i], sel, cb);
        if (i > 0 && cb.net.segments.back().p2 != seg.p0) {
            std::ostringstream m;
            m.precision(17);
            m << "starts at (" << seg.p0.x << ", " << seg.p0.y
              << ") but the previous segment ends at (" << cb.net.segments.back().p2.x << ", "
              << cb.net.segments.back().p2.y
              << "); segments of one curve must connect exactly (put separate pieces in separate "
                 "curves)";
            rd.fail(sel + "." + (seg.kind == Segment::Kind::Line ? "line" : "quad") + "[0]",
                    m.str());
        }
        cb.add(seg, sel);
    }
}

// "width": a number (the curve's width) or one per vertex (points: one per
// point; segments: one per segment start plus the last end), linear along
// each segment; a closing line runs from the last vertex's width to the
// first's. Every width > 0, in input units.
void readWidths(const json& c, const std::string& el, std::size_t firstSeg, std::size_t vertices,
                CurveInfo& info, CurveNetwork& net, const Reader& rd) {
    if (!c.contains("width")) return;
    const json& w = c["width"];
    const std::string wel = el + ".width";
    if (!w.is_array()) {
        info.width = rd.number(w, wel);
        if (!(info.width > 0.0))
            rd.fail(wel, "must be > 0 (input units), got " + fmtNum(info.width));
        return;
    }
    if (w.size() != vertices) {
        rd.fail(wel, "expected one width per vertex (" + std::to_string(vertices) + "), got " +
                         std::to_string(w.size()));
    }
    std::vector<double> v(vertices);
    for (std::size_t i = 0; i < vertices; ++i) {
        const std::string iel = wel + "[" + std::to_string(i) + "]";
        v[i] = rd.number(w[i], iel);
        if (!(v[i] > 0.0)) rd.fail(iel, "must be > 0 (input units), got " + fmtNum(v[i]));
    }
    for (std::size_t k = firstSeg; k < net.segments.size(); ++k) {
        const std::size_t i = k - firstSeg;
        net.segments[k].width0 = v[std::min(i, vertices - 1)];
        net.segments[k].width1 = i + 1 < vertices ? v[i + 1] : v[0]; // the closing line
    }
}

// One entry of "curves": its segments and its CurveInfo.
void readCurve(const json& c, const std::string& el, CurveNetwork& net, const Reader& rd) {
    if (!c.is_object()) rd.fail(el, "expected an object, got " + typeName(c));
    rd.checkKeys(c, el, {"points", "segments", "name", "profile", "width", "closed"});
    CurveInfo info = curveInfo(c, el, rd);
    bool wantClosed = false;
    if (c.contains("closed")) {
        const json& v = c["closed"];
        if (!v.is_boolean()) rd.fail(el + ".closed", "expected true or false, got " + typeName(v));
        wantClosed = v.get<bool>();
    }
    const bool hasPoints = c.contains("points"), hasSegments = c.contains("segments");
    if (hasPoints == hasSegments) {
        rd.fail(el, hasPoints ? "has both \"points\" and \"segments\"; use one"
                              : "needs \"points\" (a polyline) or \"segments\"");
    }
    CurveBuilder cb{net, rd, int(net.curves.size())};
    const std::size_t firstSeg = net.segments.size();
    if (hasPoints)
        readPolyline(c["points"], el + ".points", cb);
    else
        readSegments(c["segments"], el + ".segments", cb);
    const std::size_t vertices = net.segments.size() - firstSeg + 1;
    const glm::dvec2 start = net.segments[firstSeg].p0, end = net.segments.back().p2;
    if (wantClosed && start != end) cb.add(cb.line(end, start), el + ".closed");
    readWidths(c, el, firstSeg, vertices, info, net, rd);
    info.closed = net.segments.back().p2 == start;
    net.curves.push_back(std::move(info));
}

} // namespace

CurveNetwork parseCurvesJson(std::string_view text, const std::string& source) {
    const json root = parseText(text, source);
    io::checkJsonKeysUnique(text, source);
    Reader rd(source);
    const json& curves = curvesOf(root, rd);
    CurveNetwork net;
    net.source = source;
    net.curves.reserve(curves.size());
    for (std::size_t ci = 0; ci < curves.size(); ++ci)
        readCurve(curves[ci], "curves[" + std::to_string(ci) + "]", net, rd);
    checkNetwork(net);
    return net;
}

CurveNetwork loadCurvesJson(const std::filesystem::path& file) {
    const std::string text = io::readFile(file, kMaxJsonBytes);
    return parseCurvesJson(text, file.string());
}

} // namespace sg::features
