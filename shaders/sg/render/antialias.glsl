// Bump antialiasing that survives composition: each layer contributes the
// covariance of its slopes within the pixel footprint, mapped into the
// common frame with the same Jacobian as its derivative; independent layers
// add their covariances, as they add their surface gradients (Mikkelsen
// 2019, section 3: "the surface gradients add"); the shading widens its
// lobe by the sum.
//
// Slope distributions per layer: LEAN (Olano and Baker, "LEAN Mapping", I3D
// 2010, sections 3-4) or Toksvig ("Mipmapping Normal Maps", JGT 2005), the
// moment math of sg/lean.glsl; Loviscach, "Care and Feeding of Normal
// Vectors" (GDC 2008), "Care: Antialiasing (1)-(2)".
//
// The covariance of a surface gradient g = d.x vT + d.y vB (listing 5) with
// d of covariance C (2x2) is J C J^T, J = [vT vB] (3x2): a symmetric 3x3
// matrix of the frame's space whose range lies in the tangent plane.
//
// Lobe widening: the renderer's BRDF (sg/render/shading.glsl) is isotropic
// GGX with alpha = roughness^2. A Beckmann lobe of parameter alpha has the
// slope variance alpha^2 / 2 per axis; convolving it with a slope
// distribution of covariance S gives alpha'^2 = alpha^2 + 2 s, s the
// per-axis variance. The BRDF being isotropic, s is the mean of the two
// principal variances, trace(S) / 2, so alpha'^2 = alpha^2 + trace(S)
// (the isotropic reading of the anisotropic widening; GGX is treated like
// Beckmann here, as LEAN and Toksvig do with their Blinn-Phong lobes).
#ifndef SG_RENDER_ANTIALIAS_GLSL
#define SG_RENDER_ANTIALIAS_GLSL

#include "sg/compat.glsl"

// SG_AA_COV_UNMAPPED (a study variant, never defined by the renderer's
// own plans; docs/accuracy-cost.md, table 8, "LEAN per layer"): what an
// engine without the composition does. Each layer's slope covariance stays
// in its own texture (or noise domain) space, with no Jacobian: no
// strength, no triplanar weight or projection, no decal fade or projector,
// no projection onto the tangent plane; its trace (var x + var y) is added
// as an isotropic variance. The result is a matrix with that trace, not a
// covariance in the tangent plane: only sgSlopeCovTrace reads it.
SG_FN mat3 sgSlopeCovUnmapped(float trace) { return sgMat3Diag(trace / 3.0f); }

// Frame-space covariance of d.x * a + d.y * b for a slope d of covariance
// cov2 = (var x, var y, cov xy). a, b: the layer's Jacobian columns (e.g.
// vT, vB of its UV frame, times its strength).
SG_FN mat3 sgSlopeCovToFrame(vec3 cov2, vec3 a, vec3 b) {
#ifdef SG_AA_COV_UNMAPPED
    return sgSlopeCovUnmapped(cov2.x + cov2.y);
#else
    return cov2.x * outerProduct(a, a) + cov2.y * outerProduct(b, b) +
           cov2.z * (outerProduct(a, b) + outerProduct(b, a));
#endif
}

// trace(S): the sum of the principal slope variances of S (>= 0 for a
// covariance; rounding can leave -0).
SG_FN float sgSlopeCovTrace(mat3 s) { return max(s[0][0] + s[1][1] + s[2][2], 0.0f); }

// GGX roughness widened by the frame-space slope covariance s of the bumps
// within the pixel: alpha'^2 = alpha^2 + trace(s), alpha = roughness^2 as
// sgShadeLight uses it (with its floor 0.002), returned as a roughness
// sqrt(alpha'). Finite for any finite s; an infinite trace gives roughness
// 1e4 (a flat lobe) rather than Inf.
SG_FN float sgAaRoughness(float roughness, mat3 s) {
    float a = max(roughness * roughness, 0.002f);
    float a2 = min(a * a + sgSlopeCovTrace(s), 1e16f);
    return sqrt(sqrt(a2));
}

#endif
