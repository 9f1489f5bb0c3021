// Surface-gradient bump mapping: Mikkelsen, "Surface Gradient Based Bump
// Mapping Framework" (2019), listings 1-15. The framework: every bump
// influence becomes a surface gradient (a vector in the tangent plane), the
// gradients are scaled and summed (eq. 2-3, linearity), and one resolve
// (eq. 1) turns the sum into the perturbed normal.
//
// Conventions (written once, used by every caller):
//  - All 3D vectors are in the frame's common space (SgFrame, frame.glsl).
//  - A "derivative" is dH/d(s,t) of a height H over a texture coordinate set
//    (s right, t up: the derivative is w.r.t. the POSITIVE t axis; see
//    sgTspaceNormalToDeriv for the green-channel convention).
//  - Texture-space vectors dSTdx/dSTdy are dFdxFine/dFdyFine of the texture
//    coordinate (normalized [0,1] units per pixel).
//  - Degenerate inputs (zero vectors, zero-area UV Jacobians, edge-on views)
//    give finite results; which value comes back is stated per function.
#ifndef SG_SURFGRAD_GLSL
#define SG_SURFGRAD_GLSL

#include "sg/frame.glsl"

// Listing 1 / eq. 1: the perturbed unit normal s * normalize(n - surfGrad),
// s = resolveSign (-1 on back faces in FLIP mode, whose frame is the front
// side's: the paper's normalize(-n + surfGrad)). Always unit length: if the
// difference vanishes (a "gradient" equal to the normal, not a tangent
// vector) s * nrmBase is returned.
SG_FN vec3 sgResolve(SgFrame f, vec3 surfGrad) {
    return f.resolveSign * sgSafeNormalize(f.nrmBase - surfGrad, f.nrmBase);
}

// Listings 2 and 3: bump scale on a surface gradient or on a derivative
// (equivalent by linearity; scale -1 inverts the bumps).
SG_FN vec3 sgBumpScale(float scale, vec3 surfGrad) { return scale * surfGrad; }
SG_FN vec2 sgBumpScale(float scale, vec2 deriv) { return scale * deriv; }

// Listing 4 / eq. 5: the xy channels m of a tangent-space normal in [-1,1]
// to the derivative d = -m.xy / m.z with m.z = sqrt(1 - |m.xy|^2).
// m.z^2 is clamped below by max(m.x^2, m.y^2) / 128^2, so |d| <= 128 per
// component (steepest slope 89.55 degrees) and m on or outside the unit
// circle stays finite.
// flipV: false when texture (0,0) is the lower-left corner and green points
// up (OpenGL / glTF "Y+" convention for a lower-left origin), or (0,0) is
// upper-left and green points down; true for the other pairings ("DirectX"
// green with a lower-left origin). The result is always w.r.t. +t.
SG_FN vec2 sgTspaceNormalToDeriv(vec2 m, bool flipV) {
    float fS = 1.0f / (128.0f * 128.0f);
    vec2 mSq = m * m;
    float mzSq = 1.0f - mSq.x - mSq.y;
    float maxCompXySq = fS * max(mSq.x, mSq.y);
    // max(..., FLT_MIN) only matters for m == 0, where both terms are 0.
    float zInv = inversesqrt(max(max(mzSq, maxCompXySq), SG_FLT_MIN));
    float s = flipV ? -1.0f : 1.0f;
    return -zInv * vec2(m.x, s * m.y);
}

// Decoder paired with sgTspaceNormalToDeriv: the unit tangent-space normal
// normalize(-d.x, -d.y, 1) of a derivative (same flipV convention).
SG_FN vec3 sgDerivToTspaceNormal(vec2 d, bool flipV) {
    float s = flipV ? -1.0f : 1.0f;
    return sgSafeNormalize(vec3(-d.x, -s * d.y, 1.0f), vec3(0.0f, 0.0f, 1.0f));
}

// Listing 5 / eq. 6: TBN-style surface gradient d.x * t + d.y * b. With the
// mikktspace basis of sgMikktsBasis (section 2.2) the resolve reproduces the
// classic TBN normal exactly; with sgGenBasisTB it is the procedural frame.
SG_FN vec3 sgSurfgradFromTBN(vec2 deriv, vec3 vT, vec3 vB) { return deriv.x * vT + deriv.y * vB; }

// How much of a UV chart's frame a pixel keeps (sgGenBasisTB): the UV
// Jacobian's determinant measured in units of its own rounding. dFdxFine of
// a texture coordinate is the difference of two interpolated values, each
// rounded at the coordinate's magnitude, so each derivative carries an
// absolute error of an ulp or two of |st| (and of the vertices' UVs the
// interpolation starts from, which lie within about 16 pixels' worth of
// derivative of the pixel's own):
//   noise = 2^-22 (max|st| + 16 k),   k = the Jacobian's largest entry,
// and det J carries about k * noise: `units` = |det J| / (k noise) is the
// determinant's signal-to-noise ratio (for an anisotropic chart, about the
// shorter derivative over noise). Below SG_CHART_FADE_LO units the chart
// has no reliable frame (sign(det) and the tangent's direction would be
// rounding noise: a collapsed or collinear chart, the side walls of a
// planar projection); from SG_CHART_FADE_HI (the determinant within 1/32
// of its value) it is fully trusted; between, the frame fades in with a
// smoothstep, so nothing switches on a rounding-size change of the input.
// At |st| <= 1 this fades a chart only where its shorter screen derivative
// is below about 8e-6 per pixel (a 1024^2 map stretched over 120 pixels per
// texel, or a chart seen ~1000:1 edge-on), where the GPU's own derivatives
// are already wrong by a tenth.
//
// The weight also fades with the chart's shape on the surface: the relative
// determinant of the map from the tangent plane to (s, t), 2 |det M| /
// |M|_F^2 (1 for a conformal chart, about 2/A for one stretched A:1, about
// s for one sheared by s), from 1 at 2^-7 to 0 at 2^-10. The frame's
// direction has a condition number of about 1/shape in the chart's
// vertices: a chart thinner than 2^-10 (a shear of 1e-3) has a frame that a
// rounding-size change of its UVs turns by degrees, whatever the
// derivatives' own precision. Measured on the surface, not on the screen,
// so a conformal chart keeps its frame at any view angle, and on the
// triangle's own plane (the position's screen derivatives), so a base normal
// far from the face (a leaning vertex normal) does not count against the
// chart. With A = [dSTdx dSTdy] and P = [dPdx dPdy], M = A P^-1 gives,
// without a division by P's determinant,
//   shape = 2 |det A| |dPdx x dPdy| / (|a_s|^2 + |a_t|^2),
//   a_s = ds/dx dPdy - ds/dy dPdx,  a_t = dt/dx dPdy - dt/dy dPdx.
#define SG_CHART_ROUNDING 2.384185791e-07f // 2^-22
#define SG_CHART_FADE_LO 4.0f
#define SG_CHART_FADE_HI 32.0f
#define SG_CHART_REL_DET_LO 9.765625e-4f // 2^-10
#define SG_CHART_REL_DET_HI 7.8125e-3f   // 2^-7

// The weight in [0, 1] above (the product of the two fades), from the
// coordinate st, the Jacobian's largest entry k, its determinant scaled by
// 1/k^2 (detScaled, in [-2, 2]) and the chart's shape on the surface.
// k / noise <= 2^18, so nothing overflows; non-finite inputs give 0.
SG_FN float sgChartWeight(vec2 st, float k, float detScaled, float shape) {
    float noise = SG_CHART_ROUNDING * (sgMaxAbs2(st) + 16.0f * k);
    float units = abs(detScaled) * (k / noise);
    bool finite = units >= 0.0f && units <= SG_FLT_MAX && shape >= 0.0f && shape <= SG_FLT_MAX;
    return finite ? smoothstep(SG_CHART_FADE_LO, SG_CHART_FADE_HI, units) *
                        smoothstep(SG_CHART_REL_DET_LO, SG_CHART_REL_DET_HI, shape)
                  : 0.0f;
}

// Listing 6: orthonormal tangent/bitangent for any texture coordinate set,
// generated per pixel from the screen derivatives of the coordinate
// (dSTdx/dSTdy = dFdxFine/dFdyFine of st, the coordinate at the pixel, as
// the paper's listing takes it) and the frame's sigmas. Works for clockwise
// and counter-clockwise UV layouts (mirrored UVs): the bitangent follows +t
// in both. The UV Jacobian is scaled to unit largest entry first (the
// determinant's sign and the tangent's direction do not change), so the
// frame's directions are the same for any texture or world scale.
// Returned: vT, vB orthogonal and tangent, both of length w in [0, 1], the
// chart's weight: 1 for a well-conditioned chart, fading to 0 where the
// determinant is rounding noise (sgChartWeight) and where the tangent's
// combination of the sigmas cancels (its part off the normal below 2^-10
// of it at 0, above 2^-7 at 1: parallel sigmas, an edge-on or collapsed
// screen footprint). TBN-style layers scale by the frame, so they fade with
// it: a degenerate chart contributes nothing, and a rounding-size change of
// st, dSTdx, dSTdy or the frame moves vT, vB by a rounding-size amount.
// Zero sigmas (below ~1e-19 per pixel) or a zero or non-finite Jacobian:
// vT = vB = 0.
SG_FN void sgGenBasisTB(SgFrame f, vec2 st, vec2 dSTdx, vec2 dSTdy, SG_OUT(vec3) vT,
                        SG_OUT(vec3) vB) {
    // One straight path with a final select (llvmpipe evaluates both sides
    // of a branch; this is on every pixel of every UV set).
    float k = max(sgMaxAbs2(dSTdx), sgMaxAbs2(dSTdy));
    float rk = 1.0f / k;
    vec2 sx = dSTdx * rk;
    vec2 sy = dSTdy * rk;
    float det = sx.x * sy.y - sx.y * sy.x;
    float signDet = det < 0.0f ? -1.0f : 1.0f;
    // invCO is (dXds, dYds) up to the positive factor 1/|det|.
    vec2 invCO = signDet * vec2(sy.y, -sx.y);
    vec3 tRaw = f.sigmaX * invCO.x + f.sigmaY * invCO.y;
    // The sigmas are tangent only up to rounding; removing the normal
    // component of their combination again keeps t tangent, so vB = n x t
    // is tangent and as long as t. After one projection t is perpendicular
    // to n up to ~FLT_EPSILON |tRaw| / |t|.
    vec3 t1 = tRaw - dot(tRaw, f.nrmBase) * f.nrmBase;
    float l2 = dot(t1, t1);
    // The part off the normal and the normalization on vectors scaled to
    // unit largest component: sigmas near 1e-19 per pixel would otherwise
    // square into denormals, which a flushing GPU drops term by term.
    float rRaw = 1.0f / sgMaxAbs3(tRaw);
    vec3 tRawS = tRaw * rRaw;
    vec3 t1S = t1 * rRaw;
    float partW = smoothstep(9.5367432e-7f, 6.1035156e-5f, dot(t1S, t1S) / dot(tRawS, tRawS)); // 2^-20, 2^-14
    // The chart's shape on the surface (sgChartWeight), from the position's
    // own screen derivatives scaled to unit largest component (the ratio
    // does not change; no product of tiny or huge derivatives leaves the
    // normal range).
    float rkp = 1.0f / max(sgMaxAbs3(f.dPdx), sgMaxAbs3(f.dPdy));
    vec3 ux = f.dPdx * rkp;
    vec3 uy = f.dPdy * rkp;
    vec3 aS = uy * sx.x - ux * sy.x;
    vec3 aT = uy * sx.y - ux * sy.y;
    float shape = 2.0f * abs(det) * length(cross(ux, uy)) / (dot(aS, aS) + dot(aT, aT));
    bool valid = k >= SG_FLT_MIN && k <= SG_FLT_MAX && l2 >= SG_FLT_MIN;
    float w = valid ? sgChartWeight(st, k, det, shape) * partW : 0.0f;
    vec3 t = valid ? sgSafeNormalize(t1, sgVec3(0.0f)) * w : sgVec3(0.0f);
    vT = t;
    vB = (signDet * f.flipSign) * cross(f.nrmBase, t);
}

// Listing 7: surface gradient from a known perturbed normal v (object- or
// world-space normal map), so it blends with every other layer. v need not
// be unit length; v and nrmBase must be in the same space. A v at or below
// the horizon (dot(n, v) -> 0) is treated as FLT_EPSILON above it: the
// gradient is large but finite and resolves to a normal close to v's
// tangential direction (within about FLT_EPSILON rad of the horizon: the
// rounding of n.v, amplified by the clamped 1/(n.v), can leave it that far
// on either side; tests/bump/hardcases_test.cpp measures it).
SG_FN vec3 sgSurfgradFromPerturbedNormal(SgFrame f, vec3 v) {
    vec3 n = f.nrmBase;
    // Scale v to O(1) first so huge inputs do not overflow; the gradient is
    // invariant to a positive scale of v.
    float m = max(max(abs(v.x), abs(v.y)), abs(v.z));
    vec3 vs = m >= SG_FLT_MIN && m <= SG_FLT_MAX ? v / m : n;
    float nDotV = dot(n, vs);
    float s = 1.0f / max(SG_FLT_EPSILON, abs(nDotV));
    return s * (nDotV * n - vs);
}

// Listing 8 core: the surface gradient of a height whose screen-space
// derivatives are dHdxyDir * (gainA * gainB) (gains >= 0), eq. 3 of
// Mikkelsen 2010. The split lets sgSurfgradScaleDependent pass derivatives
// whose product would overflow binary32. dPdx and dPdy are scaled by their
// largest component k (exact for any world scale; the paper's FLT_EPSILON
// clamp on det becomes relative to k^2) and the result is kept within SG_BIG
// (sgBoundedScale3). Zero dPdx and dPdy give the zero vector.
SG_FN vec3 sgSurfgradFromScreenDerivScaled(SgFrame f, vec2 dHdxyDir, float gainA, float gainB) {
    float k = max(sgMaxAbs3(f.dPdx), sgMaxAbs3(f.dPdy));
    if (!(k >= SG_FLT_MIN) || !(k <= SG_FLT_MAX)) return sgVec3(0.0f);
    vec3 px = sgDivScale3(f.dPdx, k);
    vec3 py = sgDivScale3(f.dPdy, k);
    vec3 vR1 = cross(py, f.nrmBase);
    vec3 vR2 = cross(f.nrmBase, px);
    float det = dot(px, vR1);
    float rcpDet = sgSignedRcp(det);
    // A det below SG_FLT_MIN (a denormal: rounding noise of px, py of unit
    // scale) counts as positive in every build, flushed or not.
    vec3 w = (det <= -SG_FLT_MIN ? -1.0f : 1.0f) * (dHdxyDir.x * vR1 + dHdxyDir.y * vR2);
    return sgBoundedScale3(w, vec4(abs(rcpDet), 1.0f / k, gainA, gainB));
}

// Listing 8, case isDerivScreenSpace: the surface gradient of a height whose
// screen-space derivatives (dH/dx, dH/dy) are known (eq. 3 of Mikkelsen
// 2010), e.g. from listing 9. Uses dPdx, dPdy and nrmBase of the frame
// (dPdx/dPdy of the surface BEFORE displacement). Degenerate cases as in
// sgSurfgradFromScreenDerivScaled.
SG_FN vec3 sgSurfgradFromScreenDeriv(SgFrame f, vec2 dHdxy) {
    return sgSurfgradFromScreenDerivScaled(f, dHdxy, 1.0f, 1.0f);
}

// Listing 8: scale-dependent bump mapping (displacement-style: the bump
// strength follows the map's tiling rate and the surface's metric).
//   deriv    - dH/du, dH/dv in height units per TEXEL (u, v unnormalized:
//              one unit is one texel of a map of size texDim);
//   dSTdx/dy - screen derivatives of the normalized texture coordinate.
// The height is in the same length units as the position. The chain rule
// dH/dx = (texDim * deriv) . dSTdx is evaluated on unit-scaled factors and
// the scales are passed as gains, so no product overflows.
SG_FN vec3 sgSurfgradScaleDependent(SgFrame f, vec2 deriv, vec2 dSTdx, vec2 dSTdy, vec2 texDim) {
    // A denormal derivative is zero in every build (times texDim it would
    // be a normal value that a flushing GPU never sees).
    vec2 dHdST = texDim * sgFlushDenorm2(deriv);
    float dm = sgMaxAbs2(dHdST);
    float sm = max(sgMaxAbs2(dSTdx), sgMaxAbs2(dSTdy));
    if (!(dm >= SG_FLT_MIN) || !(sm >= SG_FLT_MIN) || !(dm <= SG_FLT_MAX) || !(sm <= SG_FLT_MAX)) {
        return sgVec3(0.0f);
    }
    vec2 d = dHdST / dm;
    vec2 sx = sgDivScale2(dSTdx, sm);
    vec2 sy = sgDivScale2(dSTdy, sm);
    return sgSurfgradFromScreenDerivScaled(f, vec2(dot(d, sx), dot(d, sy)), dm, sm);
}

// Listing 9: the 3-tap forward-difference screen-space derivative of a
// height sampled at st (hll), st + dSTdx (hlr) and st + dSTdy (hul); better
// than dFdx(height) on a 2x2 quad. Feed to sgSurfgradFromScreenDeriv.
SG_FN vec2 sgHeightDeriv3Tap(float hll, float hlr, float hul) { return vec2(hlr - hll, hul - hll); }

// Listing 10: projects a unit direction dir (same space as the frame) into
// texture space for parallax mapping / POM, using the true metric of the
// texture mapping (no orthonormal-TBN assumption).
//   bumpScale - displacement p' = p + bumpScale * H(st) * nrmBase;
//   skipProj  - true for basic parallax (Welsh 2004, section 4.3); false
//               extends the offset so its normal component is one unit.
// Returns the texture-space offset (normalized st units) along which to
// search. Edge-on directions (dot(n, dir) -> 0) are clamped (FLT_EPSILON);
// dPdx/dPdy and dSTdx/dSTdy are scaled to unit largest component as in
// listing 8 and the result is kept within SG_BIG; zero dPdx and dPdy give
// (0, 0).
SG_FN vec2 sgProjectVecToTextureSpace(SgFrame f, vec3 dir, vec2 dSTdx, vec2 dSTdy, float bumpScale,
                                      bool skipProj) {
    float k = max(sgMaxAbs3(f.dPdx), sgMaxAbs3(f.dPdy));
    float sm = max(sgMaxAbs2(dSTdx), sgMaxAbs2(dSTdy));
    float dm = sgMaxAbs3(dir);
    if (!(k >= SG_FLT_MIN) || !(k <= SG_FLT_MAX) || !(sm >= SG_FLT_MIN) || !(sm <= SG_FLT_MAX) ||
        !(dm >= SG_FLT_MIN) || !(dm <= SG_FLT_MAX)) {
        return sgVec2(0.0f);
    }
    vec3 px = sgDivScale3(f.dPdx, k);
    vec3 py = sgDivScale3(f.dPdy, k);
    // dir scaled to unit largest component: the horizon clamp on dot(n, dir)
    // is then relative to |dir| (identical for the unit dir of the contract).
    vec3 d = dir / dm;
    vec3 vR1 = cross(py, f.nrmBase);
    vec3 vR2 = cross(f.nrmBase, px);
    float det = dot(px, vR1);
    // Screen-space direction up to the factor 1 / (det k).
    vec2 dirScr = vec2(dot(vR1, d), dot(vR2, d));
    vec2 dirTex = sgDivScale2(dSTdx, sm) * dirScr.x + sgDivScale2(dSTdy, sm) * dirScr.y;
    // skipProj: linear in |dir|; otherwise divided by dot(n, dir), so |dir|
    // cancels.
    float sz = skipProj ? dm : sgSignedRcp(dot(f.nrmBase, d));
    float rcpDet = sgSignedRcp(det);
    float sgn = (rcpDet < 0.0f ? -1.0f : 1.0f) * (sz < 0.0f ? -1.0f : 1.0f) *
                (bumpScale < 0.0f ? -1.0f : 1.0f);
    return sgBoundedScale2(sgn * dirTex, vec4(abs(rcpDet), abs(sz) / k, sm, abs(bumpScale)));
}

// Listing 11: a texture-space offset corrOffs (normalized st units, from
// parallax/POM starting at the coordinate whose screen derivatives are
// dSTdx/dSTdy) mapped to the offset in the tangent plane of the surface.
// The 2x2 UV Jacobian is scaled to unit largest entry before its inverse
// (the paper's absolute FLT_EPSILON clamp on det would wrongly clamp
// ordinary fine texture mappings, e.g. dST ~ 1e-4 per pixel, det ~ 1e-8);
// near-singular Jacobians are clamped relative to their scale, and the
// result is kept within SG_BIG.
SG_FN vec3 sgTexSpaceOffsToSurface(SgFrame f, vec2 dSTdx, vec2 dSTdy, vec2 corrOffs) {
    float k = max(sgMaxAbs2(dSTdx), sgMaxAbs2(dSTdy));
    float om = sgMaxAbs2(corrOffs);
    float sm = max(sgMaxAbs3(f.sigmaX), sgMaxAbs3(f.sigmaY));
    if (!(k >= SG_FLT_MIN) || !(k <= SG_FLT_MAX) || !(om >= SG_FLT_MIN) || !(sm >= SG_FLT_MIN) ||
        !(sm <= SG_FLT_MAX)) {
        return sgVec3(0.0f);
    }
    vec2 sx = sgDivScale2(dSTdx, k);
    vec2 sy = sgDivScale2(dSTdy, k);
    vec2 o = corrOffs / om;
    float det = sx.x * sy.y - sx.y * sy.x;
    float rcpDet = sgSignedRcp(det);
    // Screen-space offset up to the factor om / (det k).
    float vx = sy.y * o.x - sy.x * o.y;
    float vy = -sx.y * o.x + sx.x * o.y;
    vec3 w = (vx * sgDivScale3(f.sigmaX, sm) + vy * sgDivScale3(f.sigmaY, sm)) * (rcpDet < 0.0f ? -1.0f : 1.0f);
    return sgBoundedScale3(w, vec4(abs(rcpDet), 1.0f / k, om, sm));
}

// Listing 12 / eq. 2 of Mikkelsen 2010: the surface gradient of a volume
// bump function with gradient grad (noise, triplanar, decals): its
// projection onto the tangent plane along nrmBase.
SG_FN vec3 sgSurfgradFromVolumeGradient(SgFrame f, vec3 grad) {
    return grad - dot(f.nrmBase, grad) * f.nrmBase;
}

// Listing 14: triplanar blend weights from a normal (Geiss 2007):
// w_i = max(|n_i| - 0.2, 0)^k, normalized to sum 1. The base is divided by
// its largest component before pow (same weights after the normalization),
// so large k cannot underflow every weight to 0. k > 0. A normal with no
// component above 0.2 (not unit length) gets equal weights.
SG_FN vec3 sgTriplanarWeights(vec3 nrm, float k) {
    vec3 b = max(abs(nrm) - sgVec3(0.2f), sgVec3(0.0f));
    float bMax = max(max(b.x, b.y), b.z);
    if (!(bMax >= SG_FLT_MIN)) return sgVec3(1.0f / 3.0f);
    vec3 w = pow(b / bMax, sgVec3(max(k, SG_FLT_EPSILON)));
    return w / (w.x + w.y + w.z);
}

// Listing 13 (eq. 7): the volume gradient of a triplanar projection. The
// derivatives come from maps sampled with (z, y), (x, z) and (x, y) for the
// x, y and z planes (left-handed frame, lower-left texture origin).
//   rightHanded     - the maps were sampled with (-z, y) and (x, -z):
//                     negates the z component of the gradient (section 2.8);
//   upperLeftOrigin - each map was sampled at (s, 1 - t): negates the second
//                     component of each derivative.
SG_FN vec3 sgTriplanarVolumeGradient(vec3 weights, vec2 derivX, vec2 derivY, vec2 derivZ,
                               bool rightHanded, bool upperLeftOrigin) {
    float v = upperLeftOrigin ? -1.0f : 1.0f;
    vec3 grad = vec3(weights.z * derivZ.x + weights.y * derivY.x,
                     v * (weights.z * derivZ.y + weights.x * derivX.y),
                     weights.x * derivX.x + v * weights.y * derivY.y);
    if (rightHanded) grad.z = -grad.z;
    return grad;
}

// Listing 13: triplanar surface gradient (weights from sgTriplanarWeights).
SG_FN vec3 sgSurfgradFromTriplanar(SgFrame f, vec3 weights, vec2 derivX, vec2 derivY, vec2 derivZ,
                             bool rightHanded, bool upperLeftOrigin) {
    return sgSurfgradFromVolumeGradient(f, sgTriplanarVolumeGradient(weights, derivX, derivY,
                                                                     derivZ, rightHanded,
                                                                     upperLeftOrigin));
}

// Section 2.9: volume gradient of a decal projector whose map is sampled
// with the projector-local (x, y): deriv.x * axisX + deriv.y * axisY.
// axisX/axisY are the projector's orthonormal axes in the frame's space;
// upperLeftOrigin negates deriv.y (map sampled at (s, 1 - t)). Gradients of
// many decals can be summed (each scaled by its fade) and projected once with
// sgSurfgradFromVolumeGradient (linearity of the volume gradient).
SG_FN vec3 sgDecalVolumeGradient(vec2 deriv, vec3 axisX, vec3 axisY, bool upperLeftOrigin) {
    float v = upperLeftOrigin ? -1.0f : 1.0f;
    return deriv.x * axisX + (v * deriv.y) * axisY;
}

// Listing 15: surface gradient of one decal projector.
SG_FN vec3 sgSurfgradFromDecal(SgFrame f, vec2 deriv, vec3 axisX, vec3 axisY, bool upperLeftOrigin) {
    return sgSurfgradFromVolumeGradient(f, sgDecalVolumeGradient(deriv, axisX, axisY,
                                                                 upperLeftOrigin));
}

#endif
