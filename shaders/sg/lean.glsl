// Normal-map antialiasing from filtered slope moments. Loviscach, "Care and
// Feeding of Normal Vectors" (GDC 2008), "Care: Antialiasing (1)-(2)":
// average the resulting colours, not the normals; measure the spread of the
// normals from what a MIP level loses. Two measures:
//  - LEAN (Olano and Baker, "LEAN Mapping", I3D 2010, sections 3-4): the
//    first moments B = E[d] and second moments M = E[d d^T] of the slope
//    d = (dh/du, dh/dv) filter linearly (MIP maps, bilinear, anisotropic);
//    the covariance of the slopes within a footprint is M - B B^T;
//  - Toksvig ("Mipmapping Normal Maps", JGT 10(3), 2005): the average N of
//    unit normals shrinks with their spread; with a Gaussian spread of
//    variance s2 the length is |N| = 1 / (1 + s2), so s2 = (1 - |N|) / |N|,
//    and a Blinn-Phong lobe of exponent p becomes one of exponent
//    p / (1 + p s2).
// Slopes are the tangent-space normal's (sgTspaceNormalToDeriv): dimensionless,
// w.r.t. +s and +t, the same at every MIP level (a level averages the
// slopes of level 0; it does not rescale them). The file layout the
// `surfgrad normalmap mips` command writes is described in
// normalmap/include/surfgrad/normalmap/operations.h and docs/normalmap.md.
#ifndef SG_LEAN_GLSL
#define SG_LEAN_GLSL

#include "sg/compat.glsl"

// The second moments (d.x^2, d.y^2, d.x d.y) of one slope: with d itself,
// the five values a LEAN texel stores at level 0 (every level holds their
// box-filtered averages).
SG_FN vec3 sgLeanSecondMoments(vec2 d) { return vec3(d.x * d.x, d.y * d.y, d.x * d.y); }

// The covariance (var x, var y, cov xy) of the slopes in a footprint whose
// filtered moments are meanD = E[d] and second = E[(x^2, y^2, xy)].
// Rounding can make M - B B^T slightly indefinite where the slopes barely
// vary (|B|^2 >> variance): the variances are clamped to >= 0 and the
// covariance to |cov| <= sqrt(var x var y), so the result is always a valid
// (positive semi-definite) covariance.
// Variances below SG_FLT_MIN are 0 (a GPU flushes such denormals; the CPU
// then does the same), and the bound is sqrt(var x) sqrt(var y), which
// neither underflows nor overflows where the product would.
SG_FN vec3 sgLeanCovariance(vec2 meanD, vec3 second) {
    float vx = second.x - meanD.x * meanD.x;
    float vy = second.y - meanD.y * meanD.y;
    vx = vx >= SG_FLT_MIN ? vx : 0.0f;
    vy = vy >= SG_FLT_MIN ? vy : 0.0f;
    float c = second.z - meanD.x * meanD.y;
    float cMax = sqrt(vx) * sqrt(vy);
    return vec3(vx, vy, clamp(c, -cMax, cMax));
}

// Toksvig's variance s2 = (1 - |N|) / |N| of an average N of unit normals.
// |N| is clamped to [2^-20, 1]: rounding can make it slightly above 1 (s2 =
// 0 then), and an average that cancels to nothing (normals spread over the
// hemisphere and beyond) gives the finite s2 = 2^20 - 1, a fully rough lobe.
SG_FN float sgToksvigVariance(vec3 avgNormal) {
    float len = clamp(length(avgNormal), 9.5367432e-7f, 1.0f);
    return (1.0f - len) / len;
}

// Toksvig's factor: the exponent p of a Blinn-Phong lobe becomes
// p * sgToksvigFactor(s2, p) = p / (1 + p s2) (s2, p >= 0; negative values
// are treated as 0). In (0, 1].
SG_FN float sgToksvigFactor(float variance, float specPower) {
    return 1.0f / (1.0f + max(specPower, 0.0f) * max(variance, 0.0f));
}

#endif
