// Bump layer: object- or world-space normal map (the map stores the already
// perturbed normal). Mikkelsen 2019, section 2.4, listing 7: the perturbed
// normal becomes a surface gradient, so it scales (`strength`, listing 2)
// and adds to every other layer.
#ifndef SG_RENDER_LAYER_OBJECT_NORMAL_GLSL
#define SG_RENDER_LAYER_OBJECT_NORMAL_GLSL

#include "sg/render/common.glsl"

// Record r0 = (strength, encoding SG_ENC_RGB or SG_ENC_FLOAT, objectSpace, 0).
struct SgObjectNormalParams {
    float strength;
    int encoding;
    bool objectSpace;
};

SG_FN SgObjectNormalParams sgUnpackObjectNormal(vec4 r0) {
    SgObjectNormalParams p;
    p.strength = r0.x;
    p.encoding = sgRecInt(r0.y);
    p.objectSpace = sgRecBool(r0.z);
    return p;
}

// normalToFrame maps an object-space normal to frame (world) space: the
// inverse transpose of the model matrix's 3x3 part. Ignored for world-space
// maps. Only the direction of the decoded vector matters (listing 7).
SG_FN vec3 sgLayerObjectNormal(SgFrame f, SgUvFrame uv, SgObjectNormalParams p, mat3 normalToFrame,
                               sampler2D tex) {
    vec4 texel = textureGrad(tex, uv.st, uv.dSTdx, uv.dSTdy);
    vec3 v = sgDecodeNormalXYZ(texel, p.encoding);
    if (p.objectSpace) v = normalToFrame * v;
    return sgBumpScale(p.strength, sgSurfgradFromPerturbedNormal(f, v));
}

#endif
