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
// r1 = (encoding, flipV, 0, 0). scale = texture repeats per domain unit.
// rightHanded: the x and y planes are sampled at (-z, y) and (x, -z), so
// their images are not mirrored in a right-handed space (section 2.8).
struct SgTriplanarParams {
    float strength;
    float scale;
    float sharpness;
    bool rightHanded;
    int encoding;
    bool flipV;
};

SG_FN SgTriplanarParams sgUnpackTriplanar(vec4 r0, vec4 r1) {
    SgTriplanarParams p;
    p.strength = r0.x;
    p.scale = r0.y;
    p.sharpness = r0.z;
    p.rightHanded = sgRecBool(r0.w);
    p.encoding = sgRecInt(r1.x);
    p.flipV = sgRecBool(r1.y);
    return p;
}

// texX/texY/texZ are the maps of the x, y and z planes (the same texture
// three times for a one-map triplanar).
SG_FN vec3 sgLayerTriplanar(SgFrame f, SgVolumeSpace vs, SgTriplanarParams p, sampler2D texX,
                            sampler2D texY, sampler2D texZ) {
    vec3 nDomain = sgSafeNormalize(vs.normalToDomain * f.nrmBase, f.nrmBase);
    vec3 w = sgTriplanarWeights(nDomain, p.sharpness);
    float zs = p.rightHanded ? -1.0f : 1.0f;
    vec3 q = p.scale * vs.pos;
    vec3 qx = p.scale * vs.dPdx;
    vec3 qy = p.scale * vs.dPdy;
    // A plane whose weight is 0 contributes nothing: skip its fetch.
    vec2 dX = vec2(0.0f);
    vec2 dY = vec2(0.0f);
    vec2 dZ = vec2(0.0f);
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
