// Feature profiles and their composition with the base normal field:
// Parilov, Zorin (TOG 2008) section 3.1, Eq. 1 (= Parilov, Rosenberg, Zorin
// TR2005-872 Eq. 1), and the surface-gradient alternative of surfgrad.
//
// A profile is a height h(d) (texels) across the feature, a function of the
// reconstructed distance d (texels) and, for one-sided profiles, the side.
// Its slope h'(d) is dimensionless, so the texture-space derivative of the
// height is h'(d) * grad d, in the same units as the derivative the bump
// framework takes from a tangent-space normal map (sgTspaceNormalToDeriv):
// height and position both measured in texels (or both in uv units).
//
// The blend b(d) = smoothstep(w0, w, d) is 0 within w0 of the curve (the
// base map has no effect) and 1 beyond w (the profile has no effect).
//
// Two compositions:
//  - paper (sgFeatNormalPaper): Eq. 1 exactly, a blend of the profile's
//    normal with the base normal N (tangent space, unit):
//      Nxy' = -(1 - b) h' grad d + b~ Nxy,  Nz' = (1 - b) + b~ Nz,
//      b~ = b sqrt(h'^2 |grad d|^2 + 1), then normalized;
//  - surfgrad (sgFeatDeriv): the derivatives blend instead,
//      deriv = (1 - b) h' grad d + b baseDeriv,
//    and the renderer turns deriv into a surface gradient
//    (sgSurfgradFromTBN with sgGenBasisTB or the mikktspace basis) and adds
//    it to every other layer. Both give the same normal where b = 0 or 1;
//    inside the blend band the paper mode interpolates directions (Eq. 1
//    rescales N to the length of the profile normal first) while surfgrad
//    interpolates slopes; docs/features.md measures the difference.
#ifndef SG_FEATURES_PROFILE_GLSL
#define SG_FEATURES_PROFILE_GLSL

#include "sg/features/layout.glsl"

// Built-in profiles; t = d / w in [0, 1], D = depth (texels).
#define SG_FEAT_PROFILE_VGROOVE 0 // h = -D (1 - t): straight flanks, sharp at d = 0 and d = w
#define SG_FEAT_PROFILE_CREASE 1  // h = -D (1 - t)^2: sharp at the curve, tangent to the surface at w
#define SG_FEAT_PROFILE_RIDGE 2   // h = +D (1 - t)^2: a raised sharp ridge
#define SG_FEAT_PROFILE_STEP 3    // left: h = D (1 - (1 - t)^2); right: h = 0 (a cliff whose top edge is rounded)
#define SG_FEAT_PROFILE_SEAM 4    // h = -D (1 - sin(pi t / 2)): pillowed sides meeting in a sharp seam
#define SG_FEAT_PROFILE_TABLE 5   // user table (below)
#define SG_FEAT_PROFILE_COUNT 6
// Table profile: tableCount (2..SG_FEAT_TABLE_MAX) heights, in units of
// depth, at t = i / (tableCount - 1); Catmull-Rom between them (so h' is
// continuous), constant beyond t = 1.
#define SG_FEAT_TABLE_MAX 16

struct SgFeatProfile {
    int kind;      // SG_FEAT_PROFILE_*
    float depth;   // D, texels (may be negative: inverts the profile)
    float w0;      // half-width of the band where only the profile acts, texels
    float w;       // feature half-width, texels (> 0)
    int tableCount;
    float table[SG_FEAT_TABLE_MAX];
};

// Height h(d) (texels) and slope h'(d) of the profile at distance d >= 0.
SG_FN vec2 sgFeatProfileHeightSlope(SgFeatProfile pr, float d, float side) {
    float w = max(pr.w, 1e-6f);
    float t = clamp(d / w, 0.0f, 1.0f);
    float inside = d < w ? 1.0f : 0.0f;
    float dd = pr.depth;
    if (pr.kind == SG_FEAT_PROFILE_VGROOVE) {
        return vec2(-dd * (1.0f - t), inside * dd / w);
    }
    if (pr.kind == SG_FEAT_PROFILE_CREASE) {
        return vec2(-dd * (1.0f - t) * (1.0f - t), 2.0f * dd * (1.0f - t) / w);
    }
    if (pr.kind == SG_FEAT_PROFILE_RIDGE) {
        return vec2(dd * (1.0f - t) * (1.0f - t), -2.0f * dd * (1.0f - t) / w);
    }
    if (pr.kind == SG_FEAT_PROFILE_STEP) {
        if (side < 0.0f) return sgVec2(0.0f);
        return vec2(dd * (1.0f - (1.0f - t) * (1.0f - t)), 2.0f * dd * (1.0f - t) / w);
    }
    if (pr.kind == SG_FEAT_PROFILE_SEAM) {
        float a = 0.5f * SG_FEAT_PI;
        // (inside: cos(pi/2) is not exactly 0 in binary32.)
        return vec2(-dd * (1.0f - sin(a * t)), inside * dd * a * cos(a * t) / w);
    }
    // Table: uniform Catmull-Rom with one-sided end tangents.
    int n = clamp(pr.tableCount, 2, SG_FEAT_TABLE_MAX);
    float x = t * float(n - 1);
    int i = min(int(floor(x)), n - 2);
    float f = x - float(i);
    float h0 = pr.table[i];
    float h1 = pr.table[i + 1];
    float m0 = i > 0 ? 0.5f * (h1 - pr.table[i - 1]) : h1 - h0;
    float m1 = i + 2 < n ? 0.5f * (pr.table[i + 2] - h0) : h1 - h0;
    float f2 = f * f;
    float f3 = f2 * f;
    float h = (2.0f * f3 - 3.0f * f2 + 1.0f) * h0 + (f3 - 2.0f * f2 + f) * m0 + (-2.0f * f3 + 3.0f * f2) * h1 +
              (f3 - f2) * m1;
    float dh = (6.0f * f2 - 6.0f * f) * h0 + (3.0f * f2 - 4.0f * f + 1.0f) * m0 + (-6.0f * f2 + 6.0f * f) * h1 +
               (3.0f * f2 - 2.0f * f) * m1;
    return vec2(dd * h, inside * dd * dh * float(n - 1) / w);
}

// b(d): 0 for d <= w0, 1 for d >= w, smoothstep between.
SG_FN float sgFeatBlend(SgFeatProfile pr, float d) {
    if (!(pr.w > pr.w0)) return d > pr.w0 ? 1.0f : 0.0f;
    float x = clamp((d - pr.w0) / (pr.w - pr.w0), 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

// surfgrad mode: the texture-space derivative of the feature height blended
// with the base layer's derivative baseDeriv (pass vec2(0) to add the
// feature to the other layers instead of masking them). Unit-free slope,
// see the file header.
SG_FN vec2 sgFeatDeriv(SgFeatResult r, SgFeatProfile pr, vec2 baseDeriv) {
    float b = sgFeatBlend(pr, r.dist);
    float slope = sgFeatProfileHeightSlope(pr, r.dist, r.side).y;
    return (1.0f - b) * slope * r.grad + b * baseDeriv;
}

// paper mode: Eq. 1 with the base map's unit tangent-space normal
// baseNormal (z up); returns the unit tangent-space normal.
SG_FN vec3 sgFeatNormalPaper(SgFeatResult r, SgFeatProfile pr, vec3 baseNormal) {
    float b = sgFeatBlend(pr, r.dist);
    float slope = sgFeatProfileHeightSlope(pr, r.dist, r.side).y;
    float bt = b * sqrt(slope * slope * dot(r.grad, r.grad) + 1.0f);
    vec2 nxy = -(1.0f - b) * slope * r.grad + bt * vec2(baseNormal.x, baseNormal.y);
    float nz = (1.0f - b) + bt * baseNormal.z;
    return sgSafeNormalize(vec3(nxy.x, nxy.y, nz), vec3(0.0f, 0.0f, 1.0f));
}

// The unit tangent-space normal of a derivative: normalize(-d.x, -d.y, 1)
// (what the resolve of a surface gradient gives on a flat, unit-scaled
// frame); used to compare the two modes.
SG_FN vec3 sgFeatNormalFromDeriv(vec2 deriv) {
    return sgSafeNormalize(vec3(-deriv.x, -deriv.y, 1.0f), vec3(0.0f, 0.0f, 1.0f));
}

#endif
