// The naive comparison baseline: what image editors do to normal maps,
// operating on the encoded vectors channel by channel and renormalising
// (Loviscach 2008, "Scaling (1)": alpha = -1 does not invert the bump,
// alpha = 2 can turn normals inward; "Deformation (5)": the standard
// deformation). Not part of the shader library: nothing renders with these;
// docs/normalmap.md and the tests measure how far they are from the
// height-field-correct operations of ops.cpp.
#include <algorithm>
#include <cmath>

#include "normalmap_internal.h"

namespace sg::normalmap::naive {

namespace g = sg::glsl;
using detail::forRows;
using detail::kFlat;

namespace {

glm::vec3 unit(glm::vec3 v) {
    return g::sgSafeNormalize(v, kFlat);
}

template <class F>
NormalField perTexel(int w, int h, F&& f) {
    NormalField r(w, h);
    forRows(h, [&](int j) {
        for (int i = 0; i < w; ++i) r.at(i, j) = unit(f(i, j));
    });
    return r;
}

} // namespace

NormalField scale(const NormalField& n, float alpha) {
    return perTexel(n.width, n.height,
                    [&](int i, int j) { return alpha * n.at(i, j) + (1.0f - alpha) * kFlat; });
}

NormalField add(const NormalField& a, float wa, const NormalField& b, float wb) {
    SG_NM_EXPECT_SAME_SIZE(a, b);
    return perTexel(a.width, a.height, [&](int i, int j) {
        return kFlat + wa * (a.at(i, j) - kFlat) + wb * (b.at(i, j) - kFlat);
    });
}

NormalField blend(const NormalField& a, const NormalField& b, const ScalarField& mask) {
    SG_NM_EXPECT_SAME_SIZE(a, b);
    SG_NM_EXPECT_SAME_SIZE(a, mask);
    return perTexel(a.width, a.height, [&](int i, int j) {
        const float m = mask.at(i, j);
        return (1.0f - m) * a.at(i, j) + m * b.at(i, j);
    });
}

NormalField modulate(const NormalField& n, const ScalarField& gain) {
    SG_NM_EXPECT_SAME_SIZE(n, gain);
    return perTexel(n.width, n.height, [&](int i, int j) {
        const float k = gain.at(i, j);
        return k * n.at(i, j) + (1.0f - k) * kFlat;
    });
}

NormalField applyCurve(const NormalField& n, const ScalarField& h, const Curve& curve) {
    SG_NM_EXPECT_SAME_SIZE(n, h);
    const ScalarField x = detail::normalisedElevation(h);
    return perTexel(n.width, n.height, [&](int i, int j) {
        const float k = curve.slopeAt(x.at(i, j));
        return k * n.at(i, j) + (1.0f - k) * kFlat;
    });
}

NormalField deform(const NormalField& n, const Warp& warp, Wrap wrap) {
    return perTexel(n.width, n.height, [&](int i, int j) {
        glm::mat2 jac;
        const glm::vec2 st = detail::warpTexel(warp, n.width, n.height, i, j, jac);
        return detail::sampleBilinear(n, st.x, st.y, wrap);
    });
}

DerivField slopesFromNormals(const NormalField& n) {
    DerivField d(n.width, n.height);
    forRows(n.height, [&](int j) {
        for (int i = 0; i < n.width; ++i) d.at(i, j) = -glm::vec2(n.at(i, j).x, n.at(i, j).y);
    });
    return d;
}

} // namespace sg::normalmap::naive
