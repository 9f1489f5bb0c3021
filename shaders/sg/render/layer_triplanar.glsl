// Bump layer: triplanar projection of tangent-space normal maps as a volume
// bump map. Mikkelsen 2019, section 2.8: eq. 7, listing 13 (volume gradient
// of the three planar projections, handedness and origin conventions),
// listing 14 (blend weights from the base normal), listing 12 (projection to
// a surface gradient). Triplanar on an already perturbed normal (section 3,
// post-resolve groups) uses the group's base normal for the weights.
#ifndef SG_RENDER_LAYER_TRIPLANAR_GLSL
#define SG_RENDER_LAYER_TRIPLANAR_GLSL

#include "sg/render/common.glsl"

// Record r0 = (strength, scale, sharpness k, rightHanded);
// r1 = (encoding, flipV, 0, 0); r2 = (texShift xyz, 0). scale = texture
// repeats per domain unit. rightHanded: the x and y planes are sampled at
// (-z, y) and (x, -z), so their images are not mirrored in a right-handed
// space (section 2.8).
// texShift: the texture position of the domain's reference point x0
// (SgVolumeSpace: vs.pos = x - x0; the camera for world space, the object
// origin for object space), so that scale * x = scale * vs.pos + texShift.
// Packed in binary64 (layer_triplanar.cpp): world space with repeating maps
// fract(scale * x0), which differs from scale * x0 by whole repeats (the
// same texels) and keeps the sum small, so a domain far from the origin
// samples as precisely as one at it; world space with a clamped map
// scale * x0 itself, the absolute position (a clamped map shows its edge
// texels far out: no repeat to reduce by); object space 0.
struct SgTriplanarParams {
    float strength;
    float scale;
    float sharpness;
    bool rightHanded;
    int encoding;
    bool flipV;
    vec3 texShift;
};

SG_FN SgTriplanarParams sgUnpackTriplanar(vec4 r0, vec4 r1, vec4 r2) {
    SgTriplanarParams p;
    p.strength = r0.x;
    p.scale = r0.y;
    p.sharpness = r0.z;
    p.rightHanded = sgRecBool(r0.w);
    p.encoding = sgRecInt(r1.x);
    p.flipV = sgRecBool(r1.y);
    p.texShift = sgRecVec3(r2);
    return p;
}

// Texture-space position of the pixel's domain point: scale * x, as
// scale * vs.pos + texShift (see SgTriplanarParams). The planes sample two
// of its components each.
SG_FN vec3 sgTriplanarTexPos(SgVolumeSpace vs, SgTriplanarParams p) {
    return p.scale * vs.pos + p.texShift;
}

// texX/texY/texZ are the maps of the x, y and z planes (the same texture
// three times for a one-map triplanar).
SG_FN vec3 sgLayerTriplanar(SgFrame f, SgVolumeSpace vs, SgTriplanarParams p, sampler2D texX,
                            sampler2D texY, sampler2D texZ) {
    vec3 nDomain = sgSafeNormalize(vs.normalToDomain * f.nrmBase, f.nrmBase);
    vec3 w = sgTriplanarWeights(nDomain, p.sharpness);
    float zs = p.rightHanded ? -1.0f : 1.0f;
    vec3 q = sgTriplanarTexPos(vs, p);
    vec3 qx = p.scale * vs.dPdx;
    vec3 qy = p.scale * vs.dPdy;
    // A plane whose weight is 0 contributes nothing: skip its fetch.
    vec2 dX = sgVec2(0.0f);
    vec2 dY = sgVec2(0.0f);
    vec2 dZ = sgVec2(0.0f);
    if (w.x > 0.0f) {
        dX = sgSampleTspaceDeriv(texX, vec2(zs * q.z, q.y), vec2(zs * qx.z, qx.y),
                                 vec2(zs * qy.z, qy.y), p.encoding, p.flipV);
    }
    if (w.y > 0.0f) {
        dY = sgSampleTspaceDeriv(texY, vec2(q.x, zs * q.z), vec2(qx.x, zs * qx.z),
                                 vec2(qy.x, zs * qy.z), p.encoding, p.flipV);
    }
    if (w.z > 0.0f) {
        dZ = sgSampleTspaceDeriv(texZ, vec2(q.x, q.y), vec2(qx.x, qx.y), vec2(qy.x, qy.y),
                                 p.encoding, p.flipV);
    }
    vec3 gradDomain = sgTriplanarVolumeGradient(w, dX, dY, dZ, p.rightHanded, false);
    return sgBumpScale(p.strength, sgSurfgradFromVolumeGradient(f, vs.gradToFrame * gradDomain));
}

#endif
