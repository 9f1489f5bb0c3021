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
//  FLIP   - the perturbed normal flips (base normal and gradient negated).
#define SG_BFACE_NONE 0
#define SG_BFACE_MIRROR 1
#define SG_BFACE_FLIP 2

struct SgFrame {
    vec3 nrmBase;      // unit base normal (negated on back faces in MIRROR/FLIP)
    vec3 dPdx;         // d(position)/d(screen x), position units per pixel
    vec3 dPdy;         // d(position)/d(screen y), position units per pixel
    vec3 sigmaX;       // dPdx minus its component along nrmBase
    vec3 sigmaY;       // dPdy minus its component along nrmBase
    float flipSign;    // -1 when (dPdx, dPdy, nrmBase) is left-handed
    float resolveSign; // -1 only for back faces in FLIP mode; used by sgResolve
};

// Unit normal of the surface from its screen derivatives (cross(dPdx, dPdy)),
// or (0,0,1) when they are parallel or zero. Used as the fallback when the
// interpolated vertex normal is degenerate; its orientation follows the
// screen winding, not the mesh.
SG_FN vec3 sgGeometricNormal(vec3 dPdx, vec3 dPdy) {
    // Scale each derivative first so the cross product cannot overflow or
    // underflow (only the direction is used).
    float mx = max(max(abs(dPdx.x), abs(dPdx.y)), abs(dPdx.z));
    float my = max(max(abs(dPdy.x), abs(dPdy.y)), abs(dPdy.z));
    vec3 ax = mx >= SG_FLT_MIN ? dPdx / mx : vec3(0.0f);
    vec3 ay = my >= SG_FLT_MIN ? dPdy / my : vec3(0.0f);
    return sgSafeNormalize(cross(ax, ay), vec3(0.0f, 0.0f, 1.0f));
}

// Recomputes the tangent-plane projections and the orientation sign of a
// frame whose nrmBase, dPdx and dPdy are set (listing 16, last three lines).
SG_FN SgFrame sgFrameUpdateSigmas(SgFrame f) {
    SgFrame r = f;
    r.sigmaX = f.dPdx - dot(f.dPdx, f.nrmBase) * f.nrmBase;
    r.sigmaY = f.dPdy - dot(f.dPdy, f.nrmBase) * f.nrmBase;
    r.flipSign = dot(f.dPdy, cross(f.nrmBase, f.dPdx)) < 0.0f ? -1.0f : 1.0f;
    return r;
}

// The prologue (listing 16) without vertex tangents.
//   vtxNormal  - interpolated vertex normal, NOT normalized (any length > 0;
//                a zero or non-finite normal falls back to the geometric
//                normal of dPdx x dPdy so the frame stays finite);
//   dPdx, dPdy - screen-space derivatives of the relative surface position
//                (dFdxFine/dFdyFine, or sgScreenDerivOfPos);
//   isFrontFacing, bfaceMode - gl_FrontFacing and one of SG_BFACE_*.
SG_FN SgFrame sgPrologue(vec3 vtxNormal, vec3 dPdx, vec3 dPdy, bool isFrontFacing, int bfaceMode) {
    SgFrame f;
    vec3 nrm = sgSafeNormalize(vtxNormal, sgGeometricNormal(dPdx, dPdy));
    bool isBackFace = !isFrontFacing;
    float fs = (isBackFace && bfaceMode != SG_BFACE_NONE) ? -1.0f : 1.0f;
    f.nrmBase = fs * nrm;
    f.resolveSign = (isBackFace && bfaceMode == SG_BFACE_FLIP) ? -1.0f : 1.0f;
    f.dPdx = dPdx;
    f.dPdy = dPdy;
    f.sigmaX = vec3(0.0f);
    f.sigmaY = vec3(0.0f);
    f.flipSign = 1.0f;
    return sgFrameUpdateSigmas(f);
}

// Reciprocal length of the interpolated vertex normal, the "renormFactor" of
// listing 16 (0 for a zero normal, which makes the mikktspace basis vanish
// instead of exploding).
SG_FN float sgRenormFactor(vec3 vtxNormal) {
    float m = max(max(abs(vtxNormal.x), abs(vtxNormal.y)), abs(vtxNormal.z));
    if (!(m >= SG_FLT_MIN) || !(m <= SG_FLT_MAX)) return 0.0f;
    vec3 s = vtxNormal / m;
    return inversesqrt(dot(s, s)) / m;
}

// Mikktspace-compliant vertex basis (section 2.2, listing 16): the
// interpolated, unnormalized tangent and the bitangent generated on the fly
// as sign(w) * cross(n, t), both scaled by 1/|n| of the interpolated vertex
// normal, so that sgSurfgradFromTBN with these vectors and a unit nrmBase
// reproduces exactly the classic unnormalized-TBN perturbed normal up to a
// positive scale that the resolve cancels.
//   vtxNormal  - interpolated vertex normal (unnormalized, as interpolated);
//   vtxTangent - interpolated vertex tangent xyz (unnormalized) and sign w.
SG_FN void sgMikktsBasis(vec3 vtxNormal, vec4 vtxTangent, SG_OUT(vec3) tang, SG_OUT(vec3) bino) {
    float renorm = sgRenormFactor(vtxNormal);
    float signW = vtxTangent.w > 0.0f ? 1.0f : -1.0f;
    vec3 t = vec3(vtxTangent.x, vtxTangent.y, vtxTangent.z);
    // cross(n, t) * renorm == cross(n * renorm, t): using the unit normal
    // keeps the product in range for any |n|.
    vec3 nUnit = vtxNormal * renorm;
    tang = renorm * t;
    bino = signW * cross(nUnit, t);
}

// Re-prologue for post-resolve bump mapping (sections 2.11 and 3): after a
// first resolve, the resolved normal becomes the base of a second round of
// bump mapping. nrmBase, sigmaX/Y and flipSign are replaced; dPdx/dPdy are
// kept unless the caller supplies new ones (e.g. from sgScreenDerivOfPos for
// a virtual surface after parallax). resolveSign is kept: in FLIP mode the
// second layer's heights flip too.
SG_FN SgFrame sgReprologue(SgFrame f, vec3 resolvedNormal, vec3 dPdx, vec3 dPdy) {
    SgFrame r = f;
    r.nrmBase = sgSafeNormalize(resolvedNormal, f.nrmBase);
    r.dPdx = dPdx;
    r.dPdy = dPdy;
    return sgFrameUpdateSigmas(r);
}

// Analytic screen-space derivatives of the position (listing 17), for when
// dFdx/dFdy are unavailable or meaningless (compute shaders, POM, the CPU
// reference renderer): intersects the pixel's neighbouring view rays with
// the tangent plane (pos, norm).
//   invViewProjScr - maps screen (x in [0,w], y in [0,h], depth in [0,1], 1)
//                    to the space of pos and norm (column-major mat4);
//   x0, y0         - the fragment's window coordinate (pixel centre at .5).
// When the plane is seen edge-on the depth coefficient is clamped away from
// zero (FLT_EPSILON, as in the paper), so the result stays finite.
SG_FN void sgScreenDerivOfPos(SG_OUT(vec3) dPdx, SG_OUT(vec3) dPdy, vec3 pos, vec3 norm,
                        mat4 invViewProjScr, float x0, float y0) {
    vec4 plane = vec4(norm.x, norm.y, norm.z, -dot(pos, norm));
    mat4 mT = transpose(invViewProjScr);
    vec4 planeScr = mT * plane;
    float sgn = planeScr.z < 0.0f ? -1.0f : 1.0f;
    float nz = sgn * max(SG_FLT_EPSILON, abs(planeScr.z));
    float ac = -planeScr.x / nz;
    float bc = -planeScr.y / nz;
    float dc = -planeScr.w / nz;
    // Columns of transpose(M) are the rows of M: the intersection point
    // (x, y, z(x, y), 1) maps to x*v0 + y*v1 + v2 in homogeneous coordinates.
    vec4 c2 = mT[2];
    vec4 v0 = mT[0] + ac * c2;
    vec4 v1 = mT[1] + bc * c2;
    vec4 v2 = mT[3] + dc * c2;
    vec4 ipw = v0 * x0 + v1 * y0 + v2;
    // Quotient rule on (ipw.xyz / ipw.w).
    float denom = max(SG_FLT_EPSILON, ipw.w * ipw.w);
    vec3 ipwXyz = vec3(ipw.x, ipw.y, ipw.z);
    dPdx = (vec3(v0.x, v0.y, v0.z) * ipw.w - ipwXyz * v0.w) / denom;
    dPdy = (vec3(v1.x, v1.y, v1.z) * ipw.w - ipwXyz * v1.w) / denom;
}

#endif
