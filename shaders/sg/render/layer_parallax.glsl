// Bump layers that move the surface: offset (parallax) mapping and parallax
// occlusion mapping on a height map. Mikkelsen 2019, section 2.6: the view
// direction goes to texture space through the true metric of the texture
// mapping (listing 10, sgProjectVecToTextureSpace), the chosen texture
// offset goes back to the tangent plane (listing 11,
// sgTexSpaceOffsToSurface) and, with the height at the corrected
// coordinate, gives the position of the virtual surface; section 3 and
// Fig. 3(c)-(d): later groups re-prologue on that virtual surface.
// Offset mapping with offset limiting is Welsh 2004 (section 4.3, the
// paper's skipProj); POM is a linear search with a secant refinement
// (Kaneko et al. 2001 and its steep-parallax descendants).
//
// Height convention: the mesh surface is the TOP of the relief (height 1)
// and the map's channel H in [0, 1] is the height of the relief, so the
// virtual surface is p + scale * (H(st) - 1) * nrmBase: the relief is carved
// below the mesh surface by scale * (1 - H), which keeps silhouettes and
// depth of the mesh valid. scale < 0 mirrors it above the surface.
//
// The corrected coordinate keeps the screen derivatives of the uncorrected
// one: every later sample reads textureGrad(tex, corrected st, dSTdx, dSTdy)
// and so the mip level of the coordinate BEFORE correction (section 3: a
// corrected coordinate is discontinuous at occlusion edges, its dFdx
// meaningless), so no seams appear at POM discontinuities.
#ifndef SG_RENDER_LAYER_PARALLAX_GLSL
#define SG_RENDER_LAYER_PARALLAX_GLSL

#include "sg/render/common.glsl"
#include "sg/render/layer_height.glsl"
#include "sg/surfgrad.glsl"

// Grazing views: the POM search vector is the offset-limited one (listing
// 10 with skipProj) divided by the view's elevation over the tangent plane,
// cos = dot(nrmBase, toEye); cos is clamped below to this value (about 87.1
// degrees from the normal), so the search is at most 20 times the
// offset-limited vector (which is itself bounded by scale times the texture
// metric): finite and bounded for edge-on and back-facing views.
#define SG_PARALLAX_MIN_ELEVATION 0.05f

// Record r0 = (scale, channel, steps, 0).
struct SgParallaxParams {
    float scale; // world units of relief per unit of the channel (depth of H = 0)
    int channel; // 0..3: r, g, b, a
    int steps;   // POM: linear search steps (clamped to [1, 1024]); parallax: unused
};

SG_FN SgParallaxParams sgUnpackParallax(vec4 r0) {
    SgParallaxParams p;
    p.scale = r0.x;
    p.channel = sgRecInt(r0.y);
    p.steps = sgRecInt(r0.z);
    return p;
}

// Records 1..4: the inverse of viewport * projection * view for the
// camera-relative space (sgScreenDerivOfPos's invViewProjScr), column i =
// (ci, ciw); the re-prologue on the virtual surface reads it.
struct SgScreenMatrix {
    vec3 c0;
    float c0w;
    vec3 c1;
    float c1w;
    vec3 c2;
    float c2w;
    vec3 c3;
    float c3w;
};

SG_FN SgScreenMatrix sgUnpackScreenMatrix(vec4 r0, vec4 r1, vec4 r2, vec4 r3) {
    SgScreenMatrix m;
    m.c0 = vec3(r0.x, r0.y, r0.z);
    m.c0w = r0.w;
    m.c1 = vec3(r1.x, r1.y, r1.z);
    m.c1w = r1.w;
    m.c2 = vec3(r2.x, r2.y, r2.z);
    m.c2w = r2.w;
    m.c3 = vec3(r3.x, r3.y, r3.z);
    m.c3w = r3.w;
    return m;
}

SG_FN mat4 sgScreenMatrixMat4(SgScreenMatrix m) {
    return mat4(vec4(m.c0, m.c0w), vec4(m.c1, m.c1w), vec4(m.c2, m.c2w), vec4(m.c3, m.c3w));
}

// The relief height H in [0, 1] (clamped: a float map may hold anything) at
// st with the LOD of the uncorrected coordinate's derivatives.
SG_FN float sgParallaxHeight(sampler2D tex, vec2 st, vec2 dSTdx, vec2 dSTdy, int channel) {
    return clamp(sgTexelChannel(textureGrad(tex, st, dSTdx, dSTdy), channel), 0.0f, 1.0f);
}

// The texture-space search vector: the st offset per unit of depth (1 - H)
// going DOWN into the relief, away from the eye (st(depth) = st0 - depth *
// searchVec). toEye need not be unit (zero gives (0, 0)).
//   offsetLimited - true: Welsh's offset limiting (listing 10, skipProj);
//                   false: divided by the clamped elevation (POM: the ray
//                   descends one unit of depth per searchVec).
SG_FN vec2 sgParallaxSearchVec(SgFrame f, SgUvFrame uv, vec3 toEye, float scale,
                               bool offsetLimited) {
    vec3 e = sgSafeNormalize(toEye, vec3(0.0f));
    vec2 v = sgProjectVecToTextureSpace(f, e, uv.dSTdx, uv.dSTdy, scale, true);
    if (offsetLimited) return v;
    return v / max(dot(f.nrmBase, e), SG_PARALLAX_MIN_ELEVATION);
}

// Offset mapping with offset limiting (Welsh 2004): the depth at the pixel's
// own coordinate, 1 - H(st0), times the offset-limited search vector. Returns
// the texture-space correction (corrected st = st0 + result).
SG_FN vec2 sgParallaxOffset(SgUvFrame uv, vec2 searchVec, sampler2D tex, int channel) {
    float h0 = sgParallaxHeight(tex, uv.st, uv.dSTdx, uv.dSTdy, channel);
    return -(1.0f - h0) * searchVec;
}

// Parallax occlusion mapping: the ray st(d) = st0 - d * searchVec at depth d
// is marched in `steps` equal steps of depth from 0 (the top) to 1 (the
// bottom, where it always meets the relief); the first sample at or below
// the relief and the one before it bracket the hit, refined by the secant
// (linear interpolation of ray height minus relief height). steps is clamped
// to [1, 1024]. Returns the texture-space correction; depthOut is the
// depth of the hit in [0, 1].
SG_FN vec2 sgParallaxOcclusion(SgUvFrame uv, vec2 searchVec, sampler2D tex, int channel, int steps,
                               SG_OUT(float) depthOut) {
    int n = clamp(steps, 1, 1024);
    float dz = 1.0f / float(n);
    float dPrev = 0.0f;
    float fPrev = 1.0f - sgParallaxHeight(tex, uv.st, uv.dSTdx, uv.dSTdy, channel);
    float dHit = 0.0f;
    if (fPrev > 0.0f) {
        dHit = 1.0f;
        for (int i = 1; i <= n; ++i) {
            float d = float(i) * dz;
            float h = sgParallaxHeight(tex, uv.st - d * searchVec, uv.dSTdx, uv.dSTdy, channel);
            float fi = (1.0f - d) - h; // ray height above the relief
            if (fi <= 0.0f) {
                // fPrev > 0 >= fi: the denominator is positive.
                dHit = dPrev + dz * (fPrev / (fPrev - fi));
                break;
            }
            dPrev = d;
            fPrev = fi;
        }
    }
    depthOut = dHit;
    return -dHit * searchVec;
}

// The offset of the virtual surface from the mesh surface (frame space):
// the tangent-plane offset of the correction (listing 11) plus the relief
// along the base normal, scale * (H(corrected) - 1) (section 2.6).
SG_FN vec3 sgParallaxSurfaceOffset(SgFrame f, SgUvFrame uv, vec2 corrOffs, float scale,
                                   sampler2D tex, int channel) {
    float h = sgParallaxHeight(tex, uv.st + corrOffs, uv.dSTdx, uv.dSTdy, channel);
    return sgTexSpaceOffsToSurface(f, uv.dSTdx, uv.dSTdy, corrOffs) + (scale * (h - 1.0f)) * f.nrmBase;
}

// Section 2.6's normal correction for a curved base surface: the screen
// offset (vx, vy) of the correction (the inverse of the UV Jacobian, as in
// listing 11) applied to the screen derivatives of the base normal,
// nrmBase + vx dNdx + vy dNdy (renormalized, and nrmBase when that
// vanishes). The screen offset is bounded as in listing 11.
SG_FN vec3 sgParallaxCorrectNormal(SgFrame f, SgUvFrame uv, vec2 corrOffs, vec3 dNdx, vec3 dNdy) {
    float k = max(sgMaxAbs2(uv.dSTdx), sgMaxAbs2(uv.dSTdy));
    float om = sgMaxAbs2(corrOffs);
    if (!(k >= SG_FLT_MIN) || !(k <= SG_FLT_MAX) || !(om >= SG_FLT_MIN)) return f.nrmBase;
    vec2 sx = uv.dSTdx / k;
    vec2 sy = uv.dSTdy / k;
    vec2 o = corrOffs / om;
    float rcpDet = sgSignedRcp(sx.x * sy.y - sx.y * sy.x);
    // Screen offset in pixels: (vx, vy) * om * rcpDet / k.
    vec2 v = vec2(sy.y * o.x - sy.x * o.y, -sx.y * o.x + sx.x * o.y);
    vec2 vs = sgBoundedScale2(v * (rcpDet < 0.0f ? -1.0f : 1.0f), vec4(abs(rcpDet), 1.0f / k, om, 1.0f));
    return sgSafeNormalize(f.nrmBase + vs.x * dNdx + vs.y * dNdy, f.nrmBase);
}

// Screen derivatives of the unit base normal from those of the interpolated
// vertex normal n (unnormalized): d(n/|n|) = (dn - u (u . dn)) / |n| with
// u = n/|n|, times the frame's orientation of the base normal (the sign of
// dot(nrmBase, n): double-sided modes flip it). Zero for a zero n.
SG_FN vec3 sgParallaxUnitNormalDeriv(SgFrame f, vec3 vtxNormal, vec3 dN) {
    float len = length(vtxNormal);
    if (!(len >= SG_FLT_MIN) || !(len <= SG_FLT_MAX)) return vec3(0.0f);
    vec3 u = vtxNormal / len;
    float s = dot(f.nrmBase, u) < 0.0f ? -1.0f : 1.0f;
    return sgBoundedScale3(s * (dN - u * dot(u, dN)), vec4(1.0f / len, 1.0f, 1.0f, 1.0f));
}

#endif
