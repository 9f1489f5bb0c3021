// The "Feeding" operations of Loviscach, "Care and Feeding of Normal
// Vectors" (GDC 2008) on whole slope fields: scaling, adding and blending,
// modulation, curves and deformation. Per texel each is one shared function
// of shaders/sg/deriv_edit.glsl; this file supplies what a texel does not
// have: the heights, the neighbours of a mask or gain (central
// differences) and the resampling at a warped coordinate.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

#include "normalmap_internal.h"

namespace sg::normalmap {

namespace g = sg::glsl;
using detail::forRows;

DerivField scale(const DerivField& d, float alpha) {
    DerivField r(d.width, d.height);
    forRows(d.height, [&](int j) {
        for (int i = 0; i < d.width; ++i) r.at(i, j) = g::sgDerivScale(d.at(i, j), alpha);
    });
    return r;
}

DerivField add(const DerivField& a, float wa, const DerivField& b, float wb) {
    SG_NM_EXPECT_SAME_SIZE(a, b);
    DerivField r(a.width, a.height);
    forRows(a.height, [&](int j) {
        for (int i = 0; i < a.width; ++i)
            r.at(i, j) = g::sgDerivAdd(a.at(i, j), wa, b.at(i, j), wb);
    });
    return r;
}

DerivField blend(const DerivField& a, const ScalarField& ha, const DerivField& b,
                 const ScalarField& hb, const ScalarField& mask, Wrap wrap) {
    SG_NM_EXPECT_SAME_SIZE(a, b);
    SG_NM_EXPECT_SAME_SIZE(a, ha);
    SG_NM_EXPECT_SAME_SIZE(a, hb);
    SG_NM_EXPECT_SAME_SIZE(a, mask);
    DerivField r(a.width, a.height);
    forRows(a.height, [&](int j) {
        for (int i = 0; i < a.width; ++i) {
            r.at(i, j) = g::sgDerivMaskBlend(a.at(i, j), ha.at(i, j), b.at(i, j), hb.at(i, j),
                                             mask.at(i, j), detail::centralSlope(mask, i, j, wrap));
        }
    });
    return r;
}

DerivField modulate(const DerivField& d, const ScalarField& h, const ScalarField& gain, Wrap wrap) {
    SG_NM_EXPECT_SAME_SIZE(d, h);
    SG_NM_EXPECT_SAME_SIZE(d, gain);
    DerivField r(d.width, d.height);
    forRows(d.height, [&](int j) {
        for (int i = 0; i < d.width; ++i) {
            r.at(i, j) = g::sgDerivModulate(d.at(i, j), h.at(i, j),
                                            detail::centralSlope(gain, i, j, wrap), gain.at(i, j));
        }
    });
    return r;
}

namespace detail {

// The normalised elevation x = (h - min) / (max - min) of every texel
// (0 for a flat field).
ScalarField normalisedElevation(const ScalarField& h) {
    float lo = 0.0f, hi = 0.0f;
    if (h.size()) {
        auto [mn, mx] = std::minmax_element(h.v.begin(), h.v.end());
        lo = *mn;
        hi = *mx;
    }
    const float range = hi - lo;
    ScalarField x(h.width, h.height);
    const float inv = range > 0.0f ? 1.0f / range : 0.0f;
    for (size_t k = 0; k < h.size(); ++k) x.v[k] = (h.v[k] - lo) * inv;
    return x;
}

} // namespace detail

DerivField applyCurve(const DerivField& d, const ScalarField& h, const Curve& curve) {
    SG_NM_EXPECT_SAME_SIZE(d, h);
    const ScalarField x = detail::normalisedElevation(h);
    DerivField r(d.width, d.height);
    forRows(d.height, [&](int j) {
        for (int i = 0; i < d.width; ++i) {
            r.at(i, j) = g::sgDerivCurve(d.at(i, j), curve.slopeAt(x.at(i, j)));
        }
    });
    return r;
}

// ---------------------------------------------------------------------------
// Deformation

Warp parseWarp(std::string_view text) {
    auto fail = [&](const std::string& why) {
        throw io::InputError("--warp", std::string(text), why);
    };
    const size_t colon = text.find(':');
    if (colon == std::string_view::npos) fail("expected sine:A,B or rotate:DEG");
    const std::string_view kind = text.substr(0, colon), args = text.substr(colon + 1);
    std::vector<float> v;
    size_t pos = 0;
    while (pos <= args.size() && v.size() < 3) {
        size_t comma = args.find(',', pos);
        if (comma == std::string_view::npos) comma = args.size();
        const std::string_view tok = args.substr(pos, comma - pos);
        float x = 0.0f;
        auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), x);
        if (ec != std::errc() || p != tok.data() + tok.size() || !std::isfinite(x) ||
            std::abs(x) > 1e6f) {
            fail("\"" + std::string(tok) + "\" is not a number within +-1e6");
        }
        v.push_back(x);
        pos = comma + 1;
    }
    Warp w;
    if (kind == "sine" && v.size() == 2) {
        w.kind = Warp::Kind::Sine;
    } else if (kind == "rotate" && v.size() == 1) {
        w.kind = Warp::Kind::Rotate;
    } else {
        fail("expected sine:A,B (t = v + A sin(B u), normalised coordinates) or rotate:DEG");
    }
    w.a = v[0];
    w.b = v.size() > 1 ? v[1] : 0.0f;
    return w;
}

namespace detail {

// The warped sampling point of texel (i, j) in texel coordinates and the
// warp's Jacobian in texel units (column-major: columns d/du, d/dv).
glm::vec2 warpTexel(const Warp& w, int width, int height, int i, int j, glm::mat2& jac) {
    const float W = float(width), H = float(height);
    const glm::vec2 p(float(i) + 0.5f, float(j) + 0.5f);
    if (w.kind == Warp::Kind::Sine) {
        const float u = p.x / W;
        // Normalised Jacobian (shared), converted to texel units:
        // d(t_tex)/d(u_tex) = (H / W) dt/du.
        glm::mat2 jn = g::sgSineWarpJacobian(u, w.a, w.b);
        jac = glm::mat2(jn[0][0], jn[0][1] * (H / W), jn[1][0] * (W / H), jn[1][1]);
        return glm::vec2(p.x, p.y + H * w.a * std::sin(w.b * u));
    }
    // Content turned counter-clockwise by a degrees about the centre: the
    // sample point turns by -a; the Jacobian is that rotation.
    const float rad = -w.a * 3.14159265358979f / 180.0f, c = std::cos(rad), s = std::sin(rad);
    jac = glm::mat2(c, s, -s, c);
    const glm::vec2 centre(0.5f * W, 0.5f * H);
    return centre + jac * (p - centre);
}

} // namespace detail

DerivField deform(const DerivField& d, const Warp& warp, Wrap wrap) {
    DerivField r(d.width, d.height);
    forRows(d.height, [&](int j) {
        for (int i = 0; i < d.width; ++i) {
            glm::mat2 jac;
            const glm::vec2 st = detail::warpTexel(warp, d.width, d.height, i, j, jac);
            r.at(i, j) = g::sgDerivDeform(detail::sampleBilinear(d, st.x, st.y, wrap), jac);
        }
    });
    return r;
}

} // namespace sg::normalmap
