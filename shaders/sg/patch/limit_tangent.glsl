// The exact tangent frame of one UV set on the tessellated limit surface
// (the "limit" tangents of an adaptive mesh), from the patch derivatives,
// written once in the shared GLSL/C++ subset: the tessellation evaluation
// stage (sg/patch/patch_tes.glsl) and the CPU tessellator
// (render/src/patch_tessellation.cpp) call it with the same inputs.
//
// Math: the chain rule of a parametric surface P(u,v) carrying UVs
// (s,t)(u,v), both over the ptex face's (u,v) (sgPatchBasis returns the
// derivatives of the position patch and of the UV set's face-varying patch
// with respect to that same (u,v), each patch's own PatchParam depth scale
// applied):
//   [dP/du dP/dv] = [dP/ds dP/dt] J,   J = [[ds/du ds/dv], [dt/du dt/dv]]
//   => dP/ds = (dt/dv dP/du - dt/du dP/dv) / det J
// (Mikkelsen 2019, section 2.3 takes the same Jacobian from screen-space
// derivatives; here it is exact). The convention is the uniform path's
// TangentMethod::Limit (sg::mesh::limitTangent, surfgrad/mesh/tangents.h):
// vec4(T, w), T the unit vector along dP/ds in the tangent plane, w the
// sign of det J, bitangent = w * cross(N, T) (MikkTSpace's).
#ifndef SG_PATCH_LIMIT_TANGENT_GLSL
#define SG_PATCH_LIMIT_TANGENT_GLSL

#include "sg/compat.glsl"

// How sgPatchLimitTangent resolved a point (sg::mesh::LimitTangentCase's
// values).
#define SG_LIMIT_TANGENT_REGULAR 0
#define SG_LIMIT_TANGENT_DEGENERATE_UV 1
#define SG_LIMIT_TANGENT_DEGENERATE_SURFACE 2

// A chart is well conditioned when its determinant, relative to the square
// of its longer derivative, exceeds this (sg::mesh::limitTangent's
// threshold): the chain rule divides by it. For derivatives of equal length
// that is the sine of their angle; relative to the longer one, not to the
// product of the two lengths, because a derivative that is rounding noise
// (the UV chart of a planar projection's side walls: dST/dv ~ 1e-7 |st|)
// has a random direction: its sine says nothing, its length says it is
// noise.
#define SG_LIMIT_TANGENT_MIN_REL_DET 1.0e-3f

// v minus its component along unit n, normalized; zero when less than 1e-4
// of |v| is left (v along n up to binary32 rounding of the projection).
SG_FN vec3 sgTangentPart(vec3 v, vec3 n) {
    vec3 t = v - dot(v, n) * n;
    if (!(length(t) > 1.0e-4f * length(v))) return sgVec3(0.0f);
    return sgSafeNormalize(t, sgVec3(0.0f));
}

// Some unit vector orthogonal to unit n.
SG_FN vec3 sgAnyOrthogonal(vec3 n) {
    vec3 axis = abs(n.x) < 0.9f ? vec3(1.0f, 0.0f, 0.0f) : vec3(0.0f, 1.0f, 0.0f);
    return sgSafeNormalize(cross(n, axis), vec3(0.0f, 0.0f, 1.0f));
}

// The limit tangent of one UV set at a tessellated point: dPdu, dPdv the
// position patch's derivatives and dSTdu, dSTdv the UV set's face-varying
// patch's, all with respect to the same ptex (u,v) and taken on the same
// patch (the one whose UVs the point carries); unitNormal the point's
// output normal (object space, unit: on shared edges and corners the owner
// patch's, sg/patch/watertight.glsl, so the frame is the one the normal
// defines). Returns vec4(T, w): T unit, orthogonal to unitNormal, w = +-1.
// Any finite or non-finite input gives a finite, unit T.
//
// Scale-free: each chart is divided by its largest component first (dP/ds
// is needed only as a direction: det J's magnitude never divides), so
// derivatives from 1e-30 to 1e30 work. Cases (`resolved`; the per-point
// rules of sg::mesh::limitTangent, then the uniform path's final
// projection onto the vertex normal):
//  - Regular: both charts well conditioned (relative determinants above
//    SG_LIMIT_TANGENT_MIN_REL_DET): T = dP/ds made orthogonal to unitNormal,
//    w = sign(det J);
//  - DegenerateUv (zero-area or collapsed UVs, det J near 0): T = dP/du
//    made orthogonal to unitNormal (dP/dv if that leaves nothing), w = +1;
//  - DegenerateSurface (dP/du, dP/dv parallel or zero, e.g. a collapsed
//    cage): dP/ds if the UV chart is regular (w = sign(det J)), else dP/du,
//    else dP/dv (w = +1), made orthogonal to unitNormal.
// Whatever is left with no direction (everything along the normal, or all
// zero): any unit vector orthogonal to unitNormal. The uniform path also
// replaces a non-regular point's tangent by the mean of its regular
// neighbours (generateLimitTangents); a tessellated point has no
// neighbour list, so it keeps this per-point rule.
SG_FN vec4 sgPatchLimitTangent(vec3 dPdu, vec3 dPdv, vec2 dSTdu, vec2 dSTdv, vec3 unitNormal,
                               SG_OUT(int) resolved) {
    float kP = max(sgMaxAbs3(dPdu), sgMaxAbs3(dPdv));
    bool finiteP = kP >= SG_FLT_MIN && kP <= SG_FLT_MAX;
    vec3 pu = finiteP ? sgDivScale3(dPdu, kP) : sgVec3(0.0f);
    vec3 pv = finiteP ? sgDivScale3(dPdv, kP) : sgVec3(0.0f);
    float kJ = max(sgMaxAbs2(dSTdu), sgMaxAbs2(dSTdv));
    bool finiteJ = kJ >= SG_FLT_MIN && kJ <= SG_FLT_MAX;
    vec2 ju = finiteJ ? sgDivScale2(dSTdu, kJ) : sgVec2(0.0f);
    vec2 jv = finiteJ ? sgDivScale2(dSTdv, kJ) : sgVec2(0.0f);
    // J = [[a b], [c d]] = [[ds/du ds/dv], [dt/du dt/dv]], entries <= 1.
    float a = ju.x, b = jv.x, c = ju.y, d = jv.y;
    float det = a * d - b * c;
    bool uvRegular = abs(det) > SG_LIMIT_TANGENT_MIN_REL_DET * max(dot(ju, ju), dot(jv, jv));
    bool surfaceRegular =
        length(cross(pu, pv)) > SG_LIMIT_TANGENT_MIN_REL_DET * max(dot(pu, pu), dot(pv, pv));
    float w = uvRegular && det < 0.0f ? -1.0f : 1.0f;
    // Along dP/ds: (d pu - c pv) / det, without the division.
    vec3 dPds = uvRegular ? w * (d * pu - c * pv) : sgVec3(0.0f);
    vec3 t = sgTangentPart(dPds, unitNormal);
    resolved = surfaceRegular ? SG_LIMIT_TANGENT_REGULAR : SG_LIMIT_TANGENT_DEGENERATE_SURFACE;
    if (sgIsZero3(t)) {
        if (surfaceRegular) resolved = SG_LIMIT_TANGENT_DEGENERATE_UV;
        t = sgTangentPart(pu, unitNormal);
        if (sgIsZero3(t)) t = sgTangentPart(pv, unitNormal);
        if (sgIsZero3(t)) t = sgAnyOrthogonal(unitNormal);
    }
    return vec4(t, w);
}

#endif // SG_PATCH_LIMIT_TANGENT_GLSL
