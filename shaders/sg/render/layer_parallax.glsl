// Bump layers that move the surface: offset (parallax) mapping and parallax
// occlusion mapping on a height map. Mikkelsen 2019, section 2.6: the view
// direction goes to texture space through the true metric of the texture
// mapping (listing 10's projection, sgParallaxSearch), and the virtual
// surface is the point of the view ray at the depth found; section 3 and
// Fig. 3(c)-(d): later groups re-prologue on that virtual surface.
//
// Listing 11 (sgTexSpaceOffsToSurface) maps the texture offset back to the
// tangent plane through the inverse UV Jacobian. Every offset here is a
// multiple of listing 10's projection J w of the view's screen-space step
// w, so J^-1 (J w) is w itself: the search keeps w and its tangent-plane
// image (the view ray's tangential travel) beside the texture step, and
// no inverse is taken. That matters on singular charts (the side walls of
// a planar projection, collapsed UVs), where J^-1 would amplify the
// rounding of a zero determinant into the virtual surface, its normal and
// every post-resolve layer on it.
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
// metric): finite and bounded for edge-on and back-facing views. The cosine
// between the base normal and the triangle's own normal is bounded by the
// same value (sgParallaxSearch).
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

// The search of a parallax layer, per unit of relief depth (1 - H) going
// down into the relief away from the eye: the change of the texture
// coordinate (st(d) = st0 - d * st), of the point on the tangent plane
// (frame space: the view ray's tangential travel; the virtual surface at
// depth d is p - d * surf + scale * (H - 1) * nrmBase) and of the pixel on
// screen (pixels; section 2.6's normal correction).
struct SgParallaxSearch {
    vec2 st;
    vec3 surf;
    vec2 scr;
};

// Listing 10 with skipProj (offset limiting, Welsh 2004) or divided by the
// view's elevation over the tangent plane clamped to
// SG_PARALLAX_MIN_ELEVATION (POM: one unit of depth per step of the ray).
// toEye need not be unit (zero gives zeros).
//   w = (vR1 . e, vR2 . e) / (det k) is the screen-space step whose
//   tangent-plane image is the view's tangential part e_t; det = n . (dPdx x
//   dPdy) / k^2 is |dPdx x dPdy| / k^2 times the cosine c between the base
//   normal and the surface's geometric normal. A vertex normal nearly in
//   the triangle's plane (c -> 0) would make w, and the search, grow as 1/c
//   (the paper clamps det at FLT_EPSILON: a 1e7 amplification, and a sign
//   that flips on rounding as c crosses 0). Here c is bounded like the
//   view's elevation: 1/det becomes det / max(det, cMin |dPdx x dPdy| /
//   k^2)^2 with cMin = SG_PARALLAX_MIN_ELEVATION, so the search grows at
//   most 20x and fades to zero through c = 0 (continuous, odd in det).
// Zero or non-finite dPdx, dPdy or UV Jacobian, or a zero toEye: zeros.
// Every output is kept within SG_BIG.
SG_FN SgParallaxSearch sgParallaxSearch(SgFrame f, SgUvFrame uv, vec3 toEye, float scale,
                                        bool offsetLimited) {
    SgParallaxSearch r;
    r.st = sgVec2(0.0f);
    r.surf = sgVec3(0.0f);
    r.scr = sgVec2(0.0f);
    vec3 e = sgSafeNormalize(toEye, sgVec3(0.0f));
    float k = max(sgMaxAbs3(f.dPdx), sgMaxAbs3(f.dPdy));
    float sm = max(sgMaxAbs2(uv.dSTdx), sgMaxAbs2(uv.dSTdy));
    if (!(k >= SG_FLT_MIN) || !(k <= SG_FLT_MAX) || !(sm >= SG_FLT_MIN) || !(sm <= SG_FLT_MAX) ||
        sgMaxAbs3(e) == 0.0f) {
        return r;
    }
    vec3 px = sgDivScale3(f.dPdx, k);
    vec3 py = sgDivScale3(f.dPdy, k);
    vec3 vR1 = cross(py, f.nrmBase);
    vec3 vR2 = cross(f.nrmBase, px);
    float det = dot(px, vR1);
    float g = SG_PARALLAX_MIN_ELEVATION * length(cross(px, py));
    float rcpDet = det / max(max(det * det, g * g), SG_FLT_MIN); // <= 1 / g
    // The screen step times k (components <= 2 / g).
    vec2 wk = rcpDet * vec2(dot(vR1, e), dot(vR2, e));
    float rcpElev = offsetLimited ? 1.0f : 1.0f / max(dot(f.nrmBase, e), SG_PARALLAX_MIN_ELEVATION);
    float sgn = scale < 0.0f ? -1.0f : 1.0f;
    vec4 gain = vec4(abs(scale), rcpElev, 1.0f, 1.0f);
    // Tangent plane: sigma / k is dimensionless, so surf is e_t (up to the
    // bounded 1/c) times scale / elevation.
    vec3 surf = sgDivScale3(f.sigmaX, k) * wk.x + sgDivScale3(f.sigmaY, k) * wk.y;
    r.surf = sgn * sgBoundedScale3(surf, gain);
    vec2 stDir = sgDivScale2(uv.dSTdx, sm) * wk.x + sgDivScale2(uv.dSTdy, sm) * wk.y;
    r.st = sgn * sgBoundedScale2(stDir, vec4(abs(scale), rcpElev, sm, 1.0f / k));
    r.scr = sgn * sgBoundedScale2(wk, vec4(abs(scale), rcpElev, 1.0f / k, 1.0f));
    return r;
}

// Offset mapping with offset limiting (Welsh 2004): the depth at the pixel's
// own coordinate, 1 - H(st0) (corrected st = st0 - depth * search.st).
SG_FN float sgParallaxOffsetDepth(SgUvFrame uv, sampler2D tex, int channel) {
    return 1.0f - sgParallaxHeight(tex, uv.st, uv.dSTdx, uv.dSTdy, channel);
}

// Parallax occlusion mapping: the ray st(d) = st0 - d * searchSt at depth d
// is marched in `steps` equal steps of depth from 0 (the top) to 1 (the
// bottom, where it always meets the relief); the first sample at or below
// the relief and the one before it bracket the hit, refined by the secant
// (linear interpolation of ray height minus relief height). steps is clamped
// to [1, 1024]. Returns the depth of the hit in [0, 1] (corrected st =
// st0 - depth * searchSt).
SG_FN float sgParallaxOcclusionDepth(SgUvFrame uv, vec2 searchSt, sampler2D tex, int channel,
                                     int steps) {
    int n = clamp(steps, 1, 1024);
    float dz = 1.0f / float(n);
    float dPrev = 0.0f;
    float fPrev = 1.0f - sgParallaxHeight(tex, uv.st, uv.dSTdx, uv.dSTdy, channel);
    float dHit = 0.0f;
    if (fPrev > 0.0f) {
        dHit = 1.0f;
        for (int i = 1; i <= n; ++i) {
            float d = float(i) * dz;
            float h = sgParallaxHeight(tex, uv.st - d * searchSt, uv.dSTdx, uv.dSTdy, channel);
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
    return dHit;
}

// The offset of the virtual surface from the mesh surface (frame space) at
// the depth found: the view ray's tangential travel, -depth * search.surf,
// plus the relief along the base normal, scale * (H(corrected) - 1)
// (section 2.6).
SG_FN vec3 sgParallaxSurfaceOffset(SgFrame f, SgUvFrame uv, SgParallaxSearch search, float depth,
                                   float scale, sampler2D tex, int channel) {
    float h = sgParallaxHeight(tex, uv.st - depth * search.st, uv.dSTdx, uv.dSTdy, channel);
    return -depth * search.surf + (scale * (h - 1.0f)) * f.nrmBase;
}

// Section 2.6's normal correction for a curved base surface: the screen
// offset scrOffs (pixels) of the correction applied to the screen
// derivatives of the base normal, nrmBase + scrOffs.x dNdx + scrOffs.y dNdy
// (renormalized, and nrmBase when that vanishes).
SG_FN vec3 sgParallaxCorrectNormal(SgFrame f, vec2 scrOffs, vec3 dNdx, vec3 dNdy) {
    return sgSafeNormalize(f.nrmBase + scrOffs.x * dNdx + scrOffs.y * dNdy, f.nrmBase);
}

// Screen derivatives of the unit base normal from those of the interpolated
// vertex normal n (unnormalized): d(n/|n|) = (dn - u (u . dn)) / |n| with
// u = n/|n|, times the frame's orientation of the base normal (the sign of
// dot(nrmBase, n): double-sided modes flip it). Zero for a zero n.
SG_FN vec3 sgParallaxUnitNormalDeriv(SgFrame f, vec3 vtxNormal, vec3 dN) {
    float len = length(vtxNormal);
    if (!(len >= SG_FLT_MIN) || !(len <= SG_FLT_MAX)) return sgVec3(0.0f);
    vec3 u = vtxNormal / len;
    float s = dot(f.nrmBase, u) < 0.0f ? -1.0f : 1.0f;
    return sgBoundedScale3(s * (dN - u * dot(u, dN)), vec4(1.0f / len, 1.0f, 1.0f, 1.0f));
}

// The layer (kinds parallax and pom), as both renderers call it: the
// search from the eye direction toEye (camera-relative: -(vRelPos +
// surfOffset)) and the depth of the hit (offset limiting, or POM when
// `occlusion`); the virtual surface added to surfOffset; section 2.6's
// normal correction of the frame's base normal (`correctNormal`, from the
// vertex normal vtxNormal and its screen derivatives dNdx, dNdy); the
// corrected coordinate written to uv.st (its derivatives kept); and the
// relief's own surface gradient there (`bump`: sgLayerHeight with the
// layer's scale and channel), returned (0 without bump). occlusion,
// correctNormal and bump are compile-time constants of the call.
SG_FN vec3 sgLayerParallax(SG_INOUT(SgFrame) frame, SG_INOUT(SgUvFrame) uv,
                           SG_INOUT(vec3) surfOffset, vec3 toEye, vec3 vtxNormal, vec3 dNdx,
                           vec3 dNdy, SgParallaxParams p, sampler2D tex, bool occlusion,
                           bool correctNormal, bool bump) {
    SgParallaxSearch search = sgParallaxSearch(frame, uv, toEye, p.scale, !occlusion);
    float depth;
    if (occlusion) {
        depth = sgParallaxOcclusionDepth(uv, search.st, tex, p.channel, p.steps);
    } else {
        depth = sgParallaxOffsetDepth(uv, tex, p.channel);
    }
    surfOffset = surfOffset +
                 sgParallaxSurfaceOffset(frame, uv, search, depth, p.scale, tex, p.channel);
    if (correctNormal) {
        vec3 n = sgParallaxCorrectNormal(frame, -depth * search.scr,
                                         sgParallaxUnitNormalDeriv(frame, vtxNormal, dNdx),
                                         sgParallaxUnitNormalDeriv(frame, vtxNormal, dNdy));
        frame = sgFrameWithBase(frame, n);
    }
    uv.st = uv.st - depth * search.st;
    vec3 surfGrad = sgVec3(0.0f);
    if (bump) {
        SgHeightParams h;
        h.scale = p.scale;
        h.channel = p.channel;
        surfGrad = sgLayerHeight(frame, uv, h, tex);
    }
    return surfGrad;
}

#endif
