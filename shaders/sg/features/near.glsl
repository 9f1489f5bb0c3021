// Exact near field of the feature curves: within the profile band, the
// distance to the input curves themselves, their gradient and side, instead
// of the interpolation of Parilov, Zorin (TOG 2008) section 5. Ours: the
// papers reconstruct d and its gradient from corner samples everywhere, so
// the gradient (which decides the direction the profile's slope faces) is
// smoothed near corners and medial axes (sec. 3.2, DFR2); here the bake keeps
// the input's quadratic pieces (texel space) and every texel within the band
// a conservative list of the pieces that can be nearest anywhere in it, and
// the shader takes the minimum over that list. The unsigned distance, its
// gradient and the side are then those of the input curves (up to binary32);
// the paper's interpolation stays outside the band. Storage and fetch cost:
// docs/features.md ("Exact near field").
//
// Closest point on a quadratic B(u) = p0 + b u + a u^2 (b = 2 (p1 - p0),
// a = p0 - 2 p1 + p2) to p: the minima of g(u) = |B(u) - p|^2 on [0, 1] are
// at the ends or at roots of f(u) = g'(u) / 2 = (B(u) - p) . B'(u), a cubic
// with positive leading coefficient 2 |a|^2. Its derivative
// f'(u) = 6 |a|^2 u^2 + 6 (a . b) u + |b|^2 + 2 a . (p0 - p) has at most two
// roots r1 <= r2; f increases on [0, r1] and [r2, 1] and decreases between,
// so every local minimum of g lies in one of those two intervals, where it
// is the unique sign change of an increasing function (or the interval's
// end). Each is found by Newton's method kept inside its bracket (a
// bisection step whenever Newton leaves it): no missed root and no division
// by a vanishing derivative, for any piece and point.
//
// GPU layout (surfgrad/features/feature_maps.h, both RGBA32UI, texelFetch only):
//   near    N x (N + overflow rows): texel (i, j) lists the pieces of texel
//           (i, j): eight 16-bit slots (piece index + 1, 0 = empty), or, when
//           bit 31 of w is set, x = count and y = the first overflow texel
//           (linear index from row N, eight slots per texel). All zero
//           outside the band.
//   pieces  SG_FEAT_PIECES_WIDTH wide: the profile table (SG_FEAT_MAX_PROFILES
//           entries of 5 texels: kind, table count; 16 table heights), then
//           two texels per piece: floatBits(p0, p1); floatBits(p2),
//           packHalf2x16(width0, width1), flags (bit 0 curved, bits 8-15
//           profile index + 1, 0 = the layer's).
// glslang-validate: SG_FEAT_NEAR 1
#ifndef SG_FEATURES_NEAR_GLSL
#define SG_FEATURES_NEAR_GLSL

#include "sg/features/curve.glsl"
#include "sg/features/profile.glsl"

#if SG_FEAT_NEAR

#define SG_FEAT_PIECES_WIDTH 1024
#define SG_FEAT_MAX_PROFILES 16
#define SG_FEAT_PROFILE_TEXELS 5
// First texel of piece 0 in the pieces texture.
#define SG_FEAT_PIECE_BASE (SG_FEAT_MAX_PROFILES * SG_FEAT_PROFILE_TEXELS)
// Newton iterations per interval; measured against binary64 in
// tests/features/near_test.cpp (4 leave the foot point 1e-7 texels off on
// every piece of the glyph and icon sets; 6 leaves a margin).
#define SG_FEAT_NEAR_ITERATIONS 6

// One input piece, texel-local (the texel's corner subtracted) or in texel
// space.
struct SgFeatPiece {
    vec2 p0;
    vec2 p1;
    vec2 p2;
    bool curved;
    int profile;  // index into the map's profile table; -1: the layer's profile
    float width0; // profile width at p0 and p2 (texels); 0: the layer's width
    float width1;
};

// The closest point of one piece.
struct SgFeatNearHit {
    float dist2;  // squared distance (texels^2)
    vec2 toPoint; // p - B(u)
    vec2 tangent; // B'(u), not normalized
    float u;      // parameter of the closest point
};

// f(u) = (B(u) - p) . B'(u) with d0 = p0 - p.
SG_FN float sgFeatFootF(vec2 d0, vec2 b, vec2 a, float u) {
    return dot(d0 + u * (b + u * a), b + (2.0f * u) * a);
}
// f'(u) = |B'(u)|^2 + 2 (B(u) - p) . a.
SG_FN float sgFeatFootDF(vec2 d0, vec2 b, vec2 a, float u) {
    vec2 t = b + (2.0f * u) * a;
    return dot(t, t) + 2.0f * dot(d0 + u * (b + u * a), a);
}

// The minimizer of g on [lo, hi], where f increases.
SG_FN float sgFeatFootOnIncreasing(vec2 d0, vec2 b, vec2 a, float lo, float hi) {
    float fl = sgFeatFootF(d0, b, a, lo);
    float fh = sgFeatFootF(d0, b, a, hi);
    if (fl >= 0.0f) return lo;
    if (fh <= 0.0f) return hi;
    // Bracketed Newton from the secant point (fh - fl > 0 here).
    float u = clamp(lo - fl * (hi - lo) / (fh - fl), lo, hi);
    for (int k = 0; k < SG_FEAT_NEAR_ITERATIONS; ++k) {
        float fu = sgFeatFootF(d0, b, a, u);
        if (fu < 0.0f) {
            lo = u;
        } else {
            hi = u;
        }
        float df = sgFeatFootDF(d0, b, a, u);
        float step = df > SG_FLT_MIN ? fu / df : 0.0f;
        float un = u - step;
        // Inclusive: a converged iterate lands on the end of the bracket it
        // just moved.
        u = (df > SG_FLT_MIN && un >= lo && un <= hi) ? un : 0.5f * (lo + hi);
    }
    return u;
}

SG_FN SgFeatNearHit sgFeatHitAt(vec2 d0, vec2 b, vec2 a, float u) {
    SgFeatNearHit h;
    h.u = u;
    h.toPoint = -(d0 + u * (b + u * a));
    h.tangent = b + (2.0f * u) * a;
    h.dist2 = dot(h.toPoint, h.toPoint);
    return h;
}

// Closest point of piece c to p (both in the same frame).
SG_FN SgFeatNearHit sgFeatClosestOnPiece(SgFeatPiece c, vec2 p) {
    vec2 d0 = c.p0 - p;
    vec2 b = 2.0f * (c.p1 - c.p0);
    float bb = dot(b, b);
    if (!c.curved) {
        // Straight: the projection, clamped.
        float uLine = bb > SG_FLT_MIN ? clamp(-dot(d0, b) / bb, 0.0f, 1.0f) : 0.0f;
        return sgFeatHitAt(d0, b, sgVec2(0.0f), uLine);
    }
    vec2 a = c.p0 - 2.0f * c.p1 + c.p2;
    // The increasing intervals of f: the roots of f' (numerically stable
    // form; q = 0 only for a vanishing f', then one interval).
    float qa = 6.0f * dot(a, a);
    float qb = 6.0f * dot(a, b);
    float qc = bb + 2.0f * dot(a, d0);
    float disc = qb * qb - 4.0f * qa * qc;
    float s = sqrt(max(disc, 0.0f));
    float q = -0.5f * (qb + (qb < 0.0f ? -s : s));
    float ra = qa > SG_FLT_MIN ? q / qa : 2.0f;
    float rb = abs(q) > SG_FLT_MIN ? qc / q : 2.0f;
    bool two = disc > 0.0f && qa > SG_FLT_MIN;
    float r1 = two ? clamp(min(ra, rb), 0.0f, 1.0f) : 1.0f;
    SgFeatNearHit h = sgFeatHitAt(d0, b, a, sgFeatFootOnIncreasing(d0, b, a, 0.0f, r1));
    // The second interval only where f' has two roots (p beyond a centre of
    // curvature of the piece): a branch, not paid where no lane needs it.
    if (two) {
        float r2 = clamp(max(ra, rb), 0.0f, 1.0f);
        SgFeatNearHit h2 = sgFeatHitAt(d0, b, a, sgFeatFootOnIncreasing(d0, b, a, r2, 1.0f));
        if (h2.dist2 < h.dist2) h = h2;
    }
    return h;
}

// Distance, unit gradient and side of the hit (the side with respect to the
// piece's direction, as the bake's corner side bits).
SG_FN SgFeatResult sgFeatNearResult(SgFeatNearHit h, SgFeatPiece c) {
    SgFeatResult r;
    r.dist = sqrt(h.dist2);
    float side = sgFeatCross(h.tangent, h.toPoint);
    r.side = side >= 0.0f ? 1.0f : -1.0f;
    // Inside the piece the gradient is the curve's normal at the foot point
    // (exact by optimality, and well defined as d -> 0); at an end it points
    // from the end to p.
    vec2 n = sgSafeNormalize2(vec2(-h.tangent.y, h.tangent.x), vec2(0.0f, 1.0f)) * r.side;
    bool interior = h.u > 0.0f && h.u < 1.0f;
    r.grad = interior ? n : sgSafeNormalize2(h.toPoint, n);
    r.profile = c.profile;
    r.width = mix(c.width0, c.width1, h.u);
    return r;
}

// ---------------------------------------------------------------------------
// Fetching. The C++ build reads CPU arrays through the sampler types of
// surfgrad/features/feature_maps.h.
#ifdef SG_CPP
#define SG_FEAT_NEAR_SAMPLER const SgFeatNearSampler&
#define SG_FEAT_PIECE_SAMPLER const SgFeatPieceSampler&
#elif defined(SG_HLSL)
#define SG_FEAT_NEAR_SAMPLER Texture2D<uint4>
#define SG_FEAT_PIECE_SAMPLER Texture2D<uint4>
#else
#define SG_FEAT_NEAR_SAMPLER usampler2D
#define SG_FEAT_PIECE_SAMPLER usampler2D
#endif

SG_FN ivec2 sgFeatPieceTexel(int flatIndex) {
    return ivec2(flatIndex % SG_FEAT_PIECES_WIDTH, flatIndex / SG_FEAT_PIECES_WIDTH);
}

// Piece `index`, with `origin` subtracted from its points (2 fetches).
SG_FN SgFeatPiece sgFeatFetchPiece(SG_FEAT_PIECE_SAMPLER pieces, int index, vec2 origin) {
    int at = SG_FEAT_PIECE_BASE + 2 * index;
    uvec4 t0 = texelFetch(pieces, sgFeatPieceTexel(at), 0);
    uvec4 t1 = texelFetch(pieces, sgFeatPieceTexel(at + 1), 0);
    SgFeatPiece c;
    c.p0 = uintBitsToFloat(uvec2(t0.x, t0.y)) - origin;
    c.p1 = uintBitsToFloat(uvec2(t0.z, t0.w)) - origin;
    c.p2 = uintBitsToFloat(uvec2(t1.x, t1.y)) - origin;
    vec2 w = sgUnpackHalf2x16(t1.z);
    c.width0 = w.x;
    c.width1 = w.y;
    c.curved = (t1.w & 1u) != 0u;
    c.profile = int((t1.w >> 8u) & 255u) - 1;
    return c;
}

// Slot k (0..7) of a list texel: the 16-bit piece index + 1 (0: empty).
SG_FN uint sgFeatListSlot(uvec4 t, int k) {
    int h = k & 7;
    uint word = h < 2 ? t.x : (h < 4 ? t.y : (h < 6 ? t.z : t.w));
    return (h & 1) == 0 ? (word & 0xFFFFu) : (word >> 16u);
}

// True when texel ij of the near texture has a list (it lies in the band).
SG_FN bool sgFeatInBand(uvec4 header) {
    return (header.x | header.y | header.z | header.w) != 0u;
}

// The exact result at texel-local p of texel ij whose list header is
// `header` (in the band): the minimum over the listed pieces.
SG_FN SgFeatResult sgFeatNearEval(SG_FEAT_NEAR_SAMPLER nearMap, SG_FEAT_PIECE_SAMPLER pieces, uvec4 header,
                                  ivec2 ij, vec2 p) {
    bool overflow = (header.w & 0x80000000u) != 0u;
    int count = overflow ? int(min(header.x, 65535u)) : 8;
    int start = int(min(header.y, 0x3FFFFFFFu));
    int width = max(textureSize(nearMap, 0).x, 1);
    uvec4 slots = header;
    SgFeatNearHit best;
    best.dist2 = SG_FLT_MAX;
    best.toPoint = sgVec2(0.0f);
    best.tangent = vec2(1.0f, 0.0f);
    best.u = 0.0f;
    SgFeatPiece bestPiece;
    bestPiece.p0 = sgVec2(0.0f);
    bestPiece.p1 = sgVec2(0.0f);
    bestPiece.p2 = sgVec2(0.0f);
    bestPiece.curved = false;
    bestPiece.profile = -1;
    bestPiece.width0 = 0.0f;
    bestPiece.width1 = 0.0f;
    for (int k = 0; k < count; ++k) {
        if (overflow && (k & 7) == 0) {
            int t = start + (k >> 3);
            slots = texelFetch(nearMap, ivec2(t % width, width + t / width), 0);
        }
        uint idx = sgFeatListSlot(slots, k);
        if (idx == 0u) break;
        SgFeatPiece c = sgFeatFetchPiece(pieces, int(idx) - 1, vec2(ij));
        // The piece lies in the box of its control points: skip the closest
        // point when that box is no nearer than the best so far.
        vec2 outside = max(max(min(min(c.p0, c.p1), c.p2) - p, p - max(max(c.p0, c.p1), c.p2)), sgVec2(0.0f));
        if (dot(outside, outside) < best.dist2) {
            SgFeatNearHit h = sgFeatClosestOnPiece(c, p);
            if (h.dist2 < best.dist2) {
                best = h;
                bestPiece = c;
            }
        }
    }
    return sgFeatNearResult(best, bestPiece);
}

// The profile at a near-field result: the nearest curve's profile kind and
// table from the map's profile table when it names one, its width when it
// has one (w0 scaled by the same factor), the layer's depth. Results of the
// paper evaluator (profile -1, width 0) keep the layer's profile.
SG_FN SgFeatProfile sgFeatCurveProfile(SG_FEAT_PIECE_SAMPLER pieces, SgFeatProfile layer, SgFeatResult r) {
    SgFeatProfile pr = layer;
    if (r.profile >= 0 && r.profile < SG_FEAT_MAX_PROFILES) {
        int at = r.profile * SG_FEAT_PROFILE_TEXELS;
        vec4 head = uintBitsToFloat(texelFetch(pieces, sgFeatPieceTexel(at), 0));
        pr.kind = int(head.x);
        pr.tableCount = int(head.y);
        for (int t = 0; t < 4; ++t) {
            vec4 v = uintBitsToFloat(texelFetch(pieces, sgFeatPieceTexel(at + 1 + t), 0));
            pr.table[4 * t] = v.x;
            pr.table[4 * t + 1] = v.y;
            pr.table[4 * t + 2] = v.z;
            pr.table[4 * t + 3] = v.w;
        }
    }
    if (r.width > 0.0f) {
        pr.w0 = layer.w > 0.0f ? layer.w0 * (r.width / layer.w) : 0.0f;
        pr.w = r.width;
    }
    return pr;
}

#endif // SG_FEAT_NEAR

#endif
