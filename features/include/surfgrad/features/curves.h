// Feature-curve networks: the input of the feature-curve normal maps of
// Parilov, Rosenberg, Zorin (2005) and Parilov, Zorin (2008).
//
// A network is a list of segments, each a line or a quadratic Bezier, in the
// input's own coordinates (any units, y up; SVG input is flipped to y up).
// Segments of one curve share endpoints; curves may be open or closed and
// may meet at junctions of any valence. Loaders validate untrusted input and
// throw sg::io::InputError naming the file, element and reason.
//
// Loaders (JSON, SVG, fonts) and their guarantees. Every loader returns a
// network that passes checkNetwork():
//  - at least one segment; every coordinate finite with |c| <= kMaxAbsCoord;
//  - no segment has all three control points equal (zero-length); lines have
//    p1 == (p0 + p2) / 2 exactly;
//  - segments of one curve are stored consecutively, in curve order, and
//    segment k+1 starts at exactly (bit for bit) the point where segment k
//    ends, so junctions are found by exact comparison (findJunctions);
//  - CurveInfo::closed == true exactly when the curve's last segment ends at
//    exactly the point where its first segment starts (a loop);
//  - curve indices are 0..curves.size()-1 and every curve has >= 1 segment.
// Cubic Beziers (SVG C/S, CFF fonts) and elliptical arcs (SVG A, rounded
// rects, circles, ellipses) are approximated by quadratic Beziers whose
// Hausdorff distance to the original is at most the tolerance of
// ApproxOptions (proven bound, see appendCubicAsQuadratics), with
// tangent-continuous joints; details and the JSON schema are in
// docs/features-input.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

namespace sg::features {

struct Segment {
    enum class Kind { Line, Quadratic };
    Kind kind = Kind::Line;
    // Quadratic: B(t) = (1-t)^2 p0 + 2t(1-t) p1 + t^2 p2.
    // Line: endpoints p0 and p2, p1 = (p0 + p2) / 2 (a degenerate quadratic,
    // so code that handles quadratics handles lines).
    glm::dvec2 p0{0.0}, p1{0.0}, p2{0.0};
    int curve = 0; // index into CurveNetwork::curves
    // Profile width (input units) at p0 and p2, linear in between (per-vertex
    // widths of the JSON input); < 0 = the curve's width (CurveInfo::width).
    double width0 = -1.0, width1 = -1.0;
};

struct CurveInfo {
    std::string name;    // id from the input (SVG element id, JSON name, glyph), may be empty
    std::string profile; // profile name, empty = the layer's default
    double width = -1.0; // profile width in input units; < 0 = the layer's default
    bool closed = false;
};

struct CurveNetwork {
    std::vector<Segment> segments;
    std::vector<CurveInfo> curves;
    std::string source; // file the network came from (for messages)

    // Axis-aligned bounds of all control points; (0,0)-(0,0) when empty.
    void bounds(glm::dvec2& lo, glm::dvec2& hi) const;
};

// ---------------------------------------------------------------------------
// Limits on untrusted input (every loader enforces them before allocating).

inline constexpr std::size_t kMaxSegments = 4'000'000; // per network, after approximation
inline constexpr std::size_t kMaxCurves = 1'000'000;   // per network
inline constexpr double kMaxAbsCoord = 1e12;           // |x|, |y| in input units (after transforms)
inline constexpr std::size_t kMaxJsonBytes = std::size_t(256) << 20; // JSON file size
inline constexpr std::size_t kMaxSvgBytes = std::size_t(64) << 20;   // SVG file size
inline constexpr std::size_t kMaxFontBytes = std::size_t(256) << 20; // font file size
inline constexpr std::size_t kMaxTextCodepoints = 10'000;            // characters of font text

// ---------------------------------------------------------------------------
// Approximation of cubics and arcs by quadratics.

struct ApproxOptions {
    // Maximum Hausdorff distance between a cubic / elliptical arc and its
    // quadratic approximation, in input units (after transforms and the SVG
    // y flip; font units for fonts). When <= 0, the tolerance is
    // relativeTolerance * drawingSize, where drawingSize is the larger side
    // of the axis-aligned bounding box of the control points of the whole
    // input (arcs contribute the control points of their <= 90 degree
    // quadratic pieces). 1e-4 keeps the error at 0.1 texel for a drawing
    // fitted into a 1024^2 map, below the maps' reconstruction error.
    double tolerance = 0.0;
    double relativeTolerance = 1e-4;
};

// The absolute tolerance ApproxOptions selects for a drawing of the given
// size (larger side of its bounding box). Throws InputError (file = source)
// when the options are not finite, or the absolute tolerance is below
// 1e-9 * drawingSize (it would need absurd numbers of segments).
double resolveTolerance(const ApproxOptions& opt, double drawingSize, const std::string& source);

// Appends quadratic Beziers approximating the cubic Bezier c0..c3 to `out`,
// all with the given curve index. The first piece starts at exactly c0 and
// the last ends at exactly c3; consecutive pieces share endpoints exactly.
// Construction (proofs in curve_approx.cpp): the cubic is split at its
// inflections, then each piece becomes the quadratic whose control point is
// the intersection of the piece's end tangents, so joints are tangent
// continuous (G1); its Hausdorff distance to the piece is bounded
// rigorously through a reparametrized Bernstein convex hull, and pieces over
// the tolerance are bisected (adaptive subdivision). Pieces with parallel
// end tangents (straight runs) or still failing after 20 bisections (near
// cusps) use the midpoint construction q = (3 (b1 + b2) - b0 - b3) / 4 with
// its exact bound sqrt(3)/36 |b3 - 3 b2 + 3 b1 - b0| over n equal
// sub-pieces (these joints are only C0). Zero-length pieces are skipped.
// Returns the largest bound of the emitted pieces (<= tolerance). Throws
// InputError (file = source, element) when more than kMaxSegments segments
// would be needed. tolerance > 0.
double appendCubicAsQuadratics(glm::dvec2 c0, glm::dvec2 c1, glm::dvec2 c2, glm::dvec2 c3,
                               double tolerance, int curve, std::vector<Segment>& out,
                               const std::string& source = {}, const std::string& element = {});

// An elliptical arc as the affine image of a unit-circle arc:
//   P(angle) = center + axes * (cos angle, sin angle),
// angle from startAngle to startAngle + sweepAngle (radians, either sign,
// |sweepAngle| <= 2 pi). `axes` columns are the images of the circle's x and
// y axes (for an SVG ellipse: CTM * rotate(phi) * diag(rx, ry)).
// `start` / `end` are the exact endpoints to use (the caller's shared
// points; they equal P(start) and P(end) up to rounding).
struct ArcParams {
    glm::dvec2 center{0.0};
    glm::dvec2 axisX{1.0, 0.0}, axisY{0.0, 1.0}; // columns of `axes`
    double startAngle = 0.0, sweepAngle = 0.0;
    glm::dvec2 start{0.0}, end{0.0};
};

// Appends quadratic Beziers approximating the arc. Each of the n equal
// angular pieces (n >= ceil(|sweep| / 90 degrees)) is the affine image of
// the quadratic through the circle piece's endpoints whose control point is
// the intersection of the end tangents; for a circle piece of half-angle h
// its Hausdorff distance to the arc is exactly (cos h + 1/cos h)/2 - 1, so
// after the affine map it is at most ||axes||_2 times that. n is the smallest
// count with bound <= tolerance. Returns the bound reached. Throws like
// appendCubicAsQuadratics.
double appendArcAsQuadratics(const ArcParams& arc, double tolerance, int curve,
                             std::vector<Segment>& out, const std::string& source = {},
                             const std::string& element = {});

// The control points of arc's quadratic pieces of <= 90 degrees (a hull of
// the arc), used for the drawing size.
void arcHullPoints(const ArcParams& arc, std::vector<glm::dvec2>& out);

// ---------------------------------------------------------------------------
// Loaders. `source` / `file` names the input in error messages and becomes
// CurveNetwork::source.

// JSON curve network (schema: docs/features-input.md):
//   {"version": 1, "curves": [{"points": [[x, y], ...]} |
//                             {"segments": [{"line": [[x,y],[x,y]]} | {"quad":
//                             [[x,y],[x,y],[x,y]]}, ...]}, optional "name", "profile", "width",
//                             "closed"]}
// Errors name the element as "curves[4].points[2]" (or "line L column C" for
// syntax errors).
CurveNetwork parseCurvesJson(std::string_view text, const std::string& source);
CurveNetwork loadCurvesJson(const std::filesystem::path& file);

struct SvgOptions {
    ApproxOptions approx;
};

// SVG drawing: <path> (M L H V Q T C S A Z, absolute and relative), <line>,
// <polyline>, <polygon>, <rect> (rx/ry), <circle>, <ellipse>, in <svg>, <g>,
// <a>, <switch>; `transform` on every element. Fill and stroke are ignored:
// every shape's outline (its path) becomes a curve, one per subpath.
// Output coordinates: the root's user space (viewBox units) flipped to y up
// by y' = 2 minY + height - y for viewBox "minX minY width height" (the
// viewBox maps onto itself), or y' = height - y without a viewBox (height
// attribute, else 0). Errors name the element as "path #3 command 7 'A'"
// (elements numbered per tag, 1-based, in document order) or "line 12".
CurveNetwork parseSvg(std::string_view text, const std::string& source, const SvgOptions& opt = {});
CurveNetwork loadSvg(const std::filesystem::path& file, const SvgOptions& opt = {});

struct FontOptions {
    int faceIndex = 0; // face in a collection (.ttc/.otc); 0 for single fonts
    ApproxOptions approx;
};

// Glyph outlines of UTF-8 `text` in font units (FT_LOAD_NO_SCALE, no
// hinting, y up), laid out left to right from the origin on the baseline by
// the glyph advances plus the font's 'kern' table kerning when present
// (GPOS kerning and shaping are not applied); '\n' starts a new line one
// face height lower. One curve per contour, named "U+0041 'A' contour 0".
// TrueType conics are quadratic Beziers (implied on-curve points between
// consecutive conic controls are exact midpoints); CFF cubics are
// approximated within opt.approx. Errors name the element as "glyph U+4E2D"
// or "text byte 5".
CurveNetwork parseFont(const std::uint8_t* data, std::size_t size, std::string_view text,
                       const std::string& source, const FontOptions& opt = {});
CurveNetwork loadFont(const std::filesystem::path& file, std::string_view text,
                      const FontOptions& opt = {});

// ---------------------------------------------------------------------------
// Checks and structure.

// Throws InputError (file = net.source) unless `net` satisfies every
// guarantee listed at the top of this header. Cost O(segments). Useful for
// networks built in code.
void checkNetwork(const CurveNetwork& net);

// A point where segment ends meet (compared exactly, bit for bit).
struct Junction {
    glm::dvec2 pos{0.0};
    // Segment ends at pos: 2 * segmentIndex + (0 for p0, 1 for p2).
    std::vector<std::uint32_t> ends;
    int valence() const { return int(ends.size()); }
};

// Every distinct segment endpoint of the network with the segment ends that
// meet there, sorted by (x, y). Interior joints of a smooth curve have
// valence 2; open curve ends have valence 1; where curves cross or branch at
// a shared endpoint the valence is the number of incident segment ends.
// T-junctions (an endpoint lying inside another segment) and crossings away
// from endpoints are not reported. O(n log n) in the number of segments.
std::vector<Junction> findJunctions(const CurveNetwork& net);

} // namespace sg::features
