// The bump-mapping frame: Mikkelsen, "Surface Gradient Based Bump Mapping
// Framework" (2019), section 2.11 listing 16 (pixel-shader prologue),
// section 2.10 (double-sided modes), section 2.2 (mikktspace-compliant basis
// rescaling), listing 17 (analytic dPdx/dPdy) and sections 2.11/3
// (re-prologue for post-resolve bump mapping).
//
// The paper keeps these values in static globals; here they live in an
// SgFrame value that the caller builds once per pixel and passes to every
// function (no GLSL globals, so the same source compiles as C++).
//
// Spaces: every vector in an SgFrame is in one common space, normally world
// space relative to the camera (listing 16's "relative world position": no
// translation enters the derivatives). Handedness does not matter to the
// frame: flipSign records the orientation of (dPdx, dPdy, nrmBase).
#ifndef SG_FRAME_GLSL
#define SG_FRAME_GLSL

#include "sg/compat.glsl"

// Double-sided modes (section 2.10) for back-facing fragments:
//  NONE   - the perturbed normal is the same as on the front side;
//  MIRROR - the base normal flips and the bump map is mirrored
//           (the surface gradient itself is unchanged);
//  FLIP   - the perturbed normal flips: exactly the negation of NONE's.
//           The frame stays the front side's (every layer sees what it
//           sees in NONE: a decal's angle fade, a parallax search's view
//           elevation) and sgResolve negates its result, which the paper
//           writes as base normal and gradient negated; sgReprologue takes
//           such a result back to the front side.
#define SG_BFACE_NONE 0
#define SG_BFACE_MIRROR 1
#define SG_BFACE_FLIP 2

struct SgFrame {
    vec3 nrmBase;      // unit base normal (negated on back faces in MIRROR)
    vec3 dPdx;         // d(position)/d(screen x), position units per pixel
    vec3 dPdy;         // d(position)/d(screen y), position units per pixel
    vec3 sigmaX;       // dPdx minus its component along nrmBase
    vec3 sigmaY;       // dPdy minus its component along nrmBase
    float flipSign;    // -1 when (dPdx, dPdy, nrmBase) is left-handed
    float resolveSign; // -1 only for back faces in FLIP mode: sgResolve negates
};

// Unit normal of the surface from its screen derivatives (cross(dPdx, dPdy)),
// or (0,0,1) when they are zero or parallel up to rounding: a replacement a
// caller may pass to sgPrologue for a degenerate interpolated vertex normal;
// its orientation follows the screen winding, not the mesh.
SG_FN vec3 sgGeometricNormal(vec3 dPdx, vec3 dPdy) {
    // Scale each derivative first so the cross product cannot overflow or
    // underflow (only the direction is used). The cross product of the
    // unit-max vectors has components of rounding size (a few FLT_EPSILON)
    // when they are parallel: its direction would be noise, so below
    // 8 FLT_EPSILON the fixed fallback is used instead.
    vec3 c = cross(sgScaleToUnitMax3(dPdx), sgScaleToUnitMax3(dPdy));
    if (!(sgMaxAbs3(c) >= 8.0f * SG_FLT_EPSILON)) return vec3(0.0f, 0.0f, 1.0f);
    return sgSafeNormalize(c, vec3(0.0f, 0.0f, 1.0f));
}

// Recomputes the tangent-plane projections and the orientation sign of a
// frame whose nrmBase, dPdx and dPdy are set (listing 16, last three lines).
// Denormal components of the derivatives are zero in every build
// (sgFlushDenorm3): a derivative of 1e-39 times one of 1e2 is a normal
// triple product whose sign a flushing GPU would not see. (The sigmas need
// no flush: the parity suites on a flushing stage pass without one.)
SG_FN SgFrame sgFrameUpdateSigmas(SgFrame f) {
    SgFrame r = f;
    r.dPdx = sgFlushDenorm3(f.dPdx);
    r.dPdy = sgFlushDenorm3(f.dPdy);
    r.sigmaX = r.dPdx - dot(r.dPdx, f.nrmBase) * f.nrmBase;
    r.sigmaY = r.dPdy - dot(r.dPdy, f.nrmBase) * f.nrmBase;
    // The triple product cannot overflow in the SG_BIG domain (|dPdx| |dPdy|
    // <= 3e36). A product below SG_FLT_MIN (derivatives below ~1e-19 per
    // pixel, or parallel ones) is a denormal that GPUs flush: it counts as
    // zero, giving flipSign = +1, in every build.
    float tp = dot(r.dPdy, cross(f.nrmBase, r.dPdx));
    r.flipSign = tp <= -SG_FLT_MIN ? -1.0f : 1.0f;
    return r;
}

// The prologue (listing 16) without vertex tangents.
//   vtxNormal  - interpolated vertex normal, NOT normalized (any length > 0;
//                a zero (or denormal) normal gives nrmBase = (0,0,1), so the
//                frame stays finite);
//   dPdx, dPdy - screen-space derivatives of the relative surface position
//                (dFdxFine/dFdyFine, or sgScreenDerivOfPos);
//   isFrontFacing, bfaceMode - gl_FrontFacing and one of SG_BFACE_*.
SG_FN SgFrame sgPrologue(vec3 vtxNormal, vec3 dPdx, vec3 dPdy, bool isFrontFacing, int bfaceMode) {
    SgFrame f;
    // A degenerate vertex normal falls back to (0,0,1), not to the geometric
    // normal of dPdx x dPdy: llvmpipe evaluates both sides of a select or
    // branch, and that fallback cost 3% of a per-pixel TBN frame on every
    // pixel (bench_bump_llvmpipe) for a case valid meshes never produce.
    // Callers that want it can pass sgGeometricNormal(dPdx, dPdy) themselves.
    vec3 nrm = sgSafeNormalize(vtxNormal, vec3(0.0f, 0.0f, 1.0f));
    bool isBackFace = !isFrontFacing;
    float fs = (isBackFace && bfaceMode == SG_BFACE_MIRROR) ? -1.0f : 1.0f;
    f.nrmBase = fs * nrm;
    f.resolveSign = (isBackFace && bfaceMode == SG_BFACE_FLIP) ? -1.0f : 1.0f;
    f.dPdx = dPdx;
    f.dPdy = dPdy;
    f.sigmaX = sgVec3(0.0f);
    f.sigmaY = sgVec3(0.0f);
    f.flipSign = 1.0f;
    return sgFrameUpdateSigmas(f);
}

// Reciprocal length of the interpolated vertex normal, the "renormFactor" of
// listing 16 (0 for a zero normal, which makes the mikktspace basis vanish
// instead of exploding).
SG_FN float sgRenormFactor(vec3 vtxNormal) {
    float m = sgMaxAbs3(vtxNormal);
    float rm = 1.0f / m;
    vec3 s = vtxNormal * rm;
    return (m >= SG_FLT_MIN && m <= SG_FLT_MAX) ? inversesqrt(dot(s, s)) * rm : 0.0f;
}

// Mikktspace-compliant vertex basis (section 2.2, listing 16): the
// interpolated, unnormalized tangent and the bitangent generated on the fly
// as sign(w) * cross(n, t), both scaled by 1/|n| of the interpolated vertex
// normal, so that sgSurfgradFromTBN with these vectors and a unit nrmBase
// reproduces exactly the classic unnormalized-TBN perturbed normal up to a
// positive scale that the resolve cancels.
//   vtxNormal  - interpolated vertex normal (unnormalized, as interpolated);
//   vtxTangent - interpolated vertex tangent xyz (unnormalized) and sign w.
// A zero (or denormal) vertex normal gives tang = bino = 0 (no bump). tang is
// |t| / |n| long, with 1/|n| clamped to SG_BIG.
SG_FN void sgMikktsBasis(vec3 vtxNormal, vec4 vtxTangent, SG_OUT(vec3) tang, SG_OUT(vec3) bino) {
    float renorm = sgRenormFactor(vtxNormal);
    float signW = vtxTangent.w > 0.0f ? 1.0f : -1.0f;
    vec3 t = vec3(vtxTangent.x, vtxTangent.y, vtxTangent.z);
    // cross(n, t) * renorm == cross(n * renorm, t): using the unit normal
    // keeps the product in range for any |n|.
    vec3 nUnit = vtxNormal * renorm;
    // 1/|n| is clamped to SG_BIG (|n| >= 1e-18), so |tang| <= |t| 1e18 stays
    // finite in the domain.
    tang = min(renorm, SG_BIG) * t;
    bino = signW * cross(nUnit, t);
}

// Re-prologue for post-resolve bump mapping (sections 2.11 and 3): after a
// first resolve, the resolved normal becomes the base of a second round of
// bump mapping. nrmBase, sigmaX/Y and flipSign are replaced; dPdx/dPdy are
// kept unless the caller supplies new ones (e.g. from sgScreenDerivOfPos for
// a virtual surface after parallax). resolvedNormal is what sgResolve
// returned with this frame (negated in FLIP mode): it is taken back to the
// front side, and resolveSign is kept, so the second round runs as in NONE
// and its resolve negates again.
SG_FN SgFrame sgReprologue(SgFrame f, vec3 resolvedNormal, vec3 dPdx, vec3 dPdy) {
    SgFrame r = f;
    r.nrmBase = sgSafeNormalize(f.resolveSign * resolvedNormal, f.nrmBase);
    r.dPdx = dPdx;
    r.dPdy = dPdy;
    return sgFrameUpdateSigmas(r);
}

// The frame with another base normal of the same side (e.g. section 2.6's
// normal correction after parallax: a moved base, not a resolved normal;
// any length, nrmBase kept when it vanishes). Derivatives and resolveSign
// are kept; sigmas and flipSign follow.
SG_FN SgFrame sgFrameWithBase(SgFrame f, vec3 nrmBase) {
    SgFrame r = f;
    r.nrmBase = sgSafeNormalize(nrmBase, f.nrmBase);
    return sgFrameUpdateSigmas(r);
}

// Analytic screen-space derivatives of the position (listing 17), for when
// dFdx/dFdy are unavailable or meaningless (compute shaders, POM, the CPU
// reference renderer): the derivative of the intersection of the pixel's
// view ray with the tangent plane (pos, norm).
//   invViewProjScr - maps screen (x in [0,w], y in [0,h], depth in [0,1], 1)
//                    to the space of pos and norm (column-major mat4), i.e.
//                    inverse(viewport * projection * view); perspective or
//                    orthographic, finite or infinite far plane;
//   x0, y0         - the fragment's window coordinate (pixel centre at .5).
// Results are in pos units per pixel. If the matrix is on normalized screen
// space [-1,1]^2 instead, scale dPdx by 2/width and dPdy by 2/height (and
// negate dPdy for a flipped y axis).
//
// Same quantity as the paper's listing, different evaluation order: the
// listing intersects in screen space, where depth is compressed (screen z
// -> 1 for distant points), and in binary32 it lost every digit for a
// camera with far/near = 1e6 (relative error 1e4 measured by the parity
// suite against binary64). Here the ray is written in world space as
// P = A + t D, with A the pixel's near-plane point (screen depth 0, well
// conditioned) and D = c2.xyz a.w - a.xyz c2.w its direction (a = the
// homogeneous near point, c2 = the matrix's depth column; D is the
// homogeneous difference of the far and near points, linear in a, so its
// screen derivatives are constant and D stays finite for an infinite far
// plane). With W = dA/dx + t dD/dx (the ray point at fixed t), the
// plane constraint gives dP/dx = W - D (n.W) / (n.D) (and the same for y).
//
// Robustness: the matrix is scaled to unit largest entry (homogeneous, so
// the result does not change) and D to unit largest component; a plane seen
// edge-on (n.D -> 0) has n.D clamped to FLT_EPSILON relative to |D| as the
// paper clamps its depth coefficient; all outputs are kept within SG_BIG. A
// zero normal, a zero matrix or a near point at infinity gives zeros.
SG_FN void sgScreenDerivOfPos(SG_OUT(vec3) dPdx, SG_OUT(vec3) dPdy, vec3 pos, vec3 norm,
                              mat4 invViewProjScr, float x0, float y0) {
    dPdx = sgVec3(0.0f);
    dPdy = sgVec3(0.0f);
    vec3 n = sgSafeNormalize(norm, sgVec3(0.0f));
    float mMax = max(max(sgMaxAbs4(invViewProjScr[0]), sgMaxAbs4(invViewProjScr[1])),
                     max(sgMaxAbs4(invViewProjScr[2]), sgMaxAbs4(invViewProjScr[3])));
    if (!(mMax >= SG_FLT_MIN) || !(mMax <= SG_FLT_MAX) || sgMaxAbs3(n) == 0.0f) return;
    mat4 m = invViewProjScr * (1.0f / mMax);
    vec4 c0 = m[0];
    vec4 c1 = m[1];
    vec4 c2 = m[2];
    // Homogeneous near-plane point of the pixel and its position.
    vec4 a = c0 * x0 + c1 * y0 + m[3];
    if (!(abs(a.w) >= SG_FLT_MIN)) return;
    float signW = a.w < 0.0f ? -1.0f : 1.0f;
    vec4 rcpW = vec4(1.0f / abs(a.w), 1.0f, 1.0f, 1.0f);
    vec3 nearPos = signW * sgBoundedScale3(vec3(a.x, a.y, a.z), rcpW);
    // d(nearPos)/dx = (c0.xyz - nearPos c0.w) / a.w, likewise for y.
    vec3 nearDx = signW * sgBoundedScale3(vec3(c0.x, c0.y, c0.z) - nearPos * c0.w, rcpW);
    vec3 nearDy = signW * sgBoundedScale3(vec3(c1.x, c1.y, c1.z) - nearPos * c1.w, rcpW);
    // Ray direction and its (constant) screen derivatives.
    vec3 c2xyz = vec3(c2.x, c2.y, c2.z);
    vec3 rayDir = c2xyz * a.w - vec3(a.x, a.y, a.z) * c2.w;
    vec3 rayDirDx = c2xyz * c0.w - vec3(c0.x, c0.y, c0.z) * c2.w;
    vec3 rayDirDy = c2xyz * c1.w - vec3(c1.x, c1.y, c1.z) * c2.w;
    float dMax = sgMaxAbs3(rayDir);
    if (!(dMax >= SG_FLT_MIN)) return;
    rayDir = rayDir / dMax;
    rayDirDx = rayDirDx / dMax;
    rayDirDy = rayDirDy / dMax;
    float rcpNDotD = sgSignedRcp(dot(n, rayDir));
    // Ray parameter of the intersection with the plane through pos.
    float t = dot(n, pos - nearPos) * rcpNDotD;
    vec3 wX = nearDx + t * rayDirDx;
    vec3 wY = nearDy + t * rayDirDy;
    dPdx = sgBoundedScale3(wX - rayDir * (dot(n, wX) * rcpNDotD), sgVec4(1.0f));
    dPdy = sgBoundedScale3(wY - rayDir * (dot(n, wY) * rcpNDotD), sgVec4(1.0f));
}

#endif
