// Antialiased decal projector (layer kind decal with "antialias": "lean" or
// "toksvig"): the projected map's slope distribution (mean and covariance
// within the pixel footprint, sg/render/slope_dist.glsl) carried into the
// frame with the Jacobian that carries its derivative. Mikkelsen 2019,
// section 2.9, listing 15: the decal's derivative d enters the surface
// gradient as fade * strength * P (d.x axisX + d.y axisY), P = I - n n^T
// (listing 12), so the covariance C of d adds J C J^T with
// J = fade * strength * P [axisX axisY] (sg/render/antialias.glsl). The
// fade is treated as constant over the footprint.
#ifndef SG_RENDER_LAYER_DECAL_AA_GLSL
#define SG_RENDER_LAYER_DECAL_AA_GLSL

#include "sg/render/antialias.glsl"
#include "sg/render/layer_decal.glsl"
#include "sg/render/slope_dist.glsl"

// mode SG_AA_LEAN: the map's moment textures A and B; SG_AA_TOKSVIG: its
// Toksvig texture twice. The surface gradient equals sgLayerDecal's on the
// mean slope. A projector parallel to the surface (axisZ in the tangent
// plane) is faded out by the angle fade before anything is sampled.
SG_FN vec3 sgLayerDecalAa(SgFrame f, vec3 relPos, SgDecalParams p, int mode, sampler2D texA,
                          sampler2D texB, SG_INOUT(mat3) slopeCov) {
    SgDecalHit h = sgDecalProject(f, relPos, p);
    if (!(h.fade > 0.0f)) return sgVec3(0.0f);
    SgSlopeDist s = sgSampleSlopes(mode, texA, texB, h.st, h.dSTdx, h.dSTdy, p.flipV);
    float k = h.fade * p.strength;
    vec3 ja = k * sgSurfgradFromVolumeGradient(f, p.axisX);
    vec3 jb = k * sgSurfgradFromVolumeGradient(f, p.axisY);
    slopeCov = slopeCov + sgSlopeCovToFrame(s.cov, ja, jb);
    return s.mean.x * ja + s.mean.y * jb;
}

#endif
