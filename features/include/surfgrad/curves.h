// Feature-curve networks: the input of the feature-curve normal maps of
// Parilov, Rosenberg, Zorin (2005) and Parilov, Zorin (2008).
//
// A network is a list of segments, each a line or a quadratic Bezier, in the
// input's own coordinates (any units, y up; SVG input is flipped to y up).
// Segments of one curve share endpoints; curves may be open or closed and
// may meet at junctions of any valence. Loaders validate untrusted input and
// throw sg::io::InputError naming the file, element and reason.
#pragma once

#include <filesystem>
#include <string>
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

} // namespace sg::features
