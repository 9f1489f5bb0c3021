// Height-field-correct normal-map editing in derivative space: Loviscach,
// "Care and Feeding of Normal Vectors" (GDC 2008), "Feeding" slides.
// The central idea: apply each image operation to the (conceptual) height
// field h and compute the result from the normal map. With derivatives
// d = (dh/du, dh/dv) (sgTspaceNormalToDeriv) every operation is linear
// algebra on d, and the result feeds the surface-gradient framework
// (sgSurfgradFromTBN, sgSurfgradScaleDependent, ...) unchanged.
// All derivatives here share one (u, v) parametrization; heights h are in
// the same units as the derivatives' numerators.
#ifndef SG_DERIV_EDIT_GLSL
#define SG_DERIV_EDIT_GLSL

#include "sg/compat.glsl"

// Largest number of layers sgDerivBlend accepts.
#define SG_DERIV_MAX_LAYERS 8

// "Scaling (2)": the derivative of alpha * h. alpha = -1 inverts the bumps
// exactly; alpha = 2 doubles the slopes, and since the resolved normal is
// normalize(-d.x, -d.y, 1) its z stays positive: it never turns inward (the
// naive normal lerp does both wrong).
SG_FN vec2 sgDerivScale(vec2 d, float alpha) { return alpha * d; }

// "Adding and Blending (1)": the derivative of alpha * h1 + beta * h2.
SG_FN vec2 sgDerivAdd(vec2 d1, float alpha, vec2 d2, float beta) { return alpha * d1 + beta * d2; }

// k layers: sum_i w[i] * d[i] for i < count (count clamped to
// [0, SG_DERIV_MAX_LAYERS]). Weights summing to 1 give a blend, any weights
// an additive mix.
SG_FN vec2 sgDerivBlend(vec2 d[SG_DERIV_MAX_LAYERS], float w[SG_DERIV_MAX_LAYERS], int count) {
    vec2 sum = sgVec2(0.0f);
    int n = clamp(count, 0, SG_DERIV_MAX_LAYERS);
    for (int i = 0; i < n; ++i) sum += w[i] * d[i];
    return sum;
}

// "Modulation": the product h1 * h2 by the product rule,
// d(h1 h2) = d1 * h2 + h1 * d2. Needs both heights (e.g. a 4th channel).
SG_FN vec2 sgDerivModulate(vec2 d1, float h1, vec2 d2, float h2) { return d1 * h2 + h1 * d2; }

// "Curves (2)-(3)": the derivative of f(h) is f'(h) * d (chain rule).
SG_FN vec2 sgDerivCurve(vec2 d, float fPrimeAtH) { return fPrimeAtH * d; }

// "Curves (4)": a curve given by points (the paper's dependent texture
// lookup, evaluated exactly). One cubic Hermite segment through
// (knots.x, knots.y) and (knots.z, knots.w) with end slopes df/dx =
// slopes.x, slopes.y; returns (f(x), f'(x)). x is clamped to the segment, so
// beyond an end the end value and end slope are returned; the caller picks
// the segment (and the slopes, e.g. Fritsch-Carlson monotone ones). A
// segment shorter than SG_FLT_EPSILON has no finite slope: (knots.y, 0).
SG_FN vec2 sgCurveHermite(float x, vec4 knots, vec2 slopes) {
    float len = knots.z - knots.x;
    if (!(len >= SG_FLT_EPSILON)) return vec2(knots.y, 0.0f);
    float t = clamp((x - knots.x) / len, 0.0f, 1.0f);
    // The Hermite cubic written around the chord y0 + t (y1 - y0) with the
    // end slopes relative to the secant slope s: the same polynomial as the
    // usual basis-function sum, without its cancellation of large terms.
    float secant = (knots.w - knots.y) / len;
    float a = slopes.x - secant;
    float b = slopes.y - secant;
    float u = 1.0f - t;
    float f = knots.y + t * (knots.w - knots.y) + len * t * u * (u * a - t * b);
    float fPrime = secant + u * (1.0f - 3.0f * t) * a + t * (3.0f * t - 2.0f) * b;
    return vec2(f, fPrime);
}

// "Curves (5)": f'(h) = 1 / (1 + P (h - H)^2): boosts slopes of elevations
// near H; P >= 0 controls the width of the affected range.
// Written as 1 / (1 + q^2), q = sqrt(P) |h - H| clamped to SG_BIG, so the
// square cannot overflow (beyond the clamp the slope is below 1e-36).
SG_FN float sgCurveBoostSlope(float h, float boostP, float centreH) {
    // P below SG_FLT_MIN is 0 in every build (a flushing GPU reads 0; sqrt of
    // a denormal P times a huge |h - H| would not be small).
    float p = boostP >= SG_FLT_MIN ? boostP : 0.0f;
    float q = min(sqrt(p) * abs(h - centreH), SG_BIG);
    return 1.0f / (1.0f + q * q);
}

// The curve itself, f(h) = atan(sqrt(P) (h - H)) / sqrt(P) (f(H) = 0), so a
// curved height can be chained into sgDerivModulate. P = 0 is the identity
// h - H.
SG_FN float sgCurveBoostValue(float h, float boostP, float centreH) {
    float p = max(boostP, 0.0f);
    float x = h - centreH;
    if (p < SG_FLT_EPSILON) return x;
    float r = sqrt(p);
    return atan(r * x) / r;
}

// "Adding and Blending" with a spatially varying mask m (the blend of two
// height fields h = (1 - m) hA + m hB): by the product rule ("Modulation")
// d = (1 - m) dA + m dB + (hB - hA) dm, where dm is the mask's derivative.
// Without the last term (constant m) this is sgDerivAdd.
SG_FN vec2 sgDerivMaskBlend(vec2 dA, float hA, vec2 dB, float hB, float m, vec2 dm) {
    return sgDerivModulate(dA, hA, -dm, 1.0f - m) + sgDerivModulate(dB, hB, dm, m);
}

// "Birth: Shorthand: Partial Derivative": the derivative (dh/du, dh/dv) of a
// height sampled one texel left, right, below and above the texel, by
// central differences ((h(u + 1) - h(u - 1)) / 2, u in texels): the slope
// the normal map normalize(-dh/du, -dh/dv, 1) stores. Compare listing 9
// (sgHeightDeriv3Tap), the forward difference, which is half a texel off.
SG_FN vec2 sgHeightDerivCentral(float hLeft, float hRight, float hDown, float hUp) {
    return vec2(0.5f * (hRight - hLeft), 0.5f * (hUp - hDown));
}

// "Deformation (2)-(3)": h(s(u, v), t(u, v)) has the derivative
// J^T * d(s, t), where d is the map's derivative sampled at the warped
// coordinate and J = d(s, t)/d(u, v) is the warp's Jacobian as a column-major
// mat2: column 0 = (ds/du, dt/du), column 1 = (ds/dv, dt/dv).
SG_FN vec2 sgDerivDeform(vec2 dAtWarped, mat2 warpJacobian) {
    return vec2(dot(dAtWarped, warpJacobian[0]), dot(dAtWarped, warpJacobian[1]));
}

// "Deformation (4)": the Jacobian of the warp s = u, t = v + A sin(B u):
// dt/du = A B cos(B u). The slope A B is clamped to +-SG_BIG (so the
// deformed derivative stays finite) and cos to [-1, 1] (GPU cos of a huge
// phase has no accuracy guarantee; any value in [-1, 1] is as good).
SG_FN mat2 sgSineWarpJacobian(float u, float amplitudeA, float frequencyB) {
    float slope = clamp(amplitudeA * frequencyB, -SG_BIG, SG_BIG);
    float c = clamp(cos(frequencyB * u), -1.0f, 1.0f);
    return mat2(1.0f, slope * c, 0.0f, 1.0f);
}

#endif
