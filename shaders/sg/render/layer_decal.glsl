// Bump layer: decal projector, a volume bump map. Mikkelsen 2019, section
// 2.9, listing 15: the map is parallel-projected along the projector's -z
// axis, so its volume gradient is deriv.x * axisX + deriv.y * axisY; the
// projector's fall-off is applied as a bump scale (the paper's closing
// remark of section 2.9). The derivative is w.r.t. unit lengths along the
// axes (TBN style, as in listing 15): the bumps do not depend on the size.
#ifndef SG_RENDER_LAYER_DECAL_GLSL
#define SG_RENDER_LAYER_DECAL_GLSL

#include "sg/render/common.glsl"

// Records (all in frame space: world, relative to the camera):
//   r0 = (origin - camera, strength)
//   r1 = (unit axis x, half size x)     r2 = (unit axis y, half size y)
//   r3 = (unit axis z, half depth)      r4 = (depth fade width in [0,1],
//        cos of the angle where the angle fade starts, cos where it ends,
//        encoding)                      r5 = (flipV, 0, 0, 0)
// The box |x| <= 1, |y| <= 1, |z| <= 1 (local, size-normalized) receives the
// decal; it fades over the last `fadeWidth` of the depth, and with the angle
// between the base normal and +z from cosStart (full) to cosEnd (none).
struct SgDecalParams {
    vec3 origin;
    float strength;
    vec3 axisX;
    vec3 axisY;
    vec3 axisZ;
    vec3 halfSize;
    float fadeWidth;
    float cosStart;
    float cosEnd;
    int encoding;
    bool flipV;
};

SG_FN SgDecalParams sgUnpackDecal(vec4 r0, vec4 r1, vec4 r2, vec4 r3, vec4 r4, vec4 r5) {
    SgDecalParams p;
    p.origin = sgRecVec3(r0);
    p.strength = r0.w;
    p.axisX = sgRecVec3(r1);
    p.axisY = sgRecVec3(r2);
    p.axisZ = sgRecVec3(r3);
    p.halfSize = vec3(r1.w, r2.w, r3.w);
    p.fadeWidth = r4.x;
    p.cosStart = r4.y;
    p.cosEnd = r4.z;
    p.encoding = sgRecInt(r4.w);
    p.flipV = sgRecBool(r5.x);
    return p;
}

// The narrowest angle fade, in cosine (about 0.06 degrees at 90): a
// narrower [start, end] (e.g. [90, 90], "no angle fade") still ramps over
// this width below cosStart, so a decal whose projection direction lies in
// the surface does not switch on the rounding of dot(n, axisZ).
#define SG_DECAL_MIN_ANGLE_FADE 9.765625e-4f // 2^-10

// Fall-off of the projector at local position l (size-normalized) for a
// surface with base normal n: 0 outside the box, 1 in its core.
SG_FN float sgDecalFade(SgDecalParams p, vec3 l, vec3 n) {
    if (abs(l.x) > 1.0f || abs(l.y) > 1.0f || abs(l.z) > 1.0f) return 0.0f;
    float depthFade = 1.0f - smoothstep(1.0f - max(p.fadeWidth, 0.0f), 1.0f, abs(l.z));
    float c = dot(n, p.axisZ);
    float cosEnd = min(p.cosEnd, p.cosStart - SG_DECAL_MIN_ANGLE_FADE);
    float angleFade = clamp((c - cosEnd) / (p.cosStart - cosEnd), 0.0f, 1.0f);
    return depthFade * angleFade;
}

// The projector's half depth as the box uses it: at least 16 ulps of the
// positions it is measured between (relPos and the origin, relative to the
// camera). A box thinner than the rounding of the positions cannot say
// which side of it a surface lies on: a decal 1e-6 deep lying on a surface
// 3 units away would fade in and out with every rounding-size move of
// either; widened to the rounding, the surface stays in its core.
SG_FN float sgDecalHalfDepth(SgDecalParams p, vec3 relPos) {
    float roundingFloor = 16.0f * SG_FLT_EPSILON * (sgMaxAbs3(relPos) + sgMaxAbs3(p.origin));
    return max(max(p.halfSize.z, roundingFloor), SG_FLT_EPSILON);
}

// The pixel in the projector's box: l in [-1, 1]^3 inside, the fade (depth
// and angle), the map coordinate st and its screen derivatives by the chain
// rule (st changes by 0.5 / halfSize per unit along each axis). relPos: the
// pixel's position relative to the camera (frame space).
struct SgDecalHit {
    vec3 l;
    float fade;
    vec2 st;
    vec2 dSTdx;
    vec2 dSTdy;
};

SG_FN SgDecalHit sgDecalProject(SgFrame f, vec3 relPos, SgDecalParams p) {
    SgDecalHit h;
    vec3 r = relPos - p.origin;
    vec3 inv = sgVec3(1.0f) / max(vec3(p.halfSize.x, p.halfSize.y, sgDecalHalfDepth(p, relPos)),
                                sgVec3(SG_FLT_EPSILON));
    h.l = vec3(dot(r, p.axisX), dot(r, p.axisY), dot(r, p.axisZ)) * inv;
    h.fade = sgDecalFade(p, h.l, f.nrmBase);
    h.st = 0.5f * vec2(h.l.x, h.l.y) + sgVec2(0.5f);
    h.dSTdx = 0.5f * vec2(dot(f.dPdx, p.axisX) * inv.x, dot(f.dPdx, p.axisY) * inv.y);
    h.dSTdy = 0.5f * vec2(dot(f.dPdy, p.axisX) * inv.x, dot(f.dPdy, p.axisY) * inv.y);
    return h;
}

SG_FN vec3 sgLayerDecal(SgFrame f, vec3 relPos, SgDecalParams p, sampler2D tex) {
    SgDecalHit h = sgDecalProject(f, relPos, p);
    if (!(h.fade > 0.0f)) return sgVec3(0.0f);
    vec2 d = sgSampleTspaceDeriv(tex, h.st, h.dSTdx, h.dSTdy, p.encoding, p.flipV);
    return sgBumpScale(h.fade * p.strength, sgSurfgradFromDecal(f, d, p.axisX, p.axisY, false));
}

#endif
