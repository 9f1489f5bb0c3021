// Internal to surfgrad_features: accumulates the outline primitives of a
// drawing (SVG shapes, glyph contours) in output coordinates, then turns
// them into a CurveNetwork once the drawing size, and so the approximation
// tolerance, is known. Shared by the SVG and font loaders so both give the
// same guarantees (surfgrad/features/curves.h): exact shared endpoints, no
// zero-length segments, closed == loop.
#pragma once

#include "surfgrad/features/curves.h"

#include <cstdint>
#include <string>
#include <vector>

namespace sg::features::detail {

class PathBuilder {
public:
    explicit PathBuilder(std::string source) : source_(std::move(source)) {}

    // Starts a subpath (a new curve) at p; ends the current one. `element`
    // names the input element for error messages.
    void moveTo(glm::dvec2 p, const CurveInfo& info, const std::string& element);
    // Drawing commands from the current point; each primitive starts at
    // exactly the current point and makes its end the current point.
    // Zero-length primitives are dropped. Need an open subpath.
    void lineTo(glm::dvec2 p);
    void quadTo(glm::dvec2 c, glm::dvec2 p);
    void cubicTo(glm::dvec2 c1, glm::dvec2 c2, glm::dvec2 p);
    // arc.start must be the current point; arc.end becomes it.
    void arcTo(const ArcParams& arc);
    // Closes the subpath with a line back to its start (if not there) and
    // ends it; the current point becomes the start.
    void close();
    // Ends the subpath without closing.
    void endSubpath();

    bool hasSubpath() const { return open_; }
    glm::dvec2 current() const { return cur_; }
    glm::dvec2 subpathStart() const { return start_; }

    // Converts everything into a network (approximating cubics and arcs
    // within opt's tolerance relative to the control-point bounds of all
    // primitives), drops curves left without segments, and checks the
    // result (checkNetwork). `emptyReason` is the message when nothing is
    // left. If maxError is given it receives the largest approximation
    // bound used (0 when there was nothing to approximate).
    CurveNetwork finish(const ApproxOptions& opt, const std::string& emptyReason,
                        double* maxError = nullptr);

private:
    struct Prim {
        enum class Kind { Line, Quad, Cubic, Arc } kind;
        glm::dvec2 p[4];
        ArcParams arc;
        int curve;
    };
    void push(const Prim& p);

    std::string source_;
    std::vector<Prim> prims_;
    std::vector<CurveInfo> curves_;
    std::vector<std::string> curveElement_;
    bool open_ = false;
    glm::dvec2 start_{0.0}, cur_{0.0};
};

// Appends code point cp (<= 0x10FFFF, not a surrogate: callers pass decoded
// text) to out as UTF-8; the loaders quote characters in error messages.
void appendUtf8(std::string& out, std::uint32_t cp);

} // namespace sg::features::detail
