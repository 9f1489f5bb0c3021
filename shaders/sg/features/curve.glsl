// Quadratic Bezier helpers of the feature-curve evaluator: evaluation,
// sub-curves (blossoming), the implicit form used by the side test (Parilov,
// Zorin 2008, section 5.2, Eq. 4) and line/curve intersection (section 5.3,
// Eq. 9-10). All positions are texel-local (see layout.glsl).
//
// A curve is B(u) = (1-u)^2 p0 + 2u(1-u) p1 + u^2 p2, u in [0, 1]. A straight
// segment is stored with curved = false (p1 is then the midpoint and is not
// used by the side test, which would degenerate: the resultant of Eq. 4
// vanishes identically for collinear control points).
#ifndef SG_FEATURES_CURVE_GLSL
#define SG_FEATURES_CURVE_GLSL

#include "sg/features/layout.glsl"

struct SgFeatCurve {
    vec2 p0;
    vec2 p1;
    vec2 p2;
    bool curved;
};

SG_FN SgFeatCurve sgFeatMakeCurve(vec2 p0, vec2 p1, vec2 p2, bool curved) {
    SgFeatCurve c;
    c.p0 = p0;
    c.p1 = p1;
    c.p2 = p2;
    c.curved = curved;
    return c;
}

SG_FN SgFeatCurve sgFeatMakeLine(vec2 p0, vec2 p2) {
    return sgFeatMakeCurve(p0, 0.5f * (p0 + p2), p2, false);
}

SG_FN SgFeatCurve sgFeatReverse(SgFeatCurve c) { return sgFeatMakeCurve(c.p2, c.p1, c.p0, c.curved); }

SG_FN float sgFeatCross(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }

SG_FN vec2 sgFeatCurvePoint(SgFeatCurve c, float u) {
    float v = 1.0f - u;
    return (v * v) * c.p0 + (2.0f * u * v) * c.p1 + (u * u) * c.p2;
}

// The curve restricted to [u0, u1] (u1 < u0 reverses it), by blossoming:
// control points B(u0), blossom(u0, u1), B(u1). Straight stays straight.
SG_FN SgFeatCurve sgFeatSubCurve(SgFeatCurve c, float u0, float u1) {
    vec2 mid = ((1.0f - u0) * (1.0f - u1)) * c.p0 + ((1.0f - u0) * u1 + u0 * (1.0f - u1)) * c.p1 +
               (u0 * u1) * c.p2;
    return sgFeatMakeCurve(sgFeatCurvePoint(c, u0), mid, sgFeatCurvePoint(c, u1), c.curved);
}

// Side function whose sign tells the two sides of the curve apart.
// Quadratic: the resultant of Eq. 4, Res[qx(s) - x; qy(s) - y] with
// q(s) = a s^2 + b s + p0, expanded in closed form:
//   (AF - CD)^2 - (AE - BD)(BF - CE)   for A s^2 + B s + C and D s^2 + E s + F.
// It vanishes on the whole parabola, so it separates the sides of the
// SEGMENT only where the parabola's other parts stay out of the texel: the
// bake guarantees that (Eq. 7 safety test, theta_min rule). Working with
// p0 - p keeps the terms O(size of the curve) instead of O(texel position).
// Straight: cross(p2 - p0, p - p0). Only the sign is meaningful; compare it
// with the sign at a reference point (sgFeatSameSide).
SG_FN float sgFeatImplicit(SgFeatCurve c, vec2 p) {
    vec2 r = p - c.p0;
    float lin = sgFeatCross(c.p2 - c.p0, r);
#if SG_FEAT_CURVED
    if (!c.curved) return lin;
    vec2 a = c.p0 - 2.0f * c.p1 + c.p2;
    vec2 b = 2.0f * (c.p1 - c.p0);
    vec2 cc = -r;
    float af = a.x * cc.y - cc.x * a.y;
    float ae = a.x * b.y - b.x * a.y;
    float bf = b.x * cc.y - cc.x * b.y;
    return af * af - ae * bf;
#else
    return lin;
#endif
}

// True when p is on the same side of the curve as ref (ref must lie off the
// curve; points on the curve count as the ref side).
SG_FN bool sgFeatSameSide(SgFeatCurve c, vec2 p, vec2 ref) {
    return (sgFeatImplicit(c, p) >= 0.0f) == (sgFeatImplicit(c, ref) >= 0.0f);
}

// Parameter of the point where the line o + lambda r meets the curve: the
// root u of cross(B(u) - o, r) = 0 that lies in [0, 1] (the bake ensures one
// such root: star-shaped or monotone triangles, section 5.3); with
// forwardOnly, roots behind o (lambda < 0) are not preferred. Returns the
// best candidate clamped to [0, 1]; never NaN for finite input.
SG_FN float sgFeatLineCurveParam(SgFeatCurve c, vec2 o, vec2 r, bool forwardOnly) {
    vec2 d0 = c.p0 - o;
    float den = sgFeatCross(c.p2 - c.p0, r);
    float uLine = abs(den) >= SG_FLT_MIN ? clamp(-sgFeatCross(d0, r) / den, 0.0f, 1.0f) : 0.5f;
#if SG_FEAT_CURVED
    if (!c.curved) return uLine;
    vec2 a = c.p0 - 2.0f * c.p1 + c.p2;
    vec2 b = 2.0f * (c.p1 - c.p0);
    float qa = sgFeatCross(a, r);
    float qb = sgFeatCross(b, r);
    float qc = sgFeatCross(d0, r);
    // Numerically stable roots: q = -(B + sign(B) sqrt(disc)) / 2,
    // u1 = q / A, u2 = C / q. A tangent line (disc < 0 by rounding) gives
    // the double root.
    float disc = max(qb * qb - 4.0f * qa * qc, 0.0f);
    float q = -0.5f * (qb + (qb < 0.0f ? -1.0f : 1.0f) * sqrt(disc));
    float u1 = abs(qa) > 1e-30f ? q / qa : 1e30f;
    float u2 = abs(q) > 1e-30f ? qc / q : (abs(qb) > 1e-30f ? -qc / qb : 0.5f);
    // Score: distance outside [0, 1], plus a penalty for points behind o.
    float s1 = max(max(-u1, u1 - 1.0f), 0.0f);
    float s2 = max(max(-u2, u2 - 1.0f), 0.0f);
    if (forwardOnly) {
        vec2 e1 = sgFeatCurvePoint(c, clamp(u1, 0.0f, 1.0f)) - o;
        vec2 e2 = sgFeatCurvePoint(c, clamp(u2, 0.0f, 1.0f)) - o;
        if (dot(e1, r) < 0.0f) s1 += 2.0f;
        if (dot(e2, r) < 0.0f) s2 += 2.0f;
    }
    return clamp(s1 <= s2 ? u1 : u2, 0.0f, 1.0f);
#else
    return uLine;
#endif
}

// Middle control point of the segment from q0 to q2 whose end tangents are
// the lines with unit directions t0 and t2: the intersection of the two
// tangent lines (appendix, step 2). ok = false when they are (nearly)
// parallel; the midpoint is returned then.
SG_FN vec2 sgFeatTangentIntersection(vec2 q0, vec2 t0, vec2 q2, vec2 t2, SG_OUT(bool) ok) {
    float den = sgFeatCross(t0, t2);
    ok = abs(den) > SG_FEAT_PARALLEL_SIN;
    if (!ok) return 0.5f * (q0 + q2);
    float alpha = sgFeatCross(q2 - q0, t2) / den;
    return q0 + alpha * t0;
}

#endif
