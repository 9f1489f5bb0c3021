// Height curves for the "Curves" operation (Loviscach 2008, "Curves
// (1)-(6)"): the paper's boost f'(h) = 1 / (1 + P (h - H)^2) or a curve
// through points, interpolated by monotone cubic Hermite segments whose
// slopes follow Fritsch and Carlson ("Monotone piecewise cubic
// interpolation", SIAM J. Numer. Anal. 17(2), 1980: the three-point
// initial slopes and the alpha^2 + beta^2 <= 9 limit). The text parser is
// fuzzed (tests/fuzz/fuzz_curve_points.cpp).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

#include "normalmap_internal.h"

namespace sg::normalmap {

namespace g = sg::glsl;

namespace {

constexpr size_t kMaxCurvePoints = 64;
constexpr size_t kMaxCurveText = 4096;
constexpr float kMinCurveGap = 1e-4f;
constexpr float kMaxCurveValue = 1e3f;

// Fritsch-Carlson slopes of points with strictly increasing x.
std::vector<float> monotoneSlopes(const std::vector<glm::vec2>& p) {
    const size_t n = p.size();
    std::vector<double> secant(n - 1), m(n);
    for (size_t k = 0; k + 1 < n; ++k) {
        secant[k] = (double(p[k + 1].y) - p[k].y) / (double(p[k + 1].x) - p[k].x);
    }
    m[0] = secant[0];
    m[n - 1] = secant[n - 2];
    for (size_t k = 1; k + 1 < n; ++k) {
        m[k] = secant[k - 1] * secant[k] <= 0.0 ? 0.0 : 0.5 * (secant[k - 1] + secant[k]);
    }
    for (size_t k = 0; k + 1 < n; ++k) {
        if (secant[k] == 0.0) {
            m[k] = m[k + 1] = 0.0;
            continue;
        }
        const double a = m[k] / secant[k], b = m[k + 1] / secant[k];
        const double r2 = a * a + b * b;
        if (r2 > 9.0) {
            const double t = 3.0 / std::sqrt(r2);
            m[k] = t * a * secant[k];
            m[k + 1] = t * b * secant[k];
        }
    }
    return std::vector<float>(m.begin(), m.end());
}

} // namespace

float Curve::slopeAt(float x) const {
    if (boost || points.size() < 2) return g::sgCurveBoostSlope(x, boostP, boostH);
    // The segment containing x (the first or last one beyond the ends).
    auto it = std::upper_bound(points.begin() + 1, points.end() - 1, x,
                               [](float v, const glm::vec2& q) { return v < q.x; });
    const size_t k = size_t(it - points.begin()) - 1;
    const glm::vec4 knots(points[k].x, points[k].y, points[k + 1].x, points[k + 1].y);
    return g::sgCurveHermite(x, knots, glm::vec2(slopes[k], slopes[k + 1])).y;
}

Curve boostCurve(float P, float H) {
    Curve c;
    c.boost = true;
    c.boostP = P;
    c.boostH = H;
    return c;
}

Curve parseCurvePoints(std::string_view text, const std::string& source) {
    if (text.size() > kMaxCurveText) {
        throw io::InputError(
            source, "", "curve text longer than " + std::to_string(kMaxCurveText) + " characters");
    }
    Curve c;
    c.boost = false;
    size_t pos = 0;
    auto isSep = [](char ch) {
        return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r' || ch == ';';
    };
    while (pos < text.size()) {
        while (pos < text.size() && isSep(text[pos])) ++pos;
        if (pos >= text.size()) break;
        size_t end = pos;
        while (end < text.size() && !isSep(text[end])) ++end;
        const std::string_view tok = text.substr(pos, end - pos);
        pos = end;
        const std::string element = "point " + std::to_string(c.points.size() + 1);
        if (c.points.size() == kMaxCurvePoints) {
            throw io::InputError(source, element,
                                 "more than " + std::to_string(kMaxCurvePoints) + " points");
        }
        const size_t comma = tok.find(',');
        if (comma == std::string_view::npos) {
            throw io::InputError(source, element, "\"" + std::string(tok) + "\" is not x,y");
        }
        float xy[2] = {0.0f, 0.0f};
        const std::string_view parts[2] = {tok.substr(0, comma), tok.substr(comma + 1)};
        for (int k = 0; k < 2; ++k) {
            auto [p, ec] =
                std::from_chars(parts[k].data(), parts[k].data() + parts[k].size(), xy[k]);
            if (parts[k].empty() || ec != std::errc() || p != parts[k].data() + parts[k].size() ||
                !std::isfinite(xy[k])) {
                throw io::InputError(source, element,
                                     "\"" + std::string(parts[k]) + "\" is not a finite number");
            }
        }
        if (!(xy[0] >= 0.0f && xy[0] <= 1.0f)) {
            throw io::InputError(source, element, "x must be in [0, 1] (normalised elevation)");
        }
        if (!(std::abs(xy[1]) <= kMaxCurveValue)) {
            throw io::InputError(source, element, "y must be within +-1000");
        }
        if (!c.points.empty() && !(xy[0] >= c.points.back().x + kMinCurveGap)) {
            throw io::InputError(source, element,
                                 "x must increase by at least 1e-4 from the previous point");
        }
        c.points.emplace_back(xy[0], xy[1]);
    }
    if (c.points.size() < 2) {
        throw io::InputError(source, "", "a curve needs at least 2 points (\"x,y x,y ...\")");
    }
    c.slopes = monotoneSlopes(c.points);
    return c;
}

} // namespace sg::normalmap
