// Antialiased triplanar projection (layer kind triplanar with "antialias":
// "lean" or "toksvig"): each plane's slope distribution (mean and
// covariance within the pixel footprint, sg/render/slope_dist.glsl) is
// carried into the frame with the Jacobian that carries its derivative.
// Mikkelsen 2019, section 2.8: eq. 7 and listing 13 (the volume gradient is
// a weighted sum of the planes' derivatives placed on the domain axes),
// listing 12 (projection to a surface gradient); Olano and Baker 2010
// (LEAN); sg/render/antialias.glsl (the covariance of a surface gradient).
//
// The Jacobian of plane i: its derivative d_i enters the surface gradient as
//   g += strength * P * G * w_i * (d_i.x a_i + d_i.y b_i),
// a_i, b_i the domain axes of listing 13 (sgTriplanarPlaneAxes), G the
// domain-to-frame gradient map (SgVolumeSpace::gradToFrame), P = I - n n^T
// the projection of listing 12. So plane i adds J_i C_i J_i^T with
// J_i = strength * w_i * P G [a_i b_i].
//
// How the weights enter: w_i^2 (J_i carries w_i). The blend is not a
// mixture (a pixel does not show plane i with probability w_i) but the sum
// g = sum_i w_i J_i d_i at every point, and the three planes sample their
// maps at different coordinates of the domain, so within a footprint their
// slopes are uncorrelated: Var(sum w_i X_i) = sum w_i^2 Var(X_i). Equal
// weights (1/3) give a third of one plane's covariance: the blend of three
// uncorrelated maps is smoother than each. The weights' own variation
// within the footprint (where the base normal turns) is not modelled.
#ifndef SG_RENDER_LAYER_TRIPLANAR_AA_GLSL
#define SG_RENDER_LAYER_TRIPLANAR_AA_GLSL

#include "sg/render/antialias.glsl"
#include "sg/render/layer_triplanar.glsl"
#include "sg/render/slope_dist.glsl"

// Texture coordinates of plane `axis` (0 x, 1 y, 2 z) at domain point q
// (scaled): (zs q.z, q.y), (q.x, zs q.z), (q.x, q.y), zs = -1 in a
// right-handed domain (as sgLayerTriplanar samples). Linear in q, so it
// maps the screen derivatives too.
SG_FN vec2 sgTriplanarPlaneSt(int axis, vec3 q, bool rightHanded) {
    float zs = rightHanded ? -1.0f : 1.0f;
    if (axis == 0) return vec2(zs * q.z, q.y);
    if (axis == 1) return vec2(q.x, zs * q.z);
    return vec2(q.x, q.y);
}

// The domain axes a, b the derivative (d.x, d.y) of plane `axis` lands on in
// listing 13's volume gradient (sgTriplanarVolumeGradient, lower-left
// origin): x plane (zs e_z, e_y), y plane (e_x, zs e_z), z plane (e_x, e_y).
SG_FN void sgTriplanarPlaneAxes(int axis, bool rightHanded, SG_OUT(vec3) a, SG_OUT(vec3) b) {
    float zs = rightHanded ? -1.0f : 1.0f;
    if (axis == 0) {
        a = vec3(0.0f, 0.0f, zs);
        b = vec3(0.0f, 1.0f, 0.0f);
    } else if (axis == 1) {
        a = vec3(1.0f, 0.0f, 0.0f);
        b = vec3(0.0f, 0.0f, zs);
    } else {
        a = vec3(1.0f, 0.0f, 0.0f);
        b = vec3(0.0f, 1.0f, 0.0f);
    }
}

// The frame-space Jacobian columns of plane `axis` at weight w:
// strength * w * P G a, strength * w * P G b (see above).
SG_FN void sgTriplanarPlaneJacobian(SgFrame f, SgVolumeSpace vs, SgTriplanarParams p, int axis,
                                    float w, SG_OUT(vec3) ja, SG_OUT(vec3) jb) {
    vec3 a;
    vec3 b;
    sgTriplanarPlaneAxes(axis, p.rightHanded, a, b);
    float s = p.strength * w;
    ja = s * sgSurfgradFromVolumeGradient(f, vs.gradToFrame * a);
    jb = s * sgSurfgradFromVolumeGradient(f, vs.gradToFrame * b);
}

// One plane: its surface gradient (on the mean slope) and, added to
// slopeCov, its covariance J C J^T. A plane of weight 0 is not fetched.
SG_FN vec3 sgTriplanarPlaneAa(SgFrame f, SgVolumeSpace vs, SgTriplanarParams p, int mode,
                              int axis, float w, sampler2D texA, sampler2D texB,
                              SG_INOUT(mat3) slopeCov) {
    if (!(w > 0.0f)) return sgVec3(0.0f);
    vec2 st = sgTriplanarPlaneSt(axis, sgTriplanarTexPos(vs, p), p.rightHanded);
    vec2 dx = sgTriplanarPlaneSt(axis, p.scale * vs.dPdx, p.rightHanded);
    vec2 dy = sgTriplanarPlaneSt(axis, p.scale * vs.dPdy, p.rightHanded);
    SgSlopeDist s = sgSampleSlopes(mode, texA, texB, st, dx, dy, p.flipV);
    vec3 ja;
    vec3 jb;
    sgTriplanarPlaneJacobian(f, vs, p, axis, w, ja, jb);
    slopeCov = slopeCov + sgSlopeCovToFrame(s.cov, ja, jb);
    return s.mean.x * ja + s.mean.y * jb;
}

// The layer (mode SG_AA_LEAN: the planes' moment textures A and B;
// SG_AA_TOKSVIG: each plane's texture twice). The surface gradient equals
// sgLayerTriplanar's on the planes' mean slopes (listing 12 is linear).
SG_FN vec3 sgLayerTriplanarAa(SgFrame f, SgVolumeSpace vs, SgTriplanarParams p, int mode,
                              sampler2D texXA, sampler2D texXB, sampler2D texYA, sampler2D texYB,
                              sampler2D texZA, sampler2D texZB, SG_INOUT(mat3) slopeCov) {
    vec3 nDomain = sgSafeNormalize(vs.normalToDomain * f.nrmBase, f.nrmBase);
    vec3 w = sgTriplanarWeights(nDomain, p.sharpness);
    vec3 g = sgTriplanarPlaneAa(f, vs, p, mode, 0, w.x, texXA, texXB, slopeCov);
    g = g + sgTriplanarPlaneAa(f, vs, p, mode, 1, w.y, texYA, texYB, slopeCov);
    g = g + sgTriplanarPlaneAa(f, vs, p, mode, 2, w.z, texZA, texZB, slopeCov);
    return g;
}

#endif
